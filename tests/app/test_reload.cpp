// Reloading a running show (SIGHUP, or a saved edit: app/live_reload.cpp): the clock, the
// devices and their simulators' scripts go on; an edit to the devices starts them over; in a
// window a saved edit is picked up on its own, a bad one is refused with file:line, and the
// title says what was reloaded.
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <csignal>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <iostream>
#include <thread>

namespace mar {
namespace {

std::string show_text(const std::string& range, const std::string& knob = "knob1") {
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  return "[show]\nrig = \"" + rig + "\"\nrate = 60\n[display]\nwidth = 160\nheight = 200\n" +
         "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n0 move " + knob + " 0\n0 move fader1 0\n" +
         "0.1 move fader1 1 over 3\n\"\"\"\n[[binding]]\ndevice = \"k\"\ncontrol = \"cc 0\"\ntarget = \"handle.chest.x\"\nrange = " +
         range + "\n";
}

// The largest distance a point moved between two poses of a figure.
double max_step(const std::vector<Points>& x, const std::vector<Points>& y) {
  double d = 0;
  for (size_t s = 0; s < x.size() && s < y.size(); ++s)
    for (size_t i = 0; i < x[s].size() && i < y[s].size(); ++i) d = std::max(d, (x[s][i] - y[s][i]).norm());
  return d;
}

// Saves as an editor does: a new file renamed over the old.
void save(const std::string& path, const std::string& text) {
  std::ofstream(path + ".tmp") << text;
  std::filesystem::rename(path + ".tmp", path);
}

std::unique_ptr<LiveShow> load(const std::string& path, LiveShow* previous = nullptr) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o, previous);
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

TEST(Reload, AnEditKeepsTheClockTheDevicesAndTheSimulatorsWhereTheyAre) {
  const std::string path = (test::temp_dir("reload-keep") / "show.toml").string();
  save(path, show_text("[140.0, 240.0]"));  // the chest's rest (x 150) is at 0.1: picked up at 0.4 s
  auto a = load(path);
  ASSERT_TRUE(a);
  const int chest = a->mapping().handle_index("chest");
  auto fader = [](long frame) { return (double(frame) / 60 - 0.1) / 3; };  // the sweep at a frame's time
  for (long k = 0; k < 90; ++k) a->frame(int64_t(double(k) * 1e9 / 60));
  EXPECT_NEAR(a->targets()[size_t(chest)].x(), 140 + 100 * fader(89), 3);
  const DeviceSet* devices = a->devices();
  save(path, show_text("[400.0, 500.0]"));  // the binding's range moves
  auto b = load(path, a.get());
  ASSERT_TRUE(b);
  EXPECT_EQ(b->restarted(), "");
  EXPECT_EQ(b->reloads(), 1);
  EXPECT_EQ(b->frames(), 90);               // the clock goes on
  EXPECT_EQ(b->devices(), devices);         // the same device set, connections and all
  for (long k = 90; k < 120; ++k) b->frame(int64_t(double(k) * 1e9 / 60));
  // The new range at once, without the fader having to pick the handle up again; and the
  // simulator's script went on from 1.5 s: the fader is where the sweep is at 2 s.
  EXPECT_NEAR(b->targets()[size_t(chest)].x(), 400 + 100 * fader(119), 3);
  const auto j = nlohmann::json::parse(b->stats_json());
  EXPECT_EQ(j["frames"], 120);
  EXPECT_EQ(j["reloads"]["count"], 1);
}

TEST(Reload, AnEditToTheDevicesStartsThemOverAndSaysWhy) {
  const std::string path = (test::temp_dir("reload-devices") / "show.toml").string();
  save(path, show_text("[100.0, 200.0]"));
  auto a = load(path);
  ASSERT_TRUE(a);
  for (long k = 0; k < 30; ++k) a->frame(int64_t(double(k) * 1e9 / 60));
  save(path, show_text("[100.0, 200.0]", "knob2"));  // the device's script changed
  auto b = load(path, a.get());
  ASSERT_TRUE(b);
  EXPECT_EQ(b->restarted(), "device 'k'");
  EXPECT_TRUE(a->released());
  EXPECT_EQ(b->frames(), 0);
}

// A reload mid-gesture: the new show's solver starts from its own guess, up to 6 % of the
// figure away from where the running show drew it (26 units here), and its chains of secondary
// motion would start at rest; the figure now moves from where it was drawn over a few frames,
// and the chains go on swinging. Across the reload no step between two frames is larger than
// the show's own steps without a reload over the same frames, plus 1 % of the figure's diagonal.
TEST(Reload, TheFigureDoesNotJumpAtAReload) {
  const std::string path = (test::temp_dir("reload-jump") / "show.toml").string();
  save(path, show_text("[100.0, 300.0]"));
  auto ref = load(path);
  auto a = load(path);
  ASSERT_TRUE(ref && a);
  std::vector<Points> last, last_ref;
  for (long k = 0; k < 90; ++k) {
    a->frame(int64_t(double(k) * 1e9 / 60));
    ref->frame(int64_t(double(k) * 1e9 / 60));
  }
  last = a->puppet().shapes;
  last_ref = ref->puppet().shapes;
  save(path, show_text("[100.0, 300.0]") + "# an edit that changes nothing the figure does\n");
  auto b = load(path, a.get());
  ASSERT_TRUE(b);
  const Bounds bb = b->puppet().character.bounds();
  const double diag = (bb.hi - bb.lo).norm();
  double across = 0, without = 0;
  for (long k = 90; k < 150; ++k) {
    b->frame(int64_t(double(k) * 1e9 / 60));
    ref->frame(int64_t(double(k) * 1e9 / 60));
    across = std::max(across, max_step(last, b->puppet().shapes));
    without = std::max(without, max_step(last_ref, ref->puppet().shapes));
    last = b->puppet().shapes;
    last_ref = ref->puppet().shapes;
  }
  std::cout << "largest step between frames 90-150: " << without << " units without a reload, " << across
            << " across it (diagonal " << diag << ")\n";
  EXPECT_LT(across, without + 0.01 * diag);
}

// A cast reloads as a whole, each character going on from where it was (by name): an edit to
// one character's rig (the robot's head held by a new handle) prepares the robot alone; the
// figure is kept as it was loaded and goes on exactly as it would with no reload, and the robot eases into its new pose over the reload's
// blend (its first frame after the reload no further than that from its last before).
TEST(Reload, AnEditToOneCharacterOfACastLeavesTheOthersWhereTheyAre) {
  const auto dir = test::temp_dir("reload-cast");
  const std::string robot = (dir / "robot.toml").string();
  const std::string robot_text = "character = \"" + (test::source_dir() / "config/characters/robot.svg").string() +
                                 "\"\niterations = 12\n[[handle]]\nname = \"chest\"\nrest = [150.0, 206.0]\n"
                                 "[[handle]]\nname = \"left-hand\"\nrest = [87.0, 266.0]\n";
  save(robot, robot_text);
  const std::string path = (dir / "show.toml").string();
  const std::string show = "[show]\nrate = 60\n[display]\nwidth = 320\nheight = 200\n"
                           "[[character]]\nname = \"figure\"\nrig = \"" + (test::source_dir() / "config/rigs/figure.toml").string() +
                           "\"\n[[character]]\nname = \"robot\"\nrig = \"" + robot + "\"\n"
                           "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n0 move fader1 0\n0 move fader2 0\n"
                           "0.1 move fader1 1 over 3\n0.1 move fader2 1 over 3\n\"\"\"\n"
                           "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 0\"\ntarget = \"figure.handle.chest.x\"\nrange = [100.0, 300.0]\n"
                           "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 1\"\ntarget = \"robot.handle.left-hand.y\"\nrange = [266.0, 150.0]\n";
  save(path, show);
  auto ref = load(path);
  auto a = load(path);
  ASSERT_TRUE(ref && a);
  for (long k = 0; k < 90; ++k) {
    a->frame(int64_t(double(k) * 1e9 / 60));
    ref->frame(int64_t(double(k) * 1e9 / 60));
  }
  std::vector<std::vector<Points>> last, last_ref;
  for (size_t c = 0; c < 2; ++c) {
    last.push_back(a->actors()[c]->puppet().shapes);
    last_ref.push_back(ref->actors()[c]->puppet().shapes);
  }
  save(robot, robot_text + "[[handle]]\nname = \"head\"\nrest = [150.0, 90.0]\n");  // the robot's head held too
  const Puppet* figure = &a->actors()[0]->puppet();
  const Puppet* old_robot = &a->actors()[1]->puppet();
  auto b = load(path, a.get());
  ASSERT_TRUE(b);
  EXPECT_EQ(b->restarted(), "") << "the devices and the clock go on";
  EXPECT_EQ(b->actors()[1]->puppet().rig.handles.size(), 3u) << "the edit took";
  // Only the edited character was prepared again: the figure is the running show's puppet.
  EXPECT_EQ(&b->actors()[0]->puppet(), figure) << "the figure's files did not change: it is kept as loaded";
  EXPECT_NE(&b->actors()[1]->puppet(), old_robot);
  EXPECT_EQ(b->kept(), std::vector<std::string>{"figure"});
  double across[2] = {0, 0}, without[2] = {0, 0}, first_robot = 0;
  for (long k = 90; k < 150; ++k) {
    b->frame(int64_t(double(k) * 1e9 / 60));
    ref->frame(int64_t(double(k) * 1e9 / 60));
    if (k == 90) first_robot = max_step(last[1], b->actors()[1]->puppet().shapes);
    for (size_t c = 0; c < 2; ++c) {
      across[c] = std::max(across[c], max_step(last[c], b->actors()[c]->puppet().shapes));
      without[c] = std::max(without[c], max_step(last_ref[c], ref->actors()[c]->puppet().shapes));
      last[c] = b->actors()[c]->puppet().shapes;
      last_ref[c] = ref->actors()[c]->puppet().shapes;
    }
  }
  double diag[2];
  for (size_t c = 0; c < 2; ++c) {
    const Bounds bb = b->actors()[c]->puppet().character.bounds();
    diag[c] = (bb.hi - bb.lo).norm();
    std::cout << b->actors()[c]->name() << ": largest step between frames 90-150: " << without[c] << " units without a reload, "
              << across[c] << " across it (diagonal " << diag[c] << ")\n";
  }
  // (kept as loaded, its solver going on: the figure moves exactly as it does with no reload)
  EXPECT_NEAR(across[0], without[0], 1e-6 * diag[0]) << "the figure, not edited";
  EXPECT_LT(first_robot, without[1] + 0.01 * diag[1]) << "the robot's first frame after the edit";
  EXPECT_GT(across[1], without[1]) << "(the edit changed the robot's pose: the test sees a reload)";
}

// A bomb saved over a running show's character (a hang for 10 minutes once, SIGTERM ignored):
// the edit is prepared on a thread of its own while the show plays on, refused with its bound,
// and the running show goes on; then a good edit is prepared the same way and takes over.
TEST(Reload, AnEditIsPreparedOffTheFrameThreadAndABombIsRefusedWhileTheShowPlays) {
  const auto dir = test::temp_dir("reload-bomb");
  const std::string character = (dir / "figure.svg").string(), path = (dir / "show.toml").string();
  std::filesystem::copy_file(test::source_dir() / "config/characters/figure.svg", character,
                             std::filesystem::copy_options::overwrite_existing);
  save(path, "[show]\ncharacter = \"" + character + "\"\n" + show_text("[140.0, 240.0]").substr(7));
  RunOptions o;
  o.headless = true;
  o.realtime = true;  // the wall clock: the files are watched
  o.quiet = true;
  o.frames = 1'000'000;
  auto loaded = LiveShow::load(path, o);
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  std::unique_ptr<LiveShow> a = std::move(*loaded.value);
  std::string bomb = "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\"><defs><g id=\"a0\"/>";
  for (int l = 1; l < 10; ++l) {
    bomb += "<g id=\"a" + std::to_string(l) + "\">";
    for (int k = 0; k < 10; ++k) bomb += "<use xlink:href=\"#a" + std::to_string(l - 1) + "\"/>";
    bomb += "</g>";
  }
  bomb += "</defs><use xlink:href=\"#a9\"/></svg>";
  std::atomic<bool> finished{false};
  std::thread editor([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    save(character, bomb);
    for (int k = 0; k < 600 && !finished; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!finished) a->stop();  // (a watch that never fired: the test fails below, not hangs)
  });
  const long before = a->frames();
  EXPECT_EQ(a->run(), 0);
  finished = true;
  editor.join();
  ASSERT_TRUE(a->reload_asked()) << "the saved character was seen";
  EXPECT_GT(a->frames(), before);
  EXPECT_GE(a->frames_while_preparing(), 1) << "the show played on while the edit was prepared";
  auto prepared = a->take_prepared();
  ASSERT_FALSE(prepared.ok());
  EXPECT_NE(prepared.error.find("figure.svg:1: "), std::string::npos) << prepared.error;
  EXPECT_NE(prepared.error.find("elements once <use> references are expanded"), std::string::npos) << prepared.error;
  a->reloaded(a->reload_cause(), prepared.error);  // as `marionette run` does: the show goes on
  // A good edit after it: prepared on its thread, taken over at a frame boundary.
  std::thread fixer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    std::filesystem::copy_file(test::source_dir() / "config/characters/figure.svg", character + ".tmp",
                               std::filesystem::copy_options::overwrite_existing);
    std::filesystem::rename(character + ".tmp", character);
    for (int k = 0; k < 600 && !finished; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  });
  finished = false;
  std::thread guard([&] {
    for (int k = 0; k < 600 && !finished; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!finished) a->stop();
  });
  EXPECT_EQ(a->run(), 0);
  finished = true;
  fixer.join();
  guard.join();
  ASSERT_TRUE(a->reload_asked());
  auto good = a->take_prepared();
  ASSERT_TRUE(good.ok()) << good.error;
  auto b = LiveShow::take_over(std::move(*good.value), a.get());
  ASSERT_TRUE(b.ok()) << b.error;
  EXPECT_EQ((*b.value)->restarted(), "");
  EXPECT_EQ((*b.value)->frames(), a->frames()) << "one clock";
}

