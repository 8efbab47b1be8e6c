// The motion stage: a rig's [[physics]] chains read, placed on the drawing, given handles for a
// show, and driven from the parent's pose — the curls lag a moving head and settle back as
// drawn; mix 0 follows rigidly; a reset or a stall puts them at rest; bad chains are refused
// with file and line.
#include "app/loop/physics.h"
#include "app/puppet.h"
#include "character/rig.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

std::string figure_rig() { return (test::source_dir() / "config/rigs/figure.toml").string(); }

TEST(PhysicsRig, BadChainsAreRefusedWithFileAndLine) {
  const std::string head = "character = \"c.svg\"\n[[handle]]\nname = \"h\"\nrest = [1.0, 2.0]\n";
  struct Case {
    const char* toml;
    const char* says;
  } cases[] = {
      {"[[physics]]\nname = \"hair\"\nfrom = \"head\"\n", "x.toml:5: physics chain 'hair' needs parts"},
      {"[[physics]]\nname = \"hair\"\nparts = \"a\"\n", "x.toml:5: physics chain 'hair' needs from"},
      {"[[physics]]\nparts = \"a\"\nfrom = \"b\"\n", "x.toml:5: a physics chain needs a name"},
      {"[[physics]]\nname = \"a.b\"\nparts = \"a\"\nfrom = \"b\"\n", "x.toml:6: a physics chain's name cannot have a '.'"},
      {"[[physics]]\nname = \"hair\"\nparts = \"a\"\nfrom = \"b\"\nmodel = \"rope\"\n", "x.toml:9: model must be"},
      {"[[physics]]\nname = \"hair\"\nparts = \"a\"\nfrom = \"b\"\nmix = 1.5\n", "x.toml:9: mix must be 0..1"},
      {"[[physics]]\nname = \"hair\"\nparts = []\nfrom = \"b\"\n", "x.toml:7: parts is empty"},
      {"[[physics]]\nname = \"hair\"\nparts = \"a\"\nfrom = \"b\"\nspin = 2\n", "x.toml:9: unknown key 'spin' in [[physics]]"},
      {"[[physics]]\nname = \"hair\"\nparts = \"a\"\nfrom = \"b\"\n[[physics]]\nname = \"hair\"\nparts = \"a\"\nfrom = \"b\"\n",
       "x.toml:10: physics chain 'hair' defined twice"},
  };
  for (const Case& c : cases) {
    auto r = parse_rig(head + c.toml, "x.toml");
    ASSERT_FALSE(r.ok()) << c.toml;
    EXPECT_NE(r.error.find(c.says), std::string::npos) << r.error;
  }
  auto ok = parse_rig(head + "[[physics]]\nname = \"hair\"\nparts = [\"a\", \"b\"]\nfrom = \"h\"\nmodel = \"spring\"\ngravity = [0, 500]\n",
                      "x.toml");
  ASSERT_TRUE(ok.ok()) << ok.error;
  ASSERT_EQ(ok.value->physics.size(), 1u);
  EXPECT_TRUE(ok.value->physics[0].spring);
  EXPECT_TRUE(ok.value->physics[0].has_gravity);
  EXPECT_EQ(ok.value->physics[0].parts, (std::vector<std::string>{"a", "b"}));
}

TEST(PhysicsRig, AChainOnPartsThatAreNotThereIsRefusedWithItsLine) {
  auto rig = load_rig(figure_rig());
  ASSERT_TRUE(rig.ok()) << rig.error;
  Rig r = *rig.value;
  r.physics.clear();
  RigPhysics ph;
  ph.name = "tail";
  ph.parts = {"tail"};
  ph.from = "torso";
  ph.line = 42;
  r.physics.push_back(ph);
  auto p = load_puppet("", r, "", true);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error.find("figure.toml:42: physics chain 'tail' names part 'tail'"), std::string::npos) << p.error;
  r.physics[0].parts = {"hair-curl-1"};
  r.physics[0].from = "nowhere";
  p = load_puppet("", r, "", true);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error.find("neither a sub-shape nor a handle"), std::string::npos) << p.error;
  r.physics[0].from = "hair-curl-1";
  p = load_puppet("", r, "", true);
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error.find("one of its own parts"), std::string::npos) << p.error;
  r.physics[0].from = "head";  // a handle: the part under it
  p = load_puppet("", r, "", true);
  ASSERT_TRUE(p.ok()) << p.error;
}

TEST(PhysicsRig, AShowsPuppetGetsAHandleAtEachChainsEndOthersDoNot) {
  auto plain = load_puppet("", figure_rig());
  ASSERT_TRUE(plain.ok()) << plain.error;
  EXPECT_TRUE((*plain.value)->chains.empty());
  for (const RigHandle& h : (*plain.value)->rig.handles) EXPECT_FALSE(h.physics);
  auto show = load_puppet("", figure_rig(), "", true);
  ASSERT_TRUE(show.ok()) << show.error;
  const Puppet& p = **show.value;
  ASSERT_EQ(p.chains.size(), 3u);
  EXPECT_EQ(p.rig.handles.size(), (*plain.value)->rig.handles.size() + 3);
  const int curl = p.rig.find_handle("physics.curl-left");
  ASSERT_GE(curl, 0);
  EXPECT_TRUE(p.rig.handles[size_t(curl)].physics);
  // The curl hangs from the cap at its end nearest it and swings by its other end.
  const PuppetChain& c = p.chains[0];
  ASSERT_EQ(c.geo.rest.size(), 2u);
  EXPECT_LT((c.geo.rest[0] - Vec2(120, 42)).norm(), 3.0) << c.geo.rest[0].transpose();
  EXPECT_LT((c.geo.rest[1] - Vec2(86, 44)).norm(), 3.0) << c.geo.rest[1].transpose();
}

