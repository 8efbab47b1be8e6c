// Hostile files and failing outputs, as a kiosk or a performer meets them: each reproduction
// ends within seconds (the runs are under `timeout`) with a message naming the file and the
// bound, and the exit code the docs give (2: bad input; 1: an output that could not be written).
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace mar {
namespace {

namespace fs = std::filesystem;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
test::RunResult run(const std::string& args) { return test::run_cli(args, "timeout 60"); }
const fs::path kDemo = test::source_dir() / "config/shows/demo.toml";

// Nine levels of ten <use> over an empty group: 10^9 elements from 2 KB.
std::string use_bomb() {
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:xlink=\"http://www.w3.org/1999/xlink\"><defs><g id=\"a0\"/>";
  for (int l = 1; l < 10; ++l) {
    s += "<g id=\"a" + std::to_string(l) + "\">";
    for (int k = 0; k < 10; ++k) s += "<use xlink:href=\"#a" + std::to_string(l - 1) + "\"/>";
    s += "</g>";
  }
  return s + "</defs><use xlink:href=\"#a9\"/><circle cx=\"5\" cy=\"5\" r=\"3\"/></svg>";
}

TEST(HostileFiles, AUseBombIsRefusedByItsElementBound) {
  const std::string bomb = use_bomb();
  ASSERT_LT(bomb.size(), 2500u);
  const auto r = run("inspect " + q(test::write_temp("bomb.svg", bomb)));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bomb.svg:1: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("more than 200000 elements once <use> references are expanded"), std::string::npos) << r.err;
}

// A circle a tiny viewBox blows up to 10^8 units: it would flatten to 131,072 points, inside
// the file's point budget; one shape's bound refuses it before anything is triangulated.
TEST(HostileFiles, AShapeOfTooManyPointsIsRefusedBeforeItIsTriangulated) {
  const auto svg = test::write_temp("tiny.svg",
                                    "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 1e-6 1e-6\" width=\"100\" "
                                    "height=\"100\"><circle r=\"1\"/></svg>");
  ASSERT_LT(fs::file_size(svg), 128u);
  for (const std::string& cmd : {"inspect " + q(svg), "rig " + q(svg) + " -o -"}) {
    const auto r = run(cmd);
    EXPECT_EQ(r.exit_code, 2) << cmd << "\n" << r.err;
    EXPECT_NE(r.err.find("tiny.svg:1: <circle>: one shape of 131072 points after flattening (at most 100000 a shape)"),
              std::string::npos)
        << r.err;
  }
}

// A dotted key 50,000 deep would overflow the stack inside the TOML parser: it is refused
// before the parser sees it, as a show, as a rig, and as a device profile's show.
TEST(HostileFiles, DeeplyNestedTomlIsRefusedBeforeItIsParsed) {
  std::string key = "a";
  for (int k = 0; k < 50000; ++k) key += ".a";
  const auto show = test::write_temp("deep-show.toml", key + " = 1\n");
  auto r = run("run " + q(show) + " --headless --frames 1");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("deep-show.toml:1: keys, tables or arrays nest deeper than 64 levels"), std::string::npos) << r.err;
  const auto rig = test::write_temp("deep-rig.toml", "[[handle]]\nname = \"x\"\n" + key + " = 1\n");
  r = run("pose " + q(test::source_dir() / "config/characters/figure.svg") + " --rig " + q(rig));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("deep-rig.toml:3: keys, tables or arrays nest deeper"), std::string::npos) << r.err;
  const auto arrays = test::write_temp("deep-arrays.toml", "[show]\nx = " + std::string(300, '[') + std::string(300, ']') + "\n");
  r = run("run " + q(arrays) + " --headless --frames 1");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("deep-arrays.toml:2: keys, tables or arrays nest deeper"), std::string::npos) << r.err;
}

