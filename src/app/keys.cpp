#include "app/keys.h"

#include "base/read_file.h"
#include "geom/polygon.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace mar {

int find_key(const Rig& rig, const std::string& name) {
  if (name == "rest") return -1;
  for (size_t k = 0; k < rig.keys.size(); ++k)
    if (rig.keys[k].name == name) return int(k);
  return -2;
}

namespace {

// How deep a JSON text nests ('[' and '{' outside strings): a key's file nests three deep, and a
// file of millions of brackets would build a document of gigabytes (read only up to 64).
int json_depth(std::string_view text) {
  int depth = 0, most = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size() && most <= 64; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      most = std::max(most, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return most;
}

// A sculpted key's frame vertices from every shape's outline as posed (RigKey::shapes): per shape
// id, per contour, samples [rest x, rest y, posed x, posed y] in outline order, as the studio
// flattened the drawing. A frame vertex on an outline moves as the nearest point of its contour's
// samples at rest does (the flattening of a show's canvas differs from the studio's, so the
// points are not the same ones); a hinge's ends (not on an outline) go where the best rigid fit
// of the outline vertices they are tied to takes them. Errors name the file and the shape.
Result<Points> frame_from_shapes(const Puppet& p, const nlohmann::json& j, const std::string& file) {
  using R = Result<Points>;
  const Character& ch = p.character;
  const FeatureFrame& f = p.feature_frame()->frame();
  if (!j.is_object() || !j.contains("shapes") || !j["shapes"].is_object())
    return R::failure(file + ": a sculpted key holds {\"shapes\": {\"ID\": [[[rest x, rest y, x, y], ...] per contour]}}");
  const nlohmann::json& js = j["shapes"];
  struct Sample {
    Vec2 rest, moved;
  };
  std::vector<std::vector<std::vector<Sample>>> samples(ch.shapes.size());
  for (size_t k = 0; k < ch.shapes.size(); ++k) {
    const SubShape& sh = ch.shapes[k];
    const std::string& id = sh.id;
    if (!js.contains(id) || !js[id].is_array())
      return R::failure(file + ": no outline for shape '" + id + "' (the drawing changed since the key was sculpted?)");
    const nlohmann::json& cs = js[id];
    if (cs.size() != sh.contours.size())
      return R::failure(file + ": shape '" + id + "' has " + std::to_string(cs.size()) + " contours, the drawing " +
                        std::to_string(sh.contours.size()));
    for (const auto& c : cs) {
      if (!c.is_array() || c.empty()) return R::failure(file + ": shape '" + id + "': a contour must be a list of samples");
      samples[k].emplace_back();
      for (const auto& e : c) {
        if (!e.is_array() || e.size() != 4 || !e[0].is_number() || !e[1].is_number() || !e[2].is_number() || !e[3].is_number())
          return R::failure(file + ": shape '" + id + "': a sample must be [rest x, rest y, x, y]");
        const Sample smp{{e[0].get<double>(), e[1].get<double>()}, {e[2].get<double>(), e[3].get<double>()}};
        if (!smp.rest.allFinite() || !smp.moved.allFinite()) return R::failure(file + ": shape '" + id + "': a sample is not finite");
        samples[k].back().push_back(smp);
      }
    }
  }
  Points v(f.rest.size(), Vec2::Zero());
  std::vector<char> on(f.rest.size(), 0);
  const double eps = 1e-9 * std::max(1.0, p.diagonal);
  for (size_t i = 0; i < f.rest.size(); ++i) {
    const FrameVertexOrigin& o = f.origin[i];
    const SubShape& sh = ch.shapes[size_t(o.shape)];
    if (size_t(o.point) >= sh.points.size() || (sh.points[size_t(o.point)] - f.rest[i]).norm() > eps) continue;
    const std::vector<Sample>& c = samples[size_t(o.shape)][size_t(o.contour)];
    const Vec2 r = f.rest[i];
    const size_t n = c.size();
    const bool closed = sh.contours[size_t(o.contour)].closed;
    double best = (c[0].rest - r).squaredNorm();
    Vec2 moved = c[0].moved - c[0].rest;
    for (size_t a = 0; a < n; ++a) {  // the nearest point of each segment, and its move
      const size_t b = a + 1 < n ? a + 1 : (closed ? 0 : a);
      const Vec2 e = c[b].rest - c[a].rest;
      const double t = e.squaredNorm() > 0 ? std::clamp((r - c[a].rest).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
      const double d = (c[a].rest + t * e - r).squaredNorm();
      if (d < best) {
        best = d;
        moved = (1 - t) * (c[a].moved - c[a].rest) + t * (c[b].moved - c[b].rest);
      }
    }
    v[i] = r + moved;
    on[i] = 1;
  }
  std::vector<Vec2> from, to;
  for (size_t i = 0; i < f.rest.size(); ++i) {
    if (on[i]) continue;
    from.clear();
    to.clear();
    for (const FrameLine& l : f.lines) {
      const int other = size_t(l.a) == i ? l.b : size_t(l.b) == i ? l.a : -1;
      if (other >= 0 && on[size_t(other)] && l.kind != FrameLine::Joint) {
        from.push_back(f.rest[size_t(other)]);
        to.push_back(v[size_t(other)]);
      }
    }
    if (from.empty()) return R::failure(file + ": frame vertex " + std::to_string(i) + " is tied to no outline");
    v[i] = rigid_fit(from, to).apply(f.rest[i]);
  }
  return R::success(std::move(v));
}

}  // namespace

Result<std::vector<Points>> solve_keys(Puppet& p, std::vector<Points>* details) {
  using R = Result<std::vector<Points>>;
  std::vector<Points> out;
  if (p.rig.keys.empty()) return R::success(std::move(out));
  FeatureFrameMethod* ff = p.feature_frame();
  auto where = [&](const RigKey& k) { return p.rig.path + ":" + std::to_string(k.line) + ": key '" + k.name + "'"; };
  if (!ff) return R::failure(where(p.rig.keys[0]) + ": key poses need the feature frame (solver = \"feature_frame\")");
  const size_t q = ff->frame().rest.size();
  // A pose from handle targets: solved from rest until converged.
  auto solve_from = [&](std::vector<Vec2> t) {
    p.solver->reset_to_rest();
    p.solver->initial_guess(t);
    if (p.chains.empty()) {
      p.solver->solve(t, 300);
    } else {  // a chain's ends follow where the pose takes them: they pull nothing
      for (int round = 0; round < 60; ++round) {
        p.solver->solve(t, 5);
        for (size_t h = 0; h < t.size(); ++h)
          if (p.rig.handles[h].physics) t[h] = p.solver->handle_point(h);
      }
    }
    const auto v = ff->core().vertices();
    return Points(v.begin(), v.end());
  };
  if (details) details->assign(p.rig.keys.size(), Points{});
  for (const RigKey& k : p.rig.keys) {
    if (!k.shapes.empty()) {
      const std::filesystem::path f = p.rig.beside(k.shapes);
      Result<std::string> file_text = read_file(f.string(), kMaxScriptBytes, "a sculpted key");
      if (!file_text.ok()) return R::failure(where(k) + ": " + file_text.error);
      if (json_depth(*file_text.value) > 8) return R::failure(where(k) + ": " + f.string() + " nests deeper than a sculpted key does");
      nlohmann::json j = nlohmann::json::parse(*file_text.value, nullptr, false);
      if (j.is_discarded()) return R::failure(where(k) + ": " + f.string() + " is not JSON");
      auto v = frame_from_shapes(p, j, f.string());
      if (!v.ok()) return R::failure(where(k) + ": " + v.error);
      // What its handles alone make of it: the sculpted detail is the rest (played on top of
      // the solve: KeyPoseStage::detail).
      if (details) {
        std::vector<Vec2> t = p.rest_targets();
        for (size_t h = 0; h < t.size(); ++h)
          if (!p.rig.handles[h].physics) t[h] = eval_param(ff->bindings()[h], *v.value);
        const Points solved = solve_from(std::move(t));
        Points& d = (*details)[out.size()];
        d.resize(q);
        for (size_t i = 0; i < q; ++i) d[i] = (*v.value)[i] - solved[i];
      }
      out.push_back(std::move(*v.value));
      continue;
    }
    if (!k.frame.empty()) {
      const std::filesystem::path f = p.rig.beside(k.frame);
      Result<std::string> file_text = read_file(f.string(), kMaxScriptBytes, "a key's frame");
      if (!file_text.ok()) return R::failure(where(k) + ": " + file_text.error);
      if (json_depth(*file_text.value) > 8) return R::failure(where(k) + ": " + f.string() + " nests deeper than a saved frame does");
      nlohmann::json j = nlohmann::json::parse(*file_text.value, nullptr, false);
      if (j.is_discarded() || !j.contains("frame_vertices") || !j["frame_vertices"].is_array())
        return R::failure(where(k) + ": cannot read frame_vertices from " + f.string());
      Points v;
      for (const auto& e : j["frame_vertices"]) {
        if (!e.is_array() || e.size() != 2 || !e[0].is_number() || !e[1].is_number())
          return R::failure(where(k) + ": " + f.string() + ": a frame vertex must be [x, y]");
        v.emplace_back(e[0].get<double>(), e[1].get<double>());
        if (!v.back().allFinite()) return R::failure(where(k) + ": " + f.string() + ": a frame vertex is not finite");
      }
      if (v.size() != q)
        return R::failure(where(k) + ": " + f.string() + " has " + std::to_string(v.size()) + " frame vertices, the rig's frame has " +
                          std::to_string(q));
      out.push_back(std::move(v));
      continue;
    }
    std::vector<Vec2> t = p.rest_targets();
    for (const auto& [name, at] : k.targets) t[size_t(p.rig.find_handle(name))] = at;
    out.push_back(solve_from(std::move(t)));
  }
  p.solver->reset_to_rest();
  return R::success(std::move(out));
}

}  // namespace mar
