#include "app/loop/brush.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>

namespace mar {

std::string BrushStage::prepare(const Puppet& p) {
  const FeatureFrameMethod* ff = p.feature_frame();
  if (!ff) return "the brush needs the feature frame (the rig's solver = \"feature_frame\")";
  if (ff->core().soft_capacity() < kMaxPoints) return "the character's solver has no room for the brush's targets";
  const FeatureFrame& f = ff->frame();
  const size_t q = f.rest.size();
  contour_of_.assign(q, -1);
  at_in_contour_.assign(q, -1);
  contour_closed_.assign(f.subframes.size(), 0);
  for (size_t c = 0; c < f.subframes.size(); ++c) {
    const std::vector<int>& list = f.subframes[c];
    for (size_t k = 0; k < list.size(); ++k) {
      contour_of_[size_t(list[k])] = int(c);
      at_in_contour_[size_t(list[k])] = int(k);
    }
    if (!list.empty()) {
      const int shape = f.origin[size_t(list.front())].shape;
      contour_closed_[c] = shape >= 0 && size_t(shape) < p.character.shapes.size() && p.character.shapes[size_t(shape)].closed();
    }
  }
  // Each part's handles (a handle is bound to a line of the frame: its first vertex's part;
  // none: the part goes as the whole character's handles ask).
  motion_.prepare(p);
  frame_ = &f;
  return {};
}

void BrushStage::touch(const Vec2& at, double radius, const ShowBrush& spec, Puppet& p) {
  FeatureFrameSolver& solver = p.feature_frame()->core();
  const std::span<const Vec2> v = solver.vertices();
  const FeatureFrame& f = *frame_;
  // The focal point: the outline's vertex nearest the pen, as the character is drawn now.
  focal_ = -1;
  double best = radius;
  for (size_t i = 0; i < v.size(); ++i)
    if (contour_of_[i] >= 0 && (v[i] - at).norm() <= best) {
      best = (v[i] - at).norm();
      focal_ = int(i);
    }
  if (focal_ < 0) return;  // (nothing of the outline under the brush)
  // What earlier strokes left is this stroke's base.
  for (int i = 0; i < n_; ++i) {
    pts_[size_t(i)].base = pts_[size_t(i)].offset;
    pts_[size_t(i)].d = 0;
  }
  releasing_ = false;
  const double sigma = radius / 3;
  // A vertex of this stroke: brushed (d from s), or an anchor just beyond the radius (d = 0: it
  // holds what it had, so the stroke bends the outline where it brushes and does not pull the
  // part away).
  auto add = [&](int vert, double s, bool anchor) {
    int at_i = -1;
    for (int i = 0; i < n_ && at_i < 0; ++i)
      if (pts_[size_t(i)].v == vert) at_i = i;
    if (at_i < 0) {
      if (n_ >= kMaxPoints) {  // full: the oldest stroke's first vertex lets go
        int old = -1;
        for (int i = 0; i < n_; ++i)
          if (pts_[size_t(i)].stroke <= strokes_ && (old < 0 || pts_[size_t(i)].stroke < pts_[size_t(old)].stroke)) old = i;
        if (old < 0) return;  // (this stroke fills it: the farthest are left out)
        for (int i = old; i + 1 < n_; ++i) pts_[size_t(i)] = pts_[size_t(i + 1)];
        --n_;
      }
      at_i = n_++;
      pts_[size_t(at_i)] = Point{vert, f.origin[size_t(vert)].shape, 0, s, Vec2::Zero(), Vec2::Zero(), strokes_ + 1};
    } else if (pts_[size_t(at_i)].d > 0 && pts_[size_t(at_i)].s <= s) {
      return;  // (reached both ways round a small contour: the nearer way counts)
    }
    pts_[size_t(at_i)].s = s;
    pts_[size_t(at_i)].d = anchor ? 0.0 : portable_exp_neg(-s * s / (2 * sigma * sigma));  // (the same bits on arm64)
    pts_[size_t(at_i)].stroke = strokes_ + 1;
  };
  add(focal_, 0, false);
  // Along the contour both ways from the focal point, by arc length on the rest drawing: the
  // brushed vertices within the radius, then the anchors up to twice it.
  const int c = contour_of_[size_t(focal_)];
  const std::vector<int>& list = f.subframes[size_t(c)];
  const int m = int(list.size());
  for (int pass = 0; pass < 2; ++pass)
    for (int dir : {1, -1}) {
      double s = 0;
      int k = at_in_contour_[size_t(focal_)], anchors = 0;
      for (int step = 1; step < m && anchors < kAnchors; ++step) {
        int next = k + dir;
        if (next < 0 || next >= m) {
          if (!contour_closed_[size_t(c)]) break;
          next = (next + m) % m;
        }
        s += (f.rest[size_t(list[size_t(next)])] - f.rest[size_t(list[size_t(k)])]).norm();
        if (s > 2 * radius || (pass == 0 && s > radius)) break;
        if ((pass == 0) == (s <= radius)) {
          add(list[size_t(next)], s, pass == 1);
          anchors += pass;
        }
        k = next;
      }
    }
  radius_ = radius;
  strength_ = spec.strength;
  for (int i = 0; i < n_; ++i) {
    ids_[size_t(i)] = pts_[size_t(i)].v;
    weights_[size_t(i)] = strength_;
  }
  if (!solver.set_soft(std::span<const int>(ids_.data(), size_t(n_)), std::span<const double>(weights_.data(), size_t(n_)))) {
    n_ = 0;
    focal_ = -1;
    return;
  }
  pen0_ = at;
  down_ = true;
  ++strokes_;
}

void BrushStage::step(const Mapping::Pen& pen, const ShowBrush* spec, double px_per_unit, double dt, bool grabbing,
                      std::span<const Vec2> targets, Puppet& p) {
  if (!frame_) return;
  motion_.set_targets(targets);
  FeatureFrameSolver& solver = p.feature_frame()->core();
  const bool on = spec && pen.down && !grabbing;
  if (on && !down_) {
    hold_ = spec->release == ShowBrush::Hold;
    release_s_ = spec->release_seconds;
    const double px = spec->radius_lo + std::clamp(pen.pressure, 0.0, 1.0) * (spec->radius_hi - spec->radius_lo);
    touch(pen.point, px / std::max(1e-9, px_per_unit), *spec, p);
  } else if (!on && down_) {  // let go: held, or springing back
    down_ = false;
    for (int i = 0; i < n_; ++i) {
      pts_[size_t(i)].base = pts_[size_t(i)].offset;
      pts_[size_t(i)].d = 0;
    }
    releasing_ = !hold_;
    release_t_ = 0;
  }
  if (n_ == 0) return;
  if (down_) {  // the drag, in each part's rest frame
    const Vec2 drag = pen.point - pen0_;
    int part = -1;
    Vec2 back = drag;
    for (int i = 0; i < n_; ++i) {
      Point& pt = pts_[size_t(i)];
      if (pt.d <= 0) continue;
      if (pt.part != part) {  // (a stroke's points are one contour's: one part, one fit)
        part = pt.part;
        back = motion_.of_part(part).back(drag);
      }
      pt.offset = pt.base + pt.d * back;
    }
  } else if (releasing_) {
    release_t_ += dt;
    const double u = release_s_ > 0 ? std::min(1.0, release_t_ / release_s_) : 1.0;
    const double k = 1 - u * u * (3 - 2 * u);
    for (int i = 0; i < n_; ++i) pts_[size_t(i)].offset = k * pts_[size_t(i)].base;
    if (u >= 1) {
      n_ = 0;
      releasing_ = false;
      solver.clear_soft();
      return;
    }
  }
  apply(p);
}

void BrushStage::apply(Puppet& p) {
  FeatureFrameSolver& solver = p.feature_frame()->core();
  const std::span<Vec2> t = solver.soft_targets();
  int part = -1;
  RigidMotion mo;
  for (int i = 0; i < n_ && size_t(i) < t.size(); ++i) {
    const Point& pt = pts_[size_t(i)];
    if (pt.part != part) {  // (earlier strokes may hold other parts)
      part = pt.part;
      mo = motion_.of_part(part);
    }
    t[size_t(i)] = mo.apply(frame_->rest[size_t(pt.v)] + pt.offset);
  }
}

void BrushStage::restore(Puppet& p) {
  if (!frame_ || n_ == 0) return;
  FeatureFrameSolver& solver = p.feature_frame()->core();
  if (!solver.set_soft(std::span<const int>(ids_.data(), size_t(n_)), std::span<const double>(weights_.data(), size_t(n_)))) {
    n_ = 0;
    return;
  }
  apply(p);
}

}  // namespace mar
