#include "app/puppet.h"

#include "character/load.h"

#include <chrono>
#include <filesystem>

namespace mar {

std::vector<Vec2> Puppet::rest_targets() const {
  std::vector<Vec2> t;
  for (const RigHandle& h : rig.handles) t.push_back(h.rest);
  return t;
}

SolverWeights Puppet::weights() const {
  SolverWeights w;
  w.rigidity = rig.w_rigidity;
  w.coupling = rig.w_coupling;
  w.position = rig.w_position;
  w.anderson = rig.anderson;
  return w;
}

Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, const std::string& rig_path,
                                            const std::string& mask_path) {
  Result<Rig> rig = load_rig(rig_path);
  if (!rig.ok()) return Result<std::unique_ptr<Puppet>>::failure(rig.error);
  return load_puppet(character_path, std::move(*rig.value), mask_path);
}

Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, Rig rig, const std::string& mask_path) {
  using R = Result<std::unique_ptr<Puppet>>;
  auto p = std::make_unique<Puppet>();
  p->rig = std::move(rig);
  p->solver = make_solver(p->rig.solver);
  if (!p->solver) {
    return R::failure(p->rig.path + ":" + std::to_string(std::max(1, p->rig.solver_line)) + ": unknown solver '" + p->rig.solver +
                      "' (known: feature_frame, rigid_grid, arap)");
  }
  const std::string path = character_path.empty() ? p->rig.character_path() : character_path;
  LoadOptions lo;
  lo.mask_path = mask_path;
  if (mask_path.empty()) {  // the rig's mask goes with the rig's character
    std::error_code ec;
    const bool own = character_path.empty() || std::filesystem::weakly_canonical(character_path, ec) ==
                                                   std::filesystem::weakly_canonical(p->rig.character_path(), ec);
    if (own) lo.mask_path = p->rig.mask_path();
  }
  Result<Character> ch = load_character(path, lo);
  if (!ch.ok()) return R::failure(ch.error);
  p->character = std::move(*ch.value);
  const Bounds b = p->character.bounds();
  p->diagonal = b.empty() ? 1.0 : std::max(1e-9, (b.hi - b.lo).norm());
  const auto t0 = std::chrono::steady_clock::now();
  std::string err;
  const bool ok = p->solver->prepare(p->character, p->rig, p->rest_targets(), p->weights(), &err);
  p->prefactor_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!ok) {
    for (const std::string& w : p->character.warnings) err += "; " + w;  // e.g. a mask with no figure
    return R::failure(path + ": " + err);
  }
  p->mesh = prepare_mesh(p->character);
  for (const SubShape& s : p->character.shapes) p->shapes.push_back(s.points);
  return R::success(std::move(p));
}

}  // namespace mar
