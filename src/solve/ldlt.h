// A sparse LDL^T factorisation (Eigen's SimplicialLDLT) solved in place on its raw arrays:
// the per-frame solve of every prefactored solver. The factor is very sparse, so Eigen's
// generic per-column iterators would dominate; this allocates nothing.
#pragma once

#include <Eigen/Sparse>

#include <vector>

namespace mar {

class PrefactoredLdlt {
 public:
  /// Factorises A (symmetric positive definite); false when it cannot.
  bool compute(const Eigen::SparseMatrix<double>& A);
  /// Solves A x = b in place: `y` holds b in permuted order (y[perm()[i]] = b[i]) and
  /// returns x in the same order.
  void solve_permuted(double* y) const;
  /// Two right-hand sides (x and y of a 2D problem) in one pass over the factor: the same
  /// results as two calls, with half the reads of L.
  void solve_permuted(double* x, double* y) const;
  /// The fill-reducing permutation: unknown i sits at perm()[i].
  const std::vector<int>& perm() const { return perm_; }
  int size() const { return int(perm_.size()); }
  long nonzeros() const { return ldlt_.matrixL().nestedExpression().nonZeros(); }

 private:
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  Eigen::VectorXd diag_;  ///< D of the factor (vectorD() copies)
  std::vector<int> perm_;
};

/// One soft point constraint added to a prefactored system without factorising again
/// (Sherman–Morrison): K' = K + weight a a^T, with a = Σ_k w_k e_{idx_k} (a point as a
/// combination of up to 4 unknowns). The caller adds weight a target to its right-hand sides,
/// solves with the factor, then calls correct(). Allocates only in reserve().
class RankOneUpdate {
 public:
  void reserve(size_t n) { z_.assign(n, 0.0); }
  /// z = K^-1 a, and the denominator; `n` entries of idx and w.
  void set(const PrefactoredLdlt& f, const int* idx, const double* w, int n, double weight);
  /// x, y (in the factor's order, as solved by K) become the solutions of K'.
  void correct(const PrefactoredLdlt& f, double* x, double* y) const;

 private:
  std::vector<double> z_;
  int idx_[4] = {0, 0, 0, 0};
  double w_[4] = {0, 0, 0, 0};
  int n_ = 0;
  double weight_ = 0, den_ = 1;
};

}  // namespace mar
