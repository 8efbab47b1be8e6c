// [[brush]] and [[curve]] tables of a show file (app/show.h): a pen that sculpts a character's
// outline, the brush of seed 004 (app/loop/brush.h), and one whose stroke a chain of parts
// takes, the drawn curve of seed 001 (app/loop/curve.h). Each becomes a pointer binding on its
// character's `brush` or `curve` target, so it is read, recorded and replayed as every control is.
#include "app/show.h"
#include "app/show_toml.h"

#include <algorithm>

namespace mar {

using namespace showtoml;

void read_brushed(const std::string& path, const toml::table& root, ShowConfig& s) {
  // (a curve's chain bends along the stroke: its parts need the finer frame a brush does)
  for (const char* word : {"brush", "curve"})
    if (const toml::array* bs = array_of_tables(path, root, word))
      for (const toml::node& n : *bs) {
        const toml::node* c = n.as_table()->get("character");
        s.brushed.push_back(c ? text(path, *c, "character") : "");
      }
}

namespace {

// The pointer binding of a [[brush]] or a [[curve]] (`word`): its device's pointer on the
// target `word` (`NAME.word` in a cast), over the canvas unless `area` says otherwise.
Binding pen_binding(const std::string& path, const toml::node& n, ShowConfig& s, const ShowRig& rig, const std::string& word,
                    int member) {
  const toml::table& t = *n.as_table();
  const std::string table = "[[" + word + "]]";
  Binding b;
  b.line = int(n.source().begin.line);
  const toml::node* dev = t.get("device");
  if (!dev) throw ShowError{at(path, n) + ": " + table + " needs a device (a pen, a tablet or the mouse)"};
  const int di = device_named(path, *dev, s);
  const std::string& dname = s.devices[size_t(di)].name;
  b.control.device = uint16_t(di);
  if (auto r = parse_control(device_control(s.devices[size_t(di)], "pointer"), b.control); !r.ok())
    throw ShowError{at(path, *dev) + ": device '" + dname + "' has no pointer for a " + word + ": " + r.error};
  b.control.text = "pointer";
  // The character it shapes: in a cast, by name.
  std::string who;
  if (auto* c = t.get("character")) who = text(path, *c, "character");
  if (!rig.cast.empty() && who.empty())
    throw ShowError{at(path, n) + ": in a cast a " + table + " names its character (character = \"NAME\")"};
  if (rig.cast.empty() && !who.empty())
    throw ShowError{at(path, *t.get("character")) + ": this show has one character (no [[character]] tables): leave character out"};
  b.target_text = who.empty() ? word : who + "." + word;
  if (auto r = parse_target(b.target_text, s, rig, b.target, b.index, nullptr); !r.ok())
    throw ShowError{at(path, *t.get("character")) + ": " + r.error};
  b.member = member;
  b.tf.takeover = false;
  b.tf.area_canvas = true;  // (the pen touches what is drawn under it)
  if (auto* x = t.get("area")) {
    const toml::array* a = x->as_array();
    if (!(x->is_string() && *x->value<std::string>() == "canvas") && (!a || a->size() != 4))
      throw ShowError{at(path, *x) + ": area must be [x0, y0, x1, y1] (character units) or \"canvas\""};
    b.tf.area_canvas = !a;
    for (size_t i = 0; i < 4 && a; ++i) b.tf.area[i] = number(path, *a->get(i), "area");
  }
  return b;
}

// `release`, `release_seconds` and `key`, as a brush and a curve read them; `who`: the cast's
// character the tool shapes (0: a single rig), whose rig's keys `key` names.
void read_release(const std::string& path, const toml::table& t, const ShowRig& rig, int who, ShowBrush::Release& release,
                  double& seconds, int& key) {
  const toml::node* k = t.get("key");
  if (auto* x = t.get("release")) {
    const std::string r = text(path, *x, "release");
    if (r != "spring" && r != "hold" && r != "key")
      throw ShowError{at(path, *x) + ": release must be \"spring\", \"hold\" or \"key\" (with key = \"NAME\")"};
    release = r == "hold" ? ShowBrush::Hold : r == "key" ? ShowBrush::Key : ShowBrush::Spring;
    if (release == ShowBrush::Key && !k)
      throw ShowError{at(path, *x) + ": release = \"key\" names the key pose it blends into: key = \"NAME\" (a [[key]] of the rig, or \"rest\")"};
  }
  if (k) {
    if (release != ShowBrush::Key) throw ShowError{at(path, *k) + ": key is for release = \"key\""};
    const std::vector<std::string>& keys = rig.cast.empty() ? rig.keys : rig.cast_rigs[size_t(who)].keys;
    const std::string name = text(path, *k, "key");
    key = name == "rest" ? -1 : int(std::find(keys.begin(), keys.end(), name) - keys.begin());
    if (keys.empty() || key == int(keys.size())) {
      std::string names;
      for (const std::string& n : keys) names += (names.empty() ? "" : ", ") + n;
      throw ShowError{at(path, *k) + ": the rig has no key pose '" + name + "'" +
                      (keys.empty() ? std::string(" (it has no [[key]] the feature frame can blend)") : " (" + names + ", rest)")};
    }
  }
  if (auto* x = t.get("release_seconds")) {
    seconds = number(path, *x, "release_seconds");
    if (!(seconds >= 0 && seconds <= 60)) throw ShowError{at(path, *x) + ": release_seconds must be 0..60"};
  }
}

double read_strength(const std::string& path, const toml::table& t, double fallback) {
  const toml::node* x = t.get("strength");
  if (!x) return fallback;
  const double v = number(path, *x, "strength");
  if (!(v > 0 && v <= 1)) throw ShowError{at(path, *x) + ": strength must be 0..1 (above 0)"};
  return v;
}

}  // namespace

void read_brushes(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig) {
  const toml::array* bs = array_of_tables(path, root, "brush");
  if (!bs) return;
  if (bs->size() > 16) throw ShowError{at(path, *bs) + ": at most 16 [[brush]] tables"};
  for (const toml::node& n : *bs) {
    const toml::table& t = *n.as_table();
    check_keys(path, t, {"device", "character", "radius", "falloff", "strength", "release", "release_seconds", "key", "area"}, "[[brush]]");
    Binding b = pen_binding(path, n, s, rig, "brush", int(s.brushes.size()));
    ShowBrush br;
    br.line = b.line;
    br.device = b.control.device;
    br.who = b.index;
    if (auto* x = t.get("radius")) {
      std::tie(br.radius_lo, br.radius_hi) = pair_of(path, *x, "radius");
      if (!(br.radius_lo > 0 && br.radius_lo <= br.radius_hi && br.radius_hi <= 4000))
        throw ShowError{at(path, *x) + ": radius must be [light, full] canvas pixels, 0 < light <= full <= 4000"};
    }
    if (auto* x = t.get("falloff"); x && text(path, *x, "falloff") != "gaussian")
      throw ShowError{at(path, *x) + ": falloff must be \"gaussian\" (seed 004's kernel)"};
    br.strength = read_strength(path, t, 1.0);
    read_release(path, t, rig, br.who, br.release, br.release_seconds, br.key);
    s.brushes.push_back(br);
    s.bindings.push_back(std::move(b));
  }
}

void read_curves(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig) {
  const toml::array* cs = array_of_tables(path, root, "curve");
  if (!cs) return;
  if (cs->size() > 16) throw ShowError{at(path, *cs) + ": at most 16 [[curve]] tables"};
  for (const toml::node& n : *cs) {
    const toml::table& t = *n.as_table();
    check_keys(path, t, {"device", "character", "parts", "from", "fit", "strength", "release", "release_seconds", "key", "area"}, "[[curve]]");
    Binding b = pen_binding(path, n, s, rig, "curve", int(s.curves.size()));
    ShowCurve c;
    c.line = b.line;
    c.device = b.control.device;
    c.who = b.index;
    if (auto* x = t.get("fit")) {
      const std::string fit = text(path, *x, "fit");
      if (fit != "chain" && fit != "contour") throw ShowError{at(path, *x) + ": fit must be \"chain\" or \"contour\""};
      c.fit = fit == "contour" ? ShowCurve::Contour : ShowCurve::Chain;
    }
    const toml::node* parts = t.get("parts");
    const toml::node* from = t.get("from");
    if (c.fit == ShowCurve::Chain && (!parts || !from))
      throw ShowError{at(path, n) + ": [[curve]] names its chain: parts = [\"...\"] (shape ids, the one nearest from first) and from (the part it hangs from)"};
    if (c.fit == ShowCurve::Contour && from)
      throw ShowError{at(path, *from) + ": from is a chain's: fit = \"contour\" redraws the outlines of parts (or of every part)"};
    if (parts) {
      if (const toml::array* a = parts->as_array()) {
        for (const toml::node& e : *a) c.parts.push_back(text(path, e, "parts"));
      } else {
        c.parts.push_back(text(path, *parts, "parts"));
      }
      if (c.parts.empty() || c.parts.size() > 32) throw ShowError{at(path, *parts) + ": parts must name 1..32 shape ids"};
    }
    if (from) c.from = text(path, *from, "from");
    c.strength = read_strength(path, t, c.fit == ShowCurve::Contour ? 1.0 : 0.5);  // (a redrawn line is meant to be where it is drawn)
    read_release(path, t, rig, c.who, c.release, c.release_seconds, c.key);
    s.curves.push_back(c);
    s.bindings.push_back(std::move(b));
  }
}

}  // namespace mar
