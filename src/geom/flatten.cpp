#include "geom/flatten.h"

namespace mar {
namespace {

double dist_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

void cubic_rec(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3, double tol,
               int depth, size_t max_size, Points& out) {
  if (out.size() >= max_size) return;
  // B(t) - chord(t) = 3t(1-t)^2 (p1 - c1) + 3t^2(1-t) (p2 - c2) with c on the chord, and
  // the two weights sum to 3t(1-t) <= 3/4: the curve is within 3/4 of the larger inner
  // control point distance from the chord.
  const double d = std::max(dist_to_segment(p1, p0, p3), dist_to_segment(p2, p0, p3));
  if (0.75 * d <= tol || depth >= 18) {
    out.push_back(p3);
    return;
  }
  const Vec2 p01 = 0.5 * (p0 + p1), p12 = 0.5 * (p1 + p2), p23 = 0.5 * (p2 + p3);
  const Vec2 p012 = 0.5 * (p01 + p12), p123 = 0.5 * (p12 + p23);
  const Vec2 mid = 0.5 * (p012 + p123);
  cubic_rec(p0, p01, p012, mid, tol, depth + 1, max_size, out);
  cubic_rec(mid, p123, p23, p3, tol, depth + 1, max_size, out);
}

}  // namespace

void flatten_cubic(const Vec2& p0, const Vec2& p1, const Vec2& p2, const Vec2& p3,
                   double tolerance, Points& out, size_t max_size) {
  if (!(p0.allFinite() && p1.allFinite() && p2.allFinite() && p3.allFinite())) return;
  cubic_rec(p0, p1, p2, p3, std::max(tolerance, 1e-9), 0, max_size, out);
}

void flatten_quad(const Vec2& p0, const Vec2& p1, const Vec2& p2, double tolerance, Points& out) {
  flatten_cubic(p0, p0 + (2.0 / 3.0) * (p1 - p0), p2 + (2.0 / 3.0) * (p1 - p2), p2, tolerance,
                out);
}

void arc_to_cubics(const Vec2& p0, double rx, double ry, double x_axis_rotation_deg,
                   bool large_arc, bool sweep, const Vec2& p1, std::vector<CubicSeg>& out) {
  if ((p0 - p1).norm() == 0.0) return;  // F.6.2: identical end points -> omitted
  rx = std::abs(rx);
  ry = std::abs(ry);
  if (rx == 0.0 || ry == 0.0 || !std::isfinite(rx) || !std::isfinite(ry)) {
    out.push_back({p0 + (p1 - p0) / 3.0, p0 + 2.0 * (p1 - p0) / 3.0, p1});  // straight line
    return;
  }
  const double phi = x_axis_rotation_deg * M_PI / 180.0;
  const double cphi = std::cos(phi), sphi = std::sin(phi);
  // F.6.5.1
  const Vec2 dh = 0.5 * (p0 - p1);
  const double x1p = cphi * dh.x() + sphi * dh.y();
  const double y1p = -sphi * dh.x() + cphi * dh.y();
  // F.6.6 radius correction
  const double lambda = (x1p * x1p) / (rx * rx) + (y1p * y1p) / (ry * ry);
  if (lambda > 1.0) {
    const double s = std::sqrt(lambda);
    rx *= s;
    ry *= s;
  }
  // F.6.5.2
  const double num = rx * rx * ry * ry - rx * rx * y1p * y1p - ry * ry * x1p * x1p;
  const double den = rx * rx * y1p * y1p + ry * ry * x1p * x1p;
  double coef = den > 0 ? std::sqrt(std::max(0.0, num / den)) : 0.0;
  if (large_arc == sweep) coef = -coef;
  const double cxp = coef * rx * y1p / ry;
  const double cyp = -coef * ry * x1p / rx;
  // F.6.5.3
  const Vec2 mid = 0.5 * (p0 + p1);
  const Vec2 c{cphi * cxp - sphi * cyp + mid.x(), sphi * cxp + cphi * cyp + mid.y()};
  // F.6.5.5/6
  auto angle = [](double ux, double uy, double vx, double vy) {
    return std::atan2(ux * vy - uy * vx, ux * vx + uy * vy);
  };
  const double ux = (x1p - cxp) / rx, uy = (y1p - cyp) / ry;
  const double vx = (-x1p - cxp) / rx, vy = (-y1p - cyp) / ry;
  const double theta1 = angle(1, 0, ux, uy);
  double dtheta = angle(ux, uy, vx, vy);
  if (!sweep && dtheta > 0) dtheta -= 2 * M_PI;
  if (sweep && dtheta < 0) dtheta += 2 * M_PI;
  if (!std::isfinite(dtheta) || !std::isfinite(theta1)) {
    out.push_back({p0 + (p1 - p0) / 3.0, p0 + 2.0 * (p1 - p0) / 3.0, p1});
    return;
  }

  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(dtheta) / (M_PI / 4) - 1e-9)));
  const double step = dtheta / n;
  const double k = 4.0 / 3.0 * std::tan(step / 4);
  auto point = [&](double t) {
    const double ct = std::cos(t), st = std::sin(t);
    return Vec2{c.x() + rx * ct * cphi - ry * st * sphi, c.y() + rx * ct * sphi + ry * st * cphi};
  };
  auto deriv = [&](double t) {
    const double ct = std::cos(t), st = std::sin(t);
    return Vec2{-rx * st * cphi - ry * ct * sphi, -rx * st * sphi + ry * ct * cphi};
  };
  Vec2 prev = p0;
  for (int i = 0; i < n; ++i) {
    const double t0 = theta1 + i * step, t1 = t0 + step;
    const Vec2 end = (i == n - 1) ? p1 : point(t1);
    out.push_back({prev + k * deriv(t0), end - k * deriv(t1), end});
    prev = end;
  }
}

}  // namespace mar