// Takes carry their show's identity and a checksum per block.
TEST(HostileFiles, DamagedAndForeignTakesAreRefusedOrSaid) {
  const fs::path dir = test::temp_dir("hostile-takes");
  const fs::path take = dir / "demo.mrec";
  auto r = run("run " + q(kDemo) + " --headless --frames 200 --record " + q(take));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Whole, it replays with exit 0.
  r = run("replay " + q(take) + " --show " + q(kDemo));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("200 frames"), std::string::npos) << r.out;
  // Cut, it plays to its last good block, says so, and exits 1.
  const fs::path cut = dir / "cut.mrec";
  fs::copy_file(take, cut);
  fs::resize_file(cut, fs::file_size(take) - 100);
  r = run("replay " + q(cut) + " --show " + q(kDemo));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("cut.mrec: damaged at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("played to frame"), std::string::npos) << r.err;
  // Another show's take (other devices) is refused unless --force.
  const fs::path other = test::source_dir() / "config/shows/gamepad.toml";
  ASSERT_TRUE(fs::exists(other));
  r = run("replay " + q(take) + " --show " + q(other));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("a take of another show"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  r = run("replay " + q(take) + " --show " + q(other) + " --force");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// Every output checks every write: /dev/full fails each with ENOSPC.
TEST(HostileFiles, AFullDiskIsAnErrorNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  auto r = run("render " + q(test::source_dir() / "config/characters/figure.svg") + " -o /dev/full");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/dev/full: No space left on device"), std::string::npos) << r.err;
  for (const char* flag : {"--stats", "--dump-poses", "--record"}) {
    r = run("run " + q(kDemo) + " --headless --frames 30 " + flag + " /dev/full");
    EXPECT_EQ(r.exit_code, 1) << flag << "\n" << r.err;
    EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << flag << "\n" << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << flag << "\n" << r.err;
  }
}

// A folder of frames on a full file system: the frames that could not be written are counted,
// none is claimed, and the run exits 1. Needs root to mount a small tmpfs.
TEST(HostileFiles, FramesOnAFullFileSystemAreCountedNotClaimed) {
  const fs::path dir = test::temp_dir("hostile-full") / "small";
  fs::create_directories(dir);
  if (::mount("tmpfs", dir.c_str(), "tmpfs", 0, "size=96k") != 0) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
  const auto r = run("run " + q(kDemo) + " --headless --frames 120 --dump-frames " + q(dir));
  size_t files = 0, empty = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    ++files;
    empty += fs::file_size(e.path()) == 0;
  }
  ::umount(dir.c_str());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(empty, 0u) << "no file is left empty";
  EXPECT_NE(r.out.find(std::to_string(files) + " frames written"), std::string::npos) << r.out << " files: " << files;
  EXPECT_NE(r.out.find("dropped"), std::string::npos) << r.out;
}

TEST(HostileFiles, OutputPathsAreCheckedBeforeTheShowStarts) {
  const fs::path dir = test::temp_dir("hostile-paths");
  const fs::path file = dir / "a-file";
  std::ofstream(file) << "x";
  // A folder of frames that cannot be made (under a file): a message, exit 1, no abort.
  for (const char* cmd : {"run ", "replay "}) {
    const std::string args = std::string(cmd) == "run " ? "run " + q(kDemo) + " --headless --frames 5"
                                                        : "replay " + q(file) + " --show " + q(kDemo);
    const auto r = run(args + " --dump-frames " + q(file / "frames"));
    EXPECT_EQ(r.exit_code, 1) << cmd << r.err;
    EXPECT_NE(r.err.find("cannot make the folder"), std::string::npos) << r.err;
  }
  // --stats, --record in a folder that does not exist: said at once, exit 1, no frame run.
  for (const char* flag : {"--stats", "--record", "--dump-poses"}) {
    const auto r = run("run " + q(kDemo) + " --headless --frames 100000 " + flag + " " + q(dir / "no" / "out"));
    EXPECT_EQ(r.exit_code, 1) << flag << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("frames,"), std::string::npos) << "the show did not run first\n" << r.out;
  }
  const auto r = run("run " + q(kDemo) + " --headless --rate 1e-300 --frames 2");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--rate must be 1..1000"), std::string::npos) << r.err;
}

// `rig -o` onto a device node (or a link to one) leaves the node as it is.
TEST(HostileFiles, RigOutputOntoADeviceNodeIsRefused) {
  const fs::path dir = test::temp_dir("hostile-node");
  const fs::path node = dir / "null", link = dir / "link";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) GTEST_SKIP() << "mknod needs root";
  fs::create_symlink(node, link);
  for (const fs::path& target : {node, link}) {
    const auto r = run("rig " + q(test::source_dir() / "config/characters/figure.svg") + " -o " + q(target));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_character_file(node)) << "the device node is still one";
  }
}

}  // namespace
}  // namespace mar
