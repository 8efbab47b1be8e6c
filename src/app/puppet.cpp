#include "app/puppet.h"
#include "rig/auto_rig.h"

#include "base/read_file.h"
#include "character/load.h"
#include "render/canvas.h"
#include "render/overlay.h"
#include "solve/make_solver.h"
#include "solve/arap.h"
#include "solve/rigid_grid.h"

#include <algorithm>
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
  // A show's chain ends are soft targets (RigPhysics::weight).
  for (const PuppetChain& c : chains)
    for (size_t h : c.handles) {
      if (w.handle_weights.size() <= h) w.handle_weights.resize(rig.handles.size(), 1.0);
      w.handle_weights[h] = c.spec->weight;
    }
  return w;
}

void append_solver_overlay(const Puppet& p, std::span<const Vec2> handle_points, const Affine2& view, DrawList& list) {
  if (const FeatureFrameMethod* ff = p.feature_frame()) append_frame_overlay(ff->frame(), ff->core().vertices(), handle_points, view, list);
  if (const auto* arap = dynamic_cast<const OutlineArap*>(p.solver.get()))
    append_mesh_overlay(arap->vertices(), arap->triangles(), handle_points, view, list);
  if (const auto* grid = dynamic_cast<const RigidGrid*>(p.solver.get()))
    append_grid_overlay(grid->nodes(), grid->grid_nodes(), grid->grid_edges(), grid->junction_triangles(), handle_points, view, list);
}

