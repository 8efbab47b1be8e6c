#include "solve/feature_frame.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cassert>
#include <limits>
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
  struct Nb {
    int n, line;  // neighbour, feature line or -1
    double w;
  };
  std::vector<std::vector<Nb>> nb(q);
  for (int li = 0; li < static_cast<int>(frame.lines.size()); ++li) {
    const FrameLine& l = frame.lines[static_cast<size_t>(li)];
    if (l.a == l.b || !(l.weight > 0) || !std::isfinite(l.weight)) continue;
    const int line = li < frame.feature_lines ? li : -1;
    nb[static_cast<size_t>(l.a)].push_back({l.b, line, l.weight});
    nb[static_cast<size_t>(l.b)].push_back({l.a, line, l.weight});
  }
  adj_begin_.assign(q + 1, 0);
  adj_.clear();
  adj_line_.clear();
  adj_w_.clear();
  for (size_t i = 0; i < q; ++i) {
    adj_begin_[i] = static_cast<int>(adj_.size());
    for (const Nb& e : nb[i]) {
      adj_.push_back(e.n);
      adj_line_.push_back(e.line);
      adj_w_.push_back(e.w);
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
  line_rest_n2_.resize(static_cast<size_t>(frame.feature_lines));
  line_w_.resize(static_cast<size_t>(frame.feature_lines));
  for (int j = 0; j < frame.feature_lines; ++j) {
    const FrameLine& l = frame.lines[static_cast<size_t>(j)];
    line_rest_[static_cast<size_t>(j)] = frame.rest[static_cast<size_t>(l.b)] - frame.rest[static_cast<size_t>(l.a)];
    line_rest_n2_[static_cast<size_t>(j)] = line_rest_[static_cast<size_t>(j)].squaredNorm();
    line_w_[static_cast<size_t>(j)] = (l.a == l.b || !(l.weight > 0) || !std::isfinite(l.weight)) ? 0.0 : l.weight;
  }
  adj_rest_n2_.assign(q, 0.0);
  for (size_t i = 0; i < q; ++i) {
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      adj_rest_n2_[i] += adj_w_[static_cast<size_t>(k)] * adj_rest_[static_cast<size_t>(k)].squaredNorm();
    }
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
  any_free_ = false;
  for (size_t i = 0; i < q; ++i) {
    free_[i] = handled[static_cast<size_t>(uf.find(static_cast<int>(i)))] ? 0 : 1;
    any_free_ = any_free_ || free_[i];
  }
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
    if (l.a == l.b || !(l.weight > 0) || !std::isfinite(l.weight)) continue;
    const double c = l.weight * ((li < frame.feature_lines ? cr : 0.0) + 2.0 * cc);
    add_block_diag(l.a, l.a, c);
    add_block_diag(l.b, l.b, c);
    add_block_diag(l.a, l.b, -c);
    add_block_diag(l.b, l.a, -c);
  }
  for (size_t hi = 0; hi < handles_.size(); ++hi) {
    const HandleCoeff k = coeff(handles_[hi]);
    const double wp = w.position * w.handle_weight(hi);
    // |M(alpha_a) v_a + M(alpha_b) v_b - c|^2 ; M(x)^T M(y) = M(conj(x) y)
    const int idx[2] = {k.a, k.b};
    const double re[2] = {k.ar, k.br}, im[2] = {k.ai, k.bi};
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) {
        // conj(alpha_r) * alpha_c
        const double pr = re[r] * re[c] + im[r] * im[c];
        const double pi = re[r] * im[c] - im[r] * re[c];
        const int I = idx[r], J = idx[c];
        t.emplace_back(2 * I, 2 * J, wp * pr);
        t.emplace_back(2 * I, 2 * J + 1, -wp * pi);
        t.emplace_back(2 * I + 1, 2 * J, wp * pi);
        t.emplace_back(2 * I + 1, 2 * J + 1, wp * pr);
      }
    }
  }
  for (size_t i = 0; i < q; ++i) {
    if (free_[i]) add_block_diag(static_cast<int>(i), static_cast<int>(i), eps_);
  }
  Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(2 * q), static_cast<Eigen::Index>(2 * q));
  A.setFromTriplets(t.begin(), t.end());
  if (!factor_.compute(A)) {
    if (error) *error = "the system matrix could not be factorised";
    return false;
  }
  rhs_.setZero(static_cast<Eigen::Index>(2 * q));
  x_.setZero(static_cast<Eigen::Index>(2 * q));
  work_.setZero(static_cast<Eigen::Index>(2 * q));
  perm_ = factor_.perm();
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
  const Eigen::Index n2 = static_cast<Eigen::Index>(2 * q);
  const int m = std::clamp(w.anderson, 0, 16);
  aa_dF_.setZero(n2, m);
  aa_dG_.setZero(n2, m);
  for (Eigen::VectorXd* vec : {&aa_x_, &aa_g_, &aa_f_, &aa_prev_g_, &aa_prev_f_, &aa_accept_g_}) vec->setZero(n2);
  aa_count_ = aa_head_ = 0;
  aa_accepted_ = aa_rejected_ = 0;
  extra_active_ = false;
  extra_z0_.setZero(n2);
  extra_z1_.setZero(n2);
  soft_n_ = 0;  // (a new factor: the brush sets its terms again)
  if (soft_cap_ > 0) soft_z_.setZero(n2, 2 * soft_cap_);
  build_bodies();
  reset_to_rest();
  return true;
}

