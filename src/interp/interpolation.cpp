#include "interp/interpolation.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>

namespace mar {

std::vector<std::array<int, 3>> frame_triangle_set(const FeatureFrame& f) {
  const size_t n = f.rest.size();
  std::vector<std::vector<int>> nb(n);
  for (const FrameLine& l : f.lines) {
    if (l.kind == FrameLine::Joint || l.kind == FrameLine::Spring || l.a == l.b) continue;
    if (size_t(l.a) >= n || size_t(l.b) >= n) continue;
    nb[size_t(l.a)].push_back(l.b);
    nb[size_t(l.b)].push_back(l.a);
  }
  for (auto& v : nb) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  const double min_area = 1e-9 * f.diagonal * f.diagonal;
  auto area = [&](int a, int b, int c) {
    return 0.5 * cross(f.rest[size_t(b)] - f.rest[size_t(a)], f.rest[size_t(c)] - f.rest[size_t(a)]);
  };
  std::vector<std::array<int, 3>> out;
  auto add = [&](int a, int b, int c) {
    if (b == c || a == b || a == c) return;
    if (area(a, b, c) < 0) std::swap(b, c);  // counter-clockwise (in y-down, shoelace-positive)
    // Near-degenerate triangles (collinear frame points) would make the affine maps of the
    // keys ill-defined and the system ill-conditioned: left out (height < 1% of the longest side).
    const double longest = std::max({(f.rest[size_t(a)] - f.rest[size_t(b)]).squaredNorm(), (f.rest[size_t(b)] - f.rest[size_t(c)]).squaredNorm(),
                                     (f.rest[size_t(c)] - f.rest[size_t(a)]).squaredNorm()});
    if (std::abs(area(a, b, c)) > std::max(min_area, 0.005 * longest)) out.push_back({a, b, c});
  };
  for (size_t i = 0; i < n; ++i) {
    std::vector<int> ring = nb[i];
    const Vec2 p = f.rest[i];
    std::sort(ring.begin(), ring.end(), [&](int a, int b) {
      const Vec2 da = f.rest[size_t(a)] - p, db = f.rest[size_t(b)] - p;
      return std::atan2(da.y(), da.x()) < std::atan2(db.y(), db.x());
    });
    const size_t r = ring.size();
    if (r == 1) {  // borrow the neighbour's neighbour that makes the widest triangle
      int best = -1;
      double most = 0;
      for (int m : nb[size_t(ring[0])])
        if (size_t(m) != i && std::abs(area(int(i), ring[0], m)) > most) most = std::abs(area(int(i), ring[0], m)), best = m;
      if (best >= 0) add(int(i), ring[0], best);
    } else if (r == 2) {
      add(int(i), ring[0], ring[1]);
    } else {
      for (size_t k = 0; k < r; ++k) add(int(i), ring[k], ring[(k + 1) % r]);
    }
  }
  return out;
}

bool KeyInterpolator::prepare(const FeatureFrame& f, std::string* error) {
  rest_ = f.rest;
  tris_ = frame_triangle_set(f);
  keys_.clear();
  const size_t n = rest_.size();
  if (n == 0) {
    if (error) *error = "the frame has no vertices to interpolate";
    return false;
  }
  // B_τ(V) row = [x_j − x_i, x_k − x_i] E^-1: coefficients of x_i, x_j, x_k for each column.
  einv_.clear();
  std::vector<Eigen::Triplet<double>> t;
  double diag = 0;
  for (const auto& tri : tris_) {
    const Vec2 e1 = rest_[size_t(tri[1])] - rest_[size_t(tri[0])], e2 = rest_[size_t(tri[2])] - rest_[size_t(tri[0])];
    const double det = e1.x() * e2.y() - e2.x() * e1.y();
    // E = [e1 e2] (columns); E^-1 = [[e2.y, -e2.x], [-e1.y, e1.x]] / det.
    const std::array<double, 4> ei{e2.y() / det, -e2.x() / det, -e1.y() / det, e1.x() / det};
    einv_.push_back(ei);
    for (int col = 0; col < 2; ++col) {
      const double cj = ei[size_t(col)], ck = ei[size_t(2 + col)], ci = -(cj + ck);
      const int idx[3] = {tri[0], tri[1], tri[2]};
      const double c[3] = {ci, cj, ck};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) t.emplace_back(idx[a], idx[b], c[a] * c[b]);
      diag += c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
    }
  }
  // Hinge pins (zero-length joint lines) tie the parts they join: |v_a − v_b − d(w)|², d the
  // blend of the keys' pin offsets, weighed like a triangle.
  pins_.clear();
  for (const FrameLine& l : f.lines)
    if (l.kind == FrameLine::Joint && l.a != l.b && size_t(l.a) < n && size_t(l.b) < n) pins_.push_back({l.a, l.b});
  pin_w_ = tris_.empty() ? 1.0 : diag / double(2 * tris_.size());
  for (const auto& pin : pins_) {
    t.emplace_back(pin[0], pin[0], pin_w_);
    t.emplace_back(pin[1], pin[1], pin_w_);
    t.emplace_back(pin[0], pin[1], -pin_w_);
    t.emplace_back(pin[1], pin[0], -pin_w_);
  }
  // Anchors: one vertex per connected piece (of triangles and pins; a vertex in none is its
  // own piece), the one nearest the piece's centroid, weighed like a typical vertex (the
  // median diagonal, which the thinnest triangles cannot dominate).
  std::vector<double> d(n, 0.0);
  for (const auto& e : t)
    if (e.row() == e.col()) d[size_t(e.row())] += e.value();
  std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(n / 2), d.end());
  anchor_w_ = d[n / 2] > 0 ? d[n / 2] : 1.0;
  std::vector<int> comp(n);
  for (size_t i = 0; i < n; ++i) comp[i] = int(i);
  auto find = [&](int i) {
    while (comp[size_t(i)] != i) i = comp[size_t(i)] = comp[size_t(comp[size_t(i)])];
    return i;
  };
  for (const auto& tri : tris_) {
    comp[size_t(find(tri[0]))] = find(tri[1]);
    comp[size_t(find(tri[1]))] = find(tri[2]);
  }
  for (const auto& pin : pins_) comp[size_t(find(pin[0]))] = find(pin[1]);
  std::vector<Vec2> csum(n, Vec2::Zero());
  std::vector<int> ccount(n, 0);
  for (size_t i = 0; i < n; ++i) {
    csum[size_t(find(int(i)))] += rest_[i];
    ++ccount[size_t(find(int(i)))];
  }
  std::vector<int> best(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const size_t c = size_t(find(int(i)));
    const Vec2 centre = csum[c] / double(ccount[c]);
    if (best[c] < 0 || (rest_[i] - centre).squaredNorm() < (rest_[size_t(best[c])] - centre).squaredNorm()) best[c] = int(i);
  }
  anchors_.clear();
  for (size_t c = 0; c < n; ++c)
    if (best[c] >= 0) {
      anchors_.push_back(best[c]);
      t.emplace_back(best[c], best[c], anchor_w_);
    }
  rest_centre_ = Vec2::Zero();
  for (const Vec2& p : rest_) rest_centre_ += p;
  rest_centre_ /= double(n);
  Eigen::SparseMatrix<double> M(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  M.setFromTriplets(t.begin(), t.end());
  if (!factor_.compute(M)) {
    if (error) *error = "the interpolation system could not be factorised";
    return false;
  }
  bx_.assign(n, 0.0);
  by_.assign(n, 0.0);
  w_.clear();
  return true;
}

