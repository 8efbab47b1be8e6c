// Comment-keeping rig edits (the rig studio's saves): one value changes, a table is added
// beside its kind or removed with its own comments, and every other byte of the text stays.
#include "character/rig.h"
#include "rig/rig_text.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

const char* kRig = R"(# My cat, rigged by hand.
character = "cat.svg"  # beside this file
iterations = 12

# The body first.
[[handle]]
name = "body"   # the torso
rest = [200.0, 160.0]  # centre

[[handle]]
name = "tail"
rest = [72.0, 76.0]

[weights]
position = 100.0

# A hinge I placed.
[[joint]]
at = [100.0, 50.0]
parts = ["tail", "body"]

[[key]]
name = "wave"
targets = { "tail" = [
  80.0, 70.0 ] }   # a value over lines
# "[[handle]]" in a comment is not a table
)";

TEST(RigText, SetChangesOneValueAndKeepsItsComment) {
  RigText t(kRig);
  ASSERT_EQ(t.count("handle"), 2u);
  EXPECT_EQ(t.get("handle", 0, "rest"), "[200.0, 160.0]");
  ASSERT_TRUE(t.set("handle", 0, "rest", "[210.0, 150.0]"));
  std::string want = kRig;
  want.replace(want.find("[200.0, 160.0]"), 14, "[210.0, 150.0]");
  EXPECT_EQ(t.text(), want);
  EXPECT_FALSE(t.set("handle", 2, "rest", "[0.0, 0.0]")) << "there is no third handle";
  EXPECT_EQ(t.text(), want);
}

TEST(RigText, SetAddsAMissingKeyAfterTheTablesLastKey) {
  RigText t(kRig);
  ASSERT_TRUE(t.set("joint", 0, "stiffness", "0.5"));
  std::string want = kRig;
  const std::string parts = "parts = [\"tail\", \"body\"]\n";
  want.insert(want.find(parts) + parts.size(), "stiffness = 0.5\n");
  EXPECT_EQ(t.text(), want);
  auto r = parse_rig(t.text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->joints.size(), 1u);
  EXPECT_DOUBLE_EQ(r.value->joints[0].stiffness, 0.5);
}

TEST(RigText, AValueOverLinesIsOneValueAndBracketsInsideItAreNoTables) {
  RigText t(kRig);
  EXPECT_EQ(t.count("key"), 1u);
  EXPECT_EQ(t.count("handle"), 2u) << "a header in a comment does not count";
  ASSERT_TRUE(t.set("key", 0, "targets", "{ \"tail\" = [90.0, 60.0] }"));
  std::string want = kRig;
  const size_t b = want.find("{ \"tail\" = [\n");
  const size_t e = want.find("# \"[[handle]]\"");
  want.replace(b, e - b, "{ \"tail\" = [90.0, 60.0] }\n");
  EXPECT_EQ(t.text(), want);
  auto r = parse_rig(t.text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->keys.size(), 1u);
  EXPECT_DOUBLE_EQ(r.value->keys[0].targets[0].second.x(), 90.0);
}

TEST(RigText, AppendGoesAfterTheLastTableOfItsKind) {
  RigText t(kRig);
  t.append("handle", "name = \"ear\"\nrest = [292.0, 50.0]\n");
  std::string want = kRig;
  const std::string tail = "rest = [72.0, 76.0]\n";
  want.insert(want.find(tail) + tail.size(), "\n[[handle]]\nname = \"ear\"\nrest = [292.0, 50.0]\n");
  EXPECT_EQ(t.text(), want);
  t.append("part", "id = \"tail\"\nstiffness = 2.0\n");  // no [[part]] yet: at the end
  EXPECT_EQ(t.text(), want + "\n[[part]]\nid = \"tail\"\nstiffness = 2.0\n");
  auto r = parse_rig(t.text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->handles.size(), 3u);
  EXPECT_EQ(r.value->handles[2].name, "ear");
  ASSERT_EQ(r.value->parts.size(), 1u);
  EXPECT_DOUBLE_EQ(r.value->parts[0].stiffness, 2.0);
}

TEST(RigText, RemoveTakesTheTableAndItsOwnCommentsOnly) {
  RigText t(kRig);
  ASSERT_TRUE(t.remove("handle", 0));
  std::string want = kRig;
  const size_t b = want.find("\n# The body first.");
  const size_t e = want.find("\n[[handle]]\nname = \"tail\"");
  want.erase(b, e - b);
  EXPECT_EQ(t.text(), want);
  ASSERT_TRUE(t.remove("joint", 0));
  auto r = parse_rig(t.text(), "cat.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.value->handles.size(), 1u);
  EXPECT_EQ(r.value->handles[0].name, "tail");
  EXPECT_TRUE(r.value->joints.empty());
  EXPECT_EQ(t.text().find("A hinge I placed"), std::string::npos) << "its comment went with it";
  EXPECT_NE(t.text().find("# My cat, rigged by hand."), std::string::npos);
  EXPECT_NE(t.text().find("position = 100.0"), std::string::npos);
  EXPECT_FALSE(t.remove("joint", 0));
}

TEST(RigText, TextWithoutANewlineAtTheEndAndEmptyText) {
  RigText t("character = \"cat.svg\"\n[[handle]]\nname = \"a\"\nrest = [1.0, 2.0]");
  ASSERT_TRUE(t.set("handle", 0, "rest", "[3.0, 4.0]"));
  t.append("handle", "name = \"b\"\nrest = [5.0, 6.0]\n");
  EXPECT_EQ(t.text(), "character = \"cat.svg\"\n[[handle]]\nname = \"a\"\nrest = [3.0, 4.0]\n\n[[handle]]\nname = \"b\"\nrest = [5.0, 6.0]\n");
  RigText empty;
  empty.append("handle", "name = \"a\"\n");
  EXPECT_EQ(empty.text(), "[[handle]]\nname = \"a\"\n");
}

TEST(RigText, StringsAndNumbersAsTomlReadsThem) {
  EXPECT_EQ(toml_string("arm \"left\"\\x\n"), "\"arm \\\"left\\\"\\\\x\\n\"");
  EXPECT_EQ(toml_number(4), "4.0");
  EXPECT_EQ(toml_number(0.25), "0.25");
  EXPECT_EQ(toml_number(1.0 / 3), "0.333");
  EXPECT_EQ(toml_point(-0.01, 12.345), "[0.0, 12.3]");
  const std::string odd = "we\"ird\\name#[x]";
  auto r = parse_rig("character = \"c.svg\"\n[[handle]]\nname = " + toml_string(odd) + "\nrest = " + toml_point(1, 2) + "\n", "x.toml");
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.value->handles[0].name, odd);
}

}  // namespace
}  // namespace mar
