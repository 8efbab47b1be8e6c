#include "solve/arap.h"

#include "geom/polygon.h"
#include "geom/triangulate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mar {
namespace {

// Interior points on a square lattice of spacing h (one lattice for the whole character,
// so overlapping parts share them), added to every closed, filled part as one-point
// contours: vertices of the solver's mesh and of the part's fill, so a deformation (and a
// texture) follows the inside of a part, not only its outline. Points nearer than h/2 to
// any line of the character are left out.
void add_interior_points(Character& ch, double h) {
  const Bounds bb = ch.bounds();
  // Every line of the character: a lattice point nearer than h/2 to any of them would make
  // a sliver triangle (and a huge cotangent weight).
  std::vector<std::pair<Vec2, Vec2>> lines;
  for (const SubShape& s : ch.shapes)
    for (const Contour& c : s.contours)
      for (int k = 0; k + (c.closed ? 0 : 1) < c.count && c.count > 1; ++k)
        lines.push_back({s.points[size_t(c.begin + k)], s.points[size_t(c.begin + (k + 1) % c.count)]});
  for (SubShape& s : ch.shapes) {
    if (!s.fill.enabled || !s.closed()) continue;
    const Bounds b = s.bounds();
    for (double y = bb.lo.y() + h * std::ceil((b.lo.y() - bb.lo.y()) / h); y < b.hi.y(); y += h)
      for (double x = bb.lo.x() + h * std::ceil((b.lo.x() - bb.lo.x()) / h); x < b.hi.x(); x += h) {
        const Vec2 p(x, y);
        if (!s.contains(p)) continue;
        bool clear = true;
        for (size_t k = 0; k < lines.size() && clear; ++k) clear = point_segment_distance(p, lines[k].first, lines[k].second) >= 0.5 * h;
        if (!clear) continue;
        s.contours.push_back({int(s.points.size()), 1, false});
        s.points.push_back(p);
      }
  }
}

double cot(const Vec2& a, const Vec2& b) {  // cotangent of the angle between a and b
  const double cross = a.x() * b.y() - a.y() * b.x();
  return (a.x() * b.x() + a.y() * b.y()) / std::max(std::abs(cross), 1e-12);
}

}  // namespace

OutlineArap::Bary OutlineArap::locate(const Vec2& p) const {
  Bary best;
  double best_d = INFINITY;
  for (const auto& t : tris_) {
    const Vec2 &a = rest_[size_t(t[0])], &b = rest_[size_t(t[1])], &c = rest_[size_t(t[2])];
    const double det = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    if (std::abs(det) < 1e-300) continue;
    const Vec2 r = p - a;
    const double v = (r.x() * (c - a).y() - r.y() * (c - a).x()) / det;
    const double w = ((b - a).x() * r.y() - (b - a).y() * r.x()) / det;
    const double u = 1 - v - w;
    // Inside: distance 0; outside (an open stroke beyond the outline): how far outside,
    // measured in barycentric units times the triangle's size.
    const double out = std::max({0.0, -u, -v, -w}) * std::sqrt(std::abs(det));
    if (out < best_d) {
      best_d = out;
      best.v[0] = t[0];
      best.v[1] = t[1];
      best.v[2] = t[2];
      best.w[0] = u;
      best.w[1] = v;
      best.w[2] = w;
      if (out == 0) break;
    }
  }
  return best;
}