int KeyInterpolator::add_key(std::span<const Vec2> v) {
  Key k;
  k.v.assign(v.begin(), v.end());
  k.v.resize(rest_.size(), Vec2::Zero());
  const Key* prev = keys_.empty() ? nullptr : &keys_.back();
  // The first key's angles are taken within π of its overall turn (the best rigid fit of all
  // its vertices), so a part turned by half a circle turns one way in every triangle.
  const RigidMotion whole = rigid_fit(rest_, k.v);
  double overall = std::atan2(whole.s, whole.c);
  if (prev) overall += 2 * M_PI * std::round((prev->overall - overall) / (2 * M_PI));
  k.overall = overall;
  k.centre = Vec2::Zero();
  for (const Vec2& p : k.v) k.centre += p;
  k.centre /= double(std::max<size_t>(1, k.v.size()));
  for (size_t t = 0; t < tris_.size(); ++t) {
    const auto& tri = tris_[t];
    const auto& ei = einv_[t];
    const Vec2 f1 = k.v[size_t(tri[1])] - k.v[size_t(tri[0])], f2 = k.v[size_t(tri[2])] - k.v[size_t(tri[0])];
    // A = [f1 f2] E^-1.
    const double a = f1.x() * ei[0] + f2.x() * ei[2], b = f1.x() * ei[1] + f2.x() * ei[3];
    const double c = f1.y() * ei[0] + f2.y() * ei[2], d = f1.y() * ei[1] + f2.y() * ei[3];
    double g = std::atan2(c - b, a + d);  // polar decomposition A = R(g) S
    const double ref = prev ? prev->gamma[t] : overall;
    g += 2 * M_PI * std::round((ref - g) / (2 * M_PI));
    const double cg = std::cos(g), sg = std::sin(g);
    // S = R(g)^T A (symmetric for A with positive determinant).
    const double s00 = cg * a + sg * c, s01 = cg * b + sg * d, s10 = -sg * a + cg * c, s11 = -sg * b + cg * d;
    k.gamma.push_back(g);
    k.s.push_back({s00, 0.5 * (s01 + s10), s11});
  }
  keys_.push_back(std::move(k));
  w_.assign(keys_.size(), 0.0);
  return int(keys_.size()) - 1;
}

