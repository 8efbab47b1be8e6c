// The prefactored LDL^T solve every mesh solver runs per iteration (solve/ldlt.h).
#include "solve/ldlt.h"

#include <gtest/gtest.h>

#include <random>

namespace mar {
namespace {

TEST(PrefactoredLdlt, SolvesAndTwoRightHandSidesMatchTwoSolves) {
  // A 2D grid Laplacian plus a diagonal: symmetric positive definite, with fill.
  const int n = 12, N = n * n;
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * n + i;
      t.emplace_back(a, a, 0.1);
      for (const int b : {i + 1 < n ? a + 1 : -1, j + 1 < n ? a + n : -1, i + 1 < n && j + 1 < n ? a + n + 1 : -1}) {
        if (b < 0) continue;
        t.emplace_back(a, a, 1.0);
        t.emplace_back(b, b, 1.0);
        t.emplace_back(a, b, -1.0);
        t.emplace_back(b, a, -1.0);
      }
    }
  Eigen::SparseMatrix<double> A(N, N);
  A.setFromTriplets(t.begin(), t.end());
  PrefactoredLdlt f;
  ASSERT_TRUE(f.compute(A));
  EXPECT_GT(f.nonzeros(), 2 * N);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd bx(N), by(N);
  for (int i = 0; i < N; ++i) bx[i] = u(rng), by[i] = u(rng);
  const size_t M = static_cast<size_t>(N);
  std::vector<double> x(M), y(M), x1(M), y1(M);
  for (int i = 0; i < N; ++i) {
    x[size_t(f.perm()[size_t(i)])] = x1[size_t(f.perm()[size_t(i)])] = bx[i];
    y[size_t(f.perm()[size_t(i)])] = y1[size_t(f.perm()[size_t(i)])] = by[i];
  }
  f.solve_permuted(x.data(), y.data());
  f.solve_permuted(x1.data());
  f.solve_permuted(y1.data());
  Eigen::VectorXd sx(N), sy(N);
  for (int i = 0; i < N; ++i) {
    EXPECT_EQ(x[size_t(i)], x1[size_t(i)]);
    EXPECT_EQ(y[size_t(i)], y1[size_t(i)]);
    sx[i] = x[size_t(f.perm()[size_t(i)])];
    sy[i] = y[size_t(f.perm()[size_t(i)])];
  }
  EXPECT_LT((A * sx - bx).norm(), 1e-10 * bx.norm());
  EXPECT_LT((A * sy - by).norm(), 1e-10 * by.norm());
}

}  // namespace
}  // namespace mar