bool OutlineArap::prepare(Character& ch, const Rig&, std::span<const Vec2> handle_rest, const SolverWeights& w,
                          std::string* error) {
  position_ = w.position;
  handle_w_ = w.handle_weights;
  const Bounds cb = ch.bounds();
  add_interior_points(ch, portable_hypot(cb.hi.x() - cb.lo.x(), cb.hi.y() - cb.lo.y()) / 48);
  Points pts;
  std::vector<Ring> rings;
  std::vector<char> closed;
  bool any_filled = false;
  for (const SubShape& sh : ch.shapes) {
    for (const Contour& ct : sh.contours) {
      rings.push_back({int(pts.size()) + ct.begin, ct.count});
      closed.push_back(ct.closed ? 1 : 0);
    }
    any_filled = any_filled || (sh.fill.enabled && sh.closed());
    pts.insert(pts.end(), sh.points.begin(), sh.points.end());
  }
  if (pts.size() < 3) {
    if (error) *error = "arap: the character has fewer than 3 points";
    return false;
  }
  const HullMesh hm = triangulate_hull(pts, rings, closed);
  // Keep the faces inside some closed, filled part (all of them for a character of strokes).
  std::vector<int> keep(hm.vertices.size(), -1);
  rest_.clear();
  tris_.clear();
  for (size_t t = 0; t + 2 < hm.triangles.size(); t += 3) {
    const int* tv = &hm.triangles[t];
    const Vec2 centroid = (hm.vertices[size_t(tv[0])] + hm.vertices[size_t(tv[1])] + hm.vertices[size_t(tv[2])]) / 3.0;
    bool in = !any_filled;
    for (size_t s = 0; s < ch.shapes.size() && !in; ++s)
      in = ch.shapes[s].fill.enabled && ch.shapes[s].closed() && ch.shapes[s].contains(centroid);
    if (!in) continue;
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      int& id = keep[size_t(tv[k])];
      if (id < 0) {
        id = int(rest_.size());
        rest_.push_back(hm.vertices[size_t(tv[k])]);
      }
      tri[size_t(k)] = id;
    }
    tris_.push_back(tri);
  }
  if (tris_.empty()) {
    if (error) *error = "arap: no triangle lies inside the character's closed parts";
    return false;
  }
  const size_t n = rest_.size();
  // Cotangent weights, half the cotangent of the opposite angle per incident triangle;
  // clamped to [1/100, 100] x their median: obtuse boundary triangles would make them
  // negative, and the flat triangles a constrained triangulation keeps between collinear
  // outline points would make them near infinite (and the system singular in practice).
  std::vector<std::vector<std::pair<int, double>>> ring(n);
  auto add = [&](int i, int j, double c) {
    for (auto& [k, weight] : ring[size_t(i)])
      if (k == j) {
        weight += c;
        return;
      }
    ring[size_t(i)].push_back({j, c});
  };
  for (const auto& t : tris_)
    for (int k = 0; k < 3; ++k) {
      const int i = t[size_t(k)], j = t[size_t((k + 1) % 3)], o = t[size_t((k + 2) % 3)];
      const double c = 0.5 * cot(rest_[size_t(i)] - rest_[size_t(o)], rest_[size_t(j)] - rest_[size_t(o)]);
      add(i, j, c);
      add(j, i, c);
    }
  // The median, not the mean: a few flat triangles' near-infinite weights would set the mean.
  std::vector<double> all;
  for (const auto& rg : ring)
    for (const auto& e : rg) all.push_back(std::abs(e.second));
  std::nth_element(all.begin(), all.begin() + long(all.size() / 2), all.end());
  const double mid = all.empty() || !(all[all.size() / 2] > 0) ? 1.0 : all[all.size() / 2];
  nb_start_.assign(n + 1, 0);
  nb_.clear();
  nb_w_.clear();
  for (size_t i = 0; i < n; ++i) {
    for (const auto& [j, c] : ring[i]) {
      nb_.push_back(j);
      nb_w_.push_back(std::clamp(c, 0.01 * mid, 100 * mid));
    }
    nb_start_[i + 1] = int(nb_.size());
  }
  binds_.clear();
  for (const SubShape& sh : ch.shapes) {
    std::vector<Bary> b;
    b.reserve(sh.points.size());
    for (const Vec2& p : sh.points) b.push_back(locate(p));
    binds_.push_back(std::move(b));
  }
  handles_.clear();
  handle_rest_.assign(handle_rest.begin(), handle_rest.end());
  for (const Vec2& h : handle_rest) handles_.push_back(locate(h));
  x_ = rest_;
  rc_.assign(n, 1.0);
  rs_.assign(n, 0.0);
  bx_.assign(n, 0.0);
  by_.assign(n, 0.0);
  grab_update_.reserve(n);
  grab_active_ = false;
  return factorise(error);
}

bool OutlineArap::factorise(std::string* error) {
  const size_t n = rest_.size();
  // K = 2 L (cotangent Laplacian) + w_p sum_h s_h a_h a_h^T (s_h: the handle's scale); a part no handle reaches gets a
  // tiny pull toward where it is, so the system stays definite.
  std::vector<int> comp(n);
  std::iota(comp.begin(), comp.end(), 0);
  auto find = [&](int i) {
    while (comp[size_t(i)] != i) i = comp[size_t(i)] = comp[size_t(comp[size_t(i)])];
    return i;
  };
  for (size_t i = 0; i < n; ++i)
    for (int p = nb_start_[i]; p < nb_start_[i + 1]; ++p) comp[size_t(find(int(i)))] = find(nb_[size_t(p)]);
  std::vector<char> held(n, 0);
  for (const Bary& h : handles_) held[size_t(find(h.v[0]))] = 1;
  std::vector<Eigen::Triplet<double>> t;
  pull_.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    double d = 0;
    for (int p = nb_start_[i]; p < nb_start_[i + 1]; ++p) {
      t.emplace_back(int(i), nb_[size_t(p)], -2 * nb_w_[size_t(p)]);
      d += 2 * nb_w_[size_t(p)];
    }
    if (!held[size_t(find(int(i)))]) pull_[i] = kFreePull * (1 + d);
    t.emplace_back(int(i), int(i), d + pull_[i]);
  }
  for (size_t k = 0; k < handles_.size(); ++k) {
    const Bary& h = handles_[k];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) t.emplace_back(h.v[a], h.v[b], position_ * handle_w(k) * h.w[a] * h.w[b]);
  }
  Eigen::SparseMatrix<double> K(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  K.setFromTriplets(t.begin(), t.end());
  if (!factor_.compute(K)) {
    if (error) *error = "arap: the system matrix could not be factorised";
    return false;
  }
  return true;
}

std::vector<SolverParameter> OutlineArap::parameters() const { return {{"position", position_, 1e-3, 1e9}}; }