void FeatureFrameSolver::reset_to_rest() {
  if (!frame_) return;
  std::copy(frame_->rest.begin(), frame_->rest.end(), v_.begin());
  // The rest pose answers the handles' rest positions: the next solve follows (or jumps)
  // from there.
  for (size_t h = 0; h < handles_.size() && h < jump_prev_.size(); ++h) jump_prev_[h] = eval_param(handles_[h], frame_->rest);
  jump_prev_n_ = std::min(handles_.size(), jump_prev_.size());
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
      const double w = adj_w_[static_cast<size_t>(k)];
      const Vec2 d = v[n] - v[i], db = f.rest[n] - f.rest[i];
      re += w * (d.x() * db.x() + d.y() * db.y());
      im += w * (d.y() * db.x() - d.x() * db.y());
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
    e_rig += l.weight * (e - rot(std::cos(a), std::sin(a), eb)).squaredNorm() / 12.0;
  }
  for (size_t i = 0; i < v.size(); ++i) {
    const double a = vertex_angle[i], c = std::cos(a), s = std::sin(a);
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const size_t n = static_cast<size_t>(adj_[static_cast<size_t>(k)]);
      e_cou += adj_w_[static_cast<size_t>(k)] * ((v[n] - v[i]) - rot(c, s, f.rest[n] - f.rest[i])).squaredNorm() / 3.0;
    }
  }
  for (size_t h = 0; h < handles_.size() && h < targets.size(); ++h) {
    e_pos += w_.handle_weight(h) * (eval_param(handles_[h], v) - targets[h]).squaredNorm();
  }
  if (extra_active_ && targets.size() > handles_.size()) e_pos += (eval_param(extra_, v) - targets[handles_.size()]).squaredNorm();
  e_pos += soft_energy(v);
  for (size_t i = 0; i < v.size(); ++i) {
    if (free_[i]) e_reg += (v[i] - anchor_[i]).squaredNorm();
  }
  return w_.rigidity * e_rig + w_.coupling * e_cou + w_.position * e_pos + eps_ * e_reg;
}

double FeatureFrameSolver::energy(std::span<const Vec2> targets) const {
  optimal_rotations(v_, scratch_line_, scratch_vert_);
  return energy_with_rotations(v_, scratch_line_, scratch_vert_, targets);
}

