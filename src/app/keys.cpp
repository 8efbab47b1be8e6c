#include "app/keys.h"

#include "base/read_file.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace mar {

int find_key(const Rig& rig, const std::string& name) {
  if (name == "rest") return -1;
  for (size_t k = 0; k < rig.keys.size(); ++k)
    if (rig.keys[k].name == name) return int(k);
  return -2;
}

Result<std::vector<Points>> solve_keys(Puppet& p) {
  using R = Result<std::vector<Points>>;
  std::vector<Points> out;
  if (p.rig.keys.empty()) return R::success(std::move(out));
  FeatureFrameMethod* ff = p.feature_frame();
  auto where = [&](const RigKey& k) { return p.rig.path + ":" + std::to_string(k.line) + ": key '" + k.name + "'"; };
  if (!ff) return R::failure(where(p.rig.keys[0]) + ": key poses need the feature frame (solver = \"feature_frame\")");
  const size_t q = ff->frame().rest.size();
  for (const RigKey& k : p.rig.keys) {
    if (!k.frame.empty()) {
      const std::filesystem::path f = p.rig.beside(k.frame);
      Result<std::string> file_text = read_file(f.string(), kMaxScriptBytes, "a key's frame");
      if (!file_text.ok()) return R::failure(where(k) + ": " + file_text.error);
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
    out.emplace_back(v.begin(), v.end());
  }
  p.solver->reset_to_rest();
  return R::success(std::move(out));
}

}  // namespace mar
