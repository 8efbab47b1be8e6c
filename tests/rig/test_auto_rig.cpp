// The automatic rig: every example character gets the limbs, hinges, handles, swap sets and
// triggers a person would give it, the rig loads as a puppet with no edits, hinges sit where
// the hand rigs put their joints, and a drawing with no names at all still gets its limbs.
#include "app/live.h"
#include "app/puppet.h"
#include "character/load.h"
#include "render/canvas.h"
#include "render/image.h"
#include "geom/polygon.h"
#include "rig/auto_rig.h"
#include "rig/limb_geometry.h"
#include "rig/starter_show.h"
#include "solve/make_solver.h"
#include "starter_util.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <limits>
#include <map>
#include <set>

namespace mar {
namespace {

struct Rigged {
  Character ch;
  AutoRig ar;
};

Rigged rig_of(const std::string& file) {
  auto ch = load_character(file);
  EXPECT_TRUE(ch.ok()) << ch.error;
  Rigged r{*ch.value, {}};
  r.ar = auto_rig(r.ch, file);
  return r;
}

std::set<std::string> ids_of(const Rigged& r, AutoRigPart::Kind kind) {
  std::set<std::string> out;
  for (const AutoRigPart& p : r.ar.parts)
    if (p.kind == kind) out.insert(r.ch.shapes[size_t(p.shape)].id);
  return out;
}

std::set<std::string> handles_of(const Rigged& r) {
  std::set<std::string> out;
  for (const RigHandle& h : r.ar.rig.handles) out.insert(h.name);
  return out;
}

// The written rig parses, and loads as a puppet whose solver takes every hinge (a hinge the
// solver cannot place is a warning).
void loads(const Rigged& r, const std::string& name) {
  const std::string text = write_auto_rig(r.ar, r.ch);
  const std::string path = test::write_temp("auto-" + name + ".toml", text);
  auto rig = load_rig(path);
  ASSERT_TRUE(rig.ok()) << rig.error << "\n" << text;
  auto puppet = load_puppet(r.ar.rig.character, *rig.value);
  ASSERT_TRUE(puppet.ok()) << puppet.error;
  const FeatureFrameMethod* ff = (*puppet.value)->feature_frame();
  ASSERT_NE(ff, nullptr);
  for (const std::string& w : ff->frame().warnings) EXPECT_EQ(w.find("joint"), std::string::npos) << name << ": " << w;
  EXPECT_EQ((*puppet.value)->rig.handles.size(), r.ar.rig.handles.size());
}

struct Expected {
  const char* name;
  std::set<std::string> limbs, handles;
  const char* body;
};

TEST(AutoRig, EveryExampleCharacterGetsItsLimbsAndLoads) {
  const Expected cases[] = {
      // the hair's curls are strokes hanging from the cap by one end: limbs with handles
      {"figure",
       {"arm-left", "arm-right", "leg-left", "leg-right", "hair-curl-1", "hair-curl-2", "hair-tuft"},
       {"torso", "face", "arm-left", "arm-right", "leg-left", "leg-right", "hair-curl-1", "hair-curl-2", "hair-tuft"},
       "torso"},
      // chains: the hands carry the handles, the arms only hinges
      {"boy",
       {"arm-left", "arm-right", "hand-left", "hand-right", "leg-left", "leg-right", "curl"},
       {"shirt", "head", "hand-left", "hand-right", "leg-left", "leg-right", "curl"},
       "shirt"},
      {"singer", {"arm-left", "arm-right", "leg-left", "leg-right"}, {"dress", "face", "arm-left", "arm-right", "leg-left", "leg-right"}, "dress"},
      {"butterfly",
       {"wing-left", "wing-right", "antenna-left", "antenna-right"},
       {"body", "head", "wing-left", "wing-right", "antenna-left", "antenna-right"},
       "body"},
      {"koi",
       {"tail", "fin-top", "fin-side", "whisker-top", "whisker-bottom"},
       {"body", "tail", "fin-top", "fin-side", "whisker-top", "whisker-bottom"},
       "body"},
      // the flame hangs from the wax by its wick (an open stroke)
      {"candle", {"arm-left", "arm-right", "flame", "handle-ring"}, {"wax", "holder", "arm-left", "arm-right", "flame", "handle-ring"}, "wax"},
      // drawn without our names: an editor's ids (the cat), German labels (the robot)
      {"cat",
       {"path2291", "rect1187", "rect1189", "rect1191", "rect1193", "path3021", "path3023"},
       {"body", "head", "limb-left", "limb-left-2", "limb-left-3", "limb-right", "limb-right-2", "limb-right-3", "limb-right-4"},
       "ellipse1042"},
      // the upper arms hang beside the torso; the forearms carry the handles
      {"robot",
       {"rect101", "rect103", "rect107", "rect109", "rect113", "rect115", "rect121"},
       {"rumpf", "kopf", "unterarm-links", "unterarm-rechts", "bein-links", "bein-rechts"},
       "rect123"},
  };
  for (const Expected& e : cases) {
    const Rigged r = rig_of((test::characters_dir() / (std::string(e.name) + ".svg")).string());
    EXPECT_EQ(ids_of(r, AutoRigPart::Limb), e.limbs) << e.name;
    EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{e.body}) << e.name;
    EXPECT_EQ(handles_of(r), e.handles) << e.name;
    // one hinge per limb, each between the limb (or its connector) and its parent, and one at
    // the head's neck
    EXPECT_EQ(r.ar.rig.joints.size(), e.limbs.size() + ids_of(r, AutoRigPart::Head).size()) << e.name;
    loads(r, e.name);
  }
}

// A character made of PNG layers (config/characters/owl) rigs as a drawing does: its parts are
// traced from each layer's alpha and named after the files.
TEST(AutoRig, AFolderOfPngLayersGetsItsLimbs) {
  const Rigged r = rig_of((test::characters_dir() / "owl").string());
  EXPECT_EQ(ids_of(r, AutoRigPart::Limb), (std::set<std::string>{"wing-left", "wing-right", "foot-left", "foot-right", "ear-left", "ear-right"}));
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"body"});
  EXPECT_EQ(handles_of(r), (std::set<std::string>{"body", "head", "wing-left", "wing-right", "foot-left", "foot-right", "ear-left", "ear-right"}));
  loads(r, "owl");
}

// The singer's mouth shapes make a swap set, her open and shut eyes a swap set and a blink.
TEST(AutoRig, NamedMouthsAndEyesBecomeSwapSetsAndABlink) {
  const Rigged r = rig_of((test::characters_dir() / "singer.svg").string());
  ASSERT_EQ(r.ar.rig.swaps.size(), 2u);
  const RigSwap& mouth = r.ar.rig.swaps[0];
  EXPECT_EQ(mouth.name, "mouth");
  EXPECT_EQ(mouth.members, (std::vector<std::string>{"mouth-smile", "mouth-a", "mouth-e", "mouth-o"}));
  EXPECT_EQ(mouth.members[size_t(mouth.default_member)], "mouth-smile");
  const RigSwap& eyes = r.ar.rig.swaps[1];
  EXPECT_EQ(eyes.name, "eyes");
  EXPECT_EQ(eyes.members, (std::vector<std::string>{"eyes-open", "eyes-shut"}));
  EXPECT_EQ(eyes.members[size_t(eyes.default_member)], "eyes-open");
  ASSERT_EQ(r.ar.rig.triggers.size(), 1u);
  EXPECT_EQ(r.ar.rig.triggers[0].name, "blink");
  EXPECT_EQ(r.ar.rig.triggers[0].shapes, std::vector<std::string>{"eyes-shut"});
  // a figure with one mouth has no swap set
  EXPECT_TRUE(rig_of((test::characters_dir() / "figure.svg").string()).ar.rig.swaps.empty());
}

// Groups, Character Animator's way: a Mouth group of visemes is a swap set (its Neutral child
// showing), an Eyes group with Open and Closed children a swap set and a blink.
TEST(AutoRig, GroupsOfVisemesAndEyesBecomeSwapSetsAndABlink) {
  const std::string svg = R"(<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
      width="200" height="300" viewBox="0 0 200 300">
  <g inkscape:label="Body"><rect id="rect10" inkscape:label="Torso" x="60" y="100" width="80" height="130" fill="#48c"/></g>
  <g inkscape:label="Head">
    <circle id="circle20" cx="100" cy="60" r="45" fill="#fc9"/>
    <g inkscape:label="Mouth">
      <ellipse id="ellipse31" inkscape:label="Ah" cx="100" cy="80" rx="8" ry="10" fill="#822"/>
      <ellipse id="ellipse32" inkscape:label="Neutral" cx="100" cy="80" rx="10" ry="3" fill="#822"/>
      <ellipse id="ellipse33" inkscape:label="Oh" cx="100" cy="80" rx="7" ry="7" fill="#822"/>
    </g>
    <g inkscape:label="Eyes">
      <circle id="circle41" inkscape:label="Open" cx="85" cy="55" r="6" fill="#222"/>
      <rect id="rect42" inkscape:label="Closed" x="78" y="54" width="14" height="3" fill="#222"/>
    </g>
  </g>
</svg>)";
  const std::string path = test::write_temp("grouped.svg", svg);
  const Rigged r = rig_of(path);
  ASSERT_EQ(r.ar.rig.swaps.size(), 2u);
  EXPECT_EQ(r.ar.rig.swaps[0].name, "mouth");
  EXPECT_EQ(r.ar.rig.swaps[0].members, (std::vector<std::string>{"ellipse31", "ellipse32", "ellipse33"}));
  EXPECT_EQ(r.ar.rig.swaps[0].members[size_t(r.ar.rig.swaps[0].default_member)], "ellipse32");
  EXPECT_EQ(r.ar.rig.swaps[1].name, "eyes");
  EXPECT_EQ(r.ar.rig.swaps[1].members, (std::vector<std::string>{"circle41", "rect42"}));
  ASSERT_EQ(r.ar.rig.triggers.size(), 1u);
  EXPECT_EQ(r.ar.rig.triggers[0].shapes, std::vector<std::string>{"rect42"});
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"rect10"});
  loads(r, "grouped");
}

