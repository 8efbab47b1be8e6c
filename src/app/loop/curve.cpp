#include "app/loop/curve.h"

#include <algorithm>
#include <cmath>

namespace mar {

std::string CurveStage::prepare(const Puppet& p, const ShowCurve& spec, const std::string& where) {
  const FeatureFrameMethod* ff = p.feature_frame();
  if (!ff) return where + "the curve needs the feature frame (the rig's solver = \"feature_frame\")";
  const FeatureFrameSolver& core = ff->core();
  RigPhysics chain;  // (a chain of parts as secondary motion names one: rig/chains.h)
  chain.name = "curve";
  chain.parts = spec.parts;
  chain.from = spec.from;
  for (const std::string& id : spec.parts) {
    bool found = false;
    for (const SubShape& sh : p.character.shapes) found = found || sh.id == id;
    if (!found) return where + "part '" + id + "' is not a sub-shape of " + p.character.source + " (inspect lists them)";
  }
  auto geo = chain_geometry(p.character, p.rig, chain);
  if (!geo.ok()) {  // (said of the show's [[curve]], not of a rig's physics chain)
    const std::string rig_words = p.rig.path + ":0: physics chain 'curve'";
    std::string e = geo.error;
    if (e.rfind(rig_words, 0) == 0) e = "the chain" + e.substr(rig_words.size());
    return where + e;
  }
  geo_ = std::move(*geo.value);
  // The far end of a chain of two or more: the last part's point farthest on along the chain's
  // way (through where its last two parts hang), not merely the farthest from where the last
  // hangs (a head's side, not its top).
  {
    const size_t e = geo_.rest.size() - 1;  // (the tip)
    const Vec2 hang = geo_.rest[e - 1];
    const Vec2 before = e >= 2 ? geo_.rest[e - 2] : hang;
    const Vec2 way = hang - before;
    if (e >= 2 && way.norm() > 0) {  // (one part: its point farthest from where it hangs, a tail's end)
      double best = 0;
      for (const Vec2& q : p.character.shapes[size_t(geo_.shapes.back())].points)
        if ((q - hang).dot(way) > best) {
          best = (q - hang).dot(way);
          geo_.rest[e] = q;
        }
    }
  }
  axis_s_.assign(geo_.rest.size(), 0.0);
  for (size_t i = 1; i < geo_.rest.size(); ++i) axis_s_[i] = axis_s_[i - 1] + (geo_.rest[i] - geo_.rest[i - 1]).norm();
  const double length = axis_s_.back();
  if (!(length > 0)) return where + "the chain has no length (its parts hang at one point)";
  const FeatureFrame& f = ff->frame();
  // The chain's frame vertices, at most the solver's room (evenly sampled when more).
  std::vector<int> all;
  for (size_t v = 0; v < f.rest.size(); ++v)
    if (std::find(geo_.shapes.begin(), geo_.shapes.end(), f.origin[v].shape) != geo_.shapes.end()) all.push_back(int(v));
  if (all.empty()) return where + "the chain's parts have no frame points";
  const size_t room = size_t(core.soft_capacity());
  if (room == 0) return where + "the character's solver has no room for the curve's targets";
  ids_.clear();
  for (size_t k = 0; k < std::min(room, all.size()); ++k) ids_.push_back(all[k * all.size() / std::min(room, all.size())]);
  weights_.assign(ids_.size(), spec.strength);
  // Each vertex's place about the axis at rest: the arc length of its nearest axis point (past
  // either end, along the end's direction) and its signed distance along the left normal.
  s_.assign(ids_.size(), 0.0);
  n_.assign(ids_.size(), 0.0);
  defect_.assign(ids_.size(), Vec2::Zero());
  for (size_t i = 0; i < ids_.size(); ++i) {
    project(f.rest[size_t(ids_[i])], s_[i], n_[i]);
    Vec2 t;
    const Vec2 a = axis_at(s_[i], t);
    defect_[i] = f.rest[size_t(ids_[i])] - (a + n_[i] * Vec2(-t.y(), t.x()));
  }
  // The parent's handles carry where the chain hangs (none: the whole character's do); the
  // chain's own follow the curve.
  motion_.prepare(p);
  const std::span<const ShapeParam> bind = ff->bindings();
  parent_handles_.clear();
  chain_handles_.clear();
  for (int h : motion_.free_handles()) {
    const int shape = f.origin[size_t(bind[size_t(h)].a)].shape;
    if (shape == geo_.parent) parent_handles_.push_back(h);
    if (std::find(geo_.shapes.begin(), geo_.shapes.end(), shape) != geo_.shapes.end()) chain_handles_.push_back(h);
  }
  hs_.assign(chain_handles_.size(), 0.0);
  hn_.assign(chain_handles_.size(), 0.0);
  hdefect_.assign(chain_handles_.size(), Vec2::Zero());
  for (size_t i = 0; i < chain_handles_.size(); ++i) {
    const Vec2 x = p.rig.handles[size_t(chain_handles_[i])].rest;
    project(x, hs_[i], hn_[i]);
    Vec2 t;
    const Vec2 a = axis_at(hs_[i], t);
    hdefect_[i] = x - (a + hn_[i] * Vec2(-t.y(), t.x()));
  }
  hang_ = geo_.rest[0];
  min_step_ = 0.005 * length;
  min_length_ = 0.05 * length;
  frame_ = &f;
  return {};
}

void CurveStage::project(const Vec2& x, double& s, double& n) const {
  double best = INFINITY;
  for (size_t j = 0; j + 1 < geo_.rest.size(); ++j) {
    const Vec2 a = geo_.rest[j], d = geo_.rest[j + 1] - a;
    const double len = d.norm();
    if (!(len > 0)) continue;
    const Vec2 t = d / len;
    double u = (x - a).dot(t);
    if (j > 0) u = std::max(u, 0.0);
    if (j + 2 < geo_.rest.size()) u = std::min(u, len);
    const Vec2 q = a + u * t;
    if ((x - q).norm() < best) {
      best = (x - q).norm();
      s = axis_s_[j] + u;
      n = (x - q).dot(Vec2(-t.y(), t.x()));
    }
  }
}

Vec2 CurveStage::axis_at(double s, Vec2& tangent) const {
  const size_t m = geo_.rest.size();
  size_t j = 0;
  while (j + 2 < m && axis_s_[j + 1] < s) ++j;
  const Vec2 d = geo_.rest[j + 1] - geo_.rest[j];
  const double len = std::max(1e-12, axis_s_[j + 1] - axis_s_[j]);
  tangent = d / len;
  return geo_.rest[j] + (s - axis_s_[j]) * tangent;
}

Vec2 CurveStage::laid(double s, double n, double k) const {
  const double h = 2 * min_step_;
  const Vec2 d = curve_at(s + h) - curve_at(s - h);
  const double dn = d.norm();
  Vec2 c = curve_at(s), t = dn > 0 ? Vec2(d / dn) : Vec2(0, -1);
  if (k > 0) {  // toward the rest axis, carried by the handles
    Vec2 ta;
    const Vec2 a = home_.apply(axis_at(s, ta));
    const Vec2 th = home_.turn(ta);
    c += k * (a - c);
    const Vec2 mix = t + k * (th - t);
    t = mix.norm() > 1e-9 ? Vec2(mix / mix.norm()) : th;
  }
  return c + n * Vec2(-t.y(), t.x());
}

Vec2 CurveStage::lay(const Vec2& rest) const {
  double s = 0, n = 0;
  project(rest, s, n);
  return laid(s, n);
}

Vec2 CurveStage::curve_at(double s) const {
  // The stroke laid with its start where the chain hangs; before its start and past its end,
  // straight on along its first and last directions.
  if (n_stroke_ < 2) return hang_;
  const Vec2 at = hang_ - stroke_[0];
  const double len = stroke_s_[size_t(n_stroke_ - 1)];
  if (s <= 0) {
    const Vec2 t = (stroke_[1] - stroke_[0]) / std::max(1e-12, stroke_s_[1]);
    return stroke_[0] + at + s * t;
  }
  if (s >= len) {
    const size_t e = size_t(n_stroke_ - 1);
    const Vec2 t = (stroke_[e] - stroke_[e - 1]) / std::max(1e-12, stroke_s_[e] - stroke_s_[e - 1]);
    return stroke_[e] + at + (s - len) * t;
  }
  const auto* hi = std::upper_bound(stroke_s_.data(), stroke_s_.data() + n_stroke_, s);
  const size_t j = size_t(std::max<std::ptrdiff_t>(1, hi - stroke_s_.data()));
  const double seg = stroke_s_[j] - stroke_s_[j - 1], u = seg > 0 ? (s - stroke_s_[j - 1]) / seg : 0;
  return stroke_[j - 1] + u * (stroke_[j] - stroke_[j - 1]) + at;
}

void CurveStage::step(const Mapping::Pen& pen, const ShowCurve* spec, double dt, bool grabbing, std::span<const Vec2> targets,
                      Puppet& p) {
  if (!frame_) return;
  FeatureFrameSolver& solver = p.feature_frame()->core();
  motion_.set_targets(targets);
  hang_ = motion_.of(parent_handles_).apply(geo_.rest[0]);  // (once a frame: every laid point reads it)
  const bool on = spec && pen.down && !grabbing;
  if (on && !down_) {  // a new stroke replaces the curve
    down_ = true;
    releasing_ = false;
    hold_ = spec->release == ShowBrush::Hold;
    release_s_ = spec->release_seconds;
    n_stroke_ = 0;
    min_step_ = 0.005 * axis_length();
    ++strokes_;
  }
  if (down_ && on) {
    if (n_stroke_ == 0 || (pen.point - stroke_[size_t(n_stroke_ - 1)]).norm() >= min_step_) {
      if (n_stroke_ == kMaxStroke) {  // full: every other point, twice the step
        for (int i = 1; i < kMaxStroke / 2; ++i) stroke_[size_t(i)] = stroke_[size_t(2 * i)];
        n_stroke_ = kMaxStroke / 2;
        min_step_ *= 2;
        for (int i = 1; i < n_stroke_; ++i)
          stroke_s_[size_t(i)] = stroke_s_[size_t(i - 1)] + (stroke_[size_t(i)] - stroke_[size_t(i - 1)]).norm();
      }
      stroke_[size_t(n_stroke_)] = pen.point;
      stroke_s_[size_t(n_stroke_)] =
          n_stroke_ == 0 ? 0.0 : stroke_s_[size_t(n_stroke_ - 1)] + (pen.point - stroke_[size_t(n_stroke_ - 1)]).norm();
      ++n_stroke_;
    }
    if (!active_ && stroke_length() >= min_length_) {  // (long enough to have a direction)
      active_ = solver.set_soft(ids_, weights_);
    }
  } else if (down_) {  // lifted: kept, or springing back
    down_ = false;
    releasing_ = active_ && !hold_;
    release_t_ = 0;
  }
  if (!active_) return;
  spring_k_ = 0;
  if (releasing_) {
    release_t_ += dt;
    if (release_s_ <= 0 || release_t_ >= release_s_) {
      active_ = releasing_ = false;
      solver.clear_soft();
      return;
    }
  }
  place(p);
}

void CurveStage::place(Puppet& p) {
  FeatureFrameSolver& solver = p.feature_frame()->core();
  const std::span<Vec2> t = solver.soft_targets();
  // Springing back: the curve eases into the rest axis as the handles carry it.
  double k = 0;
  if (releasing_) {
    const double u = std::min(1.0, release_t_ / std::max(1e-9, release_s_));
    k = u * u * (3 - 2 * u);
    home_ = motion_.of({});
  }
  spring_k_ = k;
  for (size_t i = 0; i < ids_.size() && i < t.size(); ++i) t[i] = laid(s_[i], n_[i], k) + k * home_.turn(defect_[i]);
}

void CurveStage::drive_handles(std::span<Vec2> targets) const {
  if (!frame_ || !active_) return;
  const double k = spring_k_;
  for (size_t i = 0; i < chain_handles_.size(); ++i) {
    const size_t h = size_t(chain_handles_[i]);
    if (h >= targets.size()) continue;
    const Vec2 on = laid(hs_[i], hn_[i], k) + k * home_.turn(hdefect_[i]);
    // (springing, toward where the performer holds it: its own target as the spring ends)
    targets[h] = on + k * (targets[h] - home_.apply(motion_.rest(h)));
  }
}

void CurveStage::restore(Puppet& p) {
  if (!frame_ || !active_) return;
  active_ = p.feature_frame()->core().set_soft(ids_, weights_);
  if (active_) place(p);
}

}  // namespace mar
