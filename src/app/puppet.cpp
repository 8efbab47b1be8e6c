#include "app/puppet.h"

#include "character/load.h"

#include <chrono>

namespace mar {

std::vector<Vec2> Puppet::rest_targets() const {
  std::vector<Vec2> t;
  for (const RigHandle& h : rig.handles) t.push_back(h.rest);
  return t;
}

void Puppet::reconstruct() { reconstruct_shapes(frame, solver.vertices(), shapes); }

Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, const std::string& rig_path) {
  using R = Result<std::unique_ptr<Puppet>>;
  Result<Rig> rig = load_rig(rig_path);
  if (!rig.ok()) return R::failure(rig.error);
  auto p = std::make_unique<Puppet>();
  p->rig = std::move(*rig.value);
  const std::string path = character_path.empty() ? p->rig.character_path() : character_path;
  Result<Character> ch = load_character(path);
  if (!ch.ok()) return R::failure(ch.error);
  p->character = std::move(*ch.value);
  const FrameOptions fo = frame_options_from_rig(p->rig);
  refine_for_frame(p->character, fo);
  p->frame = build_feature_frame(p->character, fo);
  for (const RigHandle& h : p->rig.handles) p->bindings.push_back(bind_point(p->frame, p->character, h.rest));
  const auto t0 = std::chrono::steady_clock::now();
  std::string err;
  const bool ok = p->solver.prepare(p->frame, p->bindings,
                                    SolverWeights{p->rig.w_rigidity, p->rig.w_coupling, p->rig.w_position, p->rig.anderson}, &err);
  p->prefactor_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!ok) return R::failure(path + ": " + err);
  p->mesh = prepare_mesh(p->character);
  for (const SubShape& s : p->character.shapes) p->shapes.push_back(s.points);
  return R::success(std::move(p));
}

}  // namespace mar