// Any other group of alternatives (one showing, the others hidden by the file, as editors hide
// them: display: none) becomes a swap set named after the group, the visible one its default.
// The hidden ones are loaded, drawn only when swapped in, and are not parts with handles.
TEST(AutoRig, AGroupOfAlternativesOneVisibleBecomesASwapSet) {
  const std::string svg = R"(<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
      width="300" height="300" viewBox="0 0 300 300">
  <rect id="torso" x="100" y="80" width="80" height="140" fill="#48c"/>
  <rect id="arm" x="170" y="100" width="90" height="24" fill="#fc9"/>
  <g inkscape:label="Hand Right">
    <circle id="hand-open" cx="262" cy="112" r="16" fill="#fc9"/>
    <circle id="hand-fist" cx="262" cy="112" r="11" fill="#c96" style="display:none"/>
    <rect id="hand-point" x="255" y="100" width="30" height="8" fill="#c96" display="none"/>
  </g>
  <g inkscape:label="Sketch" style="display:none"><rect id="sketch" x="0" y="0" width="30" height="30" fill="#000"/></g>
  <g><rect id="lonely" x="0" y="250" width="30" height="30" fill="#000" style="display:none"/></g>
</svg>)";
  const std::string path = test::write_temp("alternatives.svg", svg);
  const Rigged r = rig_of(path);
  std::set<std::string> ids;
  for (const SubShape& sh : r.ch.shapes) {
    ids.insert(sh.id);
    EXPECT_EQ(sh.hidden, sh.id == "hand-fist" || sh.id == "hand-point") << sh.id;
  }
  EXPECT_FALSE(ids.count("sketch")) << "a hidden group with nothing beside it showing is not an alternative";
  EXPECT_FALSE(ids.count("lonely"));
  ASSERT_EQ(r.ar.rig.swaps.size(), 1u);
  const RigSwap& sw = r.ar.rig.swaps[0];
  EXPECT_EQ(sw.name, "hand-right");
  EXPECT_EQ(sw.members, (std::vector<std::string>{"hand-open", "hand-fist", "hand-point"}));
  EXPECT_EQ(sw.members[size_t(sw.default_member)], "hand-open");
  for (const AutoRigPart& p : r.ar.parts) EXPECT_FALSE(r.ch.shapes[size_t(p.shape)].hidden) << "a hidden alternative is no part";
  loads(r, "alternatives");
  // Drawn: the hidden ones only when swapped in.
  auto puppet = load_puppet(path, r.ar.rig);
  ASSERT_TRUE(puppet.ok()) << puppet.error;
  Puppet& p = **puppet.value;
  auto index = [&](const std::string& id) {
    for (size_t k = 0; k < p.character.shapes.size(); ++k)
      if (p.character.shapes[k].id == id) return k;
    return size_t(0);
  };
  // `render` leaves it out: the pixel inside the pointing hand only is clear.
  RenderOptions ro;
  auto img = render_character(r.ch, prepare_mesh(r.ch), ro);
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_EQ(img.value->rgba[(size_t(104) * size_t(img.value->width) + 282) * 4 + 3], 0) << "a hidden alternative is not drawn";
  EXPECT_GT(img.value->rgba[(size_t(112) * size_t(img.value->width) + 262) * 4 + 3], 200) << "the shown one is";
  EXPECT_TRUE(p.shown[index("hand-open")]);
  EXPECT_FALSE(p.shown[index("hand-fist")]);
  EXPECT_FALSE(p.shown[index("hand-point")]);
  const std::vector<int> fist{1};
  p.show(fist, {});
  EXPECT_FALSE(p.shown[index("hand-open")]);
  EXPECT_TRUE(p.shown[index("hand-fist")]);
  EXPECT_FALSE(p.shown[index("hand-point")]);
}

// Secondary motion from names: hair, ears, tails and antennae become [[physics]] chains hanging
// from their parents, their handles the chains' ends; the written rig loads for a show with its
// chains, and a starter show leaves their handles to the motion.
TEST(AutoRig, HairEarsTailsAndAntennaeBecomeChains) {
  struct Want {
    const char* name;
    std::map<std::string, std::string> chains;  ///< chain -> from
  } wants[] = {
      {"figure", {{"hair-curl-1", "hair-cap"}, {"hair-curl-2", "hair-cap"}, {"hair-tuft", "hair-cap"}}},
      {"koi", {{"tail", "body"}}},
      {"butterfly", {{"antenna-left", "head"}, {"antenna-right", "head"}}},
  };
  for (const Want& w : wants) {
    const std::string file = (test::characters_dir() / (std::string(w.name) + ".svg")).string();
    const Rigged r = rig_of(file);
    std::map<std::string, std::string> got;
    for (const RigPhysics& ph : r.ar.rig.physics) {
      got[ph.name] = ph.from;
      EXPECT_EQ(ph.handle, ph.name) << w.name << ": the chain's end is the part's handle";
      EXPECT_GE(r.ar.rig.find_handle(ph.handle), 0);
    }
    EXPECT_EQ(got, w.chains) << w.name;
    const std::string text = write_auto_rig(r.ar, r.ch);
    auto rig = parse_rig(text, test::write_temp(std::string("auto-physics-") + w.name + ".toml", text));
    ASSERT_TRUE(rig.ok()) << rig.error;
    EXPECT_EQ(rig.value->physics.size(), w.chains.size());
    auto show = load_puppet(file, *rig.value, "", true);
    ASSERT_TRUE(show.ok()) << show.error;
    EXPECT_EQ((*show.value)->chains.size(), w.chains.size()) << w.name;
    auto starter = starter_show(r.ar, r.ch, "rig.toml", "nanokontrol2");
    ASSERT_TRUE(starter.ok()) << starter.error;
    for (const auto& [chain, from] : w.chains)
      EXPECT_EQ(starter.value->find("\"handle." + chain), std::string::npos) << w.name << ": " << chain << " is bound";
  }
}

// Hinges at the drawn joints: where the boy's and the candle's hand rigs state their joints
// (the shoulders, the hips, the wick), within 1% of the character's height. The middle of
// the overlap, where the solver's automatic hinge goes, is 5-6% away for the shoulders.
TEST(AutoRig, HingesSitAtTheJointsTheHandRigsState) {
  for (const char* name : {"boy", "candle"}) {
    const Rigged r = rig_of((test::characters_dir() / (std::string(name) + ".svg")).string());
    auto hand = load_rig((test::source_dir() / "config/rigs" / (std::string(name) + ".toml")).string());
    ASSERT_TRUE(hand.ok()) << hand.error;
    int compared = 0;
    for (const RigJoint& hj : hand.value->joints) {
      if (hj.weld || !hj.has_at) continue;
      const RigJoint* ours = nullptr;
      for (const RigJoint& j : r.ar.rig.joints)
        if (j.part_a == hj.part_a && j.part_b == hj.part_b) ours = &j;
      ASSERT_NE(ours, nullptr) << name << ": no hinge between " << hj.part_a << " and " << hj.part_b;
      EXPECT_LE((ours->at - hj.at).norm(), 0.01 * r.ch.height)
          << name << " " << hj.part_a << ": (" << ours->at.x() << ", " << ours->at.y() << ") vs (" << hj.at.x() << ", " << hj.at.y() << ")";
      ++compared;
    }
    EXPECT_GE(compared, 3) << name;
  }
}

// The boy's shorts are a detail on his shirt that both legs hang from: sewn to the shirt by one
// line, a kick turned them about it (the pose-quality benchmark's passive parts 1.09 % of the
// height off the ideal). Sewn a second time, away from the first, they stay on the body.
TEST(AutoRig, ADetailTheLimbsHangFromStaysOnItsPartWhenALimbTurns) {
  const std::string file = (test::characters_dir() / "boy.svg").string();
  Rigged r = rig_of(file);
  bool twice = false;
  for (const std::string& n : r.ar.notes_sewing) twice = twice || n == "shorts sewn to shirt a second time, away from the first: it keeps its turn";
  EXPECT_TRUE(twice) << "the shorts, which the legs hang from, are sewn to the shirt twice";
  auto rig = parse_rig(write_auto_rig(r.ar, r.ch), (test::temp_dir("boy-kick") / "rig.toml").string());
  ASSERT_TRUE(rig.ok()) << rig.error;
  const int leg = rig.value->find_handle("leg-right");
  ASSERT_GE(leg, 0);
  Vec2 hip(0, 0);
  for (const AutoRigPart& p : r.ar.parts)
    if (p.handle == "leg-right") hip = p.joint;
  std::vector<Vec2> rest;
  for (const RigHandle& h : rig.value->handles) rest.push_back(h.rest);
  Character c = r.ch;
  auto solver = make_solver(rig.value->solver);
  ASSERT_TRUE(solver);
  std::string err;
  ASSERT_TRUE(solver->prepare(c, *rig.value, rest, SolverWeights{}, &err)) << err;
  const double a = -0.785;  // (45°, the pose-quality benchmark's kick, about the rig's own hinge)
  std::vector<Vec2> t = rest;
  const Vec2 d = rest[size_t(leg)] - hip;
  t[size_t(leg)] = hip + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y());
  for (int k = 0; k < 10; ++k) solver->solve(t, rig.value->iterations);
  std::vector<Points> now;
  for (const SubShape& sh : c.shapes) now.push_back(sh.points);
  solver->shape_points(now);
  size_t shorts = 0;
  while (shorts < c.shapes.size() && c.shapes[shorts].id != "shorts") ++shorts;
  ASSERT_LT(shorts, c.shapes.size());
  double rms = 0;
  for (size_t i = 0; i < c.shapes[shorts].points.size(); ++i) rms += (now[shorts][i] - c.shapes[shorts].points[i]).squaredNorm();
  rms = std::sqrt(rms / double(c.shapes[shorts].points.size()));
  EXPECT_LT(rms, 0.008 * c.height) << "the shorts stay on the body (0.95 % of the height with one line)";
  EXPECT_LT((solver->handle_point(size_t(leg)) - t[size_t(leg)]).norm(), 0.01 * c.height) << "the leg kicks";
}