struct Stage {
  std::unique_ptr<Puppet> p;
  PhysicsStage stage;
  std::vector<Vec2> targets;
  int head = -1;
  explicit Stage(double mix = 1) {
    auto r = load_puppet("", figure_rig(), "", true);
    EXPECT_TRUE(r.ok()) << r.error;
    p = std::move(*r.value);
    ShowPhysics w;
    stage.prepare(*p, w);
    for (size_t c = 0; c < stage.size(); ++c) stage.set(2 * c + 1, mix);
    targets = p->rest_targets();
    head = p->rig.find_handle("head");
  }
  // One 60 Hz frame as a show runs it: motion, then solve.
  Vec2 before = Vec2::Zero();  ///< rigid_curl() of the pose the stage read
  void frame() {
    before = rigid_curl();
    stage.step(1.0 / 60, *p, targets);
    p->solver->solve(targets, 12);
    p->reconstruct();
  }
  Vec2 curl_target() const { return targets[p->chains[0].handles.back()]; }
  // The curl's end against where the pose the solver gave carries it rigidly.
  // Where the curl's end would be, carried rigidly with the hair cap.
  Vec2 rigid_curl() const {
    const PuppetChain& c = p->chains[0];
    Vec2 anchor;
    double a = 0;
    chain_parent_pose(*p, c, anchor, a);
    const Vec2 off = c.geo.rest[1] - c.geo.rest[0];
    return anchor + Vec2(std::cos(a) * off.x() - std::sin(a) * off.y(), std::sin(a) * off.x() + std::cos(a) * off.y());
  }
};

TEST(PhysicsStage, CurlsLagAMovingHeadAndSettleBackAsDrawn) {
  Stage s;
  ASSERT_GE(s.head, 0);
  for (int f = 0; f < 30; ++f) s.frame();
  EXPECT_LT((s.curl_target() - s.rigid_curl()).norm(), 0.5) << "at rest it rests as drawn";
  double lag = 0;
  for (int f = 0; f < 20; ++f) {  // the head swings 40 units right in a third of a second
    s.targets[size_t(s.head)] = s.p->rig.handles[size_t(s.head)].rest + Vec2(2.0 * (f + 1), 0);
    s.frame();
    lag = std::max(lag, (s.curl_target() - s.rigid_curl()).norm());
  }
  std::cout << "the curl's end lags the head by up to " << lag << " units" << std::endl;
  EXPECT_GT(lag, 2.0) << "it swings";
  for (int f = 0; f < 240; ++f) s.frame();  // four seconds still
  EXPECT_LT((s.curl_target() - s.rigid_curl()).norm(), 0.5) << "and settles";
  for (const Points& pts : s.p->shapes)
    for (const Vec2& q : pts) ASSERT_TRUE(q.allFinite());
}

TEST(PhysicsStage, MixZeroFollowsRigidlyAndResetPutsItAtRest) {
  Stage s(0.0);
  double steady = 0, worst = 0;
  for (int f = 0; f < 40; ++f) {  // the head moves steadily for a third of a second, then stops
    if (f < 20) s.targets[size_t(s.head)] = s.p->rig.handles[size_t(s.head)].rest + Vec2(2.0 * (f + 1), -1.0 * f);
    s.frame();
    const double off = (s.curl_target() - s.rigid_curl()).norm();
    worst = std::max(worst, off);
    if (f >= 5 && f < 20) steady = std::max(steady, off);
  }
  // The stage reads the last frame's pose and carries it on as it went: while the head moves
  // steadily the curl stays within a fraction of a frame's motion (2.24 units) of the cap's
  // rigid pose; a start or a stop costs at most about one frame's.
  std::cout << "mix 0: the curl's end within " << steady << " units of the cap's rigid pose while it moves, " << worst
            << " at a start or stop" << std::endl;
  EXPECT_LT(steady, 1.0);
  EXPECT_LT(worst, 2.3);
  EXPECT_LT((s.curl_target() - s.rigid_curl()).norm(), 0.1) << "and with it once still";
  Stage m;
  for (int f = 0; f < 20; ++f) {
    m.targets[size_t(m.head)] = m.p->rig.handles[size_t(m.head)].rest + Vec2(3.0 * (f + 1), 0);
    m.frame();
  }
  for (int f = 0; f < 3; ++f) m.frame();
  ASSERT_GT((m.curl_target() - m.rigid_curl()).norm(), 1.0) << "swinging";
  const long resets = m.stage.resets();
  const size_t reset = 2 * m.stage.size() + 2;
  m.stage.set(reset, 1.0);  // physics.reset pressed
  m.frame();
  EXPECT_EQ(m.stage.resets(), resets + long(m.stage.size()));
  EXPECT_LT((m.curl_target() - m.before).norm(), 1e-9) << "at rest with its parent, as the stage saw it";
  m.stage.set(reset, 1.0);  // held: once
  m.frame();
  EXPECT_EQ(m.stage.resets(), resets + long(m.stage.size()));
}

TEST(PhysicsStage, SettingsAreNamedForTheShow) {
  Stage s;
  const auto names = PhysicsStage::setting_names(*s.p);
  ASSERT_EQ(names.size(), s.stage.setting_count());
  EXPECT_EQ(names[0].name, "physics.curl-left.strength");
  EXPECT_EQ(names[1].name, "physics.curl-left.mix");
  EXPECT_EQ(names[names.size() - 3].name, "physics.wind");
  EXPECT_EQ(names[names.size() - 2].name, "physics.gravity");
  EXPECT_EQ(names.back().name, "physics.reset");
}

}  // namespace
}  // namespace mar
