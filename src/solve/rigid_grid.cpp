// The rigid grid's per-frame solve (solve/rigid_grid.h): the fast summation of the region
// sums, the local and global steps, the grab, and the live parameters. Preparation is in
// rigid_grid_prepare.cpp (the mesh) and rigid_grid_regions.cpp (the regions, the factor).
#include "solve/rigid_grid.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>

namespace mar {

namespace {
// Windowed sums along one run for C channels (C a constant, so the channel loops unroll).
template <int C>
void window_run(const int* idx, int len, int w, bool wrap, const double* in, const std::vector<int>* in_map, double* out,
                const std::vector<int>* out_map, bool accumulate, double* P) {
  const bool all = wrap && 2 * w + 1 >= len;
  // Prefix sums over the run (a closed run: starting w before its first position).
  const int pad = wrap && !all ? w : 0, total = len + 2 * pad;
  for (int c = 0; c < C; ++c) P[c] = 0;
  for (int s = 0; s < total; ++s) {
    int pos = s - pad;
    if (pos < 0) pos += len;
    else if (pos >= len) pos -= len;
    const int id = idx[pos];
    const double* v = in + size_t(in_map ? (*in_map)[size_t(id)] : id) * C;
    double* q = P + size_t(s) * C;
    for (int c = 0; c < C; ++c) q[C + c] = q[c] + v[c];
  }
  for (int p = 0; p < len; ++p) {
    int lo, hi;  // prefix indices
    if (all) lo = 0, hi = len;
    else if (wrap) lo = p, hi = p + 2 * w + 1;
    else lo = std::max(0, p - w), hi = std::min(len, p + w + 1);
    const int id = idx[p];
    double* o = out + size_t(out_map ? (*out_map)[size_t(id)] : id) * C;
    const double *ph = P + size_t(hi) * C, *pl = P + size_t(lo) * C;
    for (int c = 0; c < C; ++c) o[c] = accumulate ? o[c] + (ph[c] - pl[c]) : ph[c] - pl[c];
  }
}
}  // namespace

void RigidGrid::window_pass(const Runs& runs, const double* in, const std::vector<int>* in_map, double* out,
                            const std::vector<int>* out_map, bool accumulate, int C) const {
  for (size_t k = 0; k + 1 < runs.start.size(); ++k) {
    const int b = runs.start[k], len = runs.start[k + 1] - b;
    const int* idx = runs.idx.data() + b;
    if (C == 4) window_run<4>(idx, len, runs.half[k], runs.closed[k], in, in_map, out, out_map, accumulate, prefix_.data());
    else window_run<1>(idx, len, runs.half[k], runs.closed[k], in, in_map, out, out_map, accumulate, prefix_.data());
  }
}

void RigidGrid::gather(const double* f, double* out, int C, bool fast) const {
  if (!fast) {
    for (size_t r = 0; r < reg_center_.size(); ++r)
      for (int c = 0; c < C; ++c) {
        double s = 0;
        for (int j : region(r)) s += f[size_t(j) * size_t(C) + size_t(c)];
        out[r * size_t(C) + size_t(c)] = s;
      }
    return;
  }
  // Grid: along the rows, then along the columns (out for grid node i = its region's sum).
  window_pass(rows_, f, nullptr, ch_mid_.data(), nullptr, false, C);
  window_pass(cols_, ch_mid_.data(), nullptr, out, nullptr, false, C);
  window_pass(curve_runs_, f, &cnode_, out, &curve_region_, false, C);
}

void RigidGrid::scatter(const double* g, double* out, int C, bool fast) const {
  std::fill(out, out + rest_.size() * size_t(C), 0.0);
  if (!fast) {
    for (size_t r = 0; r < reg_center_.size(); ++r)
      for (int j : region(r))
        for (int c = 0; c < C; ++c) out[size_t(j) * size_t(C) + size_t(c)] += g[r * size_t(C) + size_t(c)];
    return;
  }
  window_pass(cols_, g, nullptr, ch_mid_.data(), nullptr, false, C);
  window_pass(rows_, ch_mid_.data(), nullptr, out, nullptr, false, C);
  window_pass(curve_runs_, g, &curve_region_, out, &cnode_, true, C);
}

void RigidGrid::region_sums(std::span<const double> f, std::span<double> out, bool fast) const {
  gather(f.data(), out.data(), 1, fast && !plain_);
}

void RigidGrid::region_scatter(std::span<const double> g, std::span<double> out, bool fast) const {
  scatter(g.data(), out.data(), 1, fast && !plain_);
}

std::vector<SolverParameter> RigidGrid::parameters() const {
  std::vector<SolverParameter> p = {{"half_width", double(half_width_), 1, 32},
                                    {"rigidity", w_r_, 1e-6, 1e9},
                                    {"junction", w_s_, 1e-6, 1e9},
                                    {"position", w_p_, 1e-3, 1e9}};
  for (const Stiff& s : stiff_)
    if (!s.name.empty()) p.push_back({"stiffness." + s.name, s.weight, 1e-3, 1e6});
  return p;
}

bool RigidGrid::set_parameters(std::span<const double> v, std::string* error) {
  size_t named = 0;
  for (const Stiff& s : stiff_) named += s.name.empty() ? 0 : 1;
  if (v.size() != 4 + named || !(v[0] >= 1 && v[0] <= 32) || !(v[1] > 0) || !(v[2] > 0) || !(v[3] > 0)) {
    if (error) *error = "rigid_grid parameters: half_width 1..32, rigidity, junction, position > 0, then each named stiffness";
    return false;
  }
  const int w = int(std::lround(v[0]));
  bool same = w == half_width_ && v[1] == w_r_ && v[2] == w_s_ && v[3] == w_p_;
  for (size_t k = 0, i = 4; k < stiff_.size(); ++k)
    if (!stiff_[k].name.empty()) same = same && std::clamp(v[i++], 1e-3, 1e6) == stiff_[k].weight;
  if (same) return true;  // (a knob on half_width moves in whole cells)
  const bool regions = w != half_width_;
  half_width_ = w;
  w_r_ = v[1];
  w_s_ = v[2];
  w_p_ = v[3];
  for (size_t k = 0, i = 4; k < stiff_.size(); ++k)
    if (!stiff_[k].name.empty()) stiff_[k].weight = std::clamp(v[i++], 1e-3, 1e6);
  if (regions) {  // new regions; the pose and (where the count allows) the rotations stay
    const std::vector<double> c(rc_), s(rs_);
    build_regions();
    if (c.size() == rc_.size()) rc_ = c, rs_ = s;
  } else {
    weigh_regions();
  }
  grab_active_ = false;  // the caller grabs again
  grab_rider_ = -1;
  return factorise(error);
}

void RigidGrid::reset_to_rest() {
  rigid_pose({}, {}, rest_, x_, rc_, rs_);
  for (Rider& d : riders_) d.c = 1, d.s = 0, d.t = d.hinge, d.angle = 0, d.rel = 0, d.base = 0, d.base_c = 1, d.base_s = 0;
}

void RigidGrid::initial_guess(std::span<const Vec2> targets) {
  rigid_pose(handle_rest_, targets, rest_, x_, rc_, rs_);
  place_riders(targets);
}

Vec2 RigidGrid::handle_point(size_t h) const {
  if (h < handle_rider_.size() && handle_rider_[h] >= 0) return riders_[size_t(handle_rider_[h])].apply(handle_rest_[h]);
  return eval(handles_[h]);
}

void RigidGrid::local_step() {
  // Each region's best rotation: the angle of Σ_j (q_j − q_c)(p_j − p_c)^T, from the region sums of
  // p·q, p×q and q (relative to the character's centre), expanded about the centre.
  const size_t n = rest_.size(), R = reg_center_.size();
  double* f = ch_in_.data();
  for (size_t j = 0; j < n; ++j) {
    const Vec2 p = p_[j], q = x_[j] - mid_;
    f[4 * j] = p.dot(q);
    f[4 * j + 1] = cross(p, q);
    f[4 * j + 2] = q.x();
    f[4 * j + 3] = q.y();
  }
  double* g = ch_out_.data();
  gather(f, g, 4, fast_);
  for (size_t r = 0; r < R; ++r) {
    if (reg_k_[r] == 0) continue;
    const size_t c = size_t(reg_center_[r]);
    const Vec2 pc = p_[c], qc = x_[c] - mid_, sq(g[4 * r + 2], g[4 * r + 3]), sp = reg_psum_[r];
    const double m = reg_size_[r];
    const double a = g[4 * r] - pc.dot(sq) - sp.dot(qc) + m * pc.dot(qc);
    const double s = g[4 * r + 1] - cross(pc, sq) - cross(sp, qc) + m * cross(pc, qc);
    const double len = portable_hypot(a, s);
    if (len > 1e-300 && std::isfinite(len)) {
      rc_[r] = a / len;
      rs_[r] = s / len;
    }
  }
}

void RigidGrid::global_step(std::span<const Vec2> targets) {
  const int* perm = factor_.perm().data();
  const size_t n = rest_.size(), R = reg_center_.size();
  // Regions: b_j += Σ_{r∋j} k_r A_r (p_j − p_c(r)); b_c(r) −= k_r A_r Σ_{j∈R_r} (p_j − p_c(r)).
  double* g = ch_in_.data();
  for (size_t r = 0; r < R; ++r) {
    const double k = reg_k_[r];
    const Vec2 ap = k * rotated(rc_[r], rs_[r], p_[size_t(reg_center_[r])]);
    g[4 * r] = k * rc_[r];
    g[4 * r + 1] = k * rs_[r];
    g[4 * r + 2] = ap.x();
    g[4 * r + 3] = ap.y();
  }
  double* T = ch_out_.data();
  scatter(g, T, 4, fast_);
  for (size_t j = 0; j < n; ++j) {
    const Vec2 v = rotated(T[4 * j], T[4 * j + 1], p_[j]) - Vec2(T[4 * j + 2], T[4 * j + 3]);
    bx_[size_t(perm[j])] = v.x();
    by_[size_t(perm[j])] = v.y();
  }
  auto add = [&](int k, const Vec2& v) {
    bx_[size_t(perm[k])] += v.x();
    by_[size_t(perm[k])] += v.y();
  };
  for (size_t r = 0; r < R; ++r) {
    if (reg_k_[r] == 0) continue;
    const int c = reg_center_[r];
    add(c, -reg_k_[r] * rotated(rc_[r], rs_[r], reg_psum_[r] - double(reg_size_[r]) * p_[size_t(c)]));
  }
  // Junction: each triangle turned by its best rotation (rigid), or each edge at its rest length
  // along its current direction (Eq. 4).
  if (tri_mode_)
    for (size_t tt = 0; tt < tris_.size(); ++tt) {
      if (!junction_[tt]) continue;
      double a = 0, sn = 0;
      for (int q = 0; q < 3; ++q) {
        const size_t i = size_t(tris_[tt][size_t(q)]), j = size_t(tris_[tt][size_t((q + 1) % 3)]);
        const Vec2 d = x_[i] - x_[j], p = rest_[i] - rest_[j];
        a += p.dot(d);
        sn += cross(p, d);
      }
      const double len = portable_hypot(a, sn);
      const double c = len > 1e-300 ? a / len : 1, si = len > 1e-300 ? sn / len : 0;
      for (int q = 0; q < 3; ++q) {
        const int i = tris_[tt][size_t(q)], j = tris_[tt][size_t((q + 1) % 3)];
        const Vec2 v = w_s_ * rotated(c, si, rest_[size_t(i)] - rest_[size_t(j)]);
        add(i, v);
        add(j, -v);
      }
    }
  for (size_t e = 0; e < edges_.size() && !tri_mode_; ++e) {
    const int i = edges_[e][0], j = edges_[e][1];
    Vec2 d = x_[size_t(i)] - x_[size_t(j)];
    const double len = d.norm();
    d = len > 1e-12 * h_ && std::isfinite(len) ? Vec2(d / len)
                                               : Vec2((rest_[size_t(i)] - rest_[size_t(j)]) / std::max(edge_len_[e], 1e-300));
    const Vec2 v = w_s_ * edge_len_[e] * d;
    add(i, v);
    add(j, -v);
  }
  for (size_t i = 0; i < n; ++i)
    if (pull_[i] != 0) add(int(i), pull_[i] * x_[i]);
  const size_t m = std::min(targets.size(), handles_.size());
  auto handle = [&](const Embed& h, const Vec2& t, double w) {  // a target that is not a number holds its handle
    const Vec2 at = t.allFinite() ? t : eval(h);
    for (int k = 0; k < h.n; ++k) add(h.v[k], w * h.w[k] * at);
  };
  for (size_t h = 0; h < m; ++h) handle(handles_[h], targets[h], w_p_ * handle_w(h));
  const bool grab = grab_active_ && grab_rider_ < 0 && targets.size() > handles_.size();
  if (grab) handle(grab_, targets[handles_.size()], w_p_);
  factor_.solve_permuted(bx_.data(), by_.data());
  if (grab) grab_update_.correct(factor_, bx_.data(), by_.data());
  for (size_t i = 0; i < n; ++i) {
    const Vec2 v(bx_[size_t(perm[i])], by_[size_t(perm[i])]);
    if (v.allFinite()) x_[i] = v;
  }
}

void RigidGrid::solve(std::span<const Vec2> targets, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    local_step();
    global_step(targets);
  }
  place_riders(targets);
}