bool OutlineArap::set_parameters(std::span<const double> v, std::string* error) {
  if (v.size() != 1 || !(v[0] > 0)) {
    if (error) *error = "arap has 1 parameter (position > 0)";
    return false;
  }
  position_ = v[0];
  grab_active_ = false;  // the caller grabs again (the grab's solve depends on the matrix)
  return factorise(error);
}

void OutlineArap::reset_to_rest() { rigid_pose({}, {}, rest_, x_, rc_, rs_); }

void OutlineArap::initial_guess(std::span<const Vec2> targets) { rigid_pose(handle_rest_, targets, rest_, x_, rc_, rs_); }

void OutlineArap::local_step() {
  for (size_t i = 0; i < x_.size(); ++i) {
    double a = 0, s = 0;
    for (int p = nb_start_[i]; p < nb_start_[i + 1]; ++p) {
      const size_t j = size_t(nb_[size_t(p)]);
      const Vec2 e = x_[i] - x_[j], r = rest_[i] - rest_[j];
      const double w = nb_w_[size_t(p)];
      a += w * r.dot(e);
      s += w * (r.x() * e.y() - r.y() * e.x());
    }
    const double len = portable_hypot(a, s);
    if (len > 1e-300) {  // else: a collapsed ring keeps its rotation
      rc_[i] = a / len;
      rs_[i] = s / len;
    }
  }
}

void OutlineArap::global_step(std::span<const Vec2> targets) {
  const int* perm = factor_.perm().data();
  for (size_t i = 0; i < x_.size(); ++i) {
    double bx = 0, by = 0;
    for (int p = nb_start_[i]; p < nb_start_[i + 1]; ++p) {
      const size_t j = size_t(nb_[size_t(p)]);
      const Vec2 r = rest_[i] - rest_[j];
      const double c = rc_[i] + rc_[j], s = rs_[i] + rs_[j], w = nb_w_[size_t(p)];
      bx += w * (c * r.x() - s * r.y());
      by += w * (s * r.x() + c * r.y());
    }
    bx += pull_[i] * x_[i].x();
    by += pull_[i] * x_[i].y();
    bx_[size_t(perm[i])] = bx;
    by_[size_t(perm[i])] = by;
  }
  auto add_handle = [&](const Bary& b, const Vec2& c, double w) {
    for (int k = 0; k < 3; ++k) {
      bx_[size_t(perm[b.v[k]])] += w * b.w[k] * c.x();
      by_[size_t(perm[b.v[k]])] += w * b.w[k] * c.y();
    }
  };
  // A target that is not a number (a broken control, a bad file) holds its handle where it is.
  auto target = [&](const Bary& b, const Vec2& t) { return t.allFinite() ? t : eval(b); };
  const size_t m = std::min(targets.size(), handles_.size());
  for (size_t h = 0; h < m; ++h) add_handle(handles_[h], target(handles_[h], targets[h]), position_ * handle_w(h));
  const bool grab = grab_active_ && targets.size() > handles_.size();
  if (grab) add_handle(grab_, target(grab_, targets[handles_.size()]), position_);
  factor_.solve_permuted(bx_.data(), by_.data());
  if (grab) grab_update_.correct(factor_, bx_.data(), by_.data());
  for (size_t i = 0; i < x_.size(); ++i) {
    const Vec2 v(bx_[size_t(perm[i])], by_[size_t(perm[i])]);
    if (v.allFinite()) x_[i] = v;  // (overflow near the double limits keeps the last pose)
  }
}

void OutlineArap::solve(std::span<const Vec2> targets, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    local_step();
    global_step(targets);
  }
}

void OutlineArap::grab(const Vec2& rest_point) {
  grab_ = locate(rest_point);
  grab_update_.set(factor_, grab_.v, grab_.w, 3, position_);
  grab_active_ = true;
}

void OutlineArap::shape_points(std::vector<Points>& out) const {
  for (size_t s = 0; s < binds_.size() && s < out.size(); ++s)
    for (size_t k = 0; k < binds_[s].size() && k < out[s].size(); ++k) out[s][k] = eval(binds_[s][k]);
}

double OutlineArap::energy() const {
  double e = 0;
  for (size_t i = 0; i < x_.size(); ++i)
    for (int p = nb_start_[i]; p < nb_start_[i + 1]; ++p) {
      const size_t j = size_t(nb_[size_t(p)]);
      const Vec2 r = rest_[i] - rest_[j];
      const Vec2 d = (x_[i] - x_[j]) - Vec2(rc_[i] * r.x() - rs_[i] * r.y(), rs_[i] * r.x() + rc_[i] * r.y());
      e += nb_w_[size_t(p)] * d.squaredNorm();
    }
  return e;
}

double OutlineArap::energy(std::span<const Vec2> targets) const {
  double e = energy();
  const size_t m = std::min(targets.size(), handles_.size());
  for (size_t h = 0; h < m; ++h)
    if (targets[h].allFinite()) e += position_ * handle_w(h) * (eval(handles_[h]) - targets[h]).squaredNorm();
  return e;
}

}  // namespace mar