// No names at all (every id removed, as a drawing exported without them): the same limbs and
// body by shape alone, with made-up handle names.
TEST(AutoRig, ADrawingWithNoNamesStillGetsLimbsAndABody) {
  std::ifstream in(test::characters_dir() / "figure.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)), {});
  // (by hand: std::regex trips GCC 12's maybe-uninitialized warning under the sanitizers)
  std::string bare = svg;
  for (const std::string attr : {" id=\"", " inkscape:label=\""})
    for (size_t at; (at = bare.find(attr)) != std::string::npos;) bare.erase(at, bare.find('"', at + attr.size()) + 1 - at);
  ASSERT_EQ(bare.find("arm-left"), std::string::npos);
  const std::string path = test::write_temp("bare-figure.svg", bare);
  const Rigged r = rig_of(path);
  int limbs = 0, strands = 0;
  for (const AutoRigPart& p : r.ar.parts)
    (r.ch.shapes[size_t(p.shape)].fill.enabled ? limbs : strands) += p.kind == AutoRigPart::Limb;
  EXPECT_EQ(limbs, 4);
  EXPECT_EQ(strands, 3) << "the curls of hair";
  const auto h = handles_of(r);
  EXPECT_TRUE(h.count("body")) << "the body's handle";
  EXPECT_TRUE(h.count("limb-left") && h.count("limb-left-2") && h.count("limb-right") && h.count("limb-right-2"));
  loads(r, "bare-figure");
}

// Filled paths drawn without a closing z (as many drawings downloaded from the web are): parts
// all the same, with the limbs and handles of the drawing that closes them.
TEST(AutoRig, FilledPathsWithoutAClosingZAreParts) {
  std::ifstream in(test::characters_dir() / "figure.svg");
  const std::string svg((std::istreambuf_iterator<char>(in)), {});
  std::string open = svg;
  int removed = 0;
  for (const std::string z : {" z\"", " Z\""})
    for (size_t at; (at = open.find(z)) != std::string::npos; ++removed) open.erase(at, 2);
  ASSERT_GE(removed, 6);
  const Rigged closed = rig_of((test::characters_dir() / "figure.svg").string());
  const Rigged r = rig_of(test::write_temp("open-figure.svg", open));
  EXPECT_EQ(ids_of(r, AutoRigPart::Limb), ids_of(closed, AutoRigPart::Limb));
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), ids_of(closed, AutoRigPart::Body));
  EXPECT_EQ(handles_of(r), handles_of(closed));
  EXPECT_GE(ids_of(r, AutoRigPart::Limb).size(), 4u);
  loads(r, "open-figure");
}

// A creature whose legs, tail and head are inside its body's one outline, and the same drawn
// as a black silhouette under colour pieces: the parts give no limbs, the silhouette gives
// them, and the rig poses on the rigid grid, a leg lifted at its hip while the body keeps its
// place and every limb its shape.
// A creature in one shape (four legs, a tail, a head on a neck) filled with `fill`, then `more`.
std::string creature(const std::string& fill, const std::string& more) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"300\" height=\"220\"><path id=\"path12\" fill=\"" + fill + "\" d=\""
         "M70 80 L215 80 L226 50 L216 14 L286 8 L292 50 L246 58 L232 95 L228 200 L210 200 L206 128 L186 128 L184 200 L166 200 "
         "L162 128 L120 128 L118 200 L100 200 L96 128 L80 128 L78 200 L60 200 L58 110 L20 70 L28 62 L62 92 Z\"/>" +
         more + "</svg>";
}

TEST(AutoRig, LimbsInsideOneShapeComeFromTheSilhouette) {
  const std::string one_shape = creature("#864", "");
  const std::string under_colour = creature("#000", "<rect id=\"rect3\" x=\"80\" y=\"86\" width=\"120\" height=\"36\" fill=\"#c96\"/>"
                                                    "<circle id=\"circle4\" cx=\"262\" cy=\"32\" r=\"8\" fill=\"#fc8\"/>");
  for (const auto& [name, text] : {std::pair{"one-shape", one_shape}, std::pair{"under-colour", under_colour}}) {
    const std::string path = test::write_temp(std::string("creature-") + name + ".svg", text);
    const Rigged r = rig_of(path);
    EXPECT_EQ(r.ar.rig.solver, "rigid_grid") << name;
    int limbs = 0, heads = 0;
    for (const AutoRigPart& p : r.ar.parts) {
      limbs += p.kind == AutoRigPart::Limb;
      heads += p.kind == AutoRigPart::Head;
    }
    EXPECT_EQ(limbs, 5) << name << ": four legs and a tail";
    EXPECT_EQ(heads, 1) << name;
    EXPECT_GE(r.ar.rig.stiffness.size(), 6u) << name << ": softer at every joint";
    const auto dir = test::temp_dir(std::string("creature-pose-") + name);
    const std::string rig = (dir / "rig.toml").string(), dump = (dir / "pose.json").string();
    std::ofstream(rig) << write_auto_rig(r.ar, r.ch);
    // the front leg's handle (its foot, near (69, 195)), lifted forward: turned 40° about its hip
    // near (69, 128) (a limb that turns whole at its joint does not shorten to a nearer target)
    std::string leg;
    for (const RigHandle& h : r.ar.rig.handles)
      if ((h.rest - Vec2(69, 195)).norm() < 15) leg = h.name;
    ASSERT_FALSE(leg.empty()) << name;
    auto p = test::run_cli("pose '" + path + "' --rig '" + rig + "' --target " + leg + "=26,179 -o '" + (dir / "p.png").string() + "' --dump '" + dump + "'");
    ASSERT_EQ(p.exit_code, 0) << p.err;
    std::ifstream in(dump);
    const auto j = nlohmann::json::parse(in);
    EXPECT_LT(j["handle_residuals"][leg].get<double>(), 8.0) << name << ": the foot follows";
    EXPECT_LT(j["handle_residuals"]["body"].get<double>(), 3.0) << name << ": the body keeps its place";
  }
}

// A creature whose legs, tail and head are inside its body's one shape, a spot on its front
// leg: each limb of its silhouette turns whole at its joint ([[bone]]), so a leg turned at its
// hip carries its spot rigidly, as far from the hip as drawn, and the body stays; without bones
// the grid bends the leg like a beam and the spot turns short of the handle's turn.
TEST(AutoRig, ALimbInsideOneShapeTurnsWholeAtItsJoint) {
  const std::string svg = creature("#864", "<circle id=\"circle3\" cx=\"69\" cy=\"175\" r=\"4\" fill=\"#fff\"/>");
  const std::string path = test::write_temp("creature-bones.svg", svg);
  for (const bool bones : {true, false}) {  // (`rig --bones`, and without)
    auto ch = load_character(path);
    ASSERT_TRUE(ch.ok()) << ch.error;
    Character c = *ch.value;
    AutoRigOptions o;
    o.bones = bones;
    const AutoRig ar = auto_rig(c, path, "", o);
    ASSERT_EQ(ar.rig.solver, "rigid_grid");
    if (bones) EXPECT_GE(ar.rig.bones.size(), 4u) << "the four legs at least";
    else EXPECT_TRUE(ar.rig.bones.empty());
    auto rig = parse_rig(write_auto_rig(ar, c), (test::temp_dir("creature-bones") / "rig.toml").string());
    ASSERT_TRUE(rig.ok()) << rig.error;
    EXPECT_EQ(rig.value->bones.size(), ar.rig.bones.size()) << "written and read back";
    int leg = -1;
    for (size_t h = 0; h < ar.rig.handles.size(); ++h)
      if ((ar.rig.handles[h].rest - Vec2(69, 195)).norm() < 15) leg = int(h);
    ASSERT_GE(leg, 0);
    Vec2 hip(0, 0);
    for (const AutoRigPart& p : ar.parts)
      if (p.handle == ar.rig.handles[size_t(leg)].name) hip = p.joint;
    EXPECT_LT((hip - Vec2(69, 128)).norm(), 20) << hip.transpose();
    std::vector<Vec2> rest;
    for (const RigHandle& h : rig.value->handles) rest.push_back(h.rest);
    auto solver = make_solver(rig.value->solver);
    ASSERT_TRUE(solver);
    std::string err;
    ASSERT_TRUE(solver->prepare(c, *rig.value, rest, SolverWeights{}, &err)) << err;
    const double a = 0.7;  // (40°, forward)
    auto turn = [&](const Vec2& p) {
      const Vec2 d = p - hip;
      return Vec2(hip + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y()));
    };
    std::vector<Vec2> t = rest;
    t[size_t(leg)] = turn(rest[size_t(leg)]);
    for (int k = 0; k < 10; ++k) solver->solve(t, rig.value->iterations);
    std::vector<Points> now;
    for (const SubShape& sh : c.shapes) now.push_back(sh.points);
    solver->shape_points(now);
    size_t spot = 0;
    while (spot < c.shapes.size() && c.shapes[spot].id != "circle3") ++spot;
    ASSERT_LT(spot, c.shapes.size());
    const Points& was = c.shapes[spot].points;
    double off = 0;
    for (size_t i = 0; i < was.size(); ++i) off = std::max(off, (now[spot][i] - turn(was[i])).norm());
    if (bones) {
      EXPECT_LT(off, 0.5) << "the spot turns with the leg about the hip, rigidly";
      EXPECT_LT((solver->handle_point(size_t(leg)) - t[size_t(leg)]).norm(), 0.5) << "the foot where it is turned";
    } else {
      EXPECT_GT(off, 2.0) << "bent by the grid, the spot is not where the leg's turn puts it";
    }
    const int body = rig.value->find_handle("body");
    ASSERT_GE(body, 0);
    EXPECT_LT((solver->handle_point(size_t(body)) - rest[size_t(body)]).norm(), 3.0) << "the body keeps its place";
    // back at rest when the foot's target is
    for (int k = 0; k < 10; ++k) solver->solve(rest, rig.value->iterations);
    solver->shape_points(now);
    double away = 0;
    for (size_t k = 0; k < c.shapes.size(); ++k)
      for (size_t i = 0; i < c.shapes[k].points.size(); ++i) away = std::max(away, (now[k][i] - c.shapes[k].points[i]).norm());
    EXPECT_LT(away, 0.5) << "back at rest";
  }
  // From the command line: `rig --bones` says which limbs turn whole, and its starter show plays.
  const auto dir = test::temp_dir("creature-bones-cli");
  const std::string rig = (dir / "rig.toml").string(), show = (dir / "show.toml").string();
  auto r = test::run_cli("rig '" + path + "' --bones -o '" + rig + "' --show '" + show + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(it turns whole there)"), std::string::npos) << r.out;
  std::ifstream in(rig);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("[[bone]]"), std::string::npos);
  auto plain = test::run_cli("rig '" + path + "' -o '" + (dir / "plain.toml").string() + "'");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(plain.out.find("(it turns whole there)"), std::string::npos) << "bones only when asked";
  auto parts = test::run_cli("rig '" + (test::characters_dir() / "boy.svg").string() + "' --bones -o '" + (dir / "boy.toml").string() + "'");
  ASSERT_EQ(parts.exit_code, 0) << parts.err;
  EXPECT_NE((parts.out + parts.err).find("--bones has nothing to do"), std::string::npos) << parts.out << parts.err;
  auto run = test::run_cli("run '" + show + "' --headless --stats '" + (dir / "s.json").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream st(dir / "s.json");
  const auto j = nlohmann::json::parse(st);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
}