// Local step for the feature lines: R_j turns ebar_j onto e_j (angle of e * conj(ebar));
// vertex_rotations() does the vertices' Rhat_i.
// Both rotation passes also sum the energy of their terms at the optimal rotations, in
// closed form: min_R |d - R dbar|^2 = |d|^2 + |dbar|^2 - 2 |d conj(dbar)| (current_energy()).
void FeatureFrameSolver::local_step() {
  const FeatureFrame& f = *frame_;
  const double cr = w_.rigidity / 12.0;
  double e = 0;
  for (int j = 0; j < f.feature_lines; ++j) {
    const FrameLine& l = f.lines[static_cast<size_t>(j)];
    const Vec2 d = v_[static_cast<size_t>(l.b)] - v_[static_cast<size_t>(l.a)];
    const Vec2& eb = line_rest_[static_cast<size_t>(j)];
    const double re = d.x() * eb.x() + d.y() * eb.y(), im = d.y() * eb.x() - d.x() * eb.y();
    const double len2 = re * re + im * im;
    const double len = std::sqrt(len2);
    e += line_w_[static_cast<size_t>(j)] * (d.squaredNorm() + line_rest_n2_[static_cast<size_t>(j)] - 2 * len);
    if (len2 > 1e-280 && std::isfinite(len2)) {  // zero-length edge keeps its rotation
      const double inv = 1.0 / len;
      line_c_[static_cast<size_t>(j)] = re * inv;
      line_s_[static_cast<size_t>(j)] = im * inv;
    }
  }
  e_lines_ = cr * e;
}

void FeatureFrameSolver::vertex_rotations() {
  const size_t q = v_.size();
  // Vertex rotations Rhat_i: angle of sum_k w_k (v_k - v_i) conj(vbar_k - vbar_i); a
  // vanishing sum keeps the previous rotation.
  double e = 0;
  for (size_t i = 0; i < q; ++i) {
    double re = 0, im = 0, n2 = 0;
    const Vec2 vi = v_[i];
    for (int k = adj_begin_[i]; k < adj_begin_[i + 1]; ++k) {
      const Vec2 d = v_[static_cast<size_t>(adj_[static_cast<size_t>(k)])] - vi;
      const Vec2& db = adj_rest_[static_cast<size_t>(k)];
      const double w = adj_w_[static_cast<size_t>(k)];
      re += w * (d.x() * db.x() + d.y() * db.y());
      im += w * (d.y() * db.x() - d.x() * db.y());
      n2 += w * d.squaredNorm();
    }
    const double len2 = re * re + im * im;
    const double len = std::sqrt(len2);
    e += n2 + adj_rest_n2_[i] - 2 * len;
    if (len2 > 1e-280 && std::isfinite(len2)) {
      const double inv = 1.0 / len;
      vert_c_[i] = re * inv;
      vert_s_[i] = im * inv;
    }
  }
  e_spokes_ = (w_.coupling / 3.0) * e;
}

