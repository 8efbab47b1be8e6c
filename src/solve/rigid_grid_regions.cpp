// The rigid grid's regions and factorisation (solve/rigid_grid.h): the runs of interior-cell
// edges and curves, each node's rigid region, their weights and stride, and the prefactored
// system a frame solves with. The mesh they stand on is built in rigid_grid_prepare.cpp.
#include "solve/rigid_grid.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mar {

void RigidGrid::build_runs() {
  // Rows and columns of grid nodes joined by an edge of an interior cell.
  auto lattice_runs = [&](bool along_x, Runs& r) {
    r = Runs{};
    const int outer = along_x ? ny_ : nx_, inner = along_x ? nx_ : ny_;
    for (int a = 0; a <= outer; ++a) {
      int prev = -1;
      for (int b = 0; b <= inner; ++b) {
        const int node = along_x ? corner_node(b, a) : corner_node(a, b);
        const bool joined = prev >= 0 && node >= 0 &&
                            (along_x ? (cell_inside(b - 1, a - 1) || cell_inside(b - 1, a))
                                     : (cell_inside(a - 1, b - 1) || cell_inside(a, b - 1)));
        if (!joined && prev >= 0) {  // close the run
          r.start.push_back(int(r.idx.size()));
          r.closed.push_back(0);
          r.half.push_back(half_width_);
        }
        if (node >= 0) r.idx.push_back(node);
        prev = node;
      }
      if (prev >= 0) {
        r.start.push_back(int(r.idx.size()));
        r.closed.push_back(0);
        r.half.push_back(half_width_);
      }
    }
  };
  lattice_runs(true, rows_);
  lattice_runs(false, cols_);
  curve_runs_ = Runs{};
  curve_region_.resize(cnode_.size());
  for (const Curve& c : curves_) {
    // w̃ = w l_in / l_b: the same reach along the curve as across the grid.
    const int wt = std::max(1, int(std::lround(half_width_ * h_ / std::max(c.spacing, 1e-9 * h_))));
    for (int k = 0; k < c.count; ++k) {
      curve_runs_.idx.push_back(c.first + k);
      curve_region_[size_t(c.first + k)] = int(grid_count_) + c.first + k;
    }
    curve_runs_.start.push_back(int(curve_runs_.idx.size()));
    curve_runs_.closed.push_back(c.closed ? 1 : 0);
    curve_runs_.half.push_back(wt);
  }
  // A window pass takes prefix sums over at most twice a run (a closed run, padded by w < len/2).
  size_t longest = 1;
  for (const Runs* r : {&rows_, &cols_, &curve_runs_})
    for (size_t k = 0; k + 1 < r->start.size(); ++k) longest = std::max(longest, size_t(r->start[k + 1] - r->start[k]));
  prefix_.assign((2 * longest + 1) * 4, 0.0);
}

