// OSC out (output/osc_out.h): a receiving socket (liblo's server) gets each value once when it
// first shows, then again only when it changes, at most `rate` times a second; publishing from
// the frame thread allocates nothing; a send that fails is counted and the show goes on; a host
// that does not resolve is named. End to end, liblo's own oscdump (an independent receiver)
// follows a running show's handles, devices and frame times.
#include "output/osc_out.h"
#include "alloc_counter.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <lo/lo.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>

namespace mar {
namespace {

struct Received {
  std::string path;
  std::vector<double> f;
  std::vector<std::string> s;
  std::vector<int> i;
};

struct Receiver {
  lo_server_thread st = nullptr;
  std::mutex m;
  std::vector<Received> got;
  int port = 0;
  Receiver() {
    st = lo_server_thread_new(nullptr, nullptr);  // any free port
    port = lo_server_thread_get_port(st);
    lo_server_thread_add_method(
        st, nullptr, nullptr,
        [](const char* path, const char* types, lo_arg** argv, int argc, lo_message, void* self) -> int {
          auto* r = static_cast<Receiver*>(self);
          Received x;
          x.path = path;
          for (int k = 0; k < argc; ++k) {  // (liblo's arguments need not be aligned for its union: copied out)
            const auto* raw = reinterpret_cast<const char*>(argv[k]);
            if (types[k] == 'f') {
              float f = 0;
              std::memcpy(&f, raw, sizeof f);
              x.f.push_back(f);
            }
            if (types[k] == 's') x.s.push_back(raw);
            if (types[k] == 'i') {
              int32_t i = 0;
              std::memcpy(&i, raw, sizeof i);
              x.i.push_back(i);
            }
          }
          std::lock_guard<std::mutex> g(r->m);
          r->got.push_back(x);
          return 0;
        },
        this);
    lo_server_thread_start(st);
  }
  ~Receiver() { lo_server_thread_free(st); }
  std::vector<Received> take() {
    std::lock_guard<std::mutex> g(m);
    return std::move(got);
  }
  /// Waits (up to 5 s: a busy machine) until `done` holds for what has come, then takes it.
  template <class F>
  std::vector<Received> take_when(F&& done) {
    for (int i = 0; i < 500; ++i) {
      {
        std::lock_guard<std::mutex> g(m);
        if (done(got)) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return take();
  }
};

ShowStateLayout layout() {
  ShowStateLayout l;
  l.handles = {"head", "hand"};
  l.keys = {"wave"};
  l.swaps = {"mouth"};
  l.swap_members = {{"smile", "mouth-a"}};
  l.triggers = {"blink"};
  l.devices = {"korg"};
  return l;
}

void fill(ShowState& s, double head_x, int mouth) {
  s.handles[0] = Vec2(head_x, 20);
  s.handles[1] = Vec2(5, 6);
  s.keys[0] = 0.25;
  s.swaps[0] = mouth;
  s.triggers[0] = 0;
  s.devices[0] = 1;  // connected
  s.frame_ms = 1.5;
  s.latency_ms = 3.0;
}

size_t count(const std::vector<Received>& v, const std::string& path) {
  return size_t(std::count_if(v.begin(), v.end(), [&](const Received& r) { return r.path == path; }));
}

TEST(OscOut, SendsEachValueOnceThenOnlyChangesAtMostAtItsRate) {
  Receiver rx;
  std::string err;
  auto out = OscOut::open({"127.0.0.1", rx.port, 50, "/marionette"}, layout(), &err);
  ASSERT_NE(out, nullptr) << err;
  fill(out->state(), 10, 0);
  out->publish();
  auto first = rx.take_when([](const std::vector<Received>& v) { return v.size() >= 7; });
  ASSERT_EQ(first.size(), 7u) << "every value once";
  std::map<std::string, Received> by;
  for (const auto& r : first) by[r.path] = r;
  EXPECT_EQ(by["/marionette/handle/head"].f, (std::vector<double>{10, 20}));
  EXPECT_EQ(by["/marionette/handle/hand"].f, (std::vector<double>{5, 6}));
  EXPECT_EQ(by["/marionette/key/wave"].f, (std::vector<double>{0.25}));
  EXPECT_EQ(by["/marionette/swap/mouth"].s, (std::vector<std::string>{"smile"}));
  EXPECT_EQ(by["/marionette/trigger/blink"].i, (std::vector<int>{0}));
  EXPECT_EQ(by["/marionette/device/korg"].s, (std::vector<std::string>{"connected"}));
  EXPECT_EQ(by["/marionette/frame"].f, (std::vector<double>{1.5, 3.0}));

  // One second of 200 frames in which the head moves every frame and the mouth opens once.
  const long before = test::allocation_count();
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < 200; ++f) {
    fill(out->state(), 10 + f, f >= 100 ? 1 : 0);
    out->publish();
    std::this_thread::sleep_until(start + std::chrono::milliseconds(5 * (f + 1)));
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "the frame thread's part allocates nothing";
  const auto run = rx.take_when([](const std::vector<Received>& v) {
    return !v.empty() && v.back().path == "/marionette/handle/head" && v.back().f[0] == 209.0;
  });
  const size_t heads = count(run, "/marionette/handle/head");
  std::printf("in 1 s at 200 frames a second: %zu head positions sent (rate 50)\n", heads);
  EXPECT_GE(heads, 25u);
  EXPECT_LE(heads, 53u) << "at most 50 a second (+ the last)";
  EXPECT_EQ(count(run, "/marionette/handle/hand"), 0u) << "a value that did not change is not sent again";
  EXPECT_EQ(count(run, "/marionette/frame"), 0u);
  ASSERT_EQ(count(run, "/marionette/swap/mouth"), 1u);
  for (const auto& r : run)
    if (r.path == "/marionette/swap/mouth") {
      EXPECT_EQ(r.s[0], "mouth-a");
    }
  EXPECT_EQ(run.back().path, "/marionette/handle/head");
  EXPECT_EQ(run.back().f[0], 209.0) << "the last position arrives";
  EXPECT_EQ(out->send_errors(), 0u);
}

// A cast's state: each handle, key, swap set and trigger under its character's name.
TEST(OscOut, ACastsAddressesCarryTheCharactersName) {
  Receiver rx;
  std::string err;
  ShowStateLayout l = layout();
  l.handle_who = {"robot", "cat"};
  l.key_who = {"robot"};
  l.swap_who = {"cat"};
  l.trigger_who = {"cat"};
  auto out = OscOut::open({"127.0.0.1", rx.port, 50, "/marionette"}, l, &err);
  ASSERT_NE(out, nullptr) << err;
  fill(out->state(), 10, 0);
  out->publish();
  auto got = rx.take_when([](const std::vector<Received>& v) { return v.size() >= 7; });
  std::map<std::string, Received> by;
  for (const auto& r : got) by[r.path] = r;
  EXPECT_EQ(by["/marionette/robot/handle/head"].f, (std::vector<double>{10, 20}));
  EXPECT_EQ(by["/marionette/cat/handle/hand"].f, (std::vector<double>{5, 6}));
  EXPECT_EQ(by["/marionette/robot/key/wave"].f, (std::vector<double>{0.25}));
  EXPECT_EQ(by["/marionette/cat/swap/mouth"].s, (std::vector<std::string>{"smile"}));
  EXPECT_EQ(by["/marionette/cat/trigger/blink"].i, (std::vector<int>{0}));
  EXPECT_EQ(by["/marionette/device/korg"].s, (std::vector<std::string>{"connected"}));  // (the show's)
  EXPECT_EQ(by.count("/marionette/handle/head"), 0u);
}

TEST(OscOut, AFailedSendIsCountedAndAHostThatDoesNotResolveIsNamed) {
  std::string err;
  // Nobody listens on port 9: after the first send the kernel refuses the rest (ECONNREFUSED).
  auto out = OscOut::open({"127.0.0.1", 9, 100, "/m"}, layout(), &err);
  ASSERT_NE(out, nullptr) << err;
  for (int f = 0; f < 500 && out->send_errors() <= 5; ++f) {  // (until six are refused: a busy machine sends less often)
    fill(out->state(), f, 0);
    out->publish();
    std::this_thread::sleep_for(std::chrono::milliseconds(12));
  }
  out->stop();
  EXPECT_GT(out->send_errors(), 5u) << "refused sends are counted (the kernel reports every other one)";
  auto bad = OscOut::open({"no-such-host.invalid", 9000, 30, "/m"}, layout(), &err);
  EXPECT_EQ(bad, nullptr);
  EXPECT_NE(err.find("no-such-host.invalid:9000"), std::string::npos) << err;
}

TEST(OscOut, OscdumpFollowsARunningShow) {
  if (std::system("command -v oscdump >/dev/null 2>&1") != 0) GTEST_SKIP() << "oscdump is not installed (Debian package liblo-tools)";
  const int port = 20000 + int(::getpid() % 20000);
  const auto dir = test::temp_dir("osc_out");
  const std::string show = test::write_temp(
      "osc_show.toml", "[show]\nrig = \"" + (test::source_dir() / "config/rigs/candle.toml").string() +
                           "\"\nrate = 60\n[osc_out]\nport = " + std::to_string(port) +
                           "\nrate = 30\n[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n0.0 move knob1 0.5\n0.3 move knob1 0.0 over 0.7\n\"\"\"\n"
                           "[[binding]]\ndevice = \"korg\"\ncontrol = \"cc 16\"\ntarget = \"physics.wind\"\nrange = [-1500.0, 1500.0]\n");
  const std::string dump = (dir / "oscdump.txt").string();
  ASSERT_EQ(std::system(("oscdump -L " + std::to_string(port) + " > '" + dump + "' 2>&1 & echo $! > '" + (dir / "pid").string() + "'").c_str()), 0);
  // oscdump listens once its UDP port shows in /proc/net/udp (a busy machine takes its time).
  char hex[8];
  std::snprintf(hex, sizeof hex, ":%04X ", port);
  bool listening = false;
  for (int i = 0; i < 100 && !listening; ++i) {
    std::ifstream udp("/proc/net/udp");
    const std::string table((std::istreambuf_iterator<char>(udp)), std::istreambuf_iterator<char>());
    listening = table.find(hex) != std::string::npos;
    if (!listening) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_TRUE(listening) << "oscdump listens on " << port;
  auto r = test::run_cli("run " + show + " --headless --realtime --frames 90 --stats " + (dir / "stats.json").string());
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  std::system(("kill $(cat '" + (dir / "pid").string() + "')").c_str());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(dump);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("/marionette/device/korg s \"connected\""), std::string::npos) << text.substr(0, 2000);
  EXPECT_NE(text.find("/marionette/handle/"), std::string::npos);
  EXPECT_NE(text.find("/marionette/frame ff"), std::string::npos);
  std::ifstream sj(dir / "stats.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_GT(stats["osc_out"]["messages"].get<int>(), 10);
  EXPECT_LE(stats["osc_out"]["bundles"].get<int>(), 47) << "at most 30 sends a second over the 1.5 s show (+ the last)";
  EXPECT_EQ(stats["osc_out"]["send_errors"], 0);
  EXPECT_EQ(stats["heap_allocations_after_warmup"], 0);
}

}  // namespace
}  // namespace mar