// A sun behind the figure (the torso crosses its edge) and a shadow under its feet: scenery,
// left out and held still, never the body; the figure rigs as it does without them. A face
// drawn first with everything on it is the character, not a backdrop.
TEST(AutoRig, ABackdropAndAGroundShadowAreLeftOutAndNeverTheBody) {
  std::ifstream in(test::characters_dir() / "figure.svg");
  std::string svg((std::istreambuf_iterator<char>(in)), {});
  const size_t first = svg.find("<g");
  ASSERT_NE(first, std::string::npos);
  svg.insert(first, "<circle id=\"circle5\" cx=\"60\" cy=\"150\" r=\"110\" fill=\"#fd0\"/>"
                    "<ellipse id=\"ellipse6\" cx=\"150\" cy=\"405\" rx=\"80\" ry=\"10\" fill=\"#333\" fill-opacity=\"0.3\"/>");
  const Rigged plain = rig_of((test::characters_dir() / "figure.svg").string());
  const Rigged r = rig_of(test::write_temp("figure-sun.svg", svg));
  std::set<std::string> left;
  for (const AutoRigLeftOut& l : r.ar.left_out) left.insert(r.ch.shapes[size_t(l.shape)].id);
  EXPECT_EQ(left, (std::set<std::string>{"circle5", "ellipse6"}));
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"torso"});
  EXPECT_EQ(ids_of(r, AutoRigPart::Limb), ids_of(plain, AutoRigPart::Limb));
  EXPECT_TRUE(handles_of(r).count("scenery")) << "held where it is drawn";
  loads(r, "figure-sun");
  // (small drawings made for the test: name, size, body)
  auto drawn = [](const std::string& name, int w, int h, const std::string& body) {
    return rig_of(test::write_temp(name, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(w) + "\" height=\"" +
                                             std::to_string(h) + "\">" + body + "</svg>"));
  };
  const std::string face_disc = "<circle id=\"circle1\" cx=\"50\" cy=\"50\" r=\"45\" fill=\"#fc0\"/>"
                                "<circle id=\"circle2\" cx=\"35\" cy=\"40\" r=\"6\"/><circle id=\"circle3\" cx=\"65\" cy=\"40\" r=\"6\"/>"
                                "<rect id=\"rect4\" x=\"30\" y=\"65\" width=\"40\" height=\"6\"/>";
  const Rigged face = drawn("face.svg", 100, 100, face_disc);
  EXPECT_TRUE(face.ar.left_out.empty());
  EXPECT_EQ(ids_of(face, AutoRigPart::Body), std::set<std::string>{"circle1"});
  // A face drawn first under its hair (the hair half over it, half beside it, as a horse over a
  // sun): its eyes and mouth lie on it and on nothing else, so it is the character, not a
  // backdrop (it was left out, held still while the hair moved, in two heads of the benchmark).
  const Rigged haired = drawn("face-under-hair.svg", 120, 110,
                              "<circle id=\"circle1\" cx=\"60\" cy=\"55\" r=\"40\" fill=\"#fc9\"/>"
                              "<path id=\"path5\" d=\"M5 60 C 5 -15, 115 -15, 115 60 L 115 105 L 95 105 L 95 45 C 90 25, 30 25, "
                              "25 45 L 25 105 L 5 105 z\" fill=\"#630\"/>"
                              "<circle id=\"circle2\" cx=\"45\" cy=\"55\" r=\"5\"/><circle id=\"circle3\" cx=\"75\" cy=\"55\" r=\"5\"/>"
                              "<rect id=\"rect4\" x=\"45\" y=\"75\" width=\"30\" height=\"5\" fill=\"#c33\"/>");
  EXPECT_TRUE(haired.ar.left_out.empty());
  EXPECT_EQ(ids_of(haired, AutoRigPart::Body), std::set<std::string>{"circle1"});
  // Long hair drawn behind the face, its locks hanging: filled most of its box as a disc is, but
  // drawn as no disc or rectangle, so it is the character's (it was left out, held still, as a
  // backdrop: head12's back hair); the face turns on it.
  const Rigged back = drawn("hair-behind-face.svg", 120, 120,
                            "<path id=\"path1\" d=\"M 15 75 A 45 35 0 0 1 105 75 L 105 110 L 95 102 L 85 110 L 75 102 L 65 110 "
                            "L 55 102 L 45 110 L 35 102 L 25 110 L 15 102 z\" fill=\"#630\"/>"
                            "<circle id=\"circle2\" cx=\"60\" cy=\"42\" r=\"28\" fill=\"#fc9\"/>"
                            "<circle id=\"circle3\" cx=\"50\" cy=\"34\" r=\"4\"/><circle id=\"circle4\" cx=\"70\" cy=\"34\" r=\"4\"/>"
                            "<rect id=\"rect5\" x=\"50\" y=\"52\" width=\"20\" height=\"4\" fill=\"#c33\"/>");
  EXPECT_TRUE(back.ar.left_out.empty());
  EXPECT_EQ(ids_of(back, AutoRigPart::Head), std::set<std::string>{"circle2"});
  // the same face on a rectangle that fills the drawing: its background
  const Rigged framed = drawn("face-on-card.svg", 100, 100, "<rect id=\"rect0\" width=\"100\" height=\"100\" fill=\"#2a6\"/>" + face_disc);
  ASSERT_EQ(framed.ar.left_out.size(), 1u);
  EXPECT_EQ(framed.ch.shapes[size_t(framed.ar.left_out[0].shape)].id, "rect0");
  EXPECT_EQ(ids_of(framed, AutoRigPart::Body), std::set<std::string>{"circle1"});
}

// A creature in one shape cut out of a rectangle that fills the drawing (a bunny on a green
// square, `animals/mammals/bunny_01.svg` of the benchmark): the rectangle is its background,
// out of the rigid grid's mesh and exactly where it is drawn on every frame of the starter
// show, while the legs turn. In the mesh, held by one handle at its middle, it joined every limb
// to every other through it and turned with them.
TEST(AutoRig, ABackgroundUnderALimbsInsideOneShapeStaysWhereItIsDrawn) {
  // (an eye and a spot: a drawing of two shapes has no background to tell)
  const std::string svg = creature("#864", "<circle id=\"circle4\" cx=\"262\" cy=\"28\" r=\"5\"/>"
                                           "<circle id=\"circle5\" cx=\"150\" cy=\"100\" r=\"8\" fill=\"#a75\"/>");
  const std::string carded = svg.substr(0, svg.find("<path")) + "<rect id=\"rect0\" width=\"300\" height=\"220\" fill=\"#2a6\"/>" +
                             svg.substr(svg.find("<path"));
  const std::string path = test::write_temp("creature-on-card.svg", carded);
  const Rigged r = rig_of(path);
  ASSERT_EQ(r.ar.rig.solver, "rigid_grid");
  ASSERT_EQ(r.ar.left_out.size(), 1u);
  EXPECT_EQ(r.ch.shapes[size_t(r.ar.left_out[0].shape)].id, "rect0");
  const Rigged plain = rig_of(test::write_temp("creature-off-card.svg", svg));
  EXPECT_EQ(ids_of(r, AutoRigPart::Limb).size(), ids_of(plain, AutoRigPart::Limb).size()) << "the same limbs";
  bool still = false;
  for (const RigRider& d : r.ar.rig.riders) still = still || (d.part == "rect0" && d.still);
  EXPECT_TRUE(still) << "a still rider";
  const auto live = test::first_frame(test::write_starter(r.ar, r.ch, "creature-on-card"));
  ASSERT_NE(live, nullptr);
  LiveShow& s = *live;
  const std::vector<Points> rest = s.puppet().shapes;
  size_t card = rest.size(), body = rest.size();
  for (size_t k = 0; k < s.puppet().character.shapes.size(); ++k) {
    if (s.puppet().character.shapes[k].id == "rect0") card = k;
    if (s.puppet().character.shapes[k].id == "path12") body = k;
  }
  ASSERT_LT(card, rest.size());
  ASSERT_LT(body, rest.size());
  double card_moved = 0, body_moved = 0;
  for (int k = 1; k <= 240; ++k) {
    s.frame(int64_t(double(k) / 60 * 1e9));
    const auto& now = s.puppet().shapes;
    for (size_t i = 0; i < rest[card].size(); ++i) card_moved = std::max(card_moved, (now[card][i] - rest[card][i]).norm());
    for (size_t i = 0; i < rest[body].size(); ++i) body_moved = std::max(body_moved, (now[body][i] - rest[body][i]).norm());
  }
  EXPECT_EQ(card_moved, 0.0) << "the background is where it is drawn";
  EXPECT_GT(body_moved, 20.0) << "the creature's limbs turn";
}

// The head turns about its neck: a hinge where it meets the body, so a tilt of the head's
// handle turns it whole while the body stays (its handle held at rest).
// (The figure without its curls of hair: their handles, held at rest by `pose`, would hold the
// head; in a show they are chains' ends and follow it.)
TEST(AutoRig, TheHeadTurnsAboutItsNeck) {
  std::ifstream in(test::characters_dir() / "figure.svg");
  std::string svg;
  for (std::string line; std::getline(in, line);)
    if (line.find("id=\"hair-curl") == std::string::npos && line.find("id=\"hair-tuft") == std::string::npos) svg += line + "\n";
  const std::string path = test::write_temp("figure-no-curls.svg", svg);
  const Rigged r = rig_of(path);
  const AutoRigPart* head = nullptr;
  for (const AutoRigPart& p : r.ar.parts)
    if (p.kind == AutoRigPart::Head) head = &p;
  ASSERT_TRUE(head);
  ASSERT_TRUE(head->has_joint);
  EXPECT_NEAR(head->joint.x(), 150, 6);
  EXPECT_NEAR(head->joint.y(), 135, 8) << "between the face and the torso";
  const auto dir = test::temp_dir("head-tilt");
  const std::string rig = (dir / "rig.toml").string(), dump = (dir / "pose.json").string();
  std::ofstream(rig) << write_auto_rig(r.ar, r.ch);
  // the face's handle (at its centre, (150, 88)) swung 25 degrees about the neck
  const Vec2 c = head->joint, h0(150, 88);
  const double a = 25 * M_PI / 180;
  const Vec2 h1 = c + Eigen::Rotation2Dd(a) * (h0 - c);
  auto p = test::run_cli("pose '" + path + "' --rig '" + rig + "' --target face=" +
                         std::to_string(h1.x()) + "," + std::to_string(h1.y()) + " -o '" + (dir / "p.png").string() + "' --dump '" + dump + "'");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  std::ifstream dumped(dump);
  const auto j = nlohmann::json::parse(dumped);
  // the face keeps its shape (its best rigid fit) and the torso stays
  for (const auto& sh : j["subshapes"]) {
    const std::string id = sh["id"];
    if (id != "face" && id != "torso") continue;
    Points posed;
    for (const auto& q : sh["points"]) posed.emplace_back(q[0].get<double>(), q[1].get<double>());
    const SubShape* rest = nullptr;
    for (const SubShape& s : r.ch.shapes)
      if (s.id == id) rest = &s;
    ASSERT_TRUE(rest) << id;
    if (id == "face") {
      ASSERT_EQ(rest->points.size(), posed.size());
      EXPECT_LT(rigid_fit_rms(rest->points, posed), 0.01 * 420) << "the face keeps its shape";
      const RigidMotion m = rigid_fit(rest->points, posed);
      EXPECT_GT(std::abs(std::atan2(m.s, m.c)) * 180 / M_PI, 10) << "and turns";
    } else {  // (the solver adds points to the torso where parts are welded: its outline is compared)
      double moved = 0;
      for (const Vec2& q : posed) moved = std::max(moved, ring_distance(Points{q}, rest->largest_ring()));
      EXPECT_LT(moved, 0.02 * 420) << "the body stays";
    }
  }
  EXPECT_LT(j["handle_residuals"]["face"].get<double>(), 0.03 * 420) << "the face follows";
}

