#include "geom/polygon.h"

#include <Eigen/LU>

namespace mar {

double signed_area(std::span<const Vec2> ring) {
  const size_t n = ring.size();
  if (n < 3) return 0.0;
  double s = 0;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    s += ring[j].x() * ring[i].y() - ring[i].x() * ring[j].y();
  }
  return 0.5 * s;
}

int winding_number(std::span<const Vec2> ring, const Vec2& p) {
  int w = 0;
  const size_t n = ring.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = ring[j];
    const Vec2& b = ring[i];
    const double cross = (b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y());
    if (a.y() <= p.y()) {
      if (b.y() > p.y() && cross > 0) ++w;
    } else if (b.y() <= p.y() && cross < 0) {
      --w;
    }
  }
  return w;
}

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

namespace {
void dp(std::span<const Vec2> pts, size_t i0, size_t i1, double tol, std::vector<char>& keep) {
  // Iterative to bound stack depth on long outlines.
  std::vector<std::pair<size_t, size_t>> stack{{i0, i1}};
  while (!stack.empty()) {
    auto [a, b] = stack.back();
    stack.pop_back();
    double best = -1;
    size_t idx = a;
    for (size_t k = a + 1; k < b; ++k) {
      const double d = point_segment_distance(pts[k], pts[a], pts[b]);
      if (d > best) {
        best = d;
        idx = k;
      }
    }
    if (best > tol) {
      keep[idx] = 1;
      stack.push_back({a, idx});
      stack.push_back({idx, b});
    }
  }
}
}  // namespace

Points simplify_polyline(std::span<const Vec2> pts, double tolerance, bool closed) {
  const size_t n = pts.size();
  if (n < 3) return Points(pts.begin(), pts.end());
  std::vector<char> keep(n, 0);
  if (!closed) {
    keep[0] = keep[n - 1] = 1;
    dp(pts, 0, n - 1, tolerance, keep);
  } else {
    // Anchor at point 0 and the point farthest from it; simplify both halves, and the
    // wrap-around half through a rotated copy.
    size_t far = 0;
    double best = -1;
    for (size_t k = 1; k < n; ++k) {
      const double d = (pts[k] - pts[0]).squaredNorm();
      if (d > best) {
        best = d;
        far = k;
      }
    }
    keep[0] = keep[far] = 1;
    dp(pts, 0, far, tolerance, keep);
    Points tail(pts.begin() + static_cast<long>(far), pts.end());
    tail.push_back(pts[0]);
    std::vector<char> keep_tail(tail.size(), 0);
    dp(tail, 0, tail.size() - 1, tolerance, keep_tail);
    for (size_t k = 1; k + 1 < tail.size(); ++k) {
      if (keep_tail[k]) keep[far + k] = 1;
    }
  }
  Points out;
  for (size_t k = 0; k < n; ++k) {
    if (keep[k]) out.push_back(pts[k]);
  }
  return out;
}

void remove_duplicate_points(Points& pts, bool closed, double eps) {
  if (pts.empty()) return;
  const double eps2 = eps * eps;
  size_t w = 1;
  for (size_t i = 1; i < pts.size(); ++i) {
    if ((pts[i] - pts[w - 1]).squaredNorm() > eps2) pts[w++] = pts[i];
  }
  pts.resize(w);
  if (closed) {
    while (pts.size() > 1 && (pts.back() - pts.front()).squaredNorm() <= eps2) pts.pop_back();
  }
}

RigidMotion rigid_fit(std::span<const Vec2> from, std::span<const Vec2> to) {
  RigidMotion m;
  const size_t n = std::min(from.size(), to.size());
  if (n == 0) return m;
  for (size_t i = 0; i < n; ++i) {
    m.from_c += from[i];
    m.to_c += to[i];
  }
  m.from_c /= static_cast<double>(n);
  m.to_c /= static_cast<double>(n);
  double re = 0, im = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p = from[i] - m.from_c, q = to[i] - m.to_c;
    re += q.x() * p.x() + q.y() * p.y();
    im += q.y() * p.x() - q.x() * p.y();
  }
  const double len = portable_hypot(re, im);
  if (len > 0 && std::isfinite(len)) m.c = re / len, m.s = im / len;
  return m;
}

double rigid_fit_rms(std::span<const Vec2> from, std::span<const Vec2> to) {
  const size_t n = std::min(from.size(), to.size());
  if (n == 0) return 0;
  const RigidMotion m = rigid_fit(from, to);
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += (m.apply(from[i]) - to[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(n));
}

void AffineFit::add(const Vec2& from, const Vec2& to) {
  n_ += 1;
  sf_ += from;
  st_ += to;
  sff_ += from * from.transpose();
  stf_ += to * from.transpose();
}

Affine2 AffineFit::result() const {
  if (n_ == 0) return {};
  const Vec2 cf = sf_ / n_, ct = st_ / n_;
  // Centred, the linear part is A = S_tf S_ff^-1.
  const Eigen::Matrix2d sff = sff_ - n_ * cf * cf.transpose(), stf = stf_ - n_ * ct * cf.transpose();
  const double tr = sff.trace();
  if (tr > 0 && sff.determinant() > 1e-12 * tr * tr) {
    const Eigen::Matrix2d m = stf * sff.inverse();
    const Vec2 t = ct - m * cf;
    if (m.allFinite() && t.allFinite()) return {m(0, 0), m(1, 0), m(0, 1), m(1, 1), t.x(), t.y()};
  }
  const Vec2 d = ct - cf;
  return Affine2::translate(d.x(), d.y());
}

Affine2 affine_fit(std::span<const Vec2> from, std::span<const Vec2> to) {
  AffineFit fit;
  for (size_t i = 0; i < std::min(from.size(), to.size()); ++i) fit.add(from[i], to[i]);
  return fit.result();
}

}  // namespace mar
