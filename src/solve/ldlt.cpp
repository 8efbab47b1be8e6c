#include "solve/ldlt.h"

#include <algorithm>
#include <numeric>

namespace mar {

bool PrefactoredLdlt::compute(const Eigen::SparseMatrix<double>& A) {
  ldlt_.compute(A);
  if (ldlt_.info() != Eigen::Success) return false;
  diag_ = ldlt_.vectorD();
  // (P b)[perm[i]] = b[i], Eigen's convention for PermutationMatrix * vector.
  const auto& P = ldlt_.permutationP().indices();
  perm_.assign(P.data(), P.data() + P.size());
  if (perm_.empty()) {
    perm_.resize(size_t(A.rows()));
    std::iota(perm_.begin(), perm_.end(), 0);
  }
  return true;
}

// L D L^T y = b with L unit lower triangular, column-major, diagonal not stored.
void PrefactoredLdlt::solve_permuted(double* y) const {
  const auto& L = ldlt_.matrixL().nestedExpression();
  const int* col = L.outerIndexPtr();
  const int* row = L.innerIndexPtr();
  const double* val = L.valuePtr();
  const double* D = diag_.data();
  const int n = size();
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
}

void PrefactoredLdlt::solve_permuted(double* x, double* y) const {
  const auto& L = ldlt_.matrixL().nestedExpression();
  const int* col = L.outerIndexPtr();
  const int* row = L.innerIndexPtr();
  const double* val = L.valuePtr();
  const double* D = diag_.data();
  const int n = size();
  for (int j = 0; j < n; ++j) {
    const double xj = x[j], yj = y[j];
    for (int p = col[j]; p < col[j + 1]; ++p) {
      x[row[p]] -= val[p] * xj;
      y[row[p]] -= val[p] * yj;
    }
  }
  for (int j = 0; j < n; ++j) {
    x[j] /= D[j];
    y[j] /= D[j];
  }
  for (int j = n - 1; j >= 0; --j) {
    double sx = x[j], sy = y[j];
    for (int p = col[j]; p < col[j + 1]; ++p) {
      sx -= val[p] * x[row[p]];
      sy -= val[p] * y[row[p]];
    }
    x[j] = sx;
    y[j] = sy;
  }
}

void RankOneUpdate::set(const PrefactoredLdlt& f, const int* idx, const double* w, int n, double weight) {
  const int* perm = f.perm().data();
  n_ = std::min(n, 4);
  weight_ = weight;
  std::fill(z_.begin(), z_.end(), 0.0);
  for (int k = 0; k < n_; ++k) {
    idx_[k] = idx[k];
    w_[k] = w[k];
    z_[size_t(perm[idx[k]])] += w[k];
  }
  f.solve_permuted(z_.data());
  double az = 0;
  for (int k = 0; k < n_; ++k) az += w_[k] * z_[size_t(perm[idx_[k]])];
  den_ = 1 + weight_ * az;
}

void RankOneUpdate::correct(const PrefactoredLdlt& f, double* x, double* y) const {
  const int* perm = f.perm().data();
  double ax = 0, ay = 0;
  for (int k = 0; k < n_; ++k) {
    ax += w_[k] * x[perm[idx_[k]]];
    ay += w_[k] * y[perm[idx_[k]]];
  }
  const double fx = weight_ * ax / den_, fy = weight_ * ay / den_;
  for (size_t i = 0; i < z_.size(); ++i) {
    x[i] -= fx * z_[i];
    y[i] -= fy * z_[i];
  }
}

}  // namespace mar