std::string puppet_stamp(const Puppet& p) {
  std::vector<std::string> files{p.rig.path, p.character.source};
  if (!p.rig.mask.empty()) files.push_back(p.rig.mask_path());
  for (const RigKey& k : p.rig.keys)
    if (!k.frame.empty()) files.push_back(p.rig.beside(k.frame));
  std::string stamp;
  for (const std::string& f : files) {
    if (f.empty()) continue;
    const Result<std::string> bytes = read_file(f, kMaxPngBytes, "a character's file");
    if (!bytes.ok()) return {};
    uint64_t h = 1469598103934665603ull;  // FNV-1a
    for (const char c : *bytes.value) h = (h ^ uint8_t(c)) * 1099511628211ull;
    stamp += f + " " + std::to_string(bytes.value->size()) + " " + std::to_string(h) + "\n";
  }
  return stamp;
}

Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, const std::string& rig_path,
                                            const std::string& mask_path, bool physics, bool images_anywhere, std::array<int, 2> canvas) {
  Result<Rig> rig = load_rig(rig_path);
  if (!rig.ok()) return Result<std::unique_ptr<Puppet>>::failure(rig.error);
  return load_puppet(character_path, std::move(*rig.value), mask_path, physics, images_anywhere, canvas);
}

Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, Rig rig, const std::string& mask_path, bool physics,
                                            bool images_anywhere, std::array<int, 2> canvas) {
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
  lo.images_anywhere = images_anywhere;
  if (canvas[0] > 0 && canvas[1] > 0)  // (as the show places it: LiveShow's view)
    lo.pixels_per_unit = [canvas](double w, double h) { return fit_view(w, h, canvas[0], canvas[1], kShowMargin).max_scale(); };
  if (mask_path.empty()) {  // the rig's mask goes with the rig's character
    std::error_code ec;
    const bool own = character_path.empty() || std::filesystem::weakly_canonical(character_path, ec) ==
                                                   std::filesystem::weakly_canonical(p->rig.character_path(), ec);
    if (own) lo.mask_path = p->rig.mask_path();
  }
  Result<Character> ch = load_character(path, lo);
  if (!ch.ok()) return R::failure(ch.error);
  p->character = std::move(*ch.value);
  // A plain rig's limbs turn at their drawn joints (rig/auto_rig.h), not about the middle of
  // where they overlap their parent: hinges the rig does not state come from the drawing.
  if (p->rig.solver == "feature_frame" && p->rig.auto_joints) add_drawn_joints(p->character, p->rig);
  // A show's chains: each link end is a handle after the rig's own — but a handle the rig has
  // on the last part (the one farthest from where the chain hangs) is its end and is driven.
  if (physics)
    for (const RigPhysics& ph : p->rig.physics) {
      auto geo = chain_geometry(p->character, p->rig, ph);
      if (!geo.ok()) return R::failure(geo.error);
      PuppetChain c;
      c.spec = &ph;
      c.geo = std::move(*geo.value);
      const SubShape& last = p->character.shapes[size_t(c.geo.shapes.back())];
      const Bounds lb = last.bounds();
      const double near = 0.02 * (lb.empty() ? 1.0 : (lb.hi - lb.lo).norm() + 1.0);
      const Vec2 hang = c.geo.rest[c.geo.rest.size() - 2];
      int own = ph.handle.empty() ? -1 : p->rig.find_handle(ph.handle);
      for (size_t h = 0; h < p->rig.handles.size() && ph.handle.empty(); ++h) {
        const RigHandle& rh = p->rig.handles[h];
        if (rh.physics) continue;
        bool on = last.closed() && last.contains(rh.rest);
        for (const Vec2& q : last.points) on = on || (q - rh.rest).norm() <= near;
        if (on && (own < 0 || (rh.rest - hang).norm() > (p->rig.handles[size_t(own)].rest - hang).norm())) own = int(h);
      }
      for (const PuppetChain& o : p->chains)
        if (own >= 0 && std::find(o.handles.begin(), o.handles.end(), size_t(own)) != o.handles.end()) {
          if (!ph.handle.empty())
            return R::failure(p->rig.path + ":" + std::to_string(ph.line) + ": physics chain '" + ph.name + "': handle '" + ph.handle +
                              "' is the end of chain '" + o.spec->name + "' already");
          own = -1;  // taken: this chain gets its own
        }
      if (own >= 0 && (p->rig.handles[size_t(own)].rest - hang).norm() > 1e-6) c.geo.rest.back() = p->rig.handles[size_t(own)].rest;
      else own = -1;
      const size_t links = c.geo.shapes.size();
      for (size_t i = 0; i < links; ++i) {
        if (i + 1 == links && own >= 0) {
          c.handles.push_back(size_t(own));
          continue;
        }
        RigHandle h;
        h.name = "physics." + ph.name + (i + 1 < links ? "." + std::to_string(i + 1) : "");
        if (p->rig.find_handle(h.name) >= 0) return R::failure(p->rig.path + ": a handle is named '" + h.name + "', the name of a chain's end");
        h.rest = c.geo.rest[i + 1];
        h.physics = true;
        c.handles.push_back(p->rig.handles.size());
        p->rig.handles.push_back(h);
      }
      p->chains.push_back(std::move(c));
    }
  // Swap members and trigger shapes are sub-shapes of the character.
  std::string bad;
  auto shape_indices = [&](const std::vector<std::string>& ids, int line, const std::string& what) {
    std::vector<int> out;
    for (const std::string& id : ids) {
      int found = -1;
      for (size_t k = 0; k < p->character.shapes.size() && found < 0; ++k)
        if (p->character.shapes[k].id == id) found = int(k);
      if (found < 0 && bad.empty())
        bad = p->rig.path + ":" + std::to_string(line) + ": " + what + " names '" + id + "', which is not a sub-shape of " + path +
              " (inspect lists them)";
      out.push_back(found);
    }
    return out;
  };
  for (const RigSwap& sw : p->rig.swaps) p->swap_shapes.push_back(shape_indices(sw.members, sw.line, "swap set '" + sw.name + "'"));
  for (const RigTrigger& tr : p->rig.triggers)
    p->trigger_shapes.push_back(shape_indices(tr.shapes, tr.line, "trigger '" + tr.name + "'"));
  if (!bad.empty()) return R::failure(bad);
  p->shown.assign(p->character.shapes.size(), 1);
  std::vector<int> defaults;
  for (const RigSwap& sw : p->rig.swaps) defaults.push_back(sw.default_member);
  p->show(defaults, std::vector<char>(p->rig.triggers.size(), 0));
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
  for (PuppetChain& c : p->chains) {
    const Bounds pb = p->character.shapes[size_t(c.geo.parent)].bounds();
    c.reach = pb.empty() ? 1.0 : std::max(1e-6, (pb.hi - pb.lo).norm() / 3);
  }
  p->mesh = prepare_mesh(p->character);
  for (const SubShape& s : p->character.shapes) p->shapes.push_back(s.points);
  p->loaded_parameters = p->solver->parameters();
  p->stamp = puppet_stamp(*p);
  return R::success(std::move(p));
}

void Puppet::show(std::span<const int> members, std::span<const char> triggers_on) {
  for (size_t k = 0; k < shown.size(); ++k) shown[k] = !character.shapes[k].hidden;  // alternatives the file hides
  for (size_t i = 0; i < swap_shapes.size() && i < members.size(); ++i)
    for (size_t m = 0; m < swap_shapes[i].size(); ++m) shown[size_t(swap_shapes[i][m])] = int(m) == members[i];
  for (size_t t = 0; t < trigger_shapes.size(); ++t)  // a trigger that is off hides its shapes
    if (t >= triggers_on.size() || !triggers_on[t])
      for (int k : trigger_shapes[t]) shown[size_t(k)] = 0;
  for (size_t t = 0; t < trigger_shapes.size() && t < triggers_on.size(); ++t) {
    if (!triggers_on[t]) continue;
    for (int k : trigger_shapes[t]) {  // one that is on shows them, over their swap sets
      for (const std::vector<int>& set : swap_shapes)
        if (std::find(set.begin(), set.end(), k) != set.end())
          for (int o : set) shown[size_t(o)] = 0;
      shown[size_t(k)] = 1;
    }
  }
}

}  // namespace mar