void FeatureFrameSolver::global_step(std::span<const Vec2> targets) {
  const double cr = w_.rigidity / 12.0, cc = w_.coupling / 3.0;
  const size_t q = v_.size();
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
      const double w = adj_w_[static_cast<size_t>(k)];
      double c = cc * w * (ci + vert_c_[n]), sn = cc * w * (si + vert_s_[n]);
      const int line = adj_line_[static_cast<size_t>(k)];
      if (line >= 0) {
        c += cr * w * line_c_[static_cast<size_t>(line)];
        sn += cr * w * line_s_[static_cast<size_t>(line)];
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
    const double wp = w_.position * w_.handle_weight(h);
    // M(alpha)^T t = conj(alpha) * t
    y[perm[2 * k.a]] += wp * (k.ar * t.x() + k.ai * t.y());
    y[perm[2 * k.a + 1]] += wp * (k.ar * t.y() - k.ai * t.x());
    y[perm[2 * k.b]] += wp * (k.br * t.x() + k.bi * t.y());
    y[perm[2 * k.b + 1]] += wp * (k.br * t.y() - k.bi * t.x());
  }
  if (extra_active_ && handles_.size() < targets.size()) {
    const HandleCoeff k = coeff(extra_);
    const Vec2 t = targets[handles_.size()] - k.offset;
    y[perm[2 * k.a]] += w_.position * (k.ar * t.x() + k.ai * t.y());
    y[perm[2 * k.a + 1]] += w_.position * (k.ar * t.y() - k.ai * t.x());
    y[perm[2 * k.b]] += w_.position * (k.br * t.x() + k.bi * t.y());
    y[perm[2 * k.b + 1]] += w_.position * (k.br * t.y() - k.bi * t.x());
  }
  const bool soft = soft_n_ > 0 && !extra_active_;
  if (soft)
    for (int i = 0; i < soft_n_; ++i) {
      const size_t j = size_t(soft_v_[size_t(i)]);
      const double w = w_.position * soft_w_[size_t(i)];
      y[perm[2 * j]] += w * soft_t_[size_t(i)].x();
      y[perm[2 * j + 1]] += w * soft_t_[size_t(i)].y();
    }
  factor_solve(y);
  if (soft) {
    // Woodbury: x = y - Z K^-1 (U^T y), K = L L^T.
    const int n = 2 * soft_n_, st = 2 * soft_cap_;
    double* r = soft_r_.data();
    for (int i = 0; i < soft_n_; ++i) {
      const size_t j = size_t(soft_v_[size_t(i)]);
      r[2 * i] = y[perm[2 * j]];
      r[2 * i + 1] = y[perm[2 * j + 1]];
    }
    const double* l = soft_l_.data();
    for (int a = 0; a < n; ++a) {  // L c' = r
      double t = r[a];
      for (int b = 0; b < a; ++b) t -= l[a * st + b] * r[b];
      r[a] = t / l[a * st + a];
    }
    for (int a = n - 1; a >= 0; --a) {  // L^T c = c'
      double t = r[a];
      for (int b = a + 1; b < n; ++b) t -= l[b * st + a] * r[b];
      r[a] = t / l[a * st + a];
    }
    const Eigen::Index rows = work_.size();
    for (int a = 0; a < n; ++a) {
      const double* z = soft_z_.data() + Eigen::Index(a) * rows;
      const double c = r[a];
      for (Eigen::Index k = 0; k < rows; ++k) y[k] -= z[k] * c;
    }
  }
  if (extra_active_) {
    // Woodbury: x = y - Z K^-1 (M y).
    const Vec2 my = extra_eval(y);
    const double c0 = extra_k_[0] * my.x() + extra_k_[1] * my.y(), c1 = extra_k_[2] * my.x() + extra_k_[3] * my.y();
    const double* z0 = extra_z0_.data();
    const double* z1 = extra_z1_.data();
    for (Eigen::Index j = 0; j < work_.size(); ++j) y[j] -= z0[j] * c0 + z1[j] * c1;
  }
  for (size_t i = 0; i < q; ++i) {
    const Vec2 p(y[perm[2 * i]], y[perm[2 * i + 1]]);
    if (p.allFinite()) v_[i] = p;  // never let a NaN through: keep the previous position
  }
}

void FeatureFrameSolver::factor_solve(double* y) const { factor_.solve_permuted(y); }

Vec2 FeatureFrameSolver::extra_eval(const double* y) const {
  const HandleCoeff k = coeff(extra_);
  const int* perm = perm_.data();
  const Vec2 a(y[perm[2 * k.a]], y[perm[2 * k.a + 1]]), b(y[perm[2 * k.b]], y[perm[2 * k.b + 1]]);
  return rot(k.ar, k.ai, a) + rot(k.br, k.bi, b);
}

void FeatureFrameSolver::reserve_soft(int k) {
  soft_cap_ = std::max(0, k);
  soft_v_.assign(size_t(soft_cap_), 0);
  soft_w_.assign(size_t(soft_cap_), 0.0);
  soft_t_.assign(size_t(soft_cap_), Vec2::Zero());
  soft_l_.assign(size_t(4 * soft_cap_ * soft_cap_), 0.0);
  soft_r_.assign(size_t(2 * soft_cap_), 0.0);
  soft_z_.setZero(Eigen::Index(2 * v_.size()), 2 * soft_cap_);
  soft_n_ = 0;
}

