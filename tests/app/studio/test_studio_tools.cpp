// The rig studio's sculpting tools: the brush and the drawn curve on the studio's live puppet,
// the result saved as a key pose (a file of every shape's points beside the rig), and that key
// recalled in a show standing as the studio left it.
#include "app/live.h"
#include "app/live_util.h"
#include "app/studio/studio.h"
#include "character/rig.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

using test::height;
using test::off_rest;
using test::shape_of;

namespace fs = std::filesystem;

fs::path cat_folder(const std::string& name) {
  const fs::path dir = test::temp_dir("studio_tools_" + name);
  fs::create_directories(dir / "rigs");
  fs::create_directories(dir / "characters");
  fs::copy_file(test::characters_dir() / "cat.svg", dir / "characters" / "cat.svg", fs::copy_options::overwrite_existing);
  fs::copy_file(test::source_dir() / "config/rigs/cat.toml", dir / "rigs" / "cat.toml", fs::copy_options::overwrite_existing);
  return dir;
}

std::unique_ptr<Studio> open_cat(const fs::path& dir) {
  auto s = Studio::open((dir / "characters" / "cat.svg").string(), (dir / "rigs" / "cat.toml").string());
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

// The saved rig in a show whose button recalls `key` at 0.1 s (0.2 s transition): how far, at
// most, its shapes stand from `posed` (the studio's) after 2 s, a fraction of the height.
double recalled_off(const fs::path& dir, const std::string& key, const Puppet& posed) {
  const std::string show = test::write_temp("recall_" + key + ".toml",
                                            "[show]\nrig = \"" + (dir / "rigs" / "cat.toml").generic_string() + "\"\n"
                                            "[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\nscript = \"0.1 press solo1 for 0.1\"\n"
                                            "[[binding]]\ndevice = \"korg\"\ncontrol = \"cc 32\"\ntarget = \"pose." + key + "\"\n"
                                            "transition = 0.2\n");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(show, o);
  EXPECT_TRUE(s.ok()) << s.error;
  if (!s.ok()) return 1e9;
  for (int f = 0; f < 120; ++f) (*s.value)->frame(int64_t(f * 1e9 / 60));
  const Puppet& p = (*s.value)->actors()[0]->puppet();
  EXPECT_EQ(p.shapes.size(), posed.shapes.size());
  // (the show flattens the drawing for its canvas, the studio for its own: each of the show's
  // points is compared with where the studio put the nearest point of its outline at rest)
  double worst = 0;
  for (size_t k = 0; k < p.shapes.size() && k < posed.shapes.size(); ++k) {
    const SubShape& mine = p.character.shapes[k];
    const SubShape& theirs = posed.character.shapes[k];
    for (size_t c = 0; c < mine.contours.size() && c < theirs.contours.size(); ++c)
      for (int i = mine.contours[c].begin; i < mine.contours[c].begin + mine.contours[c].count; ++i) {
        const Vec2 r = mine.points[size_t(i)];
        double best = 1e300;
        Vec2 at = r;
        const Contour& tc = theirs.contours[c];
        for (int a = tc.begin; a < tc.begin + tc.count; ++a) {
          const int b = a + 1 < tc.begin + tc.count ? a + 1 : tc.begin;
          const Vec2 e = theirs.points[size_t(b)] - theirs.points[size_t(a)];
          const double t = e.squaredNorm() > 0 ? std::clamp((r - theirs.points[size_t(a)]).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
          const double d = (theirs.points[size_t(a)] + t * e - r).squaredNorm();
          if (d < best) {
            best = d;
            at = (1 - t) * posed.shapes[k][size_t(a)] + t * posed.shapes[k][size_t(b)];
          }
        }
        worst = std::max(worst, (p.shapes[k][size_t(i)] - at).norm());
      }
  }
  return worst / height(p);
}

TEST(StudioTools, TheBrushSculptsTheOutlineAndTheSculptSavesAsAKeyAShowRecalls) {
  const fs::path dir = cat_folder("brush");
  auto s = open_cat(dir);
  ASSERT_TRUE(s);
  const size_t coarse = s->puppet().feature_frame()->frame().rest.size();
  ASSERT_EQ(s->set_tool(Studio::Tool::Brush), "");
  EXPECT_GT(s->puppet().feature_frame()->frame().rest.size(), 2 * coarse) << "the brush's finer frame";
  // The body's outline point lowest on the drawing (its belly), pulled down.
  const Puppet& p = s->puppet();
  const int body = shape_of(p, "ellipse1042");
  ASSERT_GE(body, 0);
  Vec2 belly = p.shapes[size_t(body)][0];
  for (const Vec2& q : p.shapes[size_t(body)]) belly = q.y() > belly.y() ? q : belly;
  const Vec2 drag(0, 0.04 * height(p));
  for (int f = 0; f <= 20; ++f) {
    s->pen(belly + drag * (f / 20.0), true, 0.6);
    s->step();
  }
  s->pen(belly + drag, false, 0);
  for (int f = 0; f < 40; ++f) s->step();
  EXPECT_TRUE(s->sculpted());
  EXPECT_NEAR(s->brush().radius(), s->brush_radius(0.6), 1e-9);
  // The belly went down with the pen (held), and the head stayed where it was.
  double moved = 0;
  for (size_t i = 0; i < p.shapes[size_t(body)].size(); ++i)
    moved = std::max(moved, p.shapes[size_t(body)][i].y() - p.character.shapes[size_t(body)].points[i].y());
  std::cout << "the belly went down " << moved / drag.y() << " of the drag\n";
  EXPECT_GT(moved, 0.6 * drag.y());
  const int head = shape_of(p, "circle877");
  ASSERT_GE(head, 0);
  EXPECT_LT(off_rest(p, head), 0.005 * height(p));
  // Saved as a key: a file beside the rig, and a [[key]] naming it; the pose stays on screen.
  ASSERT_EQ(s->save_key("belly"), "");
  EXPECT_TRUE(s->sculpted()) << "saving a key keeps the sculpt";
  EXPECT_NE(s->text().find("shapes = \"cat.belly.key.json\""), std::string::npos) << s->text();
  EXPECT_TRUE(fs::exists(dir / "rigs" / "cat.belly.key.json"));
  ASSERT_EQ(s->save(), "");
  // A show recalls it: the cat stands as the studio left it.
  const double off = recalled_off(dir, "belly", s->puppet());
  std::cout << "the recalled sculpted key off the studio's pose: " << 100 * off << " % of the height\n";
  EXPECT_LT(off, 0.005);
  // R lets the sculpt go.
  s->reset_pose();
  EXPECT_FALSE(s->sculpted());
  for (int f = 0; f < 60; ++f) s->step();
  EXPECT_LT(off_rest(s->puppet(), body), 0.002 * height(s->puppet()));
}

TEST(StudioTools, TheCurveTakesTheChainItsStrokeCrossesAndSavesAsAKey) {
  const fs::path dir = cat_folder("curve");
  auto s = open_cat(dir);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->set_tool(Studio::Tool::Curve), "");
  const Puppet& p = s->puppet();
  const int body = shape_of(p, "ellipse1042"), tail = shape_of(p, "path2291");
  ASSERT_GE(body, 0);
  ASSERT_GE(tail, 0);
  // Where the tail hangs, and its far end.
  Vec2 hinge(0, 0);
  bool found = false;
  for (const StudioHinge& j : s->hinges())
    if ((j.shape_a == tail && j.shape_b == body) || (j.shape_a == body && j.shape_b == tail)) {
      hinge = j.at;
      found = true;
    }
  ASSERT_TRUE(found) << "the cat's tail hangs from its body by a hinge";
  Vec2 tip = hinge;
  for (const Vec2& q : p.shapes[size_t(tail)]) tip = (q - hinge).norm() > (tip - hinge).norm() ? q : tip;
  const Bounds bb = p.character.shapes[size_t(body)].bounds();
  const Vec2 centre = 0.5 * (bb.lo + bb.hi);
  // The stroke starts on the body beside the hinge and runs out along the tail, bending to one side.
  const Vec2 start = hinge + 0.15 * (centre - hinge);
  ASSERT_EQ(s->part_at(start), body);
  const Vec2 axis = tip - hinge, normal(-axis.y(), axis.x());
  Vec2 end = hinge;
  for (int f = 0; f <= 30; ++f) {
    const double t = f / 30.0;
    const Vec2 q = f == 0 ? start : hinge + t * axis + 0.25 * std::sin(M_PI * t) * normal;
    s->pen(q, true, 0.7);
    s->step();
    end = q;
  }
  s->pen(end, false, 0);
  for (int f = 0; f < 60; ++f) s->step();
  const std::vector<std::string> chain = s->curve_chain();
  ASSERT_EQ(chain.size(), 2u);
  EXPECT_EQ(chain[0], s->part_name(body));
  EXPECT_EQ(chain[1], s->part_name(tail));
  EXPECT_TRUE(s->sculpted());
  EXPECT_GT(off_rest(p, tail), 0.1 * axis.norm()) << "the tail bent with the stroke";
  EXPECT_LT(off_rest(p, shape_of(p, "circle877")), 0.01 * height(p)) << "the head stayed";
  ASSERT_EQ(s->save_key("swish"), "");
  ASSERT_EQ(s->save(), "");
  const double off = recalled_off(dir, "swish", s->puppet());
  std::cout << "the recalled curve key off the studio's pose: " << 100 * off << " % of the height\n";
  // (the show's solve finds its own pose for the handles of a chain bent this far, 2.6 units
  // from the one the key's detail was taken from: the tail's bend plays, the cat shifted by that)
  EXPECT_LT(off, 0.02);
}

TEST(StudioTools, TheLineRedrawsAnOutlineAndSavesAsAKey) {
  const fs::path dir = cat_folder("line");
  auto s = open_cat(dir);
  ASSERT_TRUE(s);
  ASSERT_EQ(s->set_tool(Studio::Tool::Line), "");
  const Puppet& p = s->puppet();
  const int body = shape_of(p, "ellipse1042");
  ASSERT_GE(body, 0);
  // The body's back: from its top point a third of the way along, drawn 8 units higher.
  const Bounds b = p.character.shapes[size_t(body)].bounds();
  const Vec2 c = 0.5 * (b.lo + b.hi), r = 0.5 * (b.hi - b.lo);
  Vec2 end(0, 0);
  for (int f = 0; f <= 20; ++f) {
    const double a = M_PI * (0.62 - 0.24 * f / 20.0), lift = f == 0 ? 0.0 : 8 * std::sin(M_PI * f / 20.0);
    end = Vec2(c.x() + (r.x() + lift) * std::cos(a), c.y() - (r.y() + lift) * std::sin(a));
    s->pen(end, true, 0.5);
    s->step();
  }
  s->pen(end, false, 0);
  for (int f = 0; f < 40; ++f) s->step();
  ASSERT_TRUE(s->sculpted());
  EXPECT_GE(s->line().segment().size(), 5u);
  double up = 0;
  for (size_t i = 0; i < p.shapes[size_t(body)].size(); ++i)
    up = std::max(up, p.character.shapes[size_t(body)].points[i].y() - p.shapes[size_t(body)][i].y());
  EXPECT_GT(up, 5.0) << "the back rose with the stroke";
  ASSERT_EQ(s->save_key("proud"), "");
  ASSERT_EQ(s->save(), "");
  const double off = recalled_off(dir, "proud", s->puppet());
  std::cout << "the recalled line key off the studio's pose: " << 100 * off << " % of the height\n";
  EXPECT_LT(off, 0.005);
}

TEST(StudioTools, ABrokenSculptedKeyIsRefusedWithItsLine) {
  const fs::path dir = cat_folder("broken");
  {
    std::ofstream rig(dir / "rigs" / "cat.toml", std::ios::app);
    rig << "\n[[key]]\nname = \"bad\"\nshapes = \"bad.key.json\"\n";
  }
  std::ofstream(dir / "rigs" / "bad.key.json") << "{\"shapes\": {\"ellipse1042\": [[[1, 2, 3, 4]]]}}";
  const std::string show = test::write_temp("broken_key.toml", "[show]\nrig = \"" + (dir / "rigs" / "cat.toml").generic_string() +
                                                                   "\"\n[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\n"
                                                                   "[[binding]]\ndevice = \"korg\"\ncontrol = \"cc 32\"\ntarget = \"pose.bad\"\n");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(show, o);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error.find("key 'bad'"), std::string::npos) << s.error;
  EXPECT_NE(s.error.find("bad.key.json"), std::string::npos) << s.error;
  EXPECT_NE(s.error.find("shape 'path2291'"), std::string::npos) << s.error << " (the first shape it lacks)";
  // A file of brackets nested a million deep is refused before it is parsed.
  std::ofstream(dir / "rigs" / "bad.key.json") << "{\"shapes\": " << std::string(1000000, '[') << std::string(1000000, ']') << "}";
  auto deep = LiveShow::load(show, o);
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.error.find("nests deeper than a sculpted key does"), std::string::npos) << deep.error;
}

}  // namespace
}  // namespace mar
