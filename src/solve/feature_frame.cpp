#include "solve/feature_frame.h"

#include <cassert>
#include <cmath>
#include <numeric>

namespace mar {
namespace {

// Complex multiplication of a 2-vector by (c + i s).
inline Vec2 rot(double c, double s, const Vec2& d) { return {c * d.x() - s * d.y(), s * d.x() + c * d.y()}; }

struct UnionFind {
  std::vector<int> p;
  explicit UnionFind(size_t n) : p(n) { std::iota(p.begin(), p.end(), 0); }
  int find(int x) {
    while (p[static_cast<size_t>(x)] != x) x = p[static_cast<size_t>(x)] = p[static_cast<size_t>(p[static_cast<size_t>(x)])];
    return x;
  }
  void unite(int a, int b) { p[static_cast<size_t>(find(a))] = find(b); }
};

// Handle coefficients: eval = alpha_a v_a + alpha_b v_b + offset (alpha complex).
struct HandleCoeff {
  int a, b;
  double ar, ai, br, bi;
  Vec2 offset;
};

HandleCoeff coeff(const ShapeParam& h) {
  if (h.offset_only) return {h.a, h.a, 1, 0, 0, 0, Vec2(h.ox, h.oy)};
  return {h.a, h.b, 1 - h.zr, -h.zi, h.zr, h.zi, Vec2::Zero()};
}

}  // namespace

bool FeatureFrameSolver::prepare(const FeatureFrame& frame, std::span<const ShapeParam> handles,
                                 const SolverWeights& w, std::string* error) {
  frame_ = &frame;
  w_ = w;
  handles_.assign(handles.begin(), handles.end());
  const size_t q = frame.rest.size();
  if (q == 0) {
    if (error) *error = "the feature frame is empty (no sub-shapes)";
    return false;
  }
  for (const ShapeParam& h : handles_) {
    if (h.a < 0 || h.b < 0 || static_cast<size_t>(h.a) >= q || static_cast<size_t>(h.b) >= q) {
      if (error) *error = "a handle refers to a frame vertex that does not exist";
      return false;
    }
  }
  // Adjacency over all lines (feature + sewing), CSR.
  std::vector<std::vector<std::pair<int, int>>> nb(q);  // (neighbour, feature line or -1)
  for (int li = 0; li < static_cast<int>(frame.lines.size()); ++li) {
    const FrameLine& l = frame.lines[static_cast<size_t>(li)];
    if (l.a == l.b) continue;
    const int line = li < frame.feature_lines ? li : -1;
    nb[static_cast<size_t>(l.a)].push_back({l.b, line});
    nb[static_cast<size_t>(l.b)].push_back({l.a, line});
  }
  adj_begin_.assign(q + 1, 0);
  adj_.clear();
  adj_line_.clear();
  for (size_t i = 0; i < q; ++i) {
    adj_begin_[i] = static_cast<int>(adj_.size());
    for (const auto& [n, line] : nb[i]) {
      adj_.push_back(n);
      adj_line_.push_back(line);
    }
  }
  adj_begin_[q] = static_cast<int>(adj_.size());
  adj_rest_.resize(adj_.size());
  for (size_t i = 0; i < q; ++i) {
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      adj_rest_[static_cast<size_t>(k)] = frame.rest[static_cast<size_t>(adj_[static_cast<size_t>(k)])] - frame.rest[i];
    }
  }
  line_rest_.resize(static_cast<size_t>(frame.feature_lines));
  for (int j = 0; j < frame.feature_lines; ++j) {
    const FrameLine& l = frame.lines[static_cast<size_t>(j)];
    line_rest_[static_cast<size_t>(j)] = frame.rest[static_cast<size_t>(l.b)] - frame.rest[static_cast<size_t>(l.a)];
  }