bool FeatureFrameSolver::set_soft(std::span<const int> vertices, std::span<const double> weights) {
  soft_n_ = 0;
  const size_t q = v_.size();
  const int n = int(vertices.size());
  if (!frame_ || n == 0 || n > soft_cap_ || weights.size() != vertices.size() || soft_z_.rows() != Eigen::Index(2 * q)) return false;
  for (int i = 0; i < n; ++i) {
    if (vertices[size_t(i)] < 0 || size_t(vertices[size_t(i)]) >= q || !(weights[size_t(i)] > 0)) return false;
    soft_v_[size_t(i)] = vertices[size_t(i)];
    soft_w_[size_t(i)] = weights[size_t(i)];
    soft_t_[size_t(i)] = v_[size_t(vertices[size_t(i)])];  // (held where it is until told)
  }
  const int* perm = perm_.data();
  const Eigen::Index rows = soft_z_.rows();
  // Z's columns: A^-1 of each unit vector of U (a soft vertex's x or y, permuted order).
  for (int a = 0; a < 2 * n; ++a) {
    double* z = soft_z_.data() + Eigen::Index(a) * rows;
    std::fill(z, z + rows, 0.0);
    z[perm[2 * soft_v_[size_t(a / 2)] + (a % 2)]] = 1.0;
    factor_solve(z);
  }
  // K = C^-1 + U^T Z, then its lower Cholesky factor in place. (Written out, not Eigen's LLT:
  // its blocked products pick their blocking from the cache sizes, and a show's run_hash must
  // be the same bits on every machine; these loops run in one order everywhere.)
  const int st = 2 * soft_cap_;
  double* l = soft_l_.data();
  for (int a = 0; a < 2 * n; ++a)
    for (int b = 0; b <= a; ++b) {
      const double* zb = soft_z_.data() + Eigen::Index(b) * rows;
      l[a * st + b] = zb[perm[2 * soft_v_[size_t(a / 2)] + (a % 2)]] +
                      (a == b ? 1.0 / std::max(1e-300, w_.position * soft_w_[size_t(a / 2)]) : 0.0);
    }
  for (int a = 0; a < 2 * n; ++a) {
    for (int b = 0; b <= a; ++b) {
      double t = l[a * st + b];
      for (int c = 0; c < b; ++c) t -= l[a * st + c] * l[b * st + c];
      if (a == b) {
        if (!(t > 0) || !std::isfinite(t)) return false;
        l[a * st + a] = std::sqrt(t);
      } else {
        l[a * st + b] = t / l[b * st + b];
      }
    }
  }
  soft_n_ = n;
  return true;
}

double FeatureFrameSolver::soft_energy(std::span<const Vec2> v) const {
  double e = 0;
  if (!extra_active_)  // (the extra handle wins: the soft terms are left out of the solve then)
    for (int i = 0; i < soft_n_; ++i) e += soft_w_[size_t(i)] * (v[size_t(soft_v_[size_t(i)])] - soft_t_[size_t(i)]).squaredNorm();
  return e;
}

void FeatureFrameSolver::set_extra_handle(const ShapeParam& h) {
  const size_t q = v_.size();
  if (!frame_ || q == 0 || h.a < 0 || h.b < 0 || static_cast<size_t>(h.a) >= q || static_cast<size_t>(h.b) >= q) return;
  extra_ = h;
  const HandleCoeff k = coeff(h);
  const int* perm = perm_.data();
  // Column j of M^T: the gradient of component j of the handle's position.
  for (int j = 0; j < 2; ++j) {
    Eigen::VectorXd& z = j == 0 ? extra_z0_ : extra_z1_;
    z.setZero();
    // d(alpha v)_x / dv = (Re alpha, -Im alpha); d(alpha v)_y / dv = (Im alpha, Re alpha)
    const double ax = j == 0 ? k.ar : k.ai, ay = j == 0 ? -k.ai : k.ar;
    const double bx = j == 0 ? k.br : k.bi, by = j == 0 ? -k.bi : k.br;
    z[perm[2 * k.a]] += ax;
    z[perm[2 * k.a + 1]] += ay;
    z[perm[2 * k.b]] += bx;
    z[perm[2 * k.b + 1]] += by;
    factor_solve(z.data());
  }
  const Vec2 m0 = extra_eval(extra_z0_.data()), m1 = extra_eval(extra_z1_.data());
  // K = I / w_p + M Z (columns m0, m1)
  const double inv_w = 1.0 / std::max(w_.position, 1e-300);
  const double k00 = inv_w + m0.x(), k01 = m1.x(), k10 = m0.y(), k11 = inv_w + m1.y();
  const double det = k00 * k11 - k01 * k10;
  if (!(std::abs(det) > 1e-300) || !std::isfinite(det)) return;
  extra_k_[0] = k11 / det;
  extra_k_[1] = -k01 / det;
  extra_k_[2] = -k10 / det;
  extra_k_[3] = k00 / det;
  extra_active_ = true;
}

