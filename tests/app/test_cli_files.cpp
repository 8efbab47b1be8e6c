// Files that are not files (base/read_file.h), as a new user meets them: a typo naming a
// folder, a link to a device, a FIFO, a hostile drawing. Every path the program reads is
// opened without blocking, checked to be a regular file and its size refused past the format's
// limit before it is read: for each loader, each kind of path ends at once (well within the
// timeout the runs are under) with exit 2 and a message naming the path and what it is; an
// image an SVG names gets a warning and is skipped, and the character loads.
#include "test_util.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace mar {
namespace {

namespace fs = std::filesystem;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }

struct Paths {
  fs::path dir, fifo, huge, folder;
  Paths() {
    dir = test::temp_dir("outside_files");
    fifo = dir / "fifo";
    ::unlink(fifo.c_str());
    EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    huge = dir / "huge";  // 5 GB as its size says, nothing on disk (sparse)
    { std::ofstream(huge).put('x'); }
    fs::resize_file(huge, 5ull << 30);
    folder = dir / "folder";
    fs::create_directories(folder);
  }
  // What each kind is called in the message.
  std::vector<std::pair<std::string, std::string>> kinds() const {
    return {{"/dev/zero", "is a device"}, {fifo.string(), "is a FIFO"}, {huge.string(), "is 5.0 GB"}, {folder.string(), "is a directory"}};
  }
};

// Under a time limit: a loader that blocked or read for ever would be killed (exit 124).
test::RunResult run(const std::string& args) { return test::run_cli(args, "timeout 60"); }

TEST(OutsideFiles, EveryLoaderRefusesWhatIsNotAFileAtOnce) {
  Paths p;
  const fs::path src = test::source_dir();
  const std::string character = q(src / "config/characters/figure.svg"), rig = q(src / "config/rigs/figure.toml");
  const std::string show_head = "[show]\nrig = \"" + (src / "config/rigs/figure.toml").string() + "\"\n";
  for (const auto& [path, kind] : p.kinds()) {
    SCOPED_TRACE(path);
    const bool folder = kind == "is a directory";
    std::vector<std::pair<std::string, test::RunResult>> runs;
    if (!folder) runs.emplace_back("a character", run("inspect " + q(path)));  // (a folder is a character of PNG layers)
    runs.emplace_back("a rig", run("pose " + character + " --rig " + q(path)));
    runs.emplace_back("a show", run("run " + q(path) + " --headless --frames 1"));
    runs.emplace_back("a mask", run("render " + q(src / "config/characters/boy.png") + " --mask " + q(path) + " -o " + q(p.dir / "m.png")));
    runs.emplace_back("a take", run("replay " + q(path) + " --show " + q(src / "config/shows/demo.toml")));
    const std::string rig_show = test::write_temp("rig_is.toml", "[show]\nrig = \"" + path + "\"\n");
    runs.emplace_back("a show's rig", run("run " + q(rig_show) + " --headless --frames 1"));
    // A simulated device whose `key` names the path.
    auto device_show = [&, target = path](const char* what, const char* sim, const char* key) {
      const std::string show = test::write_temp(std::string(sim) + "_" + key + ".toml", show_head + "[[device]]\nname = \"d\"\nsim = \"" +
                                                                                             sim + "\"\n" + key + " = \"" + target + "\"\n");
      runs.emplace_back(what, run("run " + q(show) + " --headless --frames 1"));
    };
    device_show("a script", "nanokontrol2", "script_file");
    device_show("a descriptor", "gamepad", "descriptor");
    device_show("a WAV", "microphone", "file");
    for (const auto& [what, r] : runs) {
      EXPECT_EQ(r.exit_code, 2) << what << "\n" << r.err;
      EXPECT_NE(r.err.find(kind), std::string::npos) << what << ": the message says what the path is\n" << r.err;
      EXPECT_NE(r.err.find(path), std::string::npos) << what << ": the message names the path\n" << r.err;
    }
  }
}

// An <image> an SVG names: a device, a FIFO or a huge file is skipped with a warning, and so is
// one outside the character's folder (a relative path that climbs out of it) unless the show
// says images = "anywhere". The character loads either way.
TEST(OutsideFiles, AnSvgsImageThatIsNotAFileOrIsElsewhereIsSkippedWithAWarning) {
  Paths p;
  const fs::path chars = p.dir / "character";
  fs::create_directories(chars);
  // A small PNG beside the drawing and one outside its folder.
  const fs::path png = test::source_dir() / "docs/images/owl.png";
  fs::copy_file(png, chars / "beside.png", fs::copy_options::overwrite_existing);
  fs::copy_file(png, p.dir / "outside.png", fs::copy_options::overwrite_existing);
  auto svg = [&](const std::string& href) {
    const fs::path f = chars / "c.svg";
    std::ofstream(f) << "<svg xmlns='http://www.w3.org/2000/svg' xmlns:xlink='http://www.w3.org/1999/xlink' width='100' height='100'>"
                        "<rect width='50' height='50' fill='red'/><image x='0' y='0' width='40' height='40' xlink:href='"
                     << href << "'/></svg>";
    return f;
  };
  for (const auto& [path, kind] : p.kinds()) {
    SCOPED_TRACE(path);
    const auto r = run("inspect " + q(svg(path)));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const std::string all = r.out + r.err;
    EXPECT_NE(all.find("skipped"), std::string::npos) << all;
    EXPECT_NE(all.find(path), std::string::npos) << all;
  }
  auto r = run("inspect " + q(svg("beside.png")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ((r.out + r.err).find("skipped"), std::string::npos) << r.out + r.err;
  r = run("inspect " + q(svg("../outside.png")));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE((r.out + r.err).find("outside the character's folder"), std::string::npos) << r.out + r.err;
  // A show may allow it.
  const std::string rig = test::write_temp("image_rig.toml", "character = \"" + (chars / "c.svg").string() + "\"\n[[handle]]\nname = \"a\"\nrest = [25.0, 25.0]\n");
  const std::string beside = test::write_temp("images_beside.toml", "[show]\nrig = \"" + rig + "\"\n");
  const std::string anywhere = test::write_temp("images_anywhere.toml", "[show]\nrig = \"" + rig + "\"\nimages = \"anywhere\"\n");
  r = run("run " + q(beside) + " --headless --frames 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("outside the character's folder"), std::string::npos) << r.err;
  r = run("run " + q(anywhere) + " --headless --frames 1");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("outside the character's folder"), std::string::npos) << r.err;
  const std::string bad = test::write_temp("images_bad.toml", "[show]\nrig = \"" + rig + "\"\nimages = \"everywhere\"\n");
  r = run("run " + q(bad) + " --headless --frames 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("images_bad.toml:3"), std::string::npos) << r.err;
}

// A folder named as a character is a folder of PNG layers; one with none says so (it said
// "8796093022207 MB; an SVG character may have at most 64 MB").
TEST(OutsideFiles, AFolderWithNoLayersIsSaidToBeOne) {
  Paths p;
  const auto r = run("inspect " + q(p.folder));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(p.folder.string()), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("MB"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace mar