// One flat picture (a PNG, its figure from its alpha): its arms and legs come from its
// silhouette, each handle at a hand or a foot (where the hand rig of the same picture has them).
TEST(AutoRig, AFlatPictureGetsItsLimbsFromItsSilhouette) {
  const Rigged r = rig_of((test::characters_dir() / "boy.png").string());
  EXPECT_EQ(r.ar.rig.solver, "rigid_grid");
  for (const Vec2& end : {Vec2(86, 248), Vec2(214, 248), Vec2(110, 410), Vec2(190, 410)}) {
    double nearest = 1e9;
    for (const RigHandle& h : r.ar.rig.handles) nearest = std::min(nearest, (h.rest - end).norm());
    EXPECT_LT(nearest, 25) << "a handle at " << end.transpose();
  }
  const auto dir = test::temp_dir("flat-picture");
  const std::string rig = (dir / "rig.toml").string();
  std::ofstream(rig) << write_auto_rig(r.ar, r.ch);
  auto p = test::run_cli("pose '" + (test::characters_dir() / "boy.png").string() + "' --rig '" + rig + "' -o '" + (dir / "p.png").string() + "'");
  EXPECT_EQ(p.exit_code, 0) << p.err;
  // A stick figure (strokes and a ring, nothing filled: every branch as wide as its core) too.
  const Rigged stick = rig_of((test::characters_dir() / "stick.svg").string());
  EXPECT_EQ(stick.ar.rig.solver, "rigid_grid");
  int limbs = 0;
  for (const AutoRigPart& q : stick.ar.parts) limbs += q.kind == AutoRigPart::Limb;
  EXPECT_EQ(limbs, 4) << "two arms, two legs";
}

// A pen on a simulated tablet that hovers at `from`, drags to `to` (fractions of the canvas)
// over a second and leaves, on `rig`, played headless for four seconds: every frame's shapes.
std::vector<nlohmann::json> pen_drag(const std::string& name, const std::string& rig, int width, int height, const std::string& from,
                                     const std::string& to) {
  const auto dir = test::temp_dir(name);
  const std::string show = (dir / "show.toml").string(), poses = (dir / "poses.jsonl").string();
  std::ofstream(show) << "[show]\nrig = \"" << rig << "\"\nrate = 60\niterations = 8\n[display]\nwidth = " << width << "\nheight = " << height
                      << "\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n0.3 hover " << from << "\n0.5 stroke " << from
                      << " " << to
                      << " over 1.0 pressure 0.7\n1.7 leave\n\"\"\"\n"
                         "[[binding]]\ndevice = \"pen\"\ncontrol = \"pointer\"\ntarget = \"grab\"\n";
  auto r = test::run_cli("run '" + show + "' --headless --frames 240 --dump-poses '" + poses + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(poses);
  std::vector<nlohmann::json> frames;
  for (std::string line; std::getline(in, line);) frames.push_back(nlohmann::json::parse(line));
  return frames;
}

// A shape's points in a frame of `--dump-poses`, and their centre.
Points points_of(const nlohmann::json& frame, const std::string& id) {
  Points out;
  for (const auto& sh : frame["subshapes"])
    if (sh["id"] == id)
      for (const auto& q : sh["points"]) out.emplace_back(q[0].get<double>(), q[1].get<double>());
  return out;
}
Vec2 centre_of(const Points& p) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& q : p) c += q;
  return Vec2(c / double(std::max<size_t>(1, p.size())));
}
// Over the frames: how far shape `a`'s centre went from where it started; how far `b`'s place
// beside `a` (the step between their centres) strayed from its first; and the farthest any
// point of `ids` ends from where it began (infinite when a shape's points are not all there).
double most_moved(const std::vector<nlohmann::json>& frames, const std::string& a) {
  const Vec2 c0 = centre_of(points_of(frames.front(), a));
  double most = 0;
  for (const nlohmann::json& f : frames) most = std::max(most, (centre_of(points_of(f, a)) - c0).norm());
  return most;
}
double most_apart(const std::vector<nlohmann::json>& frames, const std::string& a, const std::string& b) {
  auto step = [&](const nlohmann::json& f) { return Vec2(centre_of(points_of(f, b)) - centre_of(points_of(f, a))); };
  const Vec2 step0 = step(frames.front());
  double most = 0;
  for (const nlohmann::json& f : frames) most = std::max(most, (step(f) - step0).norm());
  return most;
}
// `v` turned as much as the direction `from` turned to become `to`.
Vec2 turned_as(const Vec2& from, const Vec2& to, const Vec2& v) {
  const double n = from.norm() * to.norm(), c = from.dot(to) / n, s = (from.x() * to.y() - from.y() * to.x()) / n;
  return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}
double end_from_rest(const std::vector<nlohmann::json>& frames, std::initializer_list<const char*> ids) {
  double away = 0;
  for (const char* id : ids) {
    const Points a = points_of(frames.front(), id), b = points_of(frames.back(), id);
    EXPECT_EQ(a.size(), b.size()) << id;
    if (a.size() != b.size() || a.empty()) return std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < a.size(); ++i) away = std::max(away, (b[i] - a[i]).norm());
  }
  return away;
}

// The hardware show's pen stroke, on the figure's neck: dragged down onto the shirt while the
// pen holds it, back under the face once the pen leaves (a part sewn to what it hangs from by
// one line turned about it and stayed; now by two).
TEST(AutoRig, APenDragDoesNotLeaveTheNeckOnTheShirt) {
  const auto frames = pen_drag("pen-neck", (test::source_dir() / "config/rigs/figure.toml").string(), 480, 640, "0.5,0.3", "0.6,0.5");
  ASSERT_GE(frames.size(), 200u);
  ASSERT_FALSE(points_of(frames.front(), "neck").empty());
  auto neck_centre = [&](const nlohmann::json& f) { return centre_of(points_of(f, "neck")); };
  const Vec2 rest = neck_centre(frames.front());
  double pulled = 0;
  for (size_t k = 0; k < 100; ++k) pulled = std::max(pulled, (neck_centre(frames[k]) - rest).norm());
  EXPECT_GT(pulled, 8) << "the pen pulled it";
  EXPECT_LT((neck_centre(frames.back()) - rest).norm(), 0.01 * 420) << "and it went back";
}

// A body drawn as a black shape with its white fill inset over it (two shapes, one part), an
// arm, two legs and a head, rigged automatically; a pen drags the arm up over the head and lets
// go. The fill stays with its outline and everything comes back to rest. (The fill was tied to
// its outline by the solver's one sewing line and turned about it: it swung half out of its
// outline and stayed there, and the legs with it. The rig now sews such a part a second time,
// away from the first line, as it sews a part the solver left untied.)
TEST(AutoRig, AFillInsetInItsOutlineStaysInItUnderAPenDrag) {
  const std::string svg = test::write_temp(
      "twin-fill.svg",
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"240\"><rect id=\"rect1\" x=\"40\" y=\"60\" width=\"80\" "
      "height=\"120\" fill=\"#000\"/><rect id=\"rect2\" x=\"44\" y=\"64\" width=\"72\" height=\"112\" fill=\"#fff\"/><rect "
      "id=\"rect3\" x=\"110\" y=\"70\" width=\"70\" height=\"16\" fill=\"#c96\"/><rect id=\"rect4\" x=\"50\" y=\"170\" "
      "width=\"16\" height=\"60\" fill=\"#c96\"/><rect id=\"rect6\" x=\"94\" y=\"170\" width=\"16\" height=\"60\" "
      "fill=\"#c96\"/><circle id=\"circle5\" cx=\"80\" cy=\"40\" r=\"22\" fill=\"#fc9\"/></svg>");
  const Rigged r = rig_of(svg);
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"rect1"});
  const std::string rig = test::write_temp("twin-fill.toml", write_auto_rig(r.ar, r.ch));
  const auto frames = pen_drag("twin-fill", rig, 200, 240, "0.85,0.32", "0.6,0.05");
  ASSERT_GE(frames.size(), 200u);
  const Points fill0 = points_of(frames.front(), "rect2"), outline0 = points_of(frames.front(), "rect1");
  ASSERT_FALSE(fill0.empty());
  ASSERT_FALSE(outline0.empty());
  auto inset = [&](const nlohmann::json& f) { return Vec2(centre_of(points_of(f, "rect2")) - centre_of(points_of(f, "rect1"))); };
  EXPECT_GT(most_moved(frames, "rect1"), 20) << "the pen swung the body";
  // (while the pen swings the body round, the sewing lets the fill slide by about 11 units;
  // before, it turned 33 units out and stayed there)
  EXPECT_LT(most_apart(frames, "rect1", "rect2"), 15.0) << "the fill does not turn out of its outline";
  EXPECT_LT((inset(frames.back()) - inset(frames.front())).norm(), 1.0) << "and it is back in place once the pen has let go";
  EXPECT_LT(end_from_rest(frames, {"rect1", "rect2", "rect3", "rect4", "rect6", "circle5"}), 0.01 * 240)
      << "back at rest once the pen has let go";
}