void RigidGrid::grab(const Vec2& rest_point) {
  grab_rider_ = -1;  // on a rider (the last drawn of those under the pen): the pen turns it
  for (size_t r = 0; r < riders_.size(); ++r)
    if (!riders_[r].still && riders_[r].ring.size() >= 3 && winding_number(riders_[r].ring, rest_point) != 0 &&
        (grab_rider_ < 0 || riders_[r].shapes.front() > riders_[size_t(grab_rider_)].shapes.front()))
      grab_rider_ = int(r);
  if (grab_rider_ < 0) grab_rider_ = bone_at(rest_point);  // on a bone's limb: the pen turns the bone
  if (grab_rider_ >= 0) {
    grab_rest_ = rest_point;
    grab_active_ = true;
    return;
  }
  grab_ = embed(rest_point);
  grab_update_.set(factor_, grab_.v, grab_.w, grab_.n, w_p_);
  grab_active_ = true;
}

void RigidGrid::shape_points(std::vector<Points>& out) const {
  for (size_t s = 0; s < binds_.size() && s < out.size(); ++s)
    for (size_t k = 0; k < binds_[s].size() && k < out[s].size(); ++k) out[s][k] = eval(binds_[s][k]);
  for (const Skin& k : skin_) {  // a bone's limb: turned w of the bone's turn about its hinge
    if (size_t(k.shape) >= out.size() || size_t(k.point) >= out[size_t(k.shape)].size()) continue;
    const Rider& b = riders_[size_t(k.bone)];
    const Vec2 d = k.rest - b.hinge;
    Vec2& q = out[size_t(k.shape)][size_t(k.point)];
    if (k.w >= 1) {  // (past the band: the bone's own turn)
      q = b.t + Vec2(b.c * d.x() - b.s * d.y(), b.s * d.x() + b.c * d.y());
      continue;
    }
    const double a = b.base + k.w * (b.angle - b.base), c = std::cos(a), s = std::sin(a);
    const Vec2 turned = b.t + Vec2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
    const Vec2 grid_rigid = b.t + Vec2(b.base_c * d.x() - b.base_s * d.y(), b.base_s * d.x() + b.base_c * d.y());
    q = turned + (1 - k.w) * (q - grid_rigid);
  }
  for (const Rider& d : riders_)
    for (int si : d.shapes) {
      const Points& rest = rider_rest_[size_t(si)];
      if (size_t(si) >= out.size()) continue;
      for (size_t k = 0; k < rest.size() && k < out[size_t(si)].size(); ++k) out[size_t(si)][k] = d.apply(rest[k]);
    }
}

