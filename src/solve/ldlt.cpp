#include "solve/ldlt.h"

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

}  // namespace mar