// An outline drawn as an open stroke of its own along an arm (three sides of it, no fill) is no
// part: it rides on the arm whole. Left in the frame it hung on one sewing line and lagged the
// arm the pen swung, and stayed where the arm had been drawn.
TEST(AutoRig, AnOutlineDrawnAsAStrokeOfItsOwnRidesOnItsPart) {
  const std::string svg = test::write_temp(
      "stroke-outline.svg",
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"240\"><rect id=\"rect1\" x=\"40\" y=\"60\" width=\"80\" "
      "height=\"120\" fill=\"#468\"/><rect id=\"rect3\" x=\"110\" y=\"70\" width=\"70\" height=\"16\" fill=\"#c96\"/>"
      "<path id=\"edge\" d=\"M112 70 L180 70 L180 86 L112 86\" fill=\"none\" stroke=\"#000\" stroke-width=\"1.5\"/>"
      "<rect id=\"rect4\" x=\"50\" y=\"170\" width=\"16\" height=\"60\" fill=\"#c96\"/><rect id=\"rect6\" x=\"94\" y=\"170\" "
      "width=\"16\" height=\"60\" fill=\"#c96\"/><circle id=\"circle5\" cx=\"80\" cy=\"40\" r=\"22\" fill=\"#fc9\"/></svg>");
  const Rigged r = rig_of(svg);
  ASSERT_EQ(r.ar.rig.solver, "feature_frame");
  const RigRider* edge = nullptr;
  for (const RigRider& d : r.ar.rig.riders)
    if (d.part == "edge") edge = &d;
  ASSERT_NE(edge, nullptr) << "the stroke rides";
  EXPECT_EQ(edge->on, "rect3") << "on the arm it outlines";
  EXPECT_TRUE(edge->handle.empty());
  const std::string rig = test::write_temp("stroke-outline.toml", write_auto_rig(r.ar, r.ch));
  const auto frames = pen_drag("stroke-outline", rig, 200, 240, "0.88,0.32", "0.75,0.05");
  ASSERT_GE(frames.size(), 200u);
  const Points edge0 = points_of(frames.front(), "edge"), arm0 = points_of(frames.front(), "rect3");
  ASSERT_FALSE(edge0.empty());
  ASSERT_FALSE(arm0.empty());
  EXPECT_GT(most_moved(frames, "rect3"), 20) << "the pen swung the arm";
  // the arm's far top corner (the frame may add points to its outline: found by where it is)
  size_t corner = 0;
  for (size_t i = 0; i < arm0.size(); ++i)
    if ((arm0[i] - Vec2(180, 70)).norm() < (arm0[corner] - Vec2(180, 70)).norm()) corner = i;
  ASSERT_LT((arm0[corner] - Vec2(180, 70)).norm(), 1e-6);
  ASSERT_LT((edge0[1] - Vec2(180, 70)).norm(), 1e-6);
  double bent = 0, off = 0;
  for (const nlohmann::json& f : frames) {
    const Points e = points_of(f, "edge"), a = points_of(f, "rect3");
    ASSERT_EQ(e.size(), edge0.size());
    ASSERT_EQ(a.size(), arm0.size());
    bent = std::max(bent, rigid_fit_rms(edge0, e));
    off = std::max(off, (e[1] - a[corner]).norm());  // the edge's far corner on the arm's
  }
  EXPECT_LT(bent, 0.01) << "it turns whole (to the dump's rounding)";
  EXPECT_LT(off, 2.0) << "and stays on the arm's end";
  EXPECT_LT(end_from_rest(frames, {"rect1", "rect3", "edge", "rect4", "rect6", "circle5"}), 0.01 * 240) << "back at rest once the pen has let go";
}

// A bundle of strokes half on a part and half off it (the cat's whiskers: one path of four
// strokes, each from its muzzle outwards) rides on the part holding most of it. Left in the
// frame once the muzzle rode, they were sewn to whatever was nearest and a head tilt bent them
// (the pose-quality benchmark's cat: 0.72 % of its height).
TEST(AutoRig, StrokesHalfOnAPartRideOnIt) {
  const std::string file = (test::characters_dir() / "cat.svg").string();
  auto ch = load_character(file);
  ASSERT_TRUE(ch.ok()) << ch.error;
  const AutoRig ar = auto_rig(*ch.value, file);
  const RigRider* whiskers = nullptr;
  for (const RigRider& d : ar.rig.riders)
    if (d.part == "path887") whiskers = &d;
  ASSERT_NE(whiskers, nullptr) << "the whiskers ride";
  EXPECT_EQ(whiskers->on, "circle877") << "on the head";
}

// A part attached to nothing (a pictogram's head drawn apart from its shoulders) with no handle
// rides whole on the part nearest it. Held by one sewing line it turned and grew about that
// line's end: a clip-art woman's head swelled to eight times the drawing's height.
TEST(AutoRig, APartAttachedToNothingRidesWholeOnItsNearest) {
  const std::string svg = test::write_temp(
      "loose-head.svg",
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"240\"><path id=\"skirt\" d=\"M70 120 L130 120 L150 200 "
      "L50 200 Z\" fill=\"#222\"/><rect id=\"torso\" x=\"70\" y=\"62\" width=\"60\" height=\"60\" fill=\"#222\"/><circle "
      "id=\"disc\" cx=\"100\" cy=\"32\" r=\"22\" fill=\"#222\"/></svg>");
  auto ch = load_character(svg);
  ASSERT_TRUE(ch.ok()) << ch.error;
  AutoRigOptions parts_only;
  parts_only.silhouette = false;
  const AutoRig ar = auto_rig(*ch.value, svg, "", parts_only);
  const RigRider* disc = nullptr;
  for (const RigRider& d : ar.rig.riders)
    if (d.part == "disc") disc = &d;
  ASSERT_NE(disc, nullptr) << "the head drawn apart rides";
  EXPECT_EQ(disc->on, "torso") << "on the part nearest it";
  EXPECT_TRUE(disc->handle.empty());
  EXPECT_NEAR(disc->at.y(), 58, 1.0) << "about the middle of the gap";
  const std::string rig = test::write_temp("loose-head.toml", write_auto_rig(ar, *ch.value));
  const auto frames = pen_drag("loose-head", rig, 200, 240, "0.5,0.38", "0.85,0.2");
  ASSERT_GE(frames.size(), 200u);
  const Points disc0 = points_of(frames.front(), "disc");
  ASSERT_FALSE(disc0.empty());
  EXPECT_GT(most_moved(frames, "torso"), 20) << "the pen moved the torso";
  auto gap = [](const Points& d, const Points& t) { return ring_distance(d, t); };
  const double gap0 = gap(disc0, points_of(frames.front(), "torso"));
  double bent = 0, off = 0;
  for (const nlohmann::json& f : frames) {
    const Points d = points_of(f, "disc");
    ASSERT_EQ(d.size(), disc0.size());
    bent = std::max(bent, rigid_fit_rms(disc0, d));
    off = std::max(off, std::abs(gap(d, points_of(f, "torso")) - gap0));
  }
  EXPECT_LT(bent, 0.01) << "it keeps its shape and size (to the dump's rounding)";
  EXPECT_LT(off, 2.0) << "and its gap to the torso";
  EXPECT_LT(end_from_rest(frames, {"skirt", "torso", "disc"}), 0.01 * 240) << "back at rest once the pen has let go";
}

// A creature whose left leg is a group of two pieces side by side (its light and its shaded
// half, as artists draw a limb's light and shade), inside a group of the whole creature in a
// layer, with two eyes in a group of their own. The leg's group makes one region: one part, one
// limb, not two limbs hinged down its length; its halves stay together under a pen drag. The
// eyes' group is two regions and the creature's group most of the drawing: neither is one part.
// (A layer is none either: the robot's back layer holds its arms and legs.)
TEST(AutoRig, AGroupWhosePiecesMakeOneRegionIsOnePart) {
  const std::string svg = test::write_temp(
      "group-leg.svg",
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"240\"><g id=\"layer1\"><g id=\"g1\">"
      "<ellipse id=\"ellipse1\" cx=\"100\" cy=\"120\" rx=\"60\" ry=\"45\" fill=\"#8a6\"/>"
      "<g id=\"g2\"><rect id=\"rect1\" x=\"62\" y=\"150\" width=\"9\" height=\"80\" fill=\"#c96\"/>"
      "<rect id=\"rect2\" x=\"71\" y=\"150\" width=\"10\" height=\"80\" fill=\"#a74\"/></g>"
      "<rect id=\"rect3\" x=\"120\" y=\"150\" width=\"19\" height=\"80\" fill=\"#c96\"/>"
      "<circle id=\"circle1\" cx=\"100\" cy=\"50\" r=\"30\" fill=\"#fc9\"/>"
      "<g id=\"g3\"><circle id=\"circle2\" cx=\"90\" cy=\"45\" r=\"4\" fill=\"#000\"/>"
      "<circle id=\"circle3\" cx=\"110\" cy=\"45\" r=\"4\" fill=\"#000\"/></g></g></g></svg>");
  const Rigged r = rig_of(svg);
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"ellipse1"});
  const std::set<std::string> limbs = ids_of(r, AutoRigPart::Limb);
  EXPECT_EQ(limbs.count("rect1") + limbs.count("rect2"), 1u) << "the leg's two halves are one limb";
  EXPECT_EQ(limbs.count("rect3"), 1u);
  EXPECT_EQ(limbs.size(), 2u);
  const std::set<std::string> details = ids_of(r, AutoRigPart::Detail);
  EXPECT_EQ(details.count("rect1") + details.count("rect2"), 1u) << "the other half rides on it";
  EXPECT_TRUE(details.count("circle2") && details.count("circle3")) << "the eyes ride on the head, each";
  bool said = false;
  for (const std::string& n : r.ar.notes) said = said || n.find("1 group makes one region, one part: g2 (2 pieces") != std::string::npos;
  EXPECT_TRUE(said) << "the rig says so";
  // A pen drags the grouped leg's foot out sideways and lets go.
  const std::string rig = test::write_temp("group-leg.toml", write_auto_rig(r.ar, r.ch));
  const auto frames = pen_drag("group-leg", rig, 200, 240, "0.355,0.93", "0.1,0.8");
  ASSERT_GE(frames.size(), 200u);
  ASSERT_FALSE(points_of(frames.front(), "rect1").empty());
  EXPECT_GT(most_moved(frames, "rect1"), 10) << "the pen swung the leg";
  EXPECT_LT(most_apart(frames, "rect1", "rect2"), 3.0) << "its halves stay side by side";
  EXPECT_LT(end_from_rest(frames, {"ellipse1", "rect1", "rect2", "rect3", "circle1"}), 0.01 * 240) << "back at rest once the pen has let go";
  // The eyes ride on the head whole ([[rider]] of the feature frame): never bent, in any frame.
  const std::string text = write_auto_rig(r.ar, r.ch);
  EXPECT_NE(text.find("[[rider]]\npart = \"circle2\"\non = \"circle1\""), std::string::npos) << text;
  const Points eye0 = points_of(frames.front(), "circle2");
  ASSERT_GE(eye0.size(), 3u);
  double bent = 0;
  for (const nlohmann::json& f : frames) bent = std::max(bent, rigid_fit_rms(eye0, points_of(f, "circle2")));
  EXPECT_LT(bent, 1e-3) << "an eye is carried whole";
}