double RigidGrid::energy(std::span<const Vec2> targets) const {
  double e = 0;
  for (size_t r = 0; r < reg_center_.size(); ++r) {
    if (reg_k_[r] == 0) continue;
    const size_t c = size_t(reg_center_[r]);
    double a = 0, s = 0;
    for (int j : region(r)) {
      const Vec2 p = rest_[size_t(j)] - rest_[c], q = x_[size_t(j)] - x_[c];
      a += p.dot(q);
      s += cross(p, q);
    }
    const double len = portable_hypot(a, s);
    const double cs = len > 1e-300 ? a / len : 1, sn = len > 1e-300 ? s / len : 0;
    for (int j : region(r))
      e += reg_k_[r] * ((x_[size_t(j)] - x_[c]) - rotated(cs, sn, rest_[size_t(j)] - rest_[c])).squaredNorm();
  }
  for (size_t t = 0; t < tris_.size() && tri_mode_; ++t) {
    if (!junction_[t]) continue;
    double a = 0, sn = 0;
    for (int q = 0; q < 3; ++q) {
      const size_t i = size_t(tris_[t][size_t(q)]), j = size_t(tris_[t][size_t((q + 1) % 3)]);
      a += (rest_[i] - rest_[j]).dot(x_[i] - x_[j]);
      sn += cross(rest_[i] - rest_[j], x_[i] - x_[j]);
    }
    const double len = portable_hypot(a, sn);
    const double c = len > 1e-300 ? a / len : 1, si = len > 1e-300 ? sn / len : 0;
    for (int q = 0; q < 3; ++q) {
      const size_t i = size_t(tris_[t][size_t(q)]), j = size_t(tris_[t][size_t((q + 1) % 3)]);
      e += w_s_ * ((x_[i] - x_[j]) - rotated(c, si, rest_[i] - rest_[j])).squaredNorm();
    }
  }
  for (size_t k = 0; k < edges_.size() && !tri_mode_; ++k) {
    const double d = (x_[size_t(edges_[k][0])] - x_[size_t(edges_[k][1])]).norm() - edge_len_[k];
    e += w_s_ * d * d;
  }
  for (size_t v = 0; v + 1 < mvc_start_.size(); ++v) {
    Vec2 s = Vec2::Zero();
    for (int a = mvc_start_[v]; a < mvc_start_[v + 1]; ++a) s += mvc_w_[size_t(a)] * x_[size_t(mvc_node_[size_t(a)])];
    e += w_s_ * s.squaredNorm();
  }
  for (size_t h = 0; h < std::min(targets.size(), handles_.size()); ++h)
    e += w_p_ * (h < handle_rider_.size() && handle_rider_[h] >= 0 ? 1.0 : handle_w(h)) * (handle_point(h) - targets[h]).squaredNorm();
  return e;
}

}  // namespace mar