  // Components without a handle get a tiny pull toward the pose the solve starts from.
  UnionFind uf(q);
  for (const FrameLine& l : frame.lines) uf.unite(l.a, l.b);
  std::vector<char> handled(q, 0);
  for (const ShapeParam& h : handles_) {
    handled[static_cast<size_t>(uf.find(h.a))] = 1;
    handled[static_cast<size_t>(uf.find(h.b))] = 1;
  }
  free_.assign(q, 0);
  for (size_t i = 0; i < q; ++i) free_[i] = handled[static_cast<size_t>(uf.find(static_cast<int>(i)))] ? 0 : 1;
  eps_ = 1e-6 * std::max(w.coupling, 1e-12);

  // System matrix.
  const double cr = w.rigidity / 12.0, cc = w.coupling / 3.0;
  std::vector<Eigen::Triplet<double>> t;
  auto add_block_diag = [&](int i, int j, double v) {
    t.emplace_back(2 * i, 2 * j, v);
    t.emplace_back(2 * i + 1, 2 * j + 1, v);
  };
  for (int li = 0; li < static_cast<int>(frame.lines.size()); ++li) {
    const FrameLine& l = frame.lines[static_cast<size_t>(li)];
    if (l.a == l.b) continue;
    const double c = (li < frame.feature_lines ? cr : 0.0) + 2.0 * cc;
    add_block_diag(l.a, l.a, c);
    add_block_diag(l.b, l.b, c);
    add_block_diag(l.a, l.b, -c);
    add_block_diag(l.b, l.a, -c);
  }
  for (const ShapeParam& h : handles_) {
    const HandleCoeff k = coeff(h);
    // |M(alpha_a) v_a + M(alpha_b) v_b - c|^2 ; M(x)^T M(y) = M(conj(x) y)
    const int idx[2] = {k.a, k.b};
    const double re[2] = {k.ar, k.br}, im[2] = {k.ai, k.bi};
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) {
        // conj(alpha_r) * alpha_c
        const double pr = re[r] * re[c] + im[r] * im[c];
        const double pi = re[r] * im[c] - im[r] * re[c];
        const int I = idx[r], J = idx[c];
        t.emplace_back(2 * I, 2 * J, w.position * pr);
        t.emplace_back(2 * I, 2 * J + 1, -w.position * pi);
        t.emplace_back(2 * I + 1, 2 * J, w.position * pi);
        t.emplace_back(2 * I + 1, 2 * J + 1, w.position * pr);
      }
    }
  }
  for (size_t i = 0; i < q; ++i) {
    if (free_[i]) add_block_diag(static_cast<int>(i), static_cast<int>(i), eps_);
  }
  Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(2 * q), static_cast<Eigen::Index>(2 * q));
  A.setFromTriplets(t.begin(), t.end());
  ldlt_.compute(A);
  if (ldlt_.info() != Eigen::Success) {
    if (error) *error = "the system matrix could not be factorised";
    return false;
  }
  rhs_.setZero(static_cast<Eigen::Index>(2 * q));
  x_.setZero(static_cast<Eigen::Index>(2 * q));
  work_.setZero(static_cast<Eigen::Index>(2 * q));
  diag_ = ldlt_.vectorD();
  // (P b)[perm[i]] = b[i], Eigen's convention for PermutationMatrix * vector.
  const auto& P = ldlt_.permutationP().indices();
  perm_.assign(P.data(), P.data() + P.size());
  if (perm_.empty()) {
    perm_.resize(2 * q);
    std::iota(perm_.begin(), perm_.end(), 0);
  }
  perm_inv_.assign(perm_.size(), 0);
  for (size_t i = 0; i < perm_.size(); ++i) perm_inv_[static_cast<size_t>(perm_[i])] = static_cast<int>(i);
  line_c_.assign(frame.lines.size(), 1.0);
  line_s_.assign(frame.lines.size(), 0.0);
  vert_c_.assign(q, 1.0);
  vert_s_.assign(q, 0.0);
  v_.resize(q);
  anchor_.resize(q);
  scratch_line_.assign(frame.lines.size(), 0.0);
  scratch_vert_.assign(q, 0.0);
  reset_to_rest();
  return true;
}