// Parts and silhouette region by region: a figure whose arms are parts of their own and whose
// legs are inside its body's one shape. The silhouette gives the legs, so the grid poses it; the
// arms ride on the grid whole, each turning at its drawn shoulder, and only the legs bend in
// the grid. A pen swings an arm: it stays rigid and on its shoulder and the body does not move
// (the grid bent the arm, and the body under it, before); a pen swings a leg: it bends at its
// hip. Both come back to rest.
TEST(AutoRig, PartsAndSilhouetteAreChosenRegionByRegion) {
  const std::string svg = test::write_temp(
      "regions.svg",
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"240\"><path id=\"path1\" fill=\"#468\" "
      "d=\"M60 60 L140 60 L140 230 L112 230 L112 130 L88 130 L88 230 L60 230 Z\"/>"
      "<rect id=\"rect1\" x=\"132\" y=\"64\" width=\"60\" height=\"14\" fill=\"#c96\"/>"
      "<rect id=\"rect2\" x=\"8\" y=\"64\" width=\"60\" height=\"14\" fill=\"#c96\"/>"
      "<circle id=\"circle1\" cx=\"100\" cy=\"34\" r=\"24\" fill=\"#fc9\"/></svg>");
  const Rigged r = rig_of(svg);
  ASSERT_EQ(r.ar.rig.solver, "rigid_grid") << "the legs are the silhouette's";
  std::map<std::string, const RigRider*> riders;
  for (const RigRider& d : r.ar.rig.riders) riders[d.part] = &d;
  ASSERT_TRUE(riders.count("rect1") && riders.count("rect2")) << "the arms ride";
  EXPECT_FALSE(riders.count("path1")) << "the body is the grid's";
  ASSERT_TRUE(riders.count("circle1")) << "the head, drawn a little above the body (off its region), rides on it";
  EXPECT_TRUE(riders["circle1"]->handle.empty());
  EXPECT_EQ(riders["circle1"]->on, "path1");
  for (const char* arm : {"rect1", "rect2"}) {
    EXPECT_FALSE(riders[arm]->handle.empty()) << arm << " turns toward its handle";
    EXPECT_GT(riders[arm]->at.x(), 56) << arm << ": hinged at its shoulder, inside the body";
    EXPECT_LT(riders[arm]->at.x(), 144) << arm;
  }
  int legs = 0;
  for (const AutoRigPart& p : r.ar.parts) legs += p.kind == AutoRigPart::Limb && !riders.count(r.ch.shapes[size_t(p.shape)].id);
  EXPECT_EQ(legs, 2) << "two legs from the silhouette";
  bool said = false;
  for (const std::string& n : r.ar.notes) said = said || n.find("region by region") != std::string::npos;
  EXPECT_TRUE(said) << "the rig says so";
  const std::string rig = test::write_temp("regions.toml", write_auto_rig(r.ar, r.ch));
  auto loaded = load_rig(rig);
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  EXPECT_EQ(loaded.value->riders.size(), r.ar.rig.riders.size());

  // The right arm's hand, swung up.
  const auto arm = pen_drag("regions-arm", rig, 200, 240, "0.93,0.3", "0.75,0.02");
  ASSERT_GE(arm.size(), 200u);
  ASSERT_FALSE(points_of(arm.front(), "rect1").empty());
  EXPECT_GT(most_moved(arm, "rect1"), 20) << "the pen swung the arm";
  double bent = 0, shoulder = 0;
  const Points arm0 = points_of(arm.front(), "rect1");
  const Vec2 hinge = riders["rect1"]->at;
  for (const nlohmann::json& f : arm) {
    const Points now = points_of(f, "rect1");
    ASSERT_EQ(now.size(), arm0.size());
    bent = std::max(bent, rigid_fit_rms(arm0, now));
    // where its hinge went: the turn of its top edge, about its first corner
    shoulder = std::max(shoulder, (now[0] + turned_as(arm0[1] - arm0[0], now[1] - now[0], hinge - arm0[0]) - hinge).norm());
  }
  EXPECT_LT(bent, 0.01) << "it turns whole (to the dump's rounding)";
  EXPECT_LT(shoulder, 0.5) << "about its shoulder, which stays on the body";
  EXPECT_LT(most_moved(arm, "path1"), 0.5) << "and the body stays";
  EXPECT_LT(end_from_rest(arm, {"path1", "rect1", "rect2", "circle1"}), 0.01 * 240) << "back at rest once the pen has let go";

  // The left leg's foot, swung out.
  const auto leg = pen_drag("regions-leg", rig, 200, 240, "0.37,0.94", "0.1,0.85");
  ASSERT_GE(leg.size(), 200u);
  double foot = 0, top = 0, head = 0;
  const Points body0 = points_of(leg.front(), "path1");
  const Vec2 neck0 = centre_of(points_of(leg.front(), "circle1")) - 0.5 * (body0[0] + body0[1]);
  for (const nlohmann::json& f : leg) {
    const Points now = points_of(f, "path1");
    ASSERT_EQ(now.size(), body0.size());
    foot = std::max(foot, (now[7] - body0[7]).norm());                        // (the left leg's outer foot corner)
    top = std::max(top, (now[0] + now[1] - body0[0] - body0[1]).norm() / 2);  // (the shoulders)
    const Vec2 neck = turned_as(body0[1] - body0[0], now[1] - now[0], neck0);  // (as the shoulders' edge turned)
    head = std::max(head, (centre_of(points_of(f, "circle1")) - 0.5 * (now[0] + now[1]) - neck).norm());
  }
  EXPECT_GT(foot, 15) << "the leg swings inside the body's shape";
  EXPECT_LT(top, 0.5 * foot) << "at its hip: the shoulders move far less";
  EXPECT_LT(head, 2.0) << "and the head stays on its shoulders";
  EXPECT_LT(end_from_rest(leg, {"path1", "rect1", "rect2", "circle1"}), 0.01 * 240) << "back at rest once the pen has let go";
}

// A file of many small shapes (here 1,200 squares apart) is rigged on its 1,000 biggest: the
// rig weighs every pair of parts, and 140,000 ran it out of memory. It says so.
TEST(AutoRig, AtMostTheThousandBiggestShapesAreParts) {
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1200\" height=\"1200\">";
  for (int k = 0; k < 1200; ++k)
    svg += "<rect x=\"" + std::to_string((k % 40) * 30) + "\" y=\"" + std::to_string((k / 40) * 40) + "\" width=\"" +
           std::to_string(k < 200 ? 8 : 10) + "\" height=\"10\"/>";
  svg += "</svg>";
  const Rigged r = rig_of(test::write_temp("many.svg", svg));
  EXPECT_EQ(r.ar.parts.size(), 1000u);
  for (const AutoRigPart& p : r.ar.parts) EXPECT_GE(p.shape, 200) << "a smaller square is a part";
  bool said = false;
  for (const std::string& n : r.ar.notes) said = said || n.find("200 small filled shapes are not parts (only the 1000 biggest are)") != std::string::npos;
  EXPECT_TRUE(said);
}

// A head of hair drawn in twenty strokes: the eight longest are limbs with handles, not twenty.
TEST(AutoRig, AHeadOfHairInManyStrokesGivesEightStrandsNotAll) {
  std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"200\">"
                    "<circle id=\"circle1\" cx=\"100\" cy=\"120\" r=\"50\" fill=\"#fc9\"/>";
  for (int k = 0; k < 20; ++k)
    svg += "<path d=\"M" + std::to_string(60 + 4 * k) + " 80 l" + std::to_string(k % 5 - 2) + " -" + std::to_string(20 + k) +
           "\" stroke=\"#420\" stroke-width=\"2\" fill=\"none\"/>";
  svg += "</svg>";
  const Rigged r = rig_of(test::write_temp("hair.svg", svg));
  int strands = 0;
  double shortest = 1e9;
  for (const AutoRigPart& p : r.ar.parts)
    if (p.kind == AutoRigPart::Limb && !r.ch.shapes[size_t(p.shape)].fill.enabled) {
      ++strands;
      shortest = std::min(shortest, r.ch.shapes[size_t(p.shape)].bounds().hi.y() - r.ch.shapes[size_t(p.shape)].bounds().lo.y());
    }
  EXPECT_EQ(strands, 8);
  EXPECT_GE(shortest, 31) << "the longest eight (20 + 12 and up)";
  // and drawn as 24 thin filled locks: the 16 biggest are limbs, the others ride on the head
  std::string filled = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"200\">"
                       "<circle id=\"circle1\" cx=\"100\" cy=\"120\" r=\"50\" fill=\"#fc9\"/>";
  for (int k = 0; k < 24; ++k)
    filled += "<rect x=\"" + std::to_string(54 + 4 * k) + "\" y=\"" + std::to_string(50 - k) + "\" width=\"3\" height=\"" +
              std::to_string(30 + k) + "\" fill=\"#420\"/>";
  filled += "</svg>";
  const Rigged f = rig_of(test::write_temp("hair-filled.svg", filled));
  EXPECT_EQ(ids_of(f, AutoRigPart::Limb).size(), 16u);
}

TEST(AutoRig, NameWordsSplitsCaseAndSeparators) {
  EXPECT_EQ(name_words("armRight_2"), (std::vector<std::string>{"arm", "right", "2"}));
  EXPECT_EQ(name_words("Left Ear"), (std::vector<std::string>{"left", "ear"}));
  EXPECT_EQ(name_words("mouth-Ah"), (std::vector<std::string>{"mouth", "ah"}));
}

