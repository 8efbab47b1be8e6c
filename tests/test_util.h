// Helpers shared by the tests: locations, running the CLI, corpus access.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>
#include <cstdint>

namespace mar::test {

inline std::filesystem::path source_dir() { return MARIONETTE_SOURCE_DIR; }
inline std::filesystem::path corpus_dir() { return MARIONETTE_CORPUS_DIR; }
inline bool have_corpus() { return std::filesystem::is_directory(corpus_dir() / "svg"); }
inline std::filesystem::path characters_dir() { return source_dir() / "config" / "characters"; }

// This process's scratch folder: new and empty (mkdtemp), never one an earlier run left behind.
// A name built from the pid alone was not: on CI a pid came round again and handed a test the
// layers.toml its own earlier run had written. The process that made it removes it at exit
// (a forked child that exits does not).
inline const std::filesystem::path& temp_root() {
  static const pid_t owner = ::getpid();
  // Never destroyed, so the exit handler can still read it.
  static const std::filesystem::path* const root = [] {
    std::string t = (std::filesystem::temp_directory_path() / "marionette-test-XXXXXX").string();
    if (!::mkdtemp(t.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    std::atexit([] {
      std::error_code ec;
      if (::getpid() == owner) std::filesystem::remove_all(temp_root(), ec);
    });
    return new std::filesystem::path(t);
  }();
  return *root;
}

/// `xvfb-run -a` from a display number of this process's own: two xvfb-run -a started at once
/// by parallel tests both try 99 first, and one of them fails to start its server.
inline std::string xvfb_run() { return "xvfb-run -n " + std::to_string(200 + ::getpid() % 700) + " -a"; }

inline std::filesystem::path temp_dir(const std::string& name) {
  auto p = temp_root() / name;
  std::filesystem::create_directories(p);
  return p;
}

inline std::string write_temp(const std::string& name, const std::string& text) {
  const auto p = temp_dir("files") / name;
  std::ofstream(p, std::ios::binary) << text;
  return p.string();
}

/// Bytes from whitespace-separated hex ("9b 0c 22").
inline std::vector<uint8_t> hex_bytes(const std::string& s) {
  std::vector<uint8_t> out;
  std::istringstream in(s);
  std::string tok;
  while (in >> tok) out.push_back(uint8_t(std::stoul(tok, nullptr, 16)));
  return out;
}

struct RunResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// Runs the marionette binary with `args` (a shell-quoted string); `env`: "NAME=value ..." set
/// for it alone.
inline RunResult run_cli(const std::string& args, const std::string& env = "") {
  const auto dir = temp_dir("run");
  const auto out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = env + (env.empty() ? "" : " ") + "'" + MARIONETTE_BINARY + "' " + args + " >'" + out.string() +
                          "' 2>'" + err.string() + "'";
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// What a busy CI machine looks like to a test: more spinning threads than the machine has
/// cores, for as long as the hog lives.
class CpuHog {
 public:
  explicit CpuHog(unsigned threads = 2 * std::max(1u, std::thread::hardware_concurrency()) + 1) {
    for (unsigned k = 0; k < threads; ++k)
      threads_.emplace_back([this] {
        volatile uint64_t x = 0;
        while (!stop_.load(std::memory_order_relaxed)) x = x + 1;
      });
  }
  ~CpuHog() {
    stop_ = true;
    for (auto& t : threads_) t.join();
  }
  CpuHog(const CpuHog&) = delete;
  CpuHog& operator=(const CpuHog&) = delete;
  size_t threads() const { return threads_.size(); }

 private:
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
#else
inline constexpr bool kSanitized = false;
#endif

/// How many times a test repeats a run to show that it always gives one result: `n` in the
/// Release suite, at most 2 in the sanitizer build, where a run costs several times more and
/// the memory errors it looks for show in the first run as well as the fifth.
inline int repeats(int n) { return kSanitized ? std::min(n, 2) : n; }

}  // namespace mar::test
