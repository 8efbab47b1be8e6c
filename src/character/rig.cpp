#include "character/rig.h"

#include "base/config_toml.h"
#include "base/read_file.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace mar {

Rig default_rig() { return Rig{}; }

std::string Rig::beside(const std::string& file) const {
  const std::filesystem::path c(file);
  if (c.is_absolute()) return file;
  return (std::filesystem::path(path).parent_path() / c).lexically_normal().string();
}

std::string Rig::character_path() const { return beside(character); }

std::string Rig::mask_path() const { return mask.empty() ? "" : beside(mask); }

int Rig::find_handle(const std::string& name) const {
  for (size_t i = 0; i < handles.size(); ++i) {
    if (handles[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

using namespace cfg;
using RigError = ConfigError;

// [[physics]] (rig_physics.cpp).
void parse_rig_physics(const std::string& path, const toml::node& n, Rig& r);

namespace {

// Swap sets and triggers name sub-shapes; load_puppet checks them against the character.
std::vector<std::string> id_list(const std::string& path, const toml::node& n, const char* what) {
  std::vector<std::string> ids;
  const toml::array* a = n.as_array();
  if (!a || a->empty()) throw RigError{at(path, n) + ": " + what + " must be a list of sub-shape ids, [\"a\", \"b\"]"};
  for (const toml::node& e : *a) {
    if (!e.is_string() || e.value<std::string>()->empty())
      throw RigError{at(path, e) + ": " + what + " must be a list of sub-shape ids, [\"a\", \"b\"]"};
    ids.push_back(*e.value<std::string>());
  }
  return ids;
}

// A swap set's or trigger's name: given, and not taken by another.
std::string named(const std::string& path, const Rig& r, const toml::table& t, const toml::node& node, const char* what) {
  const toml::node* nm = t.get("name");
  if (!nm || !nm->is_string() || nm->value<std::string>()->empty()) throw RigError{at(path, node) + ": " + what + " needs a name"};
  const std::string name = *nm->value<std::string>();
  for (const RigSwap& o : r.swaps)
    if (o.name == name) throw RigError{at(path, node) + ": '" + name + "' is already a swap set"};
  for (const RigTrigger& o : r.triggers)
    if (o.name == name) throw RigError{at(path, node) + ": '" + name + "' is already a trigger"};
  return name;
}

// The rig's `weights` (its [[weights]] tables, or its [weights] table).
void read_weights(const std::string& path, const toml::node* w, Rig& r) {
  const toml::table* t = w->as_table();
  if (!t) throw RigError{at(path, *w) + ": [weights] must be a table"};
  check_keys(path, *t, {"rigidity", "coupling", "position"}, "[weights]");
  auto get = [&](const char* k, double& out) {
    if (const toml::node* n = t->get(k)) {
      out = number(path, *n, k);
      if (out < 0) throw RigError{at(path, *n) + ": " + k + " must not be negative"};
    }
  };
  get("rigidity", r.w_rigidity);
  get("coupling", r.w_coupling);
  get("position", r.w_position);
  if (r.w_coupling <= 0) throw RigError{at(path, *w) + ": coupling must be positive (it holds the parts together)"};
}

// The rig's `sampling` (its [[sampling]] tables, or its [sampling] table).
void read_sampling(const std::string& path, const toml::node* s, Rig& r) {
  const toml::table* t = s->as_table();
  if (!t) throw RigError{at(path, *s) + ": [sampling] must be a table"};
  check_keys(path, *t, {"mode", "interval"}, "[sampling]");
  if (const toml::node* m = t->get("mode")) {
    const std::string mode = m->value<std::string>().value_or("");
    if (mode == "uniform") {
      r.uniform_sampling = true;
    } else if (mode != "features") {
      throw RigError{at(path, *m) + ": sampling mode must be \"features\" or \"uniform\""};
    }
  }
  if (const toml::node* i = t->get("interval")) {
    r.interval = number(path, *i, "interval");
    if (r.interval <= 0) throw RigError{at(path, *i) + ": interval must be positive"};
  }
}

// The rig's `handle` (its [[handle]] tables, or its [handle] table).
void read_handle(const std::string& path, const toml::node* hs, Rig& r) {
  std::set<std::string> names;
  const toml::array* a = hs->as_array();
  if (!a) throw RigError{at(path, *hs) + ": use [[handle]] tables"};
  for (const toml::node& hn : *a) {
    const toml::table* t = hn.as_table();
    if (!t) throw RigError{at(path, hn) + ": a handle must be a table"};
    check_keys(path, *t, {"name", "rest"}, "[[handle]]");
    RigHandle h;
    const toml::node* name = t->get("name");
    if (!name || !name->is_string() || name->value<std::string>()->empty()) {
      throw RigError{at(path, hn) + ": a handle needs a non-empty name"};
    }
    h.name = *name->value<std::string>();
    if (!names.insert(h.name).second) throw RigError{at(path, *name) + ": handle '" + h.name + "' defined twice"};
    const toml::node* rest = t->get("rest");
    if (!rest) throw RigError{at(path, hn) + ": handle '" + h.name + "' needs rest = [x, y]"};
    h.rest = point(path, *rest, "rest");
    r.handles.push_back(std::move(h));
  }
}

// The rig's `sewing` (its [[sewing]] tables, or its [sewing] table).
void read_sewing(const std::string& path, const toml::node* ss, Rig& r) {
  const toml::array* a = ss->as_array();
  if (!a) throw RigError{at(path, *ss) + ": use [[sewing]] tables"};
  for (const toml::node& sn : *a) {
    const toml::table* t = sn.as_table();
    if (!t) throw RigError{at(path, sn) + ": a sewing edit must be a table"};
    check_keys(path, *t, {"action", "from", "to", "new_from", "new_to"}, "[[sewing]]");
    RigSewing e;
    e.line = static_cast<int>(sn.source().begin.line);
    const std::string action = t->get("action") ? t->get("action")->value<std::string>().value_or("") : "add";
    if (action == "add") {
      e.action = RigSewing::Add;
    } else if (action == "delete") {
      e.action = RigSewing::Delete;
    } else if (action == "move") {
      e.action = RigSewing::Move;
    } else {
      throw RigError{at(path, sn) + ": sewing action must be add, delete or move"};
    }
    const toml::node* from = t->get("from");
    const toml::node* to = t->get("to");
    if (!from || !to) throw RigError{at(path, sn) + ": sewing edit needs from = [x, y] and to = [x, y]"};
    e.from = point(path, *from, "from");
    e.to = point(path, *to, "to");
    if (e.action == RigSewing::Move) {
      const toml::node* nf = t->get("new_from");
      const toml::node* nt = t->get("new_to");
      if (!nf || !nt) throw RigError{at(path, sn) + ": move needs new_from = [x, y] and new_to = [x, y]"};
      e.new_from = point(path, *nf, "new_from");
      e.new_to = point(path, *nt, "new_to");
    }
    r.sewing.push_back(e);
  }
}

// The rig's `feature_frame` (its [[feature_frame]] tables, or its [feature_frame] table).
void read_feature_frame(const std::string& path, const toml::node* sv, Rig& r) {
  const toml::table* t = sv->as_table();
  if (!t) throw RigError{at(path, *sv) + ": [feature_frame] must be a table"};
  check_keys(path, *t, {"anderson", "joints", "stiffness"}, "[feature_frame]");
  if (const toml::node* n = t->get("anderson")) {
    const auto v = cfg::whole(*n);
    if (!v || *v < 0 || *v > 16) throw RigError{at(path, *n) + ": anderson must be a whole number 0..16"};
    r.anderson = static_cast<int>(*v);
  }
  auto mode = [&](const char* key, bool& out) {
    if (const toml::node* n = t->get(key)) {
      const std::string m = n->value<std::string>().value_or("");
      if (m != "auto" && m != "none") throw RigError{at(path, *n) + ": " + key + " must be \"auto\" or \"none\""};
      out = m == "auto";
    }
  };
  mode("joints", r.auto_joints);
  mode("stiffness", r.auto_stiffness);
}

// The rig's `joint` (its [[joint]] tables, or its [joint] table).
void read_joint(const std::string& path, const toml::node* js, Rig& r) {
  const toml::array* a = js->as_array();
  if (!a) throw RigError{at(path, *js) + ": use [[joint]] tables"};
  for (const toml::node& jn : *a) {
    const toml::table* t = jn.as_table();
    if (!t) throw RigError{at(path, jn) + ": a joint must be a table"};
    check_keys(path, *t, {"at", "parts", "stiffness", "kind"}, "[[joint]]");
    RigJoint j;
    j.line = static_cast<int>(jn.source().begin.line);
    if (const toml::node* n = t->get("at")) {
      j.at = point(path, *n, "at");
      j.has_at = true;
    }
    if (const toml::node* n = t->get("parts")) {
      const toml::array* pa = n->as_array();
      if (!pa || pa->size() != 2 || !pa->get(0)->is_string() || !pa->get(1)->is_string()) {
        throw RigError{at(path, *n) + ": parts must be two sub-shape ids, [\"a\", \"b\"]"};
      }
      j.part_a = *pa->get(0)->value<std::string>();
      j.part_b = *pa->get(1)->value<std::string>();
    }
    if (const toml::node* n = t->get("stiffness")) {
      j.stiffness = number(path, *n, "stiffness");
      if (j.stiffness < 0) throw RigError{at(path, *n) + ": stiffness must not be negative"};
    }
    if (const toml::node* n = t->get("kind")) {
      const std::string k = n->value<std::string>().value_or("");
      if (k != "hinge" && k != "weld") throw RigError{at(path, *n) + ": kind must be \"hinge\" or \"weld\""};
      j.weld = k == "weld";
    }
    if (j.weld && j.part_a.empty()) throw RigError{at(path, jn) + ": a weld needs parts = [\"a\", \"b\"]"};
    if (!j.has_at && j.part_a.empty()) throw RigError{at(path, jn) + ": a joint needs at = [x, y] or parts = [\"a\", \"b\"]"};
    r.joints.push_back(j);
  }
}

// The rig's `rider` (its [[rider]] tables): parts riding whole on the rigid grid, or on a part
// of the feature frame.
void read_rider(const std::string& path, const toml::node* rs, Rig& r) {
  const toml::array* a = rs->as_array();
  if (!a) throw RigError{at(path, *rs) + ": use [[rider]] tables"};
  // (on the rigid grid each rider's sweep weighs the handles of all that hangs on it: a chain of
  // n costs n² a frame, so 256 there (below); on the feature frame a rider costs its own points
  // and 64 of its part's: a head of hair in hundreds of pieces)
  if (a->size() > 4096) throw RigError{at(path, *rs) + ": at most 4096 riders"};
  auto text = [&](const toml::table& t, const char* key) -> std::string {
    const toml::node* n = t.get(key);
    if (!n) return {};
    if (!n->is_string() || n->value<std::string>()->empty()) throw RigError{at(path, *n) + ": " + key + " must be a sub-shape id or handle name"};
    return *n->value<std::string>();
  };
  for (const toml::node& rn : *a) {
    const toml::table* t = rn.as_table();
    if (!t) throw RigError{at(path, rn) + ": a rider must be a table"};
    check_keys(path, *t, {"part", "on", "at", "handle", "with", "still"}, "[[rider]]");
    RigRider d;
    d.line = static_cast<int>(rn.source().begin.line);
    d.part = text(*t, "part");
    d.on = text(*t, "on");
    d.handle = text(*t, "handle");
    if (const toml::node* st = t->get("still")) {
      if (!st->is_boolean()) throw RigError{at(path, *st) + ": still must be true or false"};
      d.still = *st->value<bool>();
    }
    const toml::node* n = t->get("at");
    if (d.still) {
      if (d.part.empty()) throw RigError{at(path, rn) + ": a rider needs part = \"sub-shape id\""};
      if (n || !d.on.empty() || !d.handle.empty())
        throw RigError{at(path, rn) + ": a still rider stays where it is drawn: it takes no on, at or handle"};
    } else {
      if (d.part.empty() || !n) throw RigError{at(path, rn) + ": a rider needs part = \"sub-shape id\" and at = [x, y] (its hinge)"};
      d.at = point(path, *n, "at");
    }
    if (const toml::node* w = t->get("with")) d.with = id_list(path, *w, "with");
    for (const RigRider& o : r.riders)
      if (o.part == d.part) throw RigError{at(path, rn) + ": part '" + d.part + "' rides twice"};
    r.riders.push_back(std::move(d));
  }
}

// The rig's `bone` (its [[bone]] tables): limbs inside one shape turning whole on the rigid grid.
// (each bone weighs every point of the drawing against its axis when the rig is prepared:
// bounded by the counts below)
void read_bone(const std::string& path, const toml::node* bs, Rig& r) {
  const toml::array* a = bs->as_array();
  if (!a) throw RigError{at(path, *bs) + ": use [[bone]] tables"};
  if (a->size() > 64) throw RigError{at(path, *bs) + ": at most 64 bones"};
  for (const toml::node& bn : *a) {
    const toml::table* t = bn.as_table();
    if (!t) throw RigError{at(path, bn) + ": a bone must be a table"};
    check_keys(path, *t, {"handle", "at", "axis", "band"}, "[[bone]]");
    RigBone b;
    b.line = static_cast<int>(bn.source().begin.line);
    if (const toml::node* h = t->get("handle")) {
      if (!h->is_string() || h->value<std::string>()->empty()) throw RigError{at(path, *h) + ": handle must be a handle name"};
      b.handle = *h->value<std::string>();
    }
    const toml::node* n = t->get("at");
    const toml::node* ax = t->get("axis");
    if (!n || !ax) throw RigError{at(path, bn) + ": a bone needs at = [x, y] (its joint) and axis = [[x, y, half-width], ...]"};
    b.at = point(path, *n, "at");
    const toml::array* pts = ax->as_array();
    if (!pts || pts->size() < 2 || pts->size() > 1024)
      throw RigError{at(path, *ax) + ": axis must be 2 to 1024 points [x, y, half-width], from the free end to the joint"};
    for (const toml::node& e : *pts) {
      const toml::array* q = e.as_array();
      if (!q || q->size() != 3) throw RigError{at(path, e) + ": an axis point must be [x, y, half-width]"};
      const double rad = number(path, *q->get(2), "a half-width");
      if (!(rad > 0)) throw RigError{at(path, e) + ": an axis point's half-width must be above 0"};
      b.axis.emplace_back(number(path, *q->get(0), "axis"), number(path, *q->get(1), "axis"));
      b.radius.push_back(rad);
    }
    if (const toml::node* bd = t->get("band")) {
      b.band = number(path, *bd, "band");
      if (b.band < 0) throw RigError{at(path, *bd) + ": band must be 0 (the half-width at the joint) or more"};
    }
    r.bones.push_back(std::move(b));
  }
  size_t points = 0;
  for (const RigBone& b : r.bones) points += b.axis.size();
  if (points > 4096) throw RigError{at(path, *bs) + ": at most 4,096 axis points in all the bones (each is weighed against every point of the drawing)"};
}

// The rig's `part` (its [[part]] tables, or its [part] table).
void read_part(const std::string& path, const toml::node* ps, Rig& r) {
  const toml::array* a = ps->as_array();
  if (!a) throw RigError{at(path, *ps) + ": use [[part]] tables"};
  for (const toml::node& pn : *a) {
    const toml::table* t = pn.as_table();
    if (!t) throw RigError{at(path, pn) + ": a part must be a table"};
    check_keys(path, *t, {"id", "stiffness"}, "[[part]]");
    RigPart p;
    p.line = static_cast<int>(pn.source().begin.line);
    const toml::node* id = t->get("id");
    if (!id || !id->is_string() || id->value<std::string>()->empty()) throw RigError{at(path, pn) + ": a part needs id = \"sub-shape id\""};
    p.id = *id->value<std::string>();
    const toml::node* k = t->get("stiffness");
    if (!k) throw RigError{at(path, pn) + ": part '" + p.id + "' needs stiffness = k"};
    p.stiffness = number(path, *k, "stiffness");
    if (p.stiffness <= 0) throw RigError{at(path, *k) + ": stiffness must be positive"};
    r.parts.push_back(p);
  }
}

// The rig's `grid` (its [[grid]] tables, or its [grid] table).
void read_grid(const std::string& path, const toml::node* gn, Rig& r) {
  const toml::table* t = gn->as_table();
  if (!t) throw RigError{at(path, *gn) + ": [grid] must be a table"};
  check_keys(path, *t, {"cell", "half_width", "stride", "weights", "junction"}, "[grid]");
  if (const toml::node* n = t->get("junction")) {
    const auto v = n->value<std::string>();
    if (!v || (*v != "triangles" && *v != "mvc")) throw RigError{at(path, *n) + ": junction must be \"triangles\" or \"mvc\""};
    r.grid_junction_term = *v;
  }
  if (const toml::node* n = t->get("cell")) {
    r.grid_cell = number(path, *n, "cell");
    if (!(r.grid_cell > 0)) throw RigError{at(path, *n) + ": cell must be positive (character units)"};
  }
  if (const toml::node* n = t->get("half_width")) {
    const auto v = cfg::whole(*n);
    if (!v || *v < 1 || *v > 32) throw RigError{at(path, *n) + ": half_width must be a whole number 1..32 (cells)"};
    r.grid_half_width = static_cast<int>(*v);
  }
  if (const toml::node* n = t->get("stride")) {
    const auto v = cfg::whole(*n);
    if (!v || *v < 0 || *v > 32)
      throw RigError{at(path, *n) + ": stride must be a whole number 0..32 (0: about half_width / 2; 1: every node)"};
    r.grid_stride = static_cast<int>(*v);
  }
  if (const toml::node* n = t->get("weights")) {
    const toml::table* w = n->as_table();
    if (!w) throw RigError{at(path, *n) + ": weights must be { rigidity = 6.0, junction = 1.0 }"};
    check_keys(path, *w, {"rigidity", "junction"}, "[grid] weights");
    if (const toml::node* x = w->get("rigidity")) r.grid_rigidity = number(path, *x, "rigidity");
    if (const toml::node* x = w->get("junction")) r.grid_junction = number(path, *x, "junction");
    if (!(r.grid_rigidity > 0) || !(r.grid_junction > 0)) throw RigError{at(path, *n) + ": grid weights must be positive"};
  }
}

// The rig's `key` (its [[key]] tables, or its [key] table).
void read_key(const std::string& path, const toml::node* kn, Rig& r) {
  const toml::array* a = kn->as_array();
  if (!a) throw RigError{at(path, *kn) + ": use [[key]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw RigError{at(path, node) + ": a key must be a table"};
    check_keys(path, *t, {"name", "targets", "frame", "shapes"}, "[[key]]");
    RigKey k;
    k.line = static_cast<int>(node.source().begin.line);
    const toml::node* nm = t->get("name");
    if (!nm || !nm->is_string() || nm->value<std::string>()->empty()) throw RigError{at(path, node) + ": a key needs a name"};
    k.name = *nm->value<std::string>();
    if (k.name == "rest") throw RigError{at(path, *nm) + ": 'rest' is the rest pose; name the key otherwise"};
    for (const RigKey& o : r.keys)
      if (o.name == k.name) throw RigError{at(path, node) + ": key '" + k.name + "' defined twice"};
    const toml::node* tg = t->get("targets");
    const toml::node* fr = t->get("frame");
    const toml::node* sh = t->get("shapes");
    if ((tg != nullptr) + (fr != nullptr) + (sh != nullptr) != 1)
      throw RigError{at(path, node) + ": key '" + k.name +
                     "' needs one of targets = { HANDLE = [x, y], ... }, frame = \"file.json\" (pose --dump) or shapes = \"file.json\" (the studio's sculpted key)"};
    if (sh) {
      if (!sh->is_string() || sh->value<std::string>()->empty())
        throw RigError{at(path, *sh) + ": shapes must be the path of a sculpted key the studio saved"};
      k.shapes = *sh->value<std::string>();
      r.max_spacing = kSculptSpacing;
    } else if (fr) {
      if (!fr->is_string()) throw RigError{at(path, *fr) + ": frame must be the path of a saved frame (pose --dump)"};
      k.frame = *fr->value<std::string>();
    } else {
      const toml::table* tt = tg->as_table();
      if (!tt) throw RigError{at(path, *tg) + ": targets must be { HANDLE = [x, y], ... }"};
      for (const auto& [hk, hv] : *tt) {
        const std::string hname(hk.str());
        if (r.find_handle(hname) < 0) throw RigError{at(path, hv) + ": key '" + k.name + "' names no handle '" + hname + "'"};
        k.targets.push_back({hname, point(path, hv, "target")});
      }
    }
    r.keys.push_back(k);
  }
}

// The rig's `stiffness` (its [[stiffness]] tables, or its [stiffness] table).
void read_stiffness(const std::string& path, const toml::node* sn, Rig& r) {
  const toml::array* a = sn->as_array();
  if (!a) throw RigError{at(path, *sn) + ": use [[stiffness]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw RigError{at(path, node) + ": a stiffness region must be a table"};
    check_keys(path, *t, {"name", "center", "radius", "weight"}, "[[stiffness]]");
    RigStiffness s;
    s.line = static_cast<int>(node.source().begin.line);
    const toml::node* c = t->get("center");
    const toml::node* rad = t->get("radius");
    const toml::node* w = t->get("weight");
    if (!c || !rad || !w) throw RigError{at(path, node) + ": a stiffness region needs center = [x, y], radius and weight"};
    if (const toml::node* nm = t->get("name")) s.name = nm->value<std::string>().value_or("");
    s.center = point(path, *c, "center");
    s.radius = number(path, *rad, "radius");
    s.weight = number(path, *w, "weight");
    if (!(s.radius > 0) || !(s.weight > 0)) throw RigError{at(path, node) + ": radius and weight must be positive"};
    for (const RigStiffness& o : r.stiffness)
      if (!s.name.empty() && o.name == s.name) throw RigError{at(path, node) + ": stiffness region '" + s.name + "' defined twice"};
    r.stiffness.push_back(s);
  }
}

// The rig's `swap` (its [[swap]] tables, or its [swap] table).
void read_swap(const std::string& path, const toml::node* sn, Rig& r) {
  const toml::array* a = sn->as_array();
  if (!a) throw RigError{at(path, *sn) + ": use [[swap]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw RigError{at(path, node) + ": a swap set must be a table"};
    check_keys(path, *t, {"name", "members", "default"}, "[[swap]]");
    RigSwap sw;
    sw.line = static_cast<int>(node.source().begin.line);
    sw.name = named(path, r, *t, node, "a swap set");
    const toml::node* m = t->get("members");
    if (!m) throw RigError{at(path, node) + ": swap set '" + sw.name + "' needs members = [\"a\", \"b\", ...]"};
    sw.members = id_list(path, *m, "members");
    if (const toml::node* d = t->get("default")) {
      const std::string dn = d->value<std::string>().value_or("");
      const auto it = std::find(sw.members.begin(), sw.members.end(), dn);
      if (it == sw.members.end()) throw RigError{at(path, *d) + ": default '" + dn + "' is not one of the members"};
      sw.default_member = int(it - sw.members.begin());
    }
    r.swaps.push_back(sw);
  }
}

// The rig's `trigger` (its [[trigger]] tables, or its [trigger] table).
void read_trigger(const std::string& path, const toml::node* tn, Rig& r) {
  const toml::array* a = tn->as_array();
  if (!a) throw RigError{at(path, *tn) + ": use [[trigger]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw RigError{at(path, node) + ": a trigger must be a table"};
    check_keys(path, *t, {"name", "shapes"}, "[[trigger]]");
    RigTrigger tr;
    tr.line = static_cast<int>(node.source().begin.line);
    tr.name = named(path, r, *t, node, "a trigger");
    const toml::node* sh = t->get("shapes");
    if (!sh) throw RigError{at(path, node) + ": trigger '" + tr.name + "' needs shapes = [\"a\", ...]"};
    tr.shapes = id_list(path, *sh, "shapes");
    r.triggers.push_back(tr);
  }
}

}  // namespace

Result<Rig> parse_rig(std::string_view text, const std::string& path) {
  Result<toml::table> parsed = parse_toml(text, path);
  if (!parsed.ok()) return Result<Rig>::failure(parsed.error);
  toml::table root = std::move(*parsed.value);
  try {
    Rig r = default_rig();
    r.path = path;
    check_keys(path, root, {"character", "mask", "solver", "iterations", "weights", "sampling", "handle", "sewing", "feature_frame", "joint",
                            "part", "grid", "stiffness", "rider", "bone", "key", "swap", "trigger", "physics"},
               "the rig");
    const toml::node* ch = root.get("character");
    if (!ch || !ch->is_string()) throw RigError{path + ":1: 'character' (path of the character file) is required"};
    r.character = ch->value<std::string>().value_or("");
    if (const toml::node* m = root.get("mask")) {
      if (!m->is_string() || m->value<std::string>()->empty()) throw RigError{at(path, *m) + ": mask must be the path of a PNG (non-black = figure)"};
      r.mask = *m->value<std::string>();
    }
    if (const toml::node* it = root.get("iterations")) {
      const auto v = cfg::whole(*it);
      if (!v || *v < 1 || *v > 1000) throw RigError{at(path, *it) + ": iterations must be a whole number 1..1000"};
      r.iterations = static_cast<int>(*v);
    }
    if (const toml::node* w = root.get("weights")) read_weights(path, w, r);
    if (const toml::node* s = root.get("sampling")) read_sampling(path, s, r);
    if (const toml::node* hs = root.get("handle")) read_handle(path, hs, r);
    if (const toml::node* ss = root.get("sewing")) read_sewing(path, ss, r);
    if (const toml::node* sv = root.get("solver")) {
      if (!sv->is_string() || sv->value<std::string>()->empty()) throw RigError{at(path, *sv) + ": solver must be a method name, e.g. \"feature_frame\""};
      r.solver = *sv->value<std::string>();
      r.solver_line = static_cast<int>(sv->source().begin.line);
    }
    if (const toml::node* sv = root.get("feature_frame")) read_feature_frame(path, sv, r);
    if (const toml::node* js = root.get("joint")) read_joint(path, js, r);
    if (const toml::node* ps = root.get("part")) read_part(path, ps, r);
    if (const toml::node* gn = root.get("grid")) read_grid(path, gn, r);
    if (const toml::node* kn = root.get("key")) read_key(path, kn, r);
    if (const toml::node* sn = root.get("stiffness")) read_stiffness(path, sn, r);
    if (const toml::node* sn = root.get("swap")) read_swap(path, sn, r);
    if (const toml::node* tn = root.get("trigger")) read_trigger(path, tn, r);
    if (const toml::node* pn = root.get("physics")) parse_rig_physics(path, *pn, r);
    if (const toml::node* rn = root.get("rider")) read_rider(path, rn, r);
    if (const toml::node* bn = root.get("bone")) read_bone(path, bn, r);
    if (r.solver == "rigid_grid" && r.riders.size() + r.bones.size() > 256)
      throw RigError{path + ":1: at most 256 riders and bones together on the rigid grid"};
    for (const RigBone& b : r.bones) {
      if (r.solver != "rigid_grid") throw RigError{path + ":" + std::to_string(b.line) + ": a [[bone]] turns on the rigid grid: it needs solver = \"rigid_grid\""};
      if (!b.handle.empty() && r.find_handle(b.handle) < 0)
        throw RigError{path + ":" + std::to_string(b.line) + ": the bone names handle '" + b.handle + "', which the rig does not have"};
    }
    for (const RigRider& d : r.riders) {
      // (on the feature frame a rider is a detail carried whole by the part it is on: it turns
      // with that part, so it has no handle of its own)
      if (d.still && r.solver != "rigid_grid")
        throw RigError{path + ":" + std::to_string(d.line) + ": a still [[rider]] is left out of the rigid grid's mesh: it needs solver = \"rigid_grid\""};
      if (r.solver == "feature_frame" && (d.on.empty() || !d.handle.empty()))
        throw RigError{path + ":" + std::to_string(d.line) + ": on the feature frame a [[rider]] rides whole on the part it is on: it needs on = \"sub-shape id\" and no handle (a rider that turns toward a handle needs solver = \"rigid_grid\")"};
      if (r.solver != "rigid_grid" && r.solver != "feature_frame")
        throw RigError{path + ":" + std::to_string(d.line) + ": a [[rider]] rides on the rigid grid or the feature frame: it needs solver = \"rigid_grid\" or \"feature_frame\""};
      if (!d.handle.empty() && r.find_handle(d.handle) < 0)
        throw RigError{path + ":" + std::to_string(d.line) + ": rider '" + d.part + "' names handle '" + d.handle + "', which the rig does not have"};
    }
    return Result<Rig>::success(std::move(r));
  } catch (const RigError& e) {
    return Result<Rig>::failure(e.message);
  }
}

Result<Rig> load_rig(const std::string& path) {
  Result<std::string> file_text = read_file(path, kMaxTomlBytes, "a rig");
  if (!file_text.ok()) return Result<Rig>::failure(file_text.error);
  return parse_rig(*file_text.value, path);
}

std::string key_toml(const RigKey& k) {
  std::ostringstream o;
  o.precision(17);
  o << "[[key]]\nname = " << toml::value<std::string>(k.name) << "\n";
  if (!k.frame.empty()) {
    o << "frame = " << toml::value<std::string>(k.frame) << "\n";
    return o.str();
  }
  if (!k.shapes.empty()) {
    o << "shapes = " << toml::value<std::string>(k.shapes) << "\n";
    return o.str();
  }
  o << "targets = { ";
  for (size_t i = 0; i < k.targets.size(); ++i)
    o << (i ? ", " : "") << toml::value<std::string>(k.targets[i].first) << " = [" << k.targets[i].second.x() << ", "
      << k.targets[i].second.y() << "]";
  o << " }\n";
  return o.str();
}

namespace {
std::string shortest(double v) {  // (the shortest text that reads back as v)
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, v);
  return std::string(b, r.ptr);
}
}  // namespace

void write_bone(std::ostream& o, const RigBone& b) {
  o << "\n[[bone]]\n";
  if (!b.handle.empty()) o << "handle = " << toml::value<std::string>(b.handle) << "\n";
  o << "at = [" << shortest(b.at.x()) << ", " << shortest(b.at.y()) << "]\naxis = [";
  for (size_t k = 0; k < b.axis.size(); ++k)
    o << (k ? ", " : "") << "[" << shortest(b.axis[k].x()) << ", " << shortest(b.axis[k].y()) << ", "
      << shortest(k < b.radius.size() ? b.radius[k] : 1.0) << "]";
  o << "]\n";
  if (b.band > 0) o << "band = " << shortest(b.band) << "\n";
}

std::string write_rig(const Rig& r) {
  std::ostringstream o;
  o.precision(17);
  auto pt = [&](const Vec2& p) {
    std::ostringstream s;
    s.precision(17);
    s << "[" << p.x() << ", " << p.y() << "]";
    return s.str();
  };
  o << "character = " << toml::value<std::string>(r.character) << "\n";
  if (!r.mask.empty()) o << "mask = " << toml::value<std::string>(r.mask) << "\n";
  if (r.solver != "feature_frame") o << "solver = " << toml::value<std::string>(r.solver) << "\n";
  o << "iterations = " << r.iterations << "\n\n";
  o << "[weights]\nrigidity = " << r.w_rigidity << "\ncoupling = " << r.w_coupling << "\nposition = " << r.w_position
    << "\n\n";
  o << "[sampling]\nmode = \"" << (r.uniform_sampling ? "uniform" : "features") << "\"\n";
  if (r.interval > 0) o << "interval = " << r.interval << "\n";
  for (const RigHandle& h : r.handles) {
    o << "\n[[handle]]\nname = " << toml::value<std::string>(h.name) << "\nrest = " << pt(h.rest) << "\n";
  }
  for (const RigSewing& e : r.sewing) {
    o << "\n[[sewing]]\naction = \""
      << (e.action == RigSewing::Add ? "add" : e.action == RigSewing::Delete ? "delete" : "move") << "\"\n";
    o << "from = " << pt(e.from) << "\nto = " << pt(e.to) << "\n";
    if (e.action == RigSewing::Move) o << "new_from = " << pt(e.new_from) << "\nnew_to = " << pt(e.new_to) << "\n";
  }
  if (r.anderson != 5 || !r.auto_joints || !r.auto_stiffness) {
    o << "\n[feature_frame]\nanderson = " << r.anderson << "\njoints = \"" << (r.auto_joints ? "auto" : "none")
      << "\"\nstiffness = \"" << (r.auto_stiffness ? "auto" : "none") << "\"\n";
  }
  for (const RigJoint& j : r.joints) {
    o << "\n[[joint]]\n";
    if (j.has_at) o << "at = " << pt(j.at) << "\n";
    if (!j.part_a.empty()) o << "parts = [" << toml::value<std::string>(j.part_a) << ", " << toml::value<std::string>(j.part_b) << "]\n";
    if (j.stiffness >= 0) o << "stiffness = " << j.stiffness << "\n";
    if (j.weld) o << "kind = \"weld\"\n";
  }
  for (const RigPart& p : r.parts) {
    o << "\n[[part]]\nid = " << toml::value<std::string>(p.id) << "\nstiffness = " << p.stiffness << "\n";
  }
  const Rig d = default_rig();
  if (r.grid_cell != d.grid_cell || r.grid_half_width != d.grid_half_width || r.grid_stride != d.grid_stride ||
      r.grid_rigidity != d.grid_rigidity ||
      r.grid_junction != d.grid_junction || r.grid_junction_term != d.grid_junction_term) {
    o << "\n[grid]\n";
    if (r.grid_cell > 0) o << "cell = " << r.grid_cell << "\n";
    o << "half_width = " << r.grid_half_width << "\n";
    if (r.grid_stride != d.grid_stride) o << "stride = " << r.grid_stride << "\n";
    o << "junction = " << toml::value<std::string>(r.grid_junction_term)
      << "\nweights = { rigidity = " << r.grid_rigidity << ", junction = " << r.grid_junction << " }\n";
  }
  for (const RigKey& k : r.keys) o << "\n" << key_toml(k);
  auto toml_string = [](const std::string& v) {
    std::ostringstream t;
    t << toml::value<std::string>(v);
    return t.str();
  };
  auto ids = [&](const std::vector<std::string>& v) {
    std::string t = "[";
    for (size_t i = 0; i < v.size(); ++i) t += (i ? ", " : "") + toml_string(v[i]);
    return t + "]";
  };
  for (const RigSwap& sw : r.swaps)
    o << "\n[[swap]]\nname = " << toml_string(sw.name) << "\nmembers = " << ids(sw.members)
      << "\ndefault = " << toml_string(sw.members[size_t(sw.default_member)]) << "\n";
  for (const RigTrigger& tr : r.triggers)
    o << "\n[[trigger]]\nname = " << toml_string(tr.name) << "\nshapes = " << ids(tr.shapes) << "\n";
  for (const RigRider& rd : r.riders) {
    o << "\n[[rider]]\npart = " << toml_string(rd.part) << "\n";
    if (!rd.on.empty()) o << "on = " << toml_string(rd.on) << "\n";
    if (rd.still) o << "still = true\n";
    else o << "at = " << pt(rd.at) << "\n";
    if (!rd.handle.empty()) o << "handle = " << toml_string(rd.handle) << "\n";
    if (!rd.with.empty()) o << "with = " << ids(rd.with) << "\n";
  }
  for (const RigBone& b : r.bones) write_bone(o, b);
  for (const RigStiffness& s : r.stiffness) {
    o << "\n[[stiffness]]\n";
    if (!s.name.empty()) o << "name = " << toml::value<std::string>(s.name) << "\n";
    o << "center = " << pt(s.center) << "\nradius = " << s.radius << "\nweight = " << s.weight << "\n";
  }
  return o.str();
}

}  // namespace mar
