// What a show resolves against before it runs (live.h): the names its rig offers, and the
// canvas it draws on.
#include "app/live.h"

namespace mar {

// What a show's names resolve against once its rig is loaded (load_show's RigLoader): the
// puppet's handles, the loop's and the solver's settings, the key poses, swap sets and triggers.
ShowRig show_rig(const Puppet& p, const ShowConfig& header) {
  ShowRig rig;
  for (const auto& h : p.rig.handles) rig.handles.push_back(h.name);
  rig.rest = p.rest_targets();
  rig.diag = p.diagonal;
  rig.settings.push_back({"iterations", std::pair<double, double>(header.min_iterations, header.iterations)});
  for (const SolverParameter& sp : p.solver->parameters()) rig.settings.push_back({sp.name, std::nullopt});
  // Key poses: morph.FROM.TO for every ordered pair of rest and the keys, blend.KEY per key.
  if (p.feature_frame() && !p.rig.keys.empty()) {
    std::vector<std::string> names{"rest"};
    for (const RigKey& k : p.rig.keys) names.push_back(k.name);
    for (size_t a = 0; a < names.size(); ++a)
      for (size_t b = 0; b < names.size(); ++b)
        if (a != b) rig.settings.push_back({"morph." + names[a] + "." + names[b], std::pair<double, double>(0, 1)});
    for (const RigKey& k : p.rig.keys) rig.settings.push_back({"blend." + k.name, std::pair<double, double>(0, 1)});
    for (const RigKey& k : p.rig.keys) rig.keys.push_back(k.name);
  }
  // Secondary motion: physics.NAME.strength|mix, physics.wind|gravity|reset.
  for (const PhysicsStage::SettingInfo& si : PhysicsStage::setting_names(p))
    rig.settings.push_back({si.name, std::pair<double, double>(si.lo, si.hi)});
  for (const RigSwap& sw : p.rig.swaps) rig.swaps.push_back({sw.name, sw.members});
  for (const RigTrigger& tr : p.rig.triggers) rig.triggers.push_back(tr.name);
  return rig;
}


// The canvas: [output]'s size, else the window's (a run's --size before either).
std::array<int, 2> canvas_size(const RunOptions& o, const ShowConfig& sh) {
  return {o.width > 0 ? o.width : sh.out_width > 0 ? sh.out_width : sh.width,
          o.height > 0 ? o.height : sh.out_height > 0 ? sh.out_height : sh.height};
}


}  // namespace mar