void KeyInterpolator::blend(std::span<const double> weights, std::span<Vec2> out) {
  const size_t n = rest_.size(), K = std::min(weights.size(), keys_.size());
  const int* perm = factor_.perm().data();
  // The overall turn and centre of the blend (a rigid key blends rigidly; a key is exact).
  double phi = 0;
  Vec2 centre = rest_centre_;
  for (size_t k = 0; k < K; ++k) {
    phi += weights[k] * keys_[k].overall;
    centre += weights[k] * (keys_[k].centre - rest_centre_);
  }
  const double cp = std::cos(phi), sp = std::sin(phi);
  std::fill(bx_.begin(), bx_.end(), 0.0);
  std::fill(by_.begin(), by_.end(), 0.0);
  // Anchors: where the blend's overall motion takes the vertex, plus each key's own departure
  // from its overall motion.
  for (int a : anchors_) {
    const Vec2 r = rest_[size_t(a)] - rest_centre_;
    Vec2 target = centre + rotated(cp, sp, r);
    for (size_t k = 0; k < K; ++k) {
      const Key& key = keys_[k];
      target += weights[k] * (key.v[size_t(a)] - key.centre - rotated(std::cos(key.overall), std::sin(key.overall), r));
    }
    bx_[size_t(perm[a])] += anchor_w_ * target.x();
    by_[size_t(perm[a])] += anchor_w_ * target.y();
  }
  for (size_t t = 0; t < tris_.size(); ++t) {
    double g = 0, s00 = 1, s01 = 0, s11 = 1;
    for (size_t k = 0; k < K; ++k) {
      const double w = weights[k];
      if (w == 0) continue;
      g += w * keys_[k].gamma[t];
      s00 += w * (keys_[k].s[t][0] - 1);
      s01 += w * keys_[k].s[t][1];
      s11 += w * (keys_[k].s[t][2] - 1);
    }
    const double cg = std::cos(g), sg = std::sin(g);
    const double A[2][2] = {{cg * s00 - sg * s01, cg * s01 - sg * s11}, {sg * s00 + cg * s01, sg * s01 + cg * s11}};
    const auto& tri = tris_[t];
    const auto& ei = einv_[t];
    for (int col = 0; col < 2; ++col) {
      const double cj = ei[size_t(col)], ck = ei[size_t(2 + col)], ci = -(cj + ck);
      const int idx[3] = {tri[0], tri[1], tri[2]};
      const double c[3] = {ci, cj, ck};
      for (int a = 0; a < 3; ++a) {
        bx_[size_t(perm[idx[a]])] += c[a] * A[0][col];
        by_[size_t(perm[idx[a]])] += c[a] * A[1][col];
      }
    }
  }
  // Pins: the rest offset turned by the blend's overall angle, plus each key's own departure
  // from its turned rest offset (so a key is exact and a rigid key stays rigid).
  for (const auto& pin : pins_) {
    const size_t a = size_t(pin[0]), b = size_t(pin[1]);
    const Vec2 r = rest_[a] - rest_[b];
    Vec2 d = rotated(cp, sp, r);
    for (size_t k = 0; k < K; ++k) {
      const double o = keys_[k].overall;
      d += weights[k] * ((keys_[k].v[a] - keys_[k].v[b]) - rotated(std::cos(o), std::sin(o), r));
    }
    bx_[size_t(perm[a])] += pin_w_ * d.x();
    by_[size_t(perm[a])] += pin_w_ * d.y();
    bx_[size_t(perm[b])] -= pin_w_ * d.x();
    by_[size_t(perm[b])] -= pin_w_ * d.y();
  }
  factor_.solve_permuted(bx_.data(), by_.data());
  for (size_t i = 0; i < n && i < out.size(); ++i) out[i] = Vec2(bx_[size_t(perm[i])], by_[size_t(perm[i])]);
}

void KeyInterpolator::morph(int a, int b, double t, std::span<Vec2> out) {
  std::fill(w_.begin(), w_.end(), 0.0);
  if (a >= 0 && size_t(a) < w_.size()) w_[size_t(a)] += 1 - t;
  if (b >= 0 && size_t(b) < w_.size()) w_[size_t(b)] += t;
  blend(w_, out);
}

void KeyInterpolator::linear_morph(int a, int b, double t, std::span<Vec2> out) const {
  const Points &va = key_vertices(a), &vb = key_vertices(b);
  for (size_t i = 0; i < rest_.size() && i < out.size(); ++i) out[i] = (1 - t) * va[i] + t * vb[i];
}

}  // namespace mar