void FeatureFrameSolver::follow_rigid_motion(std::span<const Vec2> before, std::span<const Vec2> after) {
  // Best rigid motion of the targets since the last solve; applied to the pose when it
  // explains the motion (residual under 1% of it), so a character carried as a whole does
  // not trail behind its handles.
  const size_t n = std::min(before.size(), after.size());
  Vec2 cb = Vec2::Zero(), ca = Vec2::Zero();
  size_t used = 0;
  for (size_t h = 0; h < n; ++h) {
    if (!before[h].allFinite() || !after[h].allFinite()) return;
    cb += before[h];
    ca += after[h];
    ++used;
  }
  if (used < 2) return;
  cb /= static_cast<double>(used);
  ca /= static_cast<double>(used);
  double re = 0, im = 0, moved = 0;
  for (size_t h = 0; h < n; ++h) {
    const Vec2 p = before[h] - cb, q = after[h] - ca;
    re += q.x() * p.x() + q.y() * p.y();
    im += q.y() * p.x() - q.x() * p.y();
    moved += (after[h] - before[h]).squaredNorm();
  }
  const double len = portable_hypot(re, im);
  if (!(len > 1e-300) || !std::isfinite(len) || !(moved > 1e-18 * frame_->diagonal * frame_->diagonal)) return;
  const double c = re / len, sn = im / len;
  double resid = 0;
  for (size_t h = 0; h < n; ++h) resid += (ca + rot(c, sn, before[h] - cb) - after[h]).squaredNorm();
  if (resid > 0.01 * moved) return;
  move_rigidly(c, sn, cb, ca);
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
  const double len = portable_hypot(re, im);
  const double c = len > 1e-300 ? re / len : 1.0, sn = len > 1e-300 ? im / len : 0.0;
  move_rigidly(c, sn, cp, ct);
}

