// Atomic saves: the new text replaces the file whole, nothing is left beside it, the file's
// permissions and a symbolic link to it survive, an append keeps what a person wrote, and a
// save that cannot happen says why, naming the file, and leaves the old file as it was.
#include "rig/edit.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

namespace fs = std::filesystem;

std::string read_all(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicSave, ReplacesWholeKeepsPermissionsAndLinks) {
  const auto dir = test::temp_dir("atomic");
  const fs::path file = dir / "rig.toml";
  ASSERT_EQ(write_atomically(file.string(), "a = 1\n"), "");
  EXPECT_EQ(read_all(file), "a = 1\n");
  fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  ASSERT_EQ(write_atomically(file.string(), "b = 2\n"), "");
  EXPECT_EQ(read_all(file), "b = 2\n");
  EXPECT_FALSE(fs::exists(dir / "rig.toml.tmp"));
  EXPECT_EQ(fs::status(file).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  fs::create_symlink(file, dir / "link.toml");
  ASSERT_EQ(write_atomically((dir / "link.toml").string(), "c = 3\n"), "");
  EXPECT_TRUE(fs::is_symlink(dir / "link.toml")) << "the link stays a link";
  EXPECT_EQ(read_all(file), "c = 3\n");
}

TEST(AtomicSave, AnAppendKeepsCommentsAndOrder) {
  const auto dir = test::temp_dir("atomic-append");
  const fs::path file = dir / "show.toml";
  std::ofstream(file) << "# my show\n[show]\nrig = \"r.toml\"  # the rig\nrate = 60";  // (no newline at the end)
  ASSERT_EQ(append_atomically(file.string(), "\n[[binding]]\ndevice = \"k\"\n"), "");
  EXPECT_EQ(read_all(file), "# my show\n[show]\nrig = \"r.toml\"  # the rig\nrate = 60\n\n[[binding]]\ndevice = \"k\"\n");
}

TEST(AtomicSave, AFailedSaveSaysWhyAndLeavesTheFile) {
  const auto dir = test::temp_dir("atomic-fail");
  EXPECT_NE(write_atomically((dir / "no-such-folder" / "rig.toml").string(), "x").find("no-such-folder"), std::string::npos);
  EXPECT_NE(append_atomically((dir / "missing.toml").string(), "x").find("missing.toml"), std::string::npos);
  // a folder where the file should go: the rename fails, the folder and its content stay
  fs::create_directories(dir / "taken.toml" / "inside");
  const std::string err = write_atomically((dir / "taken.toml").string(), "x");
  EXPECT_NE(err.find("taken.toml"), std::string::npos) << err;
  EXPECT_TRUE(fs::is_directory(dir / "taken.toml" / "inside"));
  EXPECT_FALSE(fs::exists(dir / "taken.toml.tmp"));
}

}  // namespace
}  // namespace mar