// On the wall clock, as a kiosk runs: an edit to one character of a cast is prepared on its own
// thread while the show plays on and poses every character (what ThreadSanitizer watches: the
// kept puppet is read there while it is posed here); only the edited one is loaded again, and
// one saved with the same bytes is kept too.
TEST(Reload, OnlyTheEditedCharacterOfACastIsPreparedWhileTheShowPlays) {
  const auto dir = test::temp_dir("reload-cast-live");
  const std::string robot = (dir / "robot.toml").string(), cat = (dir / "cat.toml").string();
  const std::string robot_text = "character = \"" + (test::source_dir() / "config/characters/robot.svg").string() +
                                 "\"\n[[handle]]\nname = \"chest\"\nrest = [150.0, 206.0]\n"
                                 "[[handle]]\nname = \"left-hand\"\nrest = [87.0, 266.0]\n";
  save(robot, robot_text);
  std::filesystem::copy_file(test::source_dir() / "config/rigs/figure.toml", cat, std::filesystem::copy_options::overwrite_existing);
  const std::string figure_svg = (test::source_dir() / "config/characters/figure.svg").string();
  std::string cat_text;
  {
    std::ifstream in(cat);
    cat_text.assign(std::istreambuf_iterator<char>(in), {});
  }
  // (the copied rig names its drawing beside it: name the shipped one)
  const size_t at = cat_text.find("character = ");
  ASSERT_NE(at, std::string::npos);
  cat_text.replace(at, cat_text.find('\n', at) - at, "character = \"" + figure_svg + "\"");
  save(cat, cat_text);
  const std::string path = (dir / "show.toml").string();
  save(path, "[show]\nrate = 60\n[display]\nwidth = 320\nheight = 200\n"
             "[[character]]\nname = \"figure\"\nrig = \"" + cat + "\"\n[[character]]\nname = \"robot\"\nrig = \"" + robot + "\"\n"
             "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n0 move fader1 0\n0.1 move fader1 1 over 30\n\"\"\"\n"
             "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 0\"\ntarget = \"figure.handle.chest.x\"\nrange = [100.0, 300.0]\n"
             "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 1\"\ntarget = \"figure.blend.wave\"\n");  // (its key poses kept too)
  RunOptions o;
  o.headless = true;
  o.realtime = true;  // the wall clock: the files are watched
  o.quiet = true;
  o.frames = 1'000'000;
  auto loaded = LiveShow::load(path, o);
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  std::unique_ptr<LiveShow> a = std::move(*loaded.value);
  const Puppet* figure = &a->actors()[0]->puppet();
  std::atomic<bool> finished{false};
  std::thread editor([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    save(robot, robot_text + "[[handle]]\nname = \"head\"\nrest = [150.0, 90.0]\n");
    save(cat, cat_text);  // the same bytes: kept (in this reload, or in one after it)
    for (int k = 0; k < 600 && !finished; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!finished) a->stop();  // (a watch that never fired: the test fails below, not hangs)
  });
  EXPECT_EQ(a->run(), 0);
  finished = true;
  editor.join();
  ASSERT_TRUE(a->reload_asked()) << "the saved rigs were seen";
  auto prepared = a->take_prepared();
  ASSERT_TRUE(prepared.ok()) << prepared.error;
  auto b = LiveShow::take_over(std::move(*prepared.value), a.get());
  ASSERT_TRUE(b.ok()) << b.error;
  LiveShow& s = **b.value;
  EXPECT_EQ(s.kept(), std::vector<std::string>{"figure"});
  EXPECT_EQ(&s.actors()[0]->puppet(), figure);
  EXPECT_EQ(s.actors()[1]->puppet().rig.handles.size(), 3u) << "the edit took";
  EXPECT_TRUE(s.actors()[0]->has_keys()) << "the kept figure's key poses, from the keys it solved at load";
  a.reset();  // (the old show gone, the kept puppet is the new show's alone)
  const long f0 = s.frames();
  for (long k = 0; k < 30; ++k) s.frame(int64_t(double(f0 + k) * 1e9 / 60));
  for (const auto& actor : s.actors())
    for (const Points& sh : actor->puppet().shapes)
      for (const Vec2& q : sh) ASSERT_TRUE(q.allFinite());
}

