// [[scenery]], [[prop]], [[group]] and [[pose]] tables of a show file (app/show.h).
#include "app/show.h"
#include "app/show_toml.h"

#include <algorithm>
#include <cmath>

namespace mar {

using namespace showtoml;

void read_scenery(const std::string& path, const toml::table& root, ShowConfig& s) {
  if (const toml::array* sc = array_of_tables(path, root, "scenery")) {
    if (sc->size() > 16) throw ShowError{at(path, *sc) + ": at most 16 [[scenery]] drawings"};
    for (const toml::node& n : *sc) {
      const toml::table& t = *n.as_table();
      check_keys(path, t, {"file", "fit", "at", "width", "front"}, "[[scenery]]");
      ShowScenery v;
      v.line = int(n.source().begin.line);
      const toml::node* f = t.get("file");
      if (!f) throw ShowError{at(path, n) + ": [[scenery]] needs a file (an SVG or a PNG)"};
      v.file = resolve(path, text(path, *f, "file"));
      if (auto* x = t.get("fit")) {
        const std::string fit = text(path, *x, "fit");
        if (fit != "cover" && fit != "contain") throw ShowError{at(path, *x) + ": fit must be cover or contain (or give at and width)"};
        v.fit = fit == "cover" ? ShowScenery::Cover : ShowScenery::Contain;
      }
      if (t.get("at") || t.get("width")) {
        if (!t.get("at") || !t.get("width") || t.get("fit"))
          throw ShowError{at(path, n) + ": a placed [[scenery]] gives at = [x, y] and width (canvas pixels), and no fit"};
        auto [x, y] = pair_of(path, *t.get("at"), "at");
        v.at = Vec2(x, y);
        v.width = number(path, *t.get("width"), "width");
        if (!(v.width > 0 && v.width <= 100000)) throw ShowError{at(path, *t.get("width")) + ": width must be > 0 canvas pixels"};
        v.fit = ShowScenery::Placed;
      }
      if (auto* x = t.get("front")) v.front = boolean(path, *x, "front");
      s.scenery.push_back(std::move(v));
    }
  }
}

void read_props(const std::string& path, const toml::table& root, ShowConfig& s) {
  if (const toml::array* ps = array_of_tables(path, root, "prop")) {
    if (ps->size() > 16) throw ShowError{at(path, *ps) + ": at most 16 [[prop]] drawings"};
    for (const toml::node& n : *ps) {
      const toml::table& t = *n.as_table();
      check_keys(path, t, {"file", "part", "at", "width", "rotation", "front"}, "[[prop]]");
      ShowProp v;
      v.line = int(n.source().begin.line);
      const toml::node* f = t.get("file");
      const toml::node* part = t.get("part");
      if (!f || !part) throw ShowError{at(path, n) + ": [[prop]] needs a file (an SVG or a PNG) and the part that holds it"};
      v.file = resolve(path, text(path, *f, "file"));
      v.part = text(path, *part, "part");
      if (auto* x = t.get("at")) {
        auto [ax, ay] = pair_of(path, *x, "at");
        v.at = Vec2(ax, ay);
        v.has_at = true;
      }
      if (auto* x = t.get("width")) {
        v.width = number(path, *x, "width");
        if (!(v.width > 0 && v.width <= 1e6)) throw ShowError{at(path, *x) + ": width must be > 0 (character units)"};
      }
      if (auto* x = t.get("rotation")) v.rotation = number(path, *x, "rotation");
      if (auto* x = t.get("front")) v.front = boolean(path, *x, "front");
      s.props.push_back(std::move(v));
    }
  }
  read_physics(path, root, s);  // loop/physics.cpp
}

void read_groups_and_poses(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig) {
  const std::vector<std::string>& handles = rig.handles;
  auto handle_of = [&](const toml::node& n) {
    const std::string h = text(path, n, "handle");
    for (size_t i = 0; i < handles.size(); ++i)
      if (handles[i] == h) return int(i);
    throw ShowError{at(path, n) + ": the rig has no handle '" + h + "'"};
  };
  if (const toml::array* gs = array_of_tables(path, root, "group")) {
    for (const toml::node& gn : *gs) {
      const toml::table& t = *gn.as_table();
      check_keys(path, t, {"name", "handles", "pivot", "pivot_handle", "follow"}, "[[group]]");
      RotationGroup g;
      if (auto* n = t.get("name")) g.name = text(path, *n, "name");
      else throw ShowError{at(path, gn) + ": [[group]] needs a name"};
      const toml::array* hs = t.get("handles") ? t.get("handles")->as_array() : nullptr;
      if (!hs || hs->empty()) throw ShowError{at(path, gn) + ": [[group]] needs handles = [\"name\", ...]"};
      for (const toml::node& h : *hs) g.handles.push_back(handle_of(h));
      if (auto* n = t.get("pivot")) {
        auto [x, y] = pair_of(path, *n, "pivot");
        g.pivot = Vec2(x, y);
      } else if (auto* ph = t.get("pivot_handle")) {
        g.pivot_handle = handle_of(*ph);
      } else {
        throw ShowError{at(path, gn) + ": [[group]] needs pivot = [x, y] or pivot_handle"};
      }
      if (auto* f = t.get("follow")) {
        if (g.pivot_handle >= 0) throw ShowError{at(path, *f) + ": [[group]] " + g.name + ": follow moves a pivot = [x, y]; pivot_handle is where its handle goes already"};
        g.follow = handle_of(*f);
        if (std::find(g.handles.begin(), g.handles.end(), g.follow) != g.handles.end())
          throw ShowError{at(path, *f) + ": [[group]] " + g.name + " follows one of its own handles"};
      }
      // (in a cast, one character's handles: its pivot is in that character's units)
      for (int h : g.handles)
        if (rig.member_of(h) != rig.member_of(g.handles.front()) || (g.pivot_handle >= 0 && rig.member_of(g.pivot_handle) != rig.member_of(h)) ||
            (g.follow >= 0 && rig.member_of(g.follow) != rig.member_of(h)))
          throw ShowError{at(path, gn) + ": a [[group]] turns one character's handles (" + g.name + " names two characters')"};
      s.groups.push_back(std::move(g));
    }
  }
  if (const toml::array* ps = array_of_tables(path, root, "pose")) {
    for (const toml::node& pn : *ps) {
      const toml::table& t = *pn.as_table();
      check_keys(path, t, {"name", "handles"}, "[[pose]]");
      Pose p;
      if (auto* n = t.get("name")) p.name = text(path, *n, "name");
      else throw ShowError{at(path, pn) + ": [[pose]] needs a name"};
      p.positions.assign(handles.size(), Vec2(NAN, NAN));
      const toml::table* hs = t.get("handles") ? t.get("handles")->as_table() : nullptr;
      if (!hs) throw ShowError{at(path, pn) + ": [[pose]] needs handles = { name = [x, y], ... }"};
      // In a cast a handle is NAME.HANDLE: TOML reads `robot.left-hand = [x, y]` as a table
      // `robot` holding `left-hand`, so a table's keys are its name's handles.
      auto put = [&](const std::string& name, const toml::node& v) {
        int hi = -1;
        for (size_t i = 0; i < handles.size(); ++i)
          if (handles[i] == name) hi = int(i);
        if (hi < 0) throw ShowError{at(path, v) + ": the rig has no handle '" + name + "'"};
        auto [x, y] = pair_of(path, v, "pose position");
        p.positions[size_t(hi)] = Vec2(x, y);
      };
      for (const auto& [k, v] : *hs) {
        if (const toml::table* who = v.as_table(); who && !rig.cast.empty()) {
          for (const auto& [k2, v2] : *who) put(std::string(k.str()) + "." + std::string(k2.str()), v2);
          continue;
        }
        put(std::string(k.str()), v);
      }
      s.poses.push_back(std::move(p));
    }
  }
}

}  // namespace mar
