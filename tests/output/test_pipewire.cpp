// PipeWire video out (output/pipewire_out.h): with no daemon the frames are dropped and counted
// and pushing allocates nothing; against a real daemon this test starts (pipewire and
// wireplumber in a private session, tests/tools/with_pipewire.sh) an independent reader —
// GStreamer's pipewiresrc — receives frames each identical to one the show dumped, in order; and
// a daemon killed mid-show does not stop the show.
#include "output/pipewire_out.h"
#include "render/image.h"
#include "alloc_counter.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <thread>

namespace mar {
namespace {

bool have(const char* tool) { return std::system((std::string("command -v ") + tool + " >/dev/null 2>&1").c_str()) == 0; }

// Outside a private PipeWire session: runs this one test again inside one. Returns true when it
// did (the caller returns; the outcome is asserted here).
bool ran_in_session(const char* test) {
  if (std::getenv("MARIONETTE_PIPEWIRE_SESSION")) return false;
  const std::string cmd = "bash '" + (test::source_dir() / "tests/tools/with_pipewire.sh").string() + "' /proc/" + std::to_string(::getpid()) +
                          "/exe --gtest_filter=" + test + " >'" + (test::temp_dir("pw") / "inner.txt").string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(test::temp_dir("pw") / "inner.txt");
  const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(out.find("[  SKIPPED ]"), std::string::npos) << out;
  if (const size_t at = out.find("[ RUN      ]"); rc == 0 && at != std::string::npos) std::printf("%s", out.substr(at).c_str());
  return true;
}

bool tools_missing(std::string& which) {
  for (const char* t : {"dbus-run-session", "pipewire", "wireplumber", "pw-cli", "gst-launch-1.0"})
    if (!have(t)) which += std::string(which.empty() ? "" : ", ") + t;
  return !which.empty();
}

std::string show_file(const std::string& name, int size) {
  return test::write_temp(name + ".toml", "[show]\nrig = \"" + (test::source_dir() / "config/rigs/candle.toml").string() +
                                              "\"\nrate = 60\niterations = 6\n[display]\nwidth = " + std::to_string(size) +
                                              "\nheight = " + std::to_string(size) + "\nbackground = \"#203040\"\n[output]\npipewire = true\n");
}

bool wait_for_node(const std::string& name, double seconds) {
  for (int i = 0; i < int(seconds * 10); ++i) {
    if (std::system(("timeout 2 pw-cli ls Node 2>/dev/null | grep -q '\"" + name + "\"'").c_str()) == 0) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return false;
}

TEST(PipeWireOut, WithNoDaemonFramesAreDroppedAndCountedAndPushAllocatesNothing) {
  const auto empty = test::temp_dir("pw-none");
  ::setenv("XDG_RUNTIME_DIR", empty.c_str(), 1);
  ::unsetenv("PIPEWIRE_REMOTE");
  PipeWireOptions o;
  o.node_name = "marionette-test";
  o.description = "test";
  o.width = 64;
  o.height = 32;
  o.rate = 120;
  auto out = PipeWireOut::open(o);
  std::vector<uint8_t> px(64 * 32 * 4, 200);
  const long before = test::allocation_count();
  for (int f = 0; f < 200; ++f) {
    px[0] = uint8_t(f);
    out->push(px.data(), 64 * 4, uint64_t(f), int64_t(f) * 8333333);
    if (f % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(test::allocation_count() - before, 0) << "push allocates nothing";
  for (int i = 0; i < 100 && out->dropped() < 200; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(out->pushed(), 200u);
  EXPECT_EQ(out->sent(), 0u);
  EXPECT_EQ(out->dropped(), 200u) << "every frame counted as dropped";
  EXPECT_EQ(out->state().rfind("unconnected: no PipeWire daemon", 0), 0u) << out->state();
}

TEST(PipeWireOut, ARealReaderReceivesTheShowsFramesInOrder) {
  std::string missing;
  if (tools_missing(missing)) GTEST_SKIP() << "no PipeWire session to test against: " << missing << " missing (Debian packages dbus, pipewire, wireplumber, gstreamer1.0-pipewire, gstreamer1.0-tools)";
  if (ran_in_session("PipeWireOut.ARealReaderReceivesTheShowsFramesInOrder")) return;
  const int size = 96;
  const std::string show = show_file("pw_show", size);
  const auto dir = test::temp_dir("pw-stream"), dumps = dir / "dumps", got = dir / "got";
  std::filesystem::create_directories(got);
  test::RunResult run;
  std::thread show_thread([&] {
    run = test::run_cli("run " + show + " --headless --realtime --frames 360 --dump-frames " + dumps.string() + " --every 1 --stats " +
                        (dir / "stats.json").string());
  });
  ASSERT_TRUE(wait_for_node("marionette-pw_show", 10)) << "the node appears";
  const std::string gst = "timeout 30 gst-launch-1.0 -q pipewiresrc target-object=marionette-pw_show num-buffers=20 ! video/x-raw,format=BGRA,width=" +
                          std::to_string(size) + ",height=" + std::to_string(size) + " ! multifilesink location=" + (got / "f%03d.bgra").string() +
                          " > " + (dir / "gst.txt").string() + " 2>&1";
  const int gst_rc = std::system(gst.c_str());
  show_thread.join();
  ASSERT_EQ(gst_rc, 0) << "gst-launch-1.0 read 20 frames";
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream sj(dir / "stats.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_EQ(stats["frames"], 360);
  EXPECT_GE(stats["pipewire"]["sent"].get<int>(), 20);
  EXPECT_EQ(stats["heap_allocations_after_warmup"], 0);

  // Every frame the reader got is one the show drew (its dump, BGRA against RGBA), in order. On
  // the wall clock a PNG writer that falls behind drops dumps (counted): a frame whose dump was
  // dropped has nothing to match, and only that many may go unmatched.
  std::vector<std::vector<uint8_t>> drawn(360);
  int dropped_dumps = 0;
  for (int f = 0; f < 360; ++f) {
    char name[64];
    std::snprintf(name, sizeof name, "frame_%06d.png", f);
    if (!std::filesystem::exists(dumps / name)) {
      ++dropped_dumps;
      continue;
    }
    auto img = read_png_image((dumps / name).string());
    ASSERT_TRUE(img.ok()) << img.error;
    drawn[size_t(f)] = img.value->rgba;
  }
  EXPECT_EQ(dropped_dumps, stats["frame_dump"]["dropped"].get<int>()) << "a dump is written or counted as dropped";
  int last = -1, distinct = 0, unmatched = 0;
  std::vector<uint8_t> prev;
  for (int k = 0; k < 20; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "f%03d.bgra", k);
    std::ifstream in(got / name, std::ios::binary);
    std::vector<uint8_t> bgra((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_EQ(bgra.size(), size_t(size * size * 4)) << name;
    std::vector<uint8_t> rgba(bgra.size());
    for (size_t i = 0; i < bgra.size(); i += 4) {
      rgba[i] = bgra[i + 2];
      rgba[i + 1] = bgra[i + 1];
      rgba[i + 2] = bgra[i];
      rgba[i + 3] = bgra[i + 3];
    }
    int match = -1;
    for (int f = std::max(0, last + (rgba == prev ? 0 : 1)); f < int(drawn.size()) && match < 0; ++f)
      if (drawn[size_t(f)] == rgba) match = f;
    prev = rgba;
    if (match < 0) {
      ++unmatched;
      continue;
    }
    distinct += match != last;
    last = match;
  }
  EXPECT_LE(unmatched, dropped_dumps) << "every frame the reader got is one the show drew, in order (or one whose dump was dropped)";
  EXPECT_GE(distinct, 10) << "the reader saw the flame move";
  std::printf("pipewiresrc read 20 frames, %d distinct, %d identical to one of the show's dumps in order (%d dumps dropped; last: frame %d)\n",
              distinct, 20 - unmatched, dropped_dumps, last);
}

TEST(PipeWireOut, ADaemonThatDiesDoesNotStopTheShow) {
  std::string missing;
  if (tools_missing(missing)) GTEST_SKIP() << "no PipeWire session to test against: " << missing << " missing (Debian packages dbus, pipewire, wireplumber, gstreamer1.0-pipewire, gstreamer1.0-tools)";
  if (ran_in_session("PipeWireOut.ADaemonThatDiesDoesNotStopTheShow")) return;
  const std::string show = show_file("pw_dies", 64);
  const auto dir = test::temp_dir("pw-dies");
  test::RunResult run;
  std::thread show_thread([&] { run = test::run_cli("run " + show + " --headless --realtime --frames 240 --stats " + (dir / "stats.json").string()); });
  ASSERT_TRUE(wait_for_node("marionette-pw_dies", 10));
  const char* pid = std::getenv("MARIONETTE_PIPEWIRE_PID");
  ASSERT_NE(pid, nullptr);
  ASSERT_EQ(std::system((std::string("kill -9 ") + pid).c_str()), 0);
  show_thread.join();
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream sj(dir / "stats.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_EQ(stats["frames"], 240) << "the show played to its end";
  EXPECT_EQ(stats["pipewire"]["state"].get<std::string>().rfind("unconnected", 0), 0u) << stats["pipewire"];
  EXPECT_GT(stats["pipewire"]["dropped"].get<int>(), 0);
  EXPECT_NE(run.err.find("warning: PipeWire video out 'marionette-pw_dies'"), std::string::npos) << run.err;
}

}  // namespace
}  // namespace mar