// In a window (under Xvfb), on the wall clock: saving the show reloads it without a restart
// (the title says so, as xdotool reads it), a bad save is refused with file:line, and the show
// goes on to the end with one clock.
TEST(Reload, ASavedEditReloadsTheShowInItsWindowAndABadOneIsRefused) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1 && command -v xdotool >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "xvfb-run or xdotool not installed";
  const auto dir = test::temp_dir("reload-watch");
  const std::string show = (dir / "show.toml").string(), stats = (dir / "stats.json").string();
  const std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string(), env = (dir / "env.txt").string(),
                    pidf = (dir / "pid.txt").string();
  save(show, show_text("[100.0, 200.0]"));
  const std::string inner = "echo \"$DISPLAY $XAUTHORITY\" > '" + env + "'; ASAN_OPTIONS=detect_leaks=0 '" + MARIONETTE_BINARY +
                            "' run '" + show + "' --frames 100000 --stats '" + stats + "' > '" + out + "' 2> '" + err +
                            "' & echo $! > '" + pidf + "'; wait";
  const std::string cmd = test::xvfb_run() + " -s '-screen 0 640x480x24' sh -c \"" + [&] {
    std::string q;
    for (char c : inner) q += c == '"' || c == '$' ? std::string("\\") + c : std::string(1, c);
    return q;
  }() + "\" >/dev/null 2>&1 &";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  auto wait_for = [&](const std::string& path, const std::string& what, int count = 1) {  // generous: a busy machine is slow
    for (int k = 0; k < 900; ++k) {
      const std::string t = slurp(path);
      int n = 0;
      for (size_t at = t.find(what); at != std::string::npos; at = t.find(what, at + 1)) ++n;
      if (n >= count) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  };
  const bool started = wait_for(out, "running") && wait_for(pidf, "\n");
  const pid_t pid = started ? pid_t(std::stol(slurp(pidf))) : -1;
  std::string title;
  if (started) {
    EXPECT_NE(slurp(out).find("in a window"), std::string::npos) << slurp(out) << slurp(err);
    save(show, show_text("[300.0, 400.0]"));
    EXPECT_TRUE(wait_for(err, "reloaded " + show + " (show.toml) at frame")) << slurp(err);
    // The window's title, read by the X server's own client.
    std::istringstream e(slurp(env));
    std::string display, xauth;
    e >> display >> xauth;
    const std::string q = "DISPLAY=" + display + " XAUTHORITY=" + xauth +
                          " xdotool search --name 'reloaded show.toml' getwindowname > '" + (dir / "title.txt").string() + "'";
    for (int k = 0; k < 50 && title.empty(); ++k) {
      if (std::system(q.c_str()) == 0) title = slurp((dir / "title.txt").string());
      else std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    save(show, show_text("[300.0, 400.0]") + "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 1\"\ntarget = \"handle.nose.x\"\n");
    EXPECT_TRUE(wait_for(err, "reload refused")) << slurp(err);
    EXPECT_NE(slurp(err).find(show + ":23: the rig has no handle 'nose'"), std::string::npos) << slurp(err);
    save(show, show_text("[100.0, 200.0]"));
    EXPECT_TRUE(wait_for(err, "reloaded " + show, 2)) << slurp(err);
    ::kill(pid, SIGINT);
  }
  ASSERT_TRUE(started) << slurp(out) << slurp(err);
  EXPECT_TRUE(wait_for(stats, "run_hash")) << slurp(err);
  EXPECT_EQ(title.rfind("marionette - show (reloaded show.toml)", 0), 0u) << title;
  std::ifstream in(stats);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["reloads"]["count"], 2);
  EXPECT_EQ(j["reloads"]["refused"], 1);
  EXPECT_GT(j["frames"].get<long>(), 30);  // one clock: the frames of every reload in one count
  // What noticing, refusing and swapping in an edit allocates is the reload's, not a frame's.
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
}

}  // namespace
}  // namespace mar
