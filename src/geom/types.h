// Basic 2D types shared by every layer.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace mar {

/// sqrt(a² + b²), with the same bits on every architecture: glibc's std::hypot gives a
/// different last bit on x86-64 and aarch64 for 44 % of arguments in ±500, which made a show's
/// run_hash differ between them. No guard against overflow or underflow: marionette's lengths
/// are far from 1e±150.
inline double portable_hypot(double a, double b) { return std::sqrt(a * a + b * b); }

/// e^x for x <= 0, with the same bits on every architecture (glibc's exp is not correctly
/// rounded, and its x86-64 build picks an FMA variant): x = n ln 2 + r, e^r by its Taylor series
/// (|r| <= ln 2 / 2, 18 terms), scaled by 2^n exactly. 0 below -700.
inline double portable_exp_neg(double x) {
  if (!(x <= 0)) return x > 0 ? 1.0 : 0.0;  // (not used above 0; NaN: 0)
  if (x < -700) return 0.0;
  constexpr double kLn2 = 0.6931471805599453094;
  constexpr double kLn2Hi = 6.93147180369123816490e-01, kLn2Lo = 1.90821492927058770002e-10;  // (n * hi is exact)
  const double n = std::floor(x / kLn2 + 0.5);
  const double r = (x - n * kLn2Hi) - n * kLn2Lo;
  double term = 1, sum = 1;
  for (int k = 1; k <= 18; ++k) {
    term = term * r / k;
    sum += term;
  }
  return std::ldexp(sum, int(n));
}

using Vec2 = Eigen::Vector2d;
using Points = std::vector<Vec2>;

/// The z of the 3D cross product of two plane vectors (twice a triangle's signed area).
inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
/// p turned by the rotation with cosine c and sine s.
inline Vec2 rotated(double c, double s, const Vec2& p) { return {c * p.x() - s * p.y(), s * p.x() + c * p.y()}; }

/// 2D affine map in SVG order: x' = a x + c y + e,  y' = b x + d y + f.
struct Affine2 {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;

  static Affine2 identity() { return {}; }
  static Affine2 translate(double tx, double ty) { return {1, 0, 0, 1, tx, ty}; }
  static Affine2 scale(double sx, double sy) { return {sx, 0, 0, sy, 0, 0}; }
  /// Rotation by `deg` degrees (positive = clockwise on a y-down screen, as in SVG).
  static Affine2 rotate(double deg) {
    const double r = deg * M_PI / 180.0;
    return {std::cos(r), std::sin(r), -std::sin(r), std::cos(r), 0, 0};
  }
  static Affine2 skew_x(double deg) { return {1, 0, std::tan(deg * M_PI / 180.0), 1, 0, 0}; }
  static Affine2 skew_y(double deg) { return {1, std::tan(deg * M_PI / 180.0), 0, 1, 0, 0}; }

  /// Composition: (*this * o)(p) = this(o(p)).
  Affine2 operator*(const Affine2& o) const {
    return {a * o.a + c * o.b,     b * o.a + d * o.b,     a * o.c + c * o.d,
            b * o.c + d * o.d,     a * o.e + c * o.f + e, b * o.e + d * o.f + f};
  }
  Vec2 apply(const Vec2& p) const { return {a * p.x() + c * p.y() + e, b * p.x() + d * p.y() + f}; }
  Vec2 apply_linear(const Vec2& v) const { return {a * v.x() + c * v.y(), b * v.x() + d * v.y()}; }
  double det() const { return a * d - b * c; }
  /// Inverse map; identity-free garbage (non-finite) when det() == 0.
  Affine2 inverse() const {
    const double k = 1.0 / det();
    return {d * k, -b * k, -c * k, a * k, (c * f - d * e) * k, (b * e - a * f) * k};
  }
  /// Largest stretch factor of the linear part (spectral norm).
  double max_scale() const {
    const double s1 = a * a + b * b + c * c + d * d;
    const double s2 = std::sqrt(std::max(0.0, s1 * s1 - 4 * det() * det()));
    return std::sqrt(std::max(0.0, 0.5 * (s1 + s2)));
  }
  bool is_finite() const {
    return std::isfinite(a) && std::isfinite(b) && std::isfinite(c) && std::isfinite(d) &&
           std::isfinite(e) && std::isfinite(f);
  }
};

/// Axis-aligned bounds; empty until a point is added.
struct Bounds {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  bool empty() const { return !(lo.x() <= hi.x()); }
  void add(const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void add(const Bounds& o) {
    if (!o.empty()) {
      add(o.lo);
      add(o.hi);
    }
  }
  double width() const { return empty() ? 0.0 : hi.x() - lo.x(); }
  double height() const { return empty() ? 0.0 : hi.y() - lo.y(); }
};

}  // namespace mar
