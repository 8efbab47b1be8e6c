// Where a point of the character is on the rigid grid (solve/rigid_grid.h): in an interior
// cell, bilinear in its corners; in a mesh triangle, barycentric; off the mesh, on the stroke it
// is drawn on, or carried by the unfilled ring around it. Handles, shape points the curves do
// not hold, and pen grabs are placed so.
#include "solve/rigid_grid.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "geom/polygon.h"

namespace mar {

RigidGrid::Embed RigidGrid::embed(const Vec2& p) const {
  Embed e;
  const int ci = int(std::floor((p.x() - origin_.x()) / h_)), cj = int(std::floor((p.y() - origin_.y()) / h_));
  if (cell_inside(ci, cj)) {  // bilinear in the cell (V²)
    const double u = (p.x() - origin_.x()) / h_ - ci, v = (p.y() - origin_.y()) / h_ - cj;
    e.n = 4;
    e.v[0] = corner_node(ci, cj), e.v[1] = corner_node(ci + 1, cj), e.v[2] = corner_node(ci, cj + 1),
    e.v[3] = corner_node(ci + 1, cj + 1);
    e.w[0] = (1 - u) * (1 - v), e.w[1] = u * (1 - v), e.w[2] = (1 - u) * v, e.w[3] = u * v;
    return e;
  }
  // Barycentric in the mesh triangle holding it.
  double best = INFINITY;
  for (const auto& t : tris_) {
    const Vec2 &a = rest_[size_t(t[0])], &b = rest_[size_t(t[1])], &c = rest_[size_t(t[2])];
    const double det = cross(b - a, c - a);
    if (std::abs(det) < 1e-12 * h_ * h_) continue;
    const double v = cross(p - a, c - a) / det, w = cross(b - a, p - a) / det, u = 1 - v - w;
    const double out = std::max({0.0, -u, -v, -w}) * std::sqrt(std::abs(det));
    if (out < best) {
      best = out;
      e.n = 3;
      e.v[0] = t[0], e.v[1] = t[1], e.v[2] = t[2];
      e.w[0] = u, e.w[1] = v, e.w[2] = w;
      if (out == 0) return e;
    }
  }
  // Off the mesh. Inside a closed curve that is not filled (a stroked circle for a head): the
  // whole ring carries it, as the affine combination of four nodes spread around it with the
  // least weights. Else on or beside a stroke (a stick figure's hand, where the mesh has no
  // triangle): the nearest point of the nearest curve, if no triangle is as near. Else the
  // nearest triangle, extrapolated (a point beyond the mesh keeps its offset to it).
  double ring_area = INFINITY;
  for (const Curve& c : curves_) {
    if (!c.closed || c.count < 4) continue;
    Points ring(size_t(c.count));
    for (int k = 0; k < c.count; ++k) ring[size_t(k)] = rest_[size_t(cnode_[size_t(c.first + k)])];
    const double area = std::abs(signed_area(ring));
    if (winding_number(ring, p) == 0 || area >= ring_area) continue;
    Eigen::Matrix<double, 3, 4> A;
    int v[4];
    for (int k = 0; k < 4; ++k) {
      v[k] = cnode_[size_t(c.first + k * c.count / 4)];
      A.col(k) << rest_[size_t(v[k])].x(), rest_[size_t(v[k])].y(), 1.0;
    }
    const Eigen::Matrix3d M = A * A.transpose();
    if (std::abs(M.determinant()) < 1e-12 * std::pow(h_, 4)) continue;  // (four nodes in a line)
    const Eigen::Vector4d wts = A.transpose() * M.ldlt().solve(Eigen::Vector3d(p.x(), p.y(), 1.0));
    ring_area = area;
    e.n = 4;
    for (int k = 0; k < 4; ++k) e.v[k] = v[k], e.w[k] = wts[k];
  }
  if (std::isfinite(ring_area)) return e;
  double seg = INFINITY;
  Embed on_curve;
  for (const Curve& c : curves_)
    for (int k = 0; k + (c.closed ? 0 : 1) < c.count; ++k) {
      const int a = cnode_[size_t(c.first + k)], b = cnode_[size_t(c.first + (k + 1) % c.count)];
      const Vec2 ab = rest_[size_t(b)] - rest_[size_t(a)];
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - rest_[size_t(a)]).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double d = (rest_[size_t(a)] + t * ab - p).norm();
      if (d < seg) {
        seg = d;
        on_curve.n = 2;
        on_curve.v[0] = a, on_curve.v[1] = b;
        on_curve.w[0] = 1 - t, on_curve.w[1] = t;
      }
    }
  if (seg <= best) return on_curve;
  if (!std::isfinite(best)) {  // no triangle and no curve: the nearest node
    size_t k = 0;
    for (size_t i = 1; i < rest_.size(); ++i)
      if ((rest_[i] - p).squaredNorm() < (rest_[k] - p).squaredNorm()) k = i;
    e.n = 1;
    e.v[0] = int(k);
    e.w[0] = 1;
  }
  return e;
}

}  // namespace mar