void RigidGrid::build_regions() {
  const size_t G = grid_count_, R = G + cnode_.size();
  for (Runs* r : {&rows_, &cols_}) std::fill(r->half.begin(), r->half.end(), half_width_);
  reg_start_.assign(1, 0);
  reg_.clear();
  reg_center_.resize(R);
  std::vector<int> row_run(G), row_pos(G), col_run(G), col_pos(G);
  for (size_t k = 0; k + 1 < rows_.start.size(); ++k)
    for (int p = rows_.start[k]; p < rows_.start[k + 1]; ++p)
      row_run[size_t(rows_.idx[size_t(p)])] = int(k), row_pos[size_t(rows_.idx[size_t(p)])] = p;
  for (size_t k = 0; k + 1 < cols_.start.size(); ++k)
    for (int p = cols_.start[k]; p < cols_.start[k + 1]; ++p)
      col_run[size_t(cols_.idx[size_t(p)])] = int(k), col_pos[size_t(cols_.idx[size_t(p)])] = p;
  const int w = half_width_;
  for (size_t i = 0; i < G; ++i) {
    if (plain_) {  // every grid node of the square, reachable or not
      for (int dj = -w; dj <= w; ++dj)
        for (int di = -w; di <= w; ++di) {
          const int ii = gxy_[i][0] + di, jj = gxy_[i][1] + dj;
          if (ii >= 0 && jj >= 0 && ii <= nx_ && jj <= ny_ && corner_node(ii, jj) >= 0) reg_.push_back(corner_node(ii, jj));
        }
    } else {  // along the column of interior-cell edges, then along the rows
      const int c = col_run[i];
      for (int p = std::max(cols_.start[size_t(c)], col_pos[i] - w);
           p <= std::min(cols_.start[size_t(c) + 1] - 1, col_pos[i] + w); ++p) {
        const size_t k = size_t(cols_.idx[size_t(p)]);
        const int r = row_run[k];
        for (int s = std::max(rows_.start[size_t(r)], row_pos[k] - w);
             s <= std::min(rows_.start[size_t(r) + 1] - 1, row_pos[k] + w); ++s)
          reg_.push_back(rows_.idx[size_t(s)]);
      }
    }
    reg_center_[i] = int(i);
    reg_start_.push_back(int(reg_.size()));
  }
  for (size_t k = 0; k + 1 < curve_runs_.start.size(); ++k) {
    const int b = curve_runs_.start[k], len = curve_runs_.start[k + 1] - b;
    const int wt = std::max(1, int(std::lround(w * h_ / std::max(curves_[k].spacing, 1e-9 * h_))));
    curve_runs_.half[k] = wt;
    const bool all = curve_runs_.closed[k] && 2 * wt + 1 >= len;
    for (int p = 0; p < len; ++p) {
      if (all)
        for (int d = 0; d < len; ++d) reg_.push_back(cnode_[size_t(b + d)]);
      else
        for (int d = -wt; d <= wt; ++d) {
          int m = p + d;
          if (curve_runs_.closed[k])
            m = ((m % len) + len) % len;
          else if (m < 0 || m >= len)
            continue;
          reg_.push_back(cnode_[size_t(b + m)]);
        }
      reg_center_[G + size_t(b + p)] = cnode_[size_t(b + p)];
      reg_start_.push_back(int(reg_.size()));
    }
  }
  // Eq. 2: a region holding a handle turns about it (the handle nearest the region's node).
  std::vector<char> is_handle(rest_.size(), 0);
  for (int hn : handle_node_)
    if (hn >= 0) is_handle[size_t(hn)] = 1;
  for (size_t r = 0; r < R; ++r) {
    const int own = reg_center_[r];
    double best = INFINITY;
    for (int j : region(r))
      if (is_handle[size_t(j)] && (rest_[size_t(j)] - rest_[size_t(own)]).squaredNorm() < best) {
        best = (rest_[size_t(j)] - rest_[size_t(own)]).squaredNorm();
        reg_center_[r] = j;
      }
  }
  // Which grid regions count (the others keep their members for the sums but weigh nothing):
  // with stride s, the nodes on every s-th row and column, and any node no such region holds.
  // Each counting region stands for the nodes nearest it among its members (a_r, Σ a_r = G), so
  // the grid weighs the same against the junction and the handles whatever s is.
  const int stride_now = stride();
  reg_a_.assign(R, 1.0);
  if (stride_now > 1 && !plain_) {
    std::vector<char> on(G, 0), held(G, 0);
    for (size_t i = 0; i < G; ++i) on[i] = gxy_[i][0] % stride_now == 0 && gxy_[i][1] % stride_now == 0;
    auto hold = [&](size_t i) {
      for (int j : region(i)) held[size_t(j)] = 1;
    };
    for (size_t i = 0; i < G; ++i)
      if (on[i]) hold(i);
    for (size_t i = 0; i < G; ++i)
      if (!held[i]) on[i] = 1, hold(i);
    std::vector<double> near(G, INFINITY);
    std::vector<int> owner(G, -1);
    for (size_t i = 0; i < G; ++i)
      if (on[i])
        for (int j : region(i)) {
          const double d = (rest_[size_t(j)] - rest_[i]).squaredNorm();
          if (d < near[size_t(j)]) near[size_t(j)] = d, owner[size_t(j)] = int(i);
        }
    for (size_t i = 0; i < G; ++i) reg_a_[i] = 0;
    for (size_t j = 0; j < G; ++j) reg_a_[size_t(owner[j])] += 1;
  }
  reg_size_.resize(R);
  reg_psum_.resize(R);
  for (size_t r = 0; r < R; ++r) {
    const auto m = region(r);
    Vec2 s = Vec2::Zero();
    for (int j : m) s += p_[size_t(j)];
    reg_size_[r] = int(m.size());
    reg_psum_[r] = s;
  }
  weigh_regions();
  rc_.assign(R, 1.0);
  rs_.assign(R, 0.0);
  const size_t nmax = std::max(rest_.size(), R);
  ch_in_.assign(nmax * 4, 0.0);
  ch_mid_.assign(nmax * 4, 0.0);
  ch_out_.assign(nmax * 4, 0.0);
  if (plain_) fast_ = false;
}

