// [[brush]] tables of a show file (app/show.h): a pen that sculpts a character's outline, the
// brush of seed 004 (app/loop/brush.h). Each becomes a pointer binding on its character's
// `brush` target, so it is read, recorded and replayed as every control is.
#include "app/show.h"
#include "app/show_toml.h"

namespace mar {

using namespace showtoml;

void read_brushed(const std::string& path, const toml::table& root, ShowConfig& s) {
  if (const toml::array* bs = array_of_tables(path, root, "brush"))
    for (const toml::node& n : *bs) {
      const toml::node* c = n.as_table()->get("character");
      s.brushed.push_back(c ? text(path, *c, "character") : "");
    }
}

void read_brushes(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig) {
  const toml::array* bs = array_of_tables(path, root, "brush");
  if (!bs) return;
  if (bs->size() > 16) throw ShowError{at(path, *bs) + ": at most 16 [[brush]] tables"};
  for (const toml::node& n : *bs) {
    const toml::table& t = *n.as_table();
    check_keys(path, t, {"device", "character", "radius", "falloff", "strength", "release", "release_seconds", "area"}, "[[brush]]");
    ShowBrush br;
    br.line = int(n.source().begin.line);
    const toml::node* dev = t.get("device");
    if (!dev) throw ShowError{at(path, n) + ": [[brush]] needs a device (a pen, a tablet or the mouse)"};
    const std::string dname = text(path, *dev, "device");
    int di = -1;
    for (size_t i = 0; i < s.devices.size(); ++i)
      if (s.devices[i].name == dname) di = int(i);
    if (di < 0) throw ShowError{at(path, *dev) + ": no [[device]] named '" + dname + "'"};
    br.device = di;
    Binding b;
    b.line = br.line;
    b.control.device = uint16_t(di);
    if (auto r = parse_control(device_control(s.devices[size_t(di)], "pointer"), b.control); !r.ok())
      throw ShowError{at(path, *dev) + ": device '" + dname + "' has no pointer for a brush: " + r.error};
    b.control.text = "pointer";
    // The character it sculpts: in a cast, by name.
    std::string who;
    if (auto* c = t.get("character")) who = text(path, *c, "character");
    if (!rig.cast.empty() && who.empty())
      throw ShowError{at(path, n) + ": in a cast a [[brush]] names its character (character = \"NAME\")"};
    if (rig.cast.empty() && !who.empty())
      throw ShowError{at(path, *t.get("character")) + ": this show has one character (no [[character]] tables): leave character out"};
    b.target_text = who.empty() ? "brush" : who + ".brush";
    if (auto r = parse_target(b.target_text, s, rig, b.target, b.index, nullptr); !r.ok())
      throw ShowError{at(path, *t.get("character")) + ": " + r.error};
    br.who = b.index;
    b.member = int(s.brushes.size());
    b.tf.takeover = false;
    if (auto* x = t.get("radius")) {
      std::tie(br.radius_lo, br.radius_hi) = pair_of(path, *x, "radius");
      if (!(br.radius_lo > 0 && br.radius_lo <= br.radius_hi && br.radius_hi <= 4000))
        throw ShowError{at(path, *x) + ": radius must be [light, full] canvas pixels, 0 < light <= full <= 4000"};
    }
    if (auto* x = t.get("falloff"); x && text(path, *x, "falloff") != "gaussian")
      throw ShowError{at(path, *x) + ": falloff must be \"gaussian\" (seed 004's kernel)"};
    if (auto* x = t.get("strength")) {
      br.strength = number(path, *x, "strength");
      if (!(br.strength > 0 && br.strength <= 1)) throw ShowError{at(path, *x) + ": strength must be 0..1 (above 0)"};
    }
    if (auto* x = t.get("release")) {
      const std::string r = text(path, *x, "release");
      if (r == "key")
        throw ShowError{at(path, *x) + ": release = \"key\" is not built yet: \"spring\" (back over release_seconds) or \"hold\""};
      if (r != "spring" && r != "hold") throw ShowError{at(path, *x) + ": release must be \"spring\" or \"hold\""};
      br.release = r == "hold" ? ShowBrush::Hold : ShowBrush::Spring;
    }
    if (auto* x = t.get("release_seconds")) {
      br.release_seconds = number(path, *x, "release_seconds");
      if (!(br.release_seconds >= 0 && br.release_seconds <= 60)) throw ShowError{at(path, *x) + ": release_seconds must be 0..60"};
    }
    b.tf.area_canvas = true;  // (the pen touches the outline drawn under it)
    if (auto* x = t.get("area")) {
      const toml::array* a = x->as_array();
      if (!(x->is_string() && *x->value<std::string>() == "canvas") && (!a || a->size() != 4))
        throw ShowError{at(path, *x) + ": area must be [x0, y0, x1, y1] (character units) or \"canvas\""};
      b.tf.area_canvas = !a;
      for (size_t i = 0; i < 4 && a; ++i) b.tf.area[i] = number(path, *a->get(i), "area");
    }
    s.brushes.push_back(br);
    s.bindings.push_back(std::move(b));
  }
}

}  // namespace mar