void FeatureFrameSolver::reset_to_rest() {
  if (!frame_) return;
  std::copy(frame_->rest.begin(), frame_->rest.end(), v_.begin());
  std::fill(line_c_.begin(), line_c_.end(), 1.0);
  std::fill(line_s_.begin(), line_s_.end(), 0.0);
  std::fill(vert_c_.begin(), vert_c_.end(), 1.0);
  std::fill(vert_s_.begin(), vert_s_.end(), 0.0);
}

void FeatureFrameSolver::set_vertices(std::span<const Vec2> v) {
  assert(v.size() == v_.size() && "set_vertices: size must equal the frame vertex count");
  for (size_t i = 0; i < v.size() && i < v_.size(); ++i) {
    if (v[i].allFinite()) v_[i] = v[i];
  }
}

void FeatureFrameSolver::optimal_rotations(std::span<const Vec2> v, std::span<double> line_angle,
                                           std::span<double> vertex_angle) const {
  const FeatureFrame& f = *frame_;
  for (size_t j = 0; j < f.lines.size() && j < line_angle.size(); ++j) {
    const FrameLine& l = f.lines[j];
    const Vec2 e = v[static_cast<size_t>(l.b)] - v[static_cast<size_t>(l.a)];
    const Vec2 eb = f.rest[static_cast<size_t>(l.b)] - f.rest[static_cast<size_t>(l.a)];
    // angle of e * conj(ebar)
    const double re = e.x() * eb.x() + e.y() * eb.y(), im = e.y() * eb.x() - e.x() * eb.y();
    line_angle[j] = (re == 0 && im == 0) ? 0.0 : std::atan2(im, re);
  }
  for (size_t i = 0; i < v.size() && i < vertex_angle.size(); ++i) {
    double re = 0, im = 0;
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const size_t n = static_cast<size_t>(adj_[static_cast<size_t>(k)]);
      const Vec2 d = v[n] - v[i], db = f.rest[n] - f.rest[i];
      re += d.x() * db.x() + d.y() * db.y();
      im += d.y() * db.x() - d.x() * db.y();
    }
    vertex_angle[i] = (re == 0 && im == 0) ? 0.0 : std::atan2(im, re);
  }
}

double FeatureFrameSolver::energy_with_rotations(std::span<const Vec2> v, std::span<const double> line_angle,
                                                 std::span<const double> vertex_angle,
                                                 std::span<const Vec2> targets) const {
  const FeatureFrame& f = *frame_;
  double e_rig = 0, e_cou = 0, e_pos = 0, e_reg = 0;
  for (int j = 0; j < f.feature_lines; ++j) {
    const FrameLine& l = f.lines[static_cast<size_t>(j)];
    const Vec2 e = v[static_cast<size_t>(l.b)] - v[static_cast<size_t>(l.a)];
    const Vec2 eb = f.rest[static_cast<size_t>(l.b)] - f.rest[static_cast<size_t>(l.a)];
    const double a = line_angle[static_cast<size_t>(j)];
    e_rig += (e - rot(std::cos(a), std::sin(a), eb)).squaredNorm() / 12.0;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    const double a = vertex_angle[i], c = std::cos(a), s = std::sin(a);
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const size_t n = static_cast<size_t>(adj_[static_cast<size_t>(k)]);
      e_cou += ((v[n] - v[i]) - rot(c, s, f.rest[n] - f.rest[i])).squaredNorm() / 3.0;
    }
  }
  for (size_t h = 0; h < handles_.size() && h < targets.size(); ++h) {
    e_pos += (eval_param(handles_[h], v) - targets[h]).squaredNorm();
  }
  for (size_t i = 0; i < v.size(); ++i) {
    if (free_[i]) e_reg += (v[i] - anchor_[i]).squaredNorm();
  }
  return w_.rigidity * e_rig + w_.coupling * e_cou + w_.position * e_pos + eps_ * e_reg;
}