// `marionette rig CHARACTER -o RIG` writes a rig `pose` then uses as is.
TEST(AutoRig, TheCommandWritesARigThatPoses) {
  const auto dir = test::temp_dir("rig-cmd");
  const std::string rig = (dir / "boy.toml").string(), png = (dir / "boy.png").string();
  auto r = test::run_cli("rig '" + (test::characters_dir() / "boy.svg").string() + "' -o '" + rig + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("8 hinges"), std::string::npos) << r.out;  // seven limbs and the neck
  EXPECT_FALSE(std::filesystem::exists(rig + ".tmp"));
  auto p = test::run_cli("pose '" + (test::characters_dir() / "boy.svg").string() + "' --rig '" + rig +
                         "' --target hand-right=230,120 -o '" + png + "'");
  ASSERT_EQ(p.exit_code, 0) << p.err;
  EXPECT_TRUE(std::filesystem::exists(png));
  auto bad = test::run_cli("rig '" + (dir / "missing.svg").string() + "' -o '" + (dir / "x.toml").string() + "'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("missing.svg"), std::string::npos) << bad.err;
}

// `rig` says what it found, a line a limb with its hinge and handle, and `--preview` draws it:
// the parts tinted, hinges purple, handles green, a legend below. A drawing with nothing to rig
// is refused with why and what to change (exit 2), and writes no rig.
TEST(AutoRig, TheCommandSaysWhatItFoundAndDrawsIt) {
  const auto dir = test::temp_dir("rig-preview");
  const std::string rig = (dir / "figure.toml").string(), png = (dir / "figure.png").string();
  auto r = test::run_cli("rig '" + (test::characters_dir() / "figure.svg").string() + "' -o '" + rig + "' --preview '" + png + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("body: torso"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("limb arm-left on torso: hinge at ("), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("head: face"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("details ride on their parts"), std::string::npos) << r.out;
  auto img = read_png_image(png);
  ASSERT_TRUE(img.ok()) << img.error;
  EXPECT_GE(img.value->width, 640);
  size_t green = 0, purple = 0, blue = 0;
  for (size_t k = 0; k + 3 < img.value->rgba.size(); k += 4) {
    const int R = img.value->rgba[k], G = img.value->rgba[k + 1], B = img.value->rgba[k + 2];
    green += G > 140 && R < 80 && B < 130;   // a handle
    purple += R > 110 && R < 170 && G < 90 && B > 170;  // a hinge
    blue += B > 120 && R < 120 && G < 120 && B > R + 40;  // the body's tint and outline
  }
  EXPECT_GT(green, 5u * 40) << "five handles or more, as discs";
  EXPECT_GT(purple, 4u * 20) << "the hinges";
  EXPECT_GT(blue, 2000u) << "the body";
  const std::string strokes = test::write_temp("only-lines.svg",
                                               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"50\" height=\"50\">"
                                               "<path d=\"M5 5 L45 45\" stroke=\"black\" fill=\"none\"/></svg>");
  auto none = test::run_cli("rig '" + strokes + "' -o '" + (dir / "none.toml").string() + "'");
  EXPECT_EQ(none.exit_code, 2);
  EXPECT_NE(none.err.find("only-lines.svg: nothing to rig"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("filled shape"), std::string::npos) << none.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "none.toml"));
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// `rig --show SHOW --device D`: a starter show that runs at once with the device's simulator
// and moves the character, for every device there is a starter for.
TEST(StarterShow, EveryDeviceRunsAndMovesTheCharacter) {
  for (const char* device : {"nanokontrol2", "gamepad", "pen_tablet", "knob_box"}) {
    const auto dir = test::temp_dir(std::string("starter-") + device);
    const std::string rig = (dir / "boy.toml").string(), show = (dir / "show.toml").string();
    auto r = test::run_cli("rig '" + (test::characters_dir() / "boy.svg").string() + "' -o '" + rig + "' --show '" + show + "' --device " + device);
    ASSERT_EQ(r.exit_code, 0) << device << ": " << r.err;
    auto run = test::run_cli("run '" + show + "' --headless --frames 121 --dump-frames '" + (dir / "f").string() + "' --every 40");
    ASSERT_EQ(run.exit_code, 0) << device << ": " << run.err;
    EXPECT_EQ(run.err.find("warning"), std::string::npos) << device << ": " << run.err;
    auto first = read_png_image((dir / "f" / "frame_000000.png").string()), later = read_png_image((dir / "f" / "frame_000080.png").string());
    ASSERT_TRUE(first.ok() && later.ok()) << device;
    const ImageDiff d = compare_images(*first.value, *later.value, 16);
    EXPECT_GT(d.differing_share(), 0.005) << device << ": the character should have moved";
  }
}

// Swap sets and triggers go on buttons; an unknown device is refused naming the ones there are;
// a show needs the rig written beside it.
TEST(StarterShow, ButtonsSwapAndTriggerAndBadArgumentsAreRefused) {
  const auto dir = test::temp_dir("starter-singer");
  const std::string rig = (dir / "singer.toml").string(), show = (dir / "show.toml").string();
  const std::string ch = (test::characters_dir() / "singer.svg").string();
  auto r = test::run_cli("rig '" + ch + "' -o '" + rig + "' --show '" + show + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(show);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("target = \"trigger.blink\""), std::string::npos) << text;
  EXPECT_NE(text.find("target = \"swap.mouth.mouth-a\""), std::string::npos) << text;
  EXPECT_NE(text.find("rig = \"singer.toml\""), std::string::npos) << "the rig, relative to the show";
  auto run = test::run_cli("run '" + show + "' --headless --frames 60");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  auto bad = test::run_cli("rig '" + ch + "' -o '" + rig + "' --show '" + show + "' --device theremin");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("knob_box"), std::string::npos) << bad.err;
  auto no_rig = test::run_cli("rig '" + ch + "' --show '" + show + "'");
  EXPECT_EQ(no_rig.exit_code, 2);
  EXPECT_NE(no_rig.err.find("-o"), std::string::npos) << no_rig.err;
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// A plain rig (handles only) turns its limbs at the drawn joints: the robot's hand rig states no
// joint, and its right hand reaches a target turned 90 and 160 degrees about the shoulder with
// the forearm kept in shape. (The middle of the overlap and the torso's grip on the forearm it
// touches used to leave the hand 3-7% of the height short and the forearm bent.)
TEST(DrawnJoints, APlainRigReachesWhatItsLimbsCanReach) {
  auto p = load_puppet("", (test::source_dir() / "config/rigs/robot.toml").string());
  ASSERT_TRUE(p.ok()) << p.error;
  Puppet& pup = **p.value;
  EXPECT_GE(pup.rig.joints.size(), 6u) << "shoulders, elbows, hips, neck from the drawing";
  const int hand = pup.rig.find_handle("right-hand");
  ASSERT_GE(hand, 0);
  const Vec2 shoulder(213, 160);
  int forearm = -1;
  for (size_t s = 0; s < pup.character.shapes.size(); ++s)
    if (pup.character.shapes[s].id == "rect109") forearm = int(s);
  ASSERT_GE(forearm, 0);
  for (double deg : {-90.0, -160.0}) {
    std::vector<Vec2> t = pup.rest_targets();
    const double a = deg * M_PI / 180;
    const Vec2 d = t[size_t(hand)] - shoulder;
    t[size_t(hand)] = shoulder + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(), std::sin(a) * d.x() + std::cos(a) * d.y());
    pup.solver->reset_to_rest();
    pup.solver->initial_guess(t);
    pup.solver->solve(t, pup.rig.iterations);
    pup.reconstruct();
    const double h = pup.character.height;
    EXPECT_LE((pup.solver->handle_point(size_t(hand)) - t[size_t(hand)]).norm(), 0.005 * h) << deg;
    EXPECT_LE(rigid_fit_rms(pup.character.shapes[size_t(forearm)].points, pup.shapes[size_t(forearm)]), 0.005 * h) << deg;
  }
}

// `joints = "none"` keeps a rig exactly as written; joints a rig states win over the drawing's.
TEST(DrawnJoints, ARigThatSaysNoneOrStatesItsOwnKeepsThem) {
  const std::string robot = (test::characters_dir() / "robot.svg").string();
  const std::string none = test::write_temp("robot-none.toml", "character = \"" + robot + "\"\n[feature_frame]\njoints = \"none\"\n[[handle]]\nname = \"h\"\nrest = [213.0, 266.0]\n");
  auto p = load_puppet("", none);
  ASSERT_TRUE(p.ok()) << p.error;
  EXPECT_TRUE((*p.value)->rig.joints.empty());
  EXPECT_TRUE((*p.value)->rig.sewing.empty());
  auto boy = load_puppet("", (test::source_dir() / "config/rigs/boy.toml").string());
  ASSERT_TRUE(boy.ok()) << boy.error;
  int wrists = 0;
  for (const RigJoint& j : (*boy.value)->rig.joints)
    if (j.part_a == "hand-right" || j.part_a == "hand-left") {
      ++wrists;
      EXPECT_TRUE(j.weld) << "the boy's rig welds its mittens; the drawing's wrist hinge does not replace that";
    }
  EXPECT_EQ(wrists, 2);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// A cap drawn edge to edge with its body, half a unit off its straight cut and not quite
// parallel to it (a ladybug's head on its back, as clip art draws it): where they meet is the
// whole edge, not the end of it that comes nearest. Hinged at that end, the head turned about
// its corner and opened a wedge of background between them.
TEST(AutoRig, ACapDrawnEdgeToEdgeWithItsBodyMeetsItAlongTheEdgeNotAtACorner) {
  const std::string svg = R"(<svg xmlns="http://www.w3.org/2000/svg" width="130" height="130" viewBox="0 0 130 130">
  <path id="back" d="M 60,40 L 100,80 C 100,140 20,160 10,110 C 0,70 40,40 60,40 z" fill="#d22"/>
  <path id="head" d="M 61.06,40.35 L 99.47,79.12 Q 111,29 61.06,40.35 z" fill="#531"/>
  <rect id="leg" x="-20" y="100" width="32" height="6" fill="#111"/>
</svg>)";
  const std::string path = test::write_temp("cap.svg", svg);
  const Rigged r = rig_of(path);
  EXPECT_EQ(ids_of(r, AutoRigPart::Body), std::set<std::string>{"back"});
  const Vec2 a(60, 40), b(100, 80), mid = (a + b) / 2;
  const double edge = (b - a).norm();
  bool head_joint = false;
  for (const RigJoint& j : r.ar.rig.joints) {
    if (j.part_a != "head" && j.part_b != "head") continue;
    head_joint = true;
    EXPECT_LT((j.at - mid).norm(), 0.25 * edge) << "the head turns about (" << j.at.x() << ", " << j.at.y() << "), near a corner of the edge it meets";
  }
  for (const AutoRigPart& p : r.ar.parts)
    if (r.ch.shapes[size_t(p.shape)].id == "head") {
      EXPECT_NE(p.kind, AutoRigPart::Limb) << "attached along its side, not at one end: " << p.why;
      EXPECT_TRUE(head_joint || p.kind != AutoRigPart::Head) << "a head hinges somewhere";
    }
  loads(r, "cap");
}

}  // namespace
}  // namespace mar
