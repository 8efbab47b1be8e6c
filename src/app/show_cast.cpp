// A show's cast: [[character]] tables, and the names of every character's rig as one ShowRig,
// each prefixed with its character's name (app/show.h).
#include "app/show.h"
#include "app/show_toml.h"

#include <algorithm>
#include <cmath>

namespace mar {

using namespace showtoml;

namespace {

bool reserved(const std::string& n) {
  static const char* const words[] = {"handle", "rotate", "pose", "grab", "brush", "curve", "solver", "morph", "blend", "swap", "trigger", "physics"};
  return std::any_of(std::begin(words), std::end(words), [&](const char* w) { return n == w; });
}

std::string cast_names(const ShowRig& rig) {
  std::string names;
  for (const ShowRig::Member& m : rig.cast) names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

}  // namespace

void read_cast(const std::string& path, const toml::table& root, ShowConfig& s) {
  const toml::array* cs = array_of_tables(path, root, "character");
  if (!cs) return;
  if (!s.rig.empty())
    throw ShowError{at(path, *cs) + ": a show has [show] rig (one character) or [[character]] tables (a cast), not both"};
  if (cs->empty() || cs->size() > 16) throw ShowError{at(path, *cs) + ": a cast has 1 to 16 [[character]] tables"};
  for (const toml::node& n : *cs) {
    const toml::table& t = *n.as_table();
    check_keys(path, t, {"name", "rig", "character", "position", "scale", "rotation", "z", "shown", "entrance", "entrance_seconds"},
               "[[character]]");
    ShowCharacter c;
    c.line = int(n.source().begin.line);
    const toml::node* name = t.get("name");
    const toml::node* rig = t.get("rig");
    if (!name || !rig) throw ShowError{at(path, n) + ": [[character]] needs a name and a rig"};
    c.name = text(path, *name, "name");
    const bool word = !c.name.empty() && c.name.size() <= 32 && std::all_of(c.name.begin(), c.name.end(), [](char ch) {
      return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
    });
    if (!word) throw ShowError{at(path, *name) + ": a character's name is 1 to 32 letters, digits, - or _ (no dots)"};
    if (reserved(c.name)) throw ShowError{at(path, *name) + ": '" + c.name + "' is a word of the target grammar; name the character otherwise"};
    for (const ShowCharacter& o : s.cast)
      if (o.name == c.name) throw ShowError{at(path, *name) + ": a second character named '" + c.name + "'"};
    c.rig = resolve(path, text(path, *rig, "rig"));
    if (auto* x = t.get("character")) c.character = resolve(path, text(path, *x, "character"));
    if (auto* x = t.get("position")) {
      auto [px, py] = pair_of(path, *x, "position");
      if (!(std::abs(px) <= 100000 && std::abs(py) <= 100000)) throw ShowError{at(path, *x) + ": position is canvas pixels, within 100000"};
      c.position = Vec2(px, py);
      c.has_position = true;
    }
    if (auto* x = t.get("scale")) {
      c.scale = number(path, *x, "scale");
      if (!(c.scale >= 0.01 && c.scale <= 100)) throw ShowError{at(path, *x) + ": scale must be 0.01..100"};
    }
    if (auto* x = t.get("rotation")) {
      c.rotation = number(path, *x, "rotation");
      if (!(std::abs(c.rotation) <= 360)) throw ShowError{at(path, *x) + ": rotation must be -360..360 degrees"};
    }
    if (auto* x = t.get("z")) c.z = integer(path, *x, "z", -1000, 1000);
    if (auto* x = t.get("shown")) c.shown = boolean(path, *x, "shown");
    if (auto* x = t.get("entrance")) {
      c.entrance = text(path, *x, "entrance");
      if (c.entrance != "fade" && c.entrance != "cut" && c.entrance != "slide-left" && c.entrance != "slide-right" &&
          c.entrance != "slide-up" && c.entrance != "slide-down")
        throw ShowError{at(path, *x) + ": entrance must be fade, slide-left, slide-right, slide-up, slide-down or cut"};
    }
    if (auto* x = t.get("entrance_seconds")) {
      c.entrance_seconds = number(path, *x, "entrance_seconds");
      if (!(c.entrance_seconds >= 0 && c.entrance_seconds <= 10)) throw ShowError{at(path, *x) + ": entrance_seconds must be 0..10"};
    }
    s.cast.push_back(std::move(c));
  }
  s.rig = s.cast.front().rig;  // (what a single-rig tool reads: the first character's)
  s.character = s.cast.front().character;
}

ShowRig cast_rig(const std::vector<std::string>& names, std::vector<ShowRig> rigs) {
  ShowRig all;
  all.diag = 0;
  all.settings.push_back(rigs.front().settings.front());  // iterations: the show's
  for (size_t c = 0; c < rigs.size(); ++c) {
    const ShowRig& r = rigs[c];
    const std::string pre = names[c] + ".";
    all.cast.push_back({names[c], all.handles.size(), all.settings.size(), all.swaps.size(), all.triggers.size(), all.keys.size()});
    for (const std::string& h : r.handles) all.handles.push_back(pre + h);
    all.rest.insert(all.rest.end(), r.rest.begin(), r.rest.end());
    all.diag = std::max(all.diag, r.diag);
    for (size_t i = 1; i < r.settings.size(); ++i) all.settings.push_back({pre + r.settings[i].name, r.settings[i].default_range});
    for (const auto& [set, members] : r.swaps) all.swaps.push_back({pre + set, members});
    for (const std::string& t : r.triggers) all.triggers.push_back(pre + t);
    for (const std::string& k : r.keys) all.keys.push_back(pre + k);
  }
  for (const std::string& n : names) all.triggers.push_back(n + ".on-stage");  // (entering and leaving, after the rigs')
  all.cast_rigs = std::move(rigs);
  return all;
}

int ShowRig::member_of(int handle) const {
  for (size_t c = 0; c < cast.size(); ++c)
    if (size_t(handle) >= cast[c].handle0 && size_t(handle) < cast[c].handle0 + cast_rigs[c].handles.size()) return int(c);
  return -1;
}

double ShowRig::diag_of(int handle) const {
  const int c = member_of(handle);
  return c < 0 ? diag : cast_rigs[size_t(c)].diag;
}

Result<bool> parse_cast_target(const std::string& t, const ShowConfig& s, const ShowRig& rig, TargetKind& kind, int& index,
                               int* member) {
  using R = Result<bool>;
  if (t == "solver.iterations" || t.rfind("rotate.", 0) == 0) return parse_target(t, s, rig.cast_rigs.front(), kind, index, member);
  if (t.rfind("pose.", 0) == 0) {  // a [[pose]] of the show's (a character's key is NAME.pose.KEY)
    kind = TargetKind::Pose;
    const std::string name = t.substr(5);
    for (size_t i = 0; i < s.poses.size(); ++i)
      if (s.poses[i].name == name) {
        index = int(i);
        return R::success(true);
      }
    return R::failure("no [[pose]] named '" + name + "' (a character's key pose is NAME.pose.KEY; the cast: " + cast_names(rig) + ")");
  }
  const size_t dot = t.find('.');
  const std::string who = t.substr(0, dot);
  int c = -1;
  for (size_t i = 0; i < rig.cast.size(); ++i)
    if (rig.cast[i].name == who) c = int(i);
  if (c < 0 || dot == std::string::npos)
    return R::failure("'" + t + "': a target of a cast starts with its character's name (" + rig.cast.front().name +
                      ".handle.NAME; the cast: " + cast_names(rig) + "), or is the show's rotate.GROUP, pose.NAME or solver.iterations");
  const ShowRig::Member& m = rig.cast[size_t(c)];
  const ShowRig& own = rig.cast_rigs[size_t(c)];
  const std::string rest = t.substr(dot + 1);
  if (rest.rfind("rotate.", 0) == 0 || rest == "solver.iterations")
    return R::failure("'" + t + "': " + rest + " is the show's, with no character in front");
  if (rest == "on-stage") {  // entering and leaving: a trigger of the stage's, after the rigs'
    kind = TargetKind::Trigger;
    index = int(rig.triggers.size() - rig.cast.size()) + c;
    return R::success(true);
  }
  if (rest.rfind("pose.", 0) == 0) {  // a recall of one of its key poses, or of its rest
    const std::string key = rest.substr(5);
    kind = TargetKind::Recall;
    index = key == "rest" ? -1 : int(std::find(own.keys.begin(), own.keys.end(), key) - own.keys.begin());
    if (own.keys.empty() || index == int(own.keys.size()))
      return R::failure("'" + t + "': " + who + "'s rig has no key pose '" + key + "'");
    if (member) *member = c;
    return R::success(true);
  }
  auto r = parse_target(rest, s, own, kind, index, member);
  if (!r.ok()) return R::failure(who + ": " + r.error);
  switch (kind) {
    case TargetKind::HandleX:
    case TargetKind::HandleY:
    case TargetKind::HandlePoint: index += int(m.handle0); break;
    case TargetKind::Setting: index = int(m.setting0) + index - 1; break;  // (its 0 is iterations, refused above)
    case TargetKind::Swap: index += int(m.swap0); break;
    case TargetKind::Trigger: index += int(m.trigger0); break;
    case TargetKind::Grab:
    case TargetKind::Brush:
    case TargetKind::Curve: index = c; break;
    default: return R::failure("'" + t + "': " + rest + " is the show's, with no character in front");
  }
  return R::success(true);
}

}  // namespace mar