void FeatureFrameSolver::move_rigidly(double c, double sn, const Vec2& from, const Vec2& to) {
  for (Vec2& x : v_) x = to + rot(c, sn, x - from);
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

double FeatureFrameSolver::current_energy(std::span<const Vec2> targets) const {
  double e = e_lines_ + e_spokes_;
  for (size_t h = 0; h < handles_.size() && h < targets.size(); ++h) {
    e += w_.position * w_.handle_weight(h) * (eval_param(handles_[h], v_) - targets[h]).squaredNorm();
  }
  if (extra_active_ && targets.size() > handles_.size()) {
    e += w_.position * (eval_param(extra_, v_) - targets[handles_.size()]).squaredNorm();
  }
  e += w_.position * soft_energy(v_);
  if (any_free_) {
    for (size_t i = 0; i < v_.size(); ++i) {
      if (free_[i]) e += eps_ * (v_[i] - anchor_[i]).squaredNorm();
    }
  }
  return e;
}

// Type-II Anderson acceleration on x -> G(x): with residuals f = G(x) - x and the history
// of differences dF, dG, theta = argmin |f - dF theta| and x+ = G(x) - dG theta.
bool FeatureFrameSolver::anderson_mix() {
  const Eigen::Index n2 = aa_x_.size();
  const int m = static_cast<int>(aa_dF_.cols());
  Eigen::Map<Eigen::VectorXd> v(v_.data()->data(), n2);
  aa_g_ = v;
  aa_f_ = aa_g_ - aa_x_;
  if (aa_count_ > 0) {
    const int col = aa_head_;
    aa_dF_.col(col) = aa_f_ - aa_prev_f_;
    aa_dG_.col(col) = aa_g_ - aa_prev_g_;
    // Gram matrix of the dF columns, kept up to date one column at a time.
    const int filled = std::min(aa_count_, m);
    for (int j = 0; j < filled; ++j) aa_gram_[col * 16 + j] = aa_gram_[j * 16 + col] = aa_dF_.col(col).dot(aa_dF_.col(j));
    aa_head_ = (aa_head_ + 1) % m;
  }
  aa_prev_f_ = aa_f_;
  aa_prev_g_ = aa_g_;
  const int k = std::min(aa_count_, m);
  ++aa_count_;
  if (k == 0) return false;  // v_ = G(x)
  // Converged to rounding: nothing to accelerate (and the history would be noise).
  if (aa_f_.squaredNorm() < 1e-24 * frame_->diagonal * frame_->diagonal * static_cast<double>(n2)) return false;
  // Normal equations (k <= 16), Tikhonov-regularised, solved on the stack.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 16, 16>;  // no heap
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 16, 1>;
  Small A(k, k);
  SmallVec b(k);
  double scale = 0;
  for (int i = 0; i < k; ++i) {
    b(i) = aa_dF_.col(i).dot(aa_f_);
    for (int j = 0; j < k; ++j) A(i, j) = aa_gram_[i * 16 + j];
    scale = std::max(scale, A(i, i));
  }
  if (!(scale > 0) || !std::isfinite(scale)) return false;
  for (int i = 0; i < k; ++i) A(i, i) += 1e-10 * scale;
  const Eigen::LDLT<Small> ldlt(A);
  const SmallVec theta = ldlt.solve(b);
  if (!theta.allFinite()) return false;
  for (int i = 0; i < k; ++i) v -= theta(i) * aa_dG_.col(i);
  return true;
}

void FeatureFrameSolver::solve(std::span<const Vec2> given, int iterations, std::span<double> energies) {
  if (!frame_ || v_.empty()) return;
  // A jump in the targets (a pose recall): start from the best of the initial guesses.
  bool jumped = false;
  const size_t n_given = std::min(given.size(), jump_prev_.size());
  if (w_.jump > 0 && jump_prev_n_ == n_given) {
    const double limit2 = w_.jump * w_.jump * frame_->diagonal * frame_->diagonal;
    for (size_t h = 0; h < n_given && !jumped; ++h) jumped = (given[h] - jump_prev_[h]).squaredNorm() > limit2;
  }
  if (!jumped && jump_prev_n_ == n_given) follow_rigid_motion(std::span<const Vec2>(jump_prev_.data(), n_given), given);
  if (jumped) {
    ++jumps_;
    apply_reach(given);
    initial_guess(effective_targets());
  }
  std::copy(given.begin(), given.begin() + static_cast<long>(n_given), jump_prev_.begin());
  jump_prev_n_ = n_given;
  apply_reach(given);
  const std::span<const Vec2> targets = effective_targets();
  std::copy(v_.begin(), v_.end(), anchor_.begin());
  const bool record = energies.size() >= static_cast<size_t>(iterations) + 1;
  const bool aa = aa_dF_.cols() > 0 && iterations > 1;
  const Eigen::Index n2 = static_cast<Eigen::Index>(2 * v_.size());
  Eigen::Map<Eigen::VectorXd> v(v_.data()->data(), n2);
  aa_count_ = aa_head_ = 0;
  double accepted = std::numeric_limits<double>::infinity();
  bool mixed = false;  // the current iterate is an Anderson extrapolation, not a plain step
  const double rounding = 1e-14 * frame_->diagonal * frame_->diagonal;  // energy noise floor
  for (int it = 0; it < iterations; ++it) {
    local_step();
    vertex_rotations();
    if (aa || record) {
      double e = current_energy(targets);
      if (mixed && e > accepted + 1e-12 * accepted + rounding) {
        // The accelerated iterate raised the energy (beyond rounding): take the plain step.
        v = aa_accept_g_;
        ++aa_rejected_;
        aa_count_ = aa_head_ = 0;
        local_step();
        vertex_rotations();
        e = current_energy(targets);
      } else if (mixed) {
        ++aa_accepted_;
      }
      if (record) energies[static_cast<size_t>(it)] = std::isfinite(accepted) ? std::min(e, accepted) : e;
      accepted = std::min(accepted, e);
    }
    if (aa) aa_x_ = v;
    global_step(targets);
    mixed = false;
    if (aa && it + 1 < iterations) {
      aa_accept_g_ = v;  // G(x): the fallback
      mixed = anderson_mix();
    }
  }
  if (record) {
    local_step();
    vertex_rotations();
    energies[static_cast<size_t>(iterations)] = current_energy(targets);
  }
}

}  // namespace mar