double FeatureFrameSolver::energy(std::span<const Vec2> targets) const {
  optimal_rotations(v_, scratch_line_, scratch_vert_);
  return energy_with_rotations(v_, scratch_line_, scratch_vert_, targets);
}

// Local step for the feature lines: R_j turns ebar_j onto e_j (angle of e * conj(ebar)).
// The vertex rotations Rhat_i are computed inside global_step, fused with their use.
void FeatureFrameSolver::local_step() {
  const FeatureFrame& f = *frame_;
  for (int j = 0; j < f.feature_lines; ++j) {
    const FrameLine& l = f.lines[static_cast<size_t>(j)];
    const Vec2 e = v_[static_cast<size_t>(l.b)] - v_[static_cast<size_t>(l.a)];
    const Vec2& eb = line_rest_[static_cast<size_t>(j)];
    const double re = e.x() * eb.x() + e.y() * eb.y(), im = e.y() * eb.x() - e.x() * eb.y();
    const double len2 = re * re + im * im;
    if (len2 > 1e-280 && std::isfinite(len2)) {  // zero-length edge keeps its rotation
      const double inv = 1.0 / std::sqrt(len2);
      line_c_[static_cast<size_t>(j)] = re * inv;
      line_s_[static_cast<size_t>(j)] = im * inv;
    }
  }
}

void FeatureFrameSolver::global_step(std::span<const Vec2> targets) {
  const double cr = w_.rigidity / 12.0, cc = w_.coupling / 3.0;
  const size_t q = v_.size();
  // Vertex rotations Rhat_i: angle of sum_k (v_k - v_i) conj(vbar_k - vbar_i); a vanishing
  // sum keeps the previous rotation.
  for (size_t i = 0; i < q; ++i) {
    double re = 0, im = 0;
    const Vec2 vi = v_[i];
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const Vec2 d = v_[static_cast<size_t>(adj_[static_cast<size_t>(k)])] - vi;
      const Vec2& db = adj_rest_[static_cast<size_t>(k)];
      re += d.x() * db.x() + d.y() * db.y();
      im += d.y() * db.x() - d.x() * db.y();
    }
    const double len2 = re * re + im * im;
    if (len2 > 1e-280 && std::isfinite(len2)) {
      const double inv = 1.0 / std::sqrt(len2);
      vert_c_[i] = re * inv;
      vert_s_[i] = im * inv;
    }
  }
  // Right-hand side, gathered per vertex, written in the factor's permuted order:
  //   b_i = -sum_{k in N(i)} [ c_c (Rhat_i + Rhat_k) + c_r R_j ] (vbar_k - vbar_i)
  // (R_j only when (i, k) is feature line j), plus handle and regulariser terms.
  double* y = work_.data();
  const int* perm = perm_.data();
  for (size_t i = 0; i < q; ++i) {
    double gx = 0, gy = 0;
    const double ci = vert_c_[i], si = vert_s_[i];
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const size_t n = static_cast<size_t>(adj_[static_cast<size_t>(k)]);
      double c = cc * (ci + vert_c_[n]), sn = cc * (si + vert_s_[n]);
      const int line = adj_line_[static_cast<size_t>(k)];
      if (line >= 0) {
        c += cr * line_c_[static_cast<size_t>(line)];
        sn += cr * line_s_[static_cast<size_t>(line)];
      }
      const Vec2& db = adj_rest_[static_cast<size_t>(k)];
      gx -= c * db.x() - sn * db.y();
      gy -= sn * db.x() + c * db.y();
    }
    if (free_[i]) {
      gx += eps_ * anchor_[i].x();
      gy += eps_ * anchor_[i].y();
    }
    y[perm[2 * i]] = gx;
    y[perm[2 * i + 1]] = gy;
  }
  for (size_t h = 0; h < handles_.size() && h < targets.size(); ++h) {
    const HandleCoeff k = coeff(handles_[h]);
    const Vec2 t = targets[h] - k.offset;
    // M(alpha)^T t = conj(alpha) * t
    y[perm[2 * k.a]] += w_.position * (k.ar * t.x() + k.ai * t.y());
    y[perm[2 * k.a + 1]] += w_.position * (k.ar * t.y() - k.ai * t.x());
    y[perm[2 * k.b]] += w_.position * (k.br * t.x() + k.bi * t.y());
    y[perm[2 * k.b + 1]] += w_.position * (k.br * t.y() - k.bi * t.x());
  }
  // Solve L D L^T y = P b in place on the factor's raw arrays (L unit lower, column-major,
  // diagonal not stored): the factor is very sparse, so Eigen's generic per-column
  // iterator overhead would dominate.
  const auto& L = ldlt_.matrixL().nestedExpression();
  const int* col = L.outerIndexPtr();
  const int* row = L.innerIndexPtr();
  const double* val = L.valuePtr();
  const double* D = diag_.data();
  const int n = static_cast<int>(work_.size());
  for (int j = 0; j < n; ++j) {
    const double yj = y[j];
    for (int p = col[j]; p < col[j + 1]; ++p) y[row[p]] -= val[p] * yj;
  }
  for (int j = 0; j < n; ++j) y[j] /= D[j];
  for (int j = n - 1; j >= 0; --j) {
    double sum = y[j];
    for (int p = col[j]; p < col[j + 1]; ++p) sum -= val[p] * y[row[p]];
    y[j] = sum;
  }
  for (size_t i = 0; i < q; ++i) {
    const Vec2 p(y[perm[2 * i]], y[perm[2 * i + 1]]);
    if (p.allFinite()) v_[i] = p;  // never let a NaN through: keep the previous position
  }
}

