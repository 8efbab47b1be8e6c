#include "app/loop/contour.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>

namespace mar {

std::string ContourStage::prepare(const Puppet& p, const ShowCurve& spec, const std::string& where) {
  const FeatureFrameMethod* ff = p.feature_frame();
  if (!ff) return where + "the contour fit needs the feature frame (the rig's solver = \"feature_frame\")";
  if (ff->core().soft_capacity() < kMaxPoints + 2 * kAnchors) return where + "the character's solver has no room for the fit's targets";
  for (const std::string& id : spec.parts) {
    bool found = false;
    for (const SubShape& sh : p.character.shapes) found = found || sh.id == id;
    if (!found) return where + "part '" + id + "' is not a sub-shape of " + p.character.source + " (inspect lists them)";
  }
  const FeatureFrame& f = ff->frame();
  const size_t q = f.rest.size();
  contour_of_.assign(q, -1);
  at_in_contour_.assign(q, -1);
  rest_s_.assign(q, 0.0);
  contour_closed_.assign(f.subframes.size(), 0);
  allowed_.assign(f.subframes.size(), 0);
  bool any = false;
  for (size_t c = 0; c < f.subframes.size(); ++c) {
    const std::vector<int>& list = f.subframes[c];
    if (list.size() < 3) continue;  // (a point or a line: nothing to redraw)
    const int shape = f.origin[size_t(list.front())].shape;
    const SubShape& sh = p.character.shapes[size_t(shape)];
    contour_closed_[c] = sh.closed();
    allowed_[c] = spec.parts.empty() || std::find(spec.parts.begin(), spec.parts.end(), sh.id) != spec.parts.end();
    any = any || allowed_[c];
    double s = 0;
    for (size_t k = 0; k < list.size(); ++k) {
      if (k > 0) s += (f.rest[size_t(list[k])] - f.rest[size_t(list[k - 1])]).norm();
      contour_of_[size_t(list[k])] = int(c);
      at_in_contour_[size_t(list[k])] = int(k);
      rest_s_[size_t(list[k])] = s;
    }
  }
  if (!any) return where + "the parts have no outline on the frame to fit";
  motion_.prepare(p);
  seen_.assign(q, Vec2::Zero());
  min_step_ = 0.002 * p.diagonal;
  reach_ = 0.08 * p.diagonal;
  frame_ = &f;
  return {};
}

int ContourStage::nearest(const Vec2& at, int contour, std::span<const Vec2> v, double reach) const {
  int best = -1;
  double bd = reach * reach;
  for (size_t i = 0; i < v.size(); ++i) {
    const int c = contour_of_[i];
    if (c < 0 || !allowed_[size_t(c)] || (contour >= 0 && c != contour)) continue;
    if (const double d = (v[i] - at).squaredNorm(); d < bd) {
      bd = d;
      best = int(i);
    }
  }
  return best;
}

void ContourStage::choose(int end, Puppet& p) {
  const FeatureFrame& f = *frame_;
  const std::vector<int>& list = f.subframes[size_t(c_)];
  const int m = int(list.size());
  const int ia = at_in_contour_[size_t(a_)], ib = at_in_contour_[size_t(end)];
  int dir = ib >= ia ? 1 : -1, steps = std::abs(ib - ia);
  if (contour_closed_[size_t(c_)]) {  // the shorter way round, by arc length at rest
    const double total = rest_s_[size_t(list.back())] + (f.rest[size_t(list.back())] - f.rest[size_t(list.front())]).norm();
    const double fwd = std::fmod(rest_s_[size_t(end)] - rest_s_[size_t(a_)] + total, total);
    dir = fwd <= total - fwd ? 1 : -1;
    steps = dir > 0 ? (ib - ia + m) % m : (ia - ib + m) % m;
  }
  const int count = std::min(steps + 1, kMaxPoints);
  auto at = [&](int j) {  // the contour's vertex j steps from a_ (-1: off an open contour's end)
    int k = ia + dir * j;
    if (contour_closed_[size_t(c_)]) return list[size_t(((k % m) + m) % m)];
    return k >= 0 && k < m ? list[size_t(k)] : -1;
  };
  int n = 0;
  for (int j = 0; j < count; ++j) ids_[size_t(n++)] = at(j);
  seg_ = n;
  // Anchors beyond both ends, where the contour has them and the segment does not take them.
  for (int side : {-1, 1})
    for (int j = 1; j <= kAnchors; ++j) {
      const int v = at(side < 0 ? -j : count - 1 + j);
      if (v < 0 || std::find(ids_.begin(), ids_.begin() + n, v) != ids_.begin() + n) break;
      held_[size_t(n)] = seen_[size_t(v)];
      ids_[size_t(n++)] = v;
    }
  // Arc fractions, and the detail: each vertex's offset from the segment's gross shape at rest
  // (its least-squares quadratic in arc fraction: an arc of a cheek is all shape, a zigzag on it
  // is all detail), along and across that shape's direction.
  double total = 0;
  u_[0] = 0;
  for (int j = 1; j < seg_; ++j) {
    total += (f.rest[size_t(ids_[size_t(j)])] - f.rest[size_t(ids_[size_t(j - 1)])]).norm();
    u_[size_t(j)] = total;
  }
  for (int j = 0; j < seg_; ++j) u_[size_t(j)] = total > 0 ? u_[size_t(j)] / total : 0.0;
  const int order = seg_ >= 4 ? 3 : std::min(seg_, 2);  // coefficients: quadratic, a chord, a point
  double mat[3][3] = {}, bx[3] = {}, by[3] = {};
  for (int j = 0; j < seg_; ++j) {
    const double pw[3] = {1, u_[size_t(j)], u_[size_t(j)] * u_[size_t(j)]};
    const Vec2& r = f.rest[size_t(ids_[size_t(j)])];
    for (int x = 0; x < order; ++x) {
      for (int y = 0; y < order; ++y) mat[x][y] += pw[x] * pw[y];
      bx[x] += pw[x] * r.x();
      by[x] += pw[x] * r.y();
    }
  }
  for (int col = 0; col < order; ++col)  // (Gaussian elimination; the fractions span [0, 1]: well posed)
    for (int row = col + 1; row < order; ++row) {
      const double k = mat[col][col] != 0 ? mat[row][col] / mat[col][col] : 0.0;
      for (int x = col; x < order; ++x) mat[row][x] -= k * mat[col][x];
      bx[row] -= k * bx[col];
      by[row] -= k * by[col];
    }
  double cx[3] = {}, cy[3] = {};
  for (int row = order - 1; row >= 0; --row) {
    double sx = bx[row], sy = by[row];
    for (int x = row + 1; x < order; ++x) {
      sx -= mat[row][x] * cx[x];
      sy -= mat[row][x] * cy[x];
    }
    cx[row] = mat[row][row] != 0 ? sx / mat[row][row] : 0.0;
    cy[row] = mat[row][row] != 0 ? sy / mat[row][row] : 0.0;
  }
  const Vec2 chord = f.rest[size_t(ids_[size_t(seg_ - 1)])] - f.rest[size_t(ids_[0])];
  for (int j = 0; j < seg_; ++j) {
    const double u = u_[size_t(j)];
    const Vec2 base(cx[0] + cx[1] * u + cx[2] * u * u, cy[0] + cy[1] * u + cy[2] * u * u);
    Vec2 t(cx[1] + 2 * cx[2] * u, cy[1] + 2 * cy[2] * u);
    if (!(t.norm() > 0)) t = chord;
    t = t.norm() > 0 ? Vec2(t / t.norm()) : Vec2(1, 0);
    const Vec2 d = f.rest[size_t(ids_[size_t(j)])] - base;
    detail_[size_t(j)] = Vec2(d.dot(t), d.x() * -t.y() + d.y() * t.x());
  }
  for (int i = 0; i < n; ++i) weights_[size_t(i)] = strength_;
  FeatureFrameSolver& solver = p.feature_frame()->core();
  n_ = solver.set_soft(std::span<const int>(ids_.data(), size_t(n)), std::span<const double>(weights_.data(), size_t(n))) ? n : 0;
  b_ = end;
}

Vec2 ContourStage::stroke_at(double s, Vec2& tangent) const {
  tangent = Vec2(1, 0);
  if (n_stroke_ == 0) return Vec2::Zero();
  if (n_stroke_ == 1) return stroke_[0];
  int i = 0;
  while (i + 2 < n_stroke_ && stroke_s_[size_t(i + 1)] < s) ++i;
  const double len = stroke_s_[size_t(i + 1)] - stroke_s_[size_t(i)];
  const double t = len > 0 ? std::clamp((s - stroke_s_[size_t(i)]) / len, 0.0, 1.0) : 0.0;
  // (the direction over the two pieces about the point: a hand's jitter turns the detail less)
  const Vec2 d = stroke_[size_t(std::min(i + 2, n_stroke_ - 1))] - stroke_[size_t(std::max(i - 1, 0))];
  if (d.norm() > 0) tangent = d / d.norm();
  return stroke_[size_t(i)] + t * (stroke_[size_t(i + 1)] - stroke_[size_t(i)]);
}

void ContourStage::step(const Mapping::Pen& pen, const ShowCurve* spec, double dt, bool grabbing, std::span<const Vec2> targets,
                        Puppet& p) {
  if (!frame_) return;
  FeatureFrameSolver& solver = p.feature_frame()->core();
  motion_.set_targets(targets);
  const bool on = spec && pen.down && !grabbing;
  if (on && !down_) {  // a new stroke replaces the fit
    down_ = true;
    ++strokes_;
    if (n_ > 0) solver.clear_soft();
    n_ = seg_ = 0;
    n_stroke_ = 0;
    releasing_ = false;
    hold_ = spec->release == ShowBrush::Hold;
    release_s_ = spec->release_seconds;
    strength_ = spec->strength;
    const std::span<const Vec2> v = solver.vertices();
    std::copy(v.begin(), v.end(), seen_.begin());
    a_ = nearest(pen.point, -1, v, reach_);
    c_ = a_ >= 0 ? contour_of_[size_t(a_)] : -1;
    part_ = a_ >= 0 ? frame_->origin[size_t(a_)].shape : -1;
    b_ = -1;
  }
  if (down_ && on) {
    if (n_stroke_ < kMaxStroke && (n_stroke_ == 0 || (pen.point - stroke_[size_t(n_stroke_ - 1)]).norm() >= min_step_)) {
      stroke_[size_t(n_stroke_)] = pen.point;
      stroke_s_[size_t(n_stroke_)] =
          n_stroke_ == 0 ? 0.0 : stroke_s_[size_t(n_stroke_ - 1)] + (pen.point - stroke_[size_t(n_stroke_ - 1)]).norm();
      ++n_stroke_;
    }
    if (c_ >= 0) {
      const int end = nearest(pen.point, c_, seen_, 1e300);
      if (end >= 0 && end != a_ && end != b_) choose(end, p);
    }
  } else if (down_) {  // lifted: what the fit made rides on its part (held, or springing back)
    down_ = false;
    if (n_ > 0) {
      const std::span<Vec2> t = solver.soft_targets();
      const RigidMotion mo = motion_.of_part(part_);
      for (int i = 0; i < n_; ++i) {
        const Vec2 at_rest = mo.from_c + mo.back(t[size_t(i)] - mo.to_c);
        held_[size_t(i)] = at_rest - frame_->rest[size_t(ids_[size_t(i)])];
      }
      releasing_ = !hold_;
      release_t_ = 0;
    }
  }
  if (n_ == 0) return;
  spring_k_ = 1;
  if (releasing_) {
    release_t_ += dt;
    const double u = release_s_ > 0 ? std::min(1.0, release_t_ / release_s_) : 1.0;
    spring_k_ = 1 - u * u * (3 - 2 * u);
    if (u >= 1) {
      n_ = seg_ = 0;
      releasing_ = false;
      solver.clear_soft();
      return;
    }
  }
  place(p);
}

void ContourStage::place(Puppet& p) {
  const std::span<Vec2> t = p.feature_frame()->core().soft_targets();
  if (down_) {
    const double length = n_stroke_ > 0 ? stroke_s_[size_t(n_stroke_ - 1)] : 0.0;
    for (int j = 0; j < seg_ && size_t(j) < t.size(); ++j) {
      Vec2 tan;
      const Vec2 s = stroke_at(u_[size_t(j)] * length, tan);
      const Vec2 across(-tan.y(), tan.x());
      t[size_t(j)] = s + detail_[size_t(j)].x() * tan + detail_[size_t(j)].y() * across;
    }
    for (int i = seg_; i < n_ && size_t(i) < t.size(); ++i) t[size_t(i)] = held_[size_t(i)];
    return;
  }
  const RigidMotion mo = motion_.of_part(part_);
  for (int i = 0; i < n_ && size_t(i) < t.size(); ++i)
    t[size_t(i)] = mo.apply(frame_->rest[size_t(ids_[size_t(i)])] + spring_k_ * held_[size_t(i)]);
}

void ContourStage::restore(Puppet& p) {
  if (!frame_ || n_ == 0) return;
  if (!p.feature_frame()->core().set_soft(std::span<const int>(ids_.data(), size_t(n_)),
                                         std::span<const double>(weights_.data(), size_t(n_)))) {
    n_ = seg_ = 0;
    return;
  }
  place(p);
}

}  // namespace mar
