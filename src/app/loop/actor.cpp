#include "app/loop/actor.h"

#include "app/keys.h"
#include "app/loop/hud.h"
#include "geom/polygon.h"

#include <algorithm>

namespace mar {

std::string Actor::prepare(std::shared_ptr<Puppet> p, const ShowConfig& sh, Mapping& m, size_t handle0, size_t swap0,
                           size_t trigger0, int who) {
  puppet_ = std::move(p);
  Puppet& pp = *puppet_;
  r_.handle0 = handle0;
  r_.handles = pp.rig.handles.size();
  r_.who = who;
  // Its settings, in the order its ShowRig names them (live_setup.cpp show_rig): the solver's
  // parameters (a change re-factorises), its key poses' (0..1), its chains'.
  r_.solver0 = int(m.setting_count());
  for (const SolverParameter& sp : pp.loaded_parameters) {
    m.add_setting({sp.value, sp.lo, sp.hi, false});
    solver_params_.push_back(sp.value);
  }
  if (pp.feature_frame() && !pp.rig.keys.empty()) keys_.add_settings(m, int(pp.rig.keys.size()));
  physics_.prepare(pp, sh.physics);
  r_.physics0 = int(m.setting_count());
  for (const PhysicsStage::SettingInfo& si : physics_.settings()) m.add_setting({si.value, si.lo, si.hi, false});
  // The keys are solved once, whether a binding drives them or not: a reload that keeps this
  // puppet reads them instead of posing it (Puppet::solved_keys). Only the key settings a
  // binding drives count; their interpolation is prepared when one does.
  // (a rig whose keys cannot be solved is refused only when a binding drives them)
  bool driven = keys_.keep_driven(sh, who);
  for (const ShowBrush& br : sh.brushes) driven = driven || (br.who == who && br.release == ShowBrush::Key);
  for (const ShowCurve& c : sh.curves) driven = driven || (c.who == who && c.release == ShowBrush::Key);
  if (!pp.solved_keys && (driven || (pp.feature_frame() && !pp.rig.keys.empty()))) {
    std::vector<Points> details;
    auto keys = solve_keys(pp, &details);
    if (!keys.ok() && driven) return keys.error;
    if (keys.ok()) {
      pp.solved_keys = std::make_shared<const std::vector<Points>>(std::move(*keys.value));
      pp.key_details = std::make_shared<const std::vector<Points>>(std::move(details));
    }
  }
  if (driven) {
    if (std::string err = keys_.prepare(pp, *pp.solved_keys, pp.key_details.get()); !err.empty()) return err;
    if (keys_.has_detail()) detailed_v_.assign(pp.feature_frame()->frame().rest.size(), Vec2::Zero());
    key_values_.assign(keys_.settings().size(), 0.0);
  }
  for (const ShowBrush& br : sh.brushes)  // a [[brush]] sculpts it (loop/brush.h)
    if (br.who == who && !brush_.prepared())
      if (std::string e = brush_.prepare(pp); !e.empty()) return sh.path + ":" + std::to_string(br.line) + ": [[brush]]: " + e;
  for (const ShowCurve& c : sh.curves)  // a [[curve]] lays a chain along a stroke (loop/curve.h)
    if (c.who == who) {
      const std::string where = sh.path + ":" + std::to_string(c.line) + ": [[curve]]: ";
      if (brush_.prepared() || curve_.prepared() || contour_.prepared())
        return where + "a character takes one pen tool, a [[brush]] or a [[curve]] (they share its solver's soft targets)";
      if (std::string e = c.fit == ShowCurve::Contour ? contour_.prepare(pp, c, where) : curve_.prepare(pp, c, where); !e.empty())
        return e;
    }
  r_.swap0 = swap0;
  r_.swaps = pp.rig.swaps.size();
  r_.trigger0 = trigger0;
  r_.triggers = pp.rig.triggers.size();
  presence_ = shown ? 1 : 0;
  rest_bounds = pp.character.bounds();
  rest_cover = cover_cells(pp.character, rest_bounds, kCoverCells);  // (the HUD keeps off them)
  solve_targets_ = pp.rest_targets();
  solve_targets_.push_back(Vec2::Zero());  // the grab's temporary handle (used while grabbing)
  n_solve_ = r_.handles;
  return {};
}

bool Actor::apply_settings(const Mapping& m) {
  bool changed = false;
  for (size_t k = 0; k < solver_params_.size(); ++k) {
    const double v = m.setting(r_.solver0 + int(k));
    changed = changed || v != solver_params_[k];
    solver_params_[k] = v;
  }
  if (!changed) return false;
  puppet_->solver->set_parameters(solver_params_, nullptr);
  grab_.restore(m.grab_point(), *puppet_);
  brush_.restore(*puppet_);
  curve_.restore(*puppet_);
  contour_.restore(*puppet_);
  return true;
}

void Actor::apply_grab(const Vec2& point, std::span<Vec2> targets) {
  n_solve_ = grab_.apply(point, targets, solve_targets_.back());
}

void Actor::solve(std::span<const Vec2> targets, int iterations) {
  const bool was_down = brush_.down() || curve_.drawing() || contour_.drawing();
  if (brush_.prepared()) brush_.step(pen_, pen_spec_, px_per_unit, pen_dt_, grab_.active(), targets, *puppet_);
  if (curve_.prepared()) curve_.step(pen_, curve_spec_, pen_dt_, grab_.active(), targets, *puppet_);
  if (contour_.prepared()) contour_.step(pen_, curve_spec_, pen_dt_, grab_.active(), targets, *puppet_);
  const bool is_down = brush_.down() || curve_.drawing() || contour_.drawing();
  // A tool that lets go into a key pose: its shape springs back while the next frames' poses
  // recall the key over the same seconds (KeyPoseStage's recall, as `pose.KEY` asks).
  if (!was_down && is_down) {
    tool_release_ = pen_spec_ ? pen_spec_->release : curve_spec_ ? curve_spec_->release : ShowBrush::Spring;
    tool_recall_.key = pen_spec_ ? pen_spec_->key : curve_spec_ ? curve_spec_->key : -1;
    tool_recall_.seconds = pen_spec_ ? pen_spec_->release_seconds : curve_spec_ ? curve_spec_->release_seconds : 0;
    tool_recall_.who = r_.who;
  }
  if (was_down && !is_down && tool_release_ == ShowBrush::Key) tool_recall_on_ = true;
  std::copy(targets.begin(), targets.end(), solve_targets_.begin());
  if (curve_.prepared()) curve_.drive_handles(std::span<Vec2>(solve_targets_.data(), targets.size()));
  puppet_->solver->solve(std::span<const Vec2>(solve_targets_.data(), n_solve_), iterations);
}

double Actor::reconstruct() {
  Puppet& p = *puppet_;
  if (keys_.detailed()) {  // a sculpted key's detail on the solve (KeyPoseStage::detail_onto)
    const FeatureFrameMethod& ff = *p.feature_frame();
    keys_.detail_onto(ff.core().vertices(), detailed_v_);
    ff.place(detailed_v_, p.shapes);
  } else {
    p.reconstruct();
  }
  // After a reload, the figure moves from where the running show drew it to where this show's
  // solver puts it over kReloadBlendFrames (the new solver starts from its own guess, up to 6 %
  // of the figure away): no jump in one frame (Reload.TheFigureDoesNotJumpAtAReload).
  if (blend_left_ > 0) {
    const double u = 1.0 - double(blend_left_) / double(kReloadBlendFrames + 1), w = u * u * (3 - 2 * u);
    for (size_t k = 0; k < p.shapes.size(); ++k)
      for (size_t i = 0; i < p.shapes[k].size(); ++i) p.shapes[k][i] = blend_from_[k][i] + w * (p.shapes[k][i] - blend_from_[k][i]);
    --blend_left_;
  }
  // Pose quality: the worst part's distortion (RMS residual of its best rigid fit to its rest
  // shape), in percent of the character's height.
  double worst = 0;
  worst_shape_ = -1;
  for (size_t k = 0; k < p.shapes.size(); ++k)
    if (const double d = rigid_fit_rms(p.character.shapes[k].points, p.shapes[k]); d > worst) {
      worst = d;
      worst_shape_ = int(k);
    }
  return worst * 100.0 / std::max(1e-9, p.character.height);
}

void Actor::draw(DrawList& list) const {
  const Puppet& p = *puppet_;
  build_draw_list(p.character, p.mesh, p.shapes, drawn_view(), 0.3, list, p.shown, opacity());
}

void Actor::stage_step(bool on, double dt) {
  const double step = entrance_s > 0 ? dt / entrance_s : 1.0;
  presence_ = on ? std::min(1.0, presence_ + step) : std::max(0.0, presence_ - step);
}

namespace {
double smooth(double u) { return u * u * (3 - 2 * u); }
}  // namespace

size_t Actor::layer_depth() const {
  size_t depth = 0;
  std::vector<int> ends;
  for (const Composite& c : puppet_->character.composites) {
    while (!ends.empty() && ends.back() <= c.first) ends.pop_back();
    ends.push_back(c.end);
    depth = std::max(depth, ends.size());
  }
  return depth + (fade ? 1 : 0);
}

float Actor::opacity() const { return fade ? float(smooth(presence_)) : 1.0f; }

Affine2 Actor::drawn_view() const {
  if (fade || presence_ >= 1) return view;
  const Vec2 o = (1 - smooth(presence_)) * offstage;
  return Affine2::translate(o.x(), o.y()) * view;
}

void Actor::carry_from(const Actor& old) {
  physics_.carry_from(old.physics_);  // the chains go on swinging
}

void Actor::take_puppet_from(Actor& old) {
  if (puppet_ != old.puppet_) return;
  // The reload kept the running show's puppet (its files unchanged): its solver goes on from
  // where it is, with the parameters it has and no grab of the old actor's left in it.
  old.set_grab(false, Vec2::Zero());
  solver_params_ = old.solver_params_;
  if (brush_.prepared() && old.brush_.prepared()) brush_ = old.brush_;  // (what it brushed stays)
  else if (curve_.prepared() && old.curve_.prepared()) curve_ = old.curve_;  // (and the curve it took)
  else if (contour_.prepared() && old.contour_.prepared()) contour_ = old.contour_;
  else if (FeatureFrameMethod* ff = puppet_->feature_frame()) ff->core().clear_soft();
}

void Actor::carry_shapes_from(const Actor& old) {
  if (puppet_ == old.puppet_) return;  // (the same shapes, going on)
  Puppet& p = *puppet_;
  const Puppet& o = *old.puppet_;
  bool same = o.shapes.size() == p.shapes.size();
  for (size_t k = 0; same && k < p.shapes.size(); ++k) same = o.shapes[k].size() == p.shapes[k].size();
  if (!same) return;
  blend_from_ = o.shapes;
  blend_left_ = kReloadBlendFrames;
  p.shapes = o.shapes;
}

}  // namespace mar