void RigidGrid::weigh_regions() {
  // Local stiffness per node: the largest weight of the [[stiffness]] regions holding it.
  node_w_.assign(rest_.size(), 1.0);
  for (size_t k = 0; k < rest_.size(); ++k) {
    double wk = 0;
    for (const Stiff& s : stiff_)
      if ((rest_[k] - s.center).norm() <= s.radius) wk = std::max(wk, s.weight);
    if (wk > 0) node_w_[k] = wk;
  }
  const size_t G = grid_count_;
  reg_k_.resize(reg_center_.size());
  for (size_t r = 0; r < reg_center_.size(); ++r) {
    const int own = r < G ? int(r) : cnode_[r - G];
    reg_k_[r] = reg_size_[r] > 1 ? reg_a_[r] * w_r_ * node_w_[size_t(own)] / double(reg_size_[r]) : 0.0;
  }
}

bool RigidGrid::set_plain_regions(bool plain, std::string* error) {
  plain_ = plain;
  fast_ = !plain;
  build_regions();
  return factorise(error);
}

bool RigidGrid::set_stride(int s, std::string* error) {
  region_stride_ = std::clamp(s, 0, 32);
  build_regions();
  return factorise(error);
}

bool RigidGrid::factorise(std::string* error) {
  const size_t n = rest_.size();
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> diag(n, 0.0);
  // Regions: k Σ_j (e_j − e_c)(e_j − e_c)^T.
  for (size_t r = 0; r < reg_center_.size(); ++r) {
    const double k = reg_k_[r];
    if (k == 0) continue;
    const int c = reg_center_[r];
    for (int j : region(r)) {
      if (j == c) continue;
      diag[size_t(j)] += k;
      diag[size_t(c)] += k;
      t.emplace_back(j, c, -k);
      t.emplace_back(c, j, -k);
    }
  }
  if (tri_mode_)
    for (size_t tt = 0; tt < tris_.size(); ++tt)
      if (junction_[tt])
        for (int q = 0; q < 3; ++q) {
          const int a = tris_[tt][size_t(q)], b = tris_[tt][size_t((q + 1) % 3)];
          diag[size_t(a)] += w_s_;
          diag[size_t(b)] += w_s_;
          t.emplace_back(a, b, -w_s_);
          t.emplace_back(b, a, -w_s_);
        }
  for (const auto& e : edges_) {
    if (tri_mode_) break;
    diag[size_t(e[0])] += w_s_;
    diag[size_t(e[1])] += w_s_;
    t.emplace_back(e[0], e[1], -w_s_);
    t.emplace_back(e[1], e[0], -w_s_);
  }
  for (size_t v = 0; v + 1 < mvc_start_.size(); ++v)
    for (int a = mvc_start_[v]; a < mvc_start_[v + 1]; ++a)
      for (int b = mvc_start_[v]; b < mvc_start_[v + 1]; ++b)
        t.emplace_back(mvc_node_[size_t(a)], mvc_node_[size_t(b)], w_s_ * mvc_w_[size_t(a)] * mvc_w_[size_t(b)]);
  for (size_t k = 0; k < handles_.size(); ++k) {
    const Embed& h = handles_[k];
    for (int a = 0; a < h.n; ++a)
      for (int b = 0; b < h.n; ++b) t.emplace_back(h.v[a], h.v[b], w_p_ * handle_w(k) * h.w[a] * h.w[b]);
  }
  // Parts no handle reaches (through regions, junction edges or rings) get a tiny pull to where
  // they are.
  std::vector<int> comp(n);
  std::iota(comp.begin(), comp.end(), 0);
  auto find = [&](int i) {
    while (comp[size_t(i)] != i) i = comp[size_t(i)] = comp[size_t(comp[size_t(i)])];
    return i;
  };
  auto join = [&](int a, int b) { comp[size_t(find(a))] = find(b); };
  for (size_t r = 0; r < reg_center_.size(); ++r)
    for (int j : region(r)) join(j, reg_center_[r]);
  for (const auto& e : edges_) join(e[0], e[1]);
  for (size_t v = 0; v + 1 < mvc_start_.size(); ++v)
    for (int a = mvc_start_[v]; a < mvc_start_[v + 1]; ++a) join(mvc_node_[size_t(a)], mvc_node_[size_t(mvc_start_[v])]);
  std::vector<char> held(n, 0);
  for (size_t k = 0; k < handles_.size(); ++k)
    for (int a = 0; a < handles_[k].n; ++a)
      if (handles_[k].w[a] != 0 && handle_rider_[k] < 0) held[size_t(find(handles_[k].v[a]))] = 1;
  pull_.assign(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    if (!held[size_t(find(int(i)))]) pull_[i] = kFreePull * (1 + diag[i]);
    t.emplace_back(int(i), int(i), diag[i] + pull_[i]);
  }
  Eigen::SparseMatrix<double> K(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  K.setFromTriplets(t.begin(), t.end());
  if (!factor_.compute(K)) {
    if (error) *error = "rigid_grid: the system matrix could not be factorised";
    return false;
  }
  return true;
}

}  // namespace mar