void FeatureFrameSolver::align_to(std::span<const Vec2> targets) {
  const size_t n = std::min(handles_.size(), targets.size());
  if (n == 0 || v_.empty()) return;
  Vec2 cp = Vec2::Zero(), ct = Vec2::Zero();
  size_t used = 0;
  for (size_t h = 0; h < n; ++h) {
    if (!targets[h].allFinite()) continue;
    cp += eval_param(handles_[h], v_);
    ct += targets[h];
    ++used;
  }
  if (used == 0) return;
  cp /= static_cast<double>(used);
  ct /= static_cast<double>(used);
  double re = 0, im = 0;  // sum of (t - ct) * conj(p - cp)
  for (size_t h = 0; h < n; ++h) {
    if (!targets[h].allFinite()) continue;
    const Vec2 p = eval_param(handles_[h], v_) - cp, t = targets[h] - ct;
    re += t.x() * p.x() + t.y() * p.y();
    im += t.y() * p.x() - t.x() * p.y();
  }
  const double len = std::hypot(re, im);
  const double c = len > 1e-300 ? re / len : 1.0, sn = len > 1e-300 ? im / len : 0.0;
  for (Vec2& x : v_) x = ct + rot(c, sn, x - cp);
  // Rotations follow the pose.
  for (size_t j = 0; j < line_c_.size(); ++j) {
    const double lc = line_c_[j], ls = line_s_[j];
    line_c_[j] = c * lc - sn * ls;
    line_s_[j] = sn * lc + c * ls;
  }
  for (size_t i = 0; i < vert_c_.size(); ++i) {
    const double vc = vert_c_[i], vs = vert_s_[i];
    vert_c_[i] = c * vc - sn * vs;
    vert_s_[i] = sn * vc + c * vs;
  }
}

void FeatureFrameSolver::solve(std::span<const Vec2> targets, int iterations, std::span<double> energies) {
  if (!frame_ || v_.empty()) return;
  std::copy(v_.begin(), v_.end(), anchor_.begin());
  const bool record = energies.size() >= static_cast<size_t>(iterations) + 1;
  if (record) energies[0] = energy(targets);
  for (int it = 0; it < iterations; ++it) {
    local_step();
    global_step(targets);
    if (record) energies[static_cast<size_t>(it) + 1] = energy(targets);
  }
}

}  // namespace mar
