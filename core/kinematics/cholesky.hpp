// Cholesky factorisation and solves of a small fixed-size symmetric positive definite matrix,
// unblocked and in place: what the damped least-squares kernels (N = 6) and the task-priority IK
// (N = 12 and 4) need, without Eigen's size-generic LLT, whose blocked triangular solve (GEMM
// kernels with a heap fallback and a function-local static guarded by a lock) would otherwise be
// reachable from the RC task's period (toolchain/rt_verify.py finds it).
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace rescue::kin {

template <int N>
class SmallCholesky {
 public:
  using Matrix = Eigen::Matrix<double, N, N>;
  using Vector = Eigen::Matrix<double, N, 1>;

  // Factorises A = L L^T (lower triangle of A used). False when A is not positive definite.
  bool compute(const Matrix& a) noexcept {
    l_ = a;
    for (int j = 0; j < N; ++j) {
      double d = l_(j, j);
      for (int k = 0; k < j; ++k) d -= l_(j, k) * l_(j, k);
      if (!(d > 0.0)) return false;
      d = std::sqrt(d);
      l_(j, j) = d;
      for (int i = j + 1; i < N; ++i) {
        double v = l_(i, j);
        for (int k = 0; k < j; ++k) v -= l_(i, k) * l_(j, k);
        l_(i, j) = v / d;
      }
    }
    return true;
  }

  // X = A^-1 B, column by column (no blocked triangular solve).
  template <int Cols>
  Eigen::Matrix<double, N, Cols> solve_columns(const Eigen::Matrix<double, N, Cols>& b) const noexcept {
    Eigen::Matrix<double, N, Cols> x;
    for (int c = 0; c < Cols; ++c) x.col(c) = solve(b.col(c));
    return x;
  }

  // x = A^-1 b.
  Vector solve(const Vector& b) const noexcept {
    Vector y;
    for (int i = 0; i < N; ++i) {
      double v = b(i);
      for (int k = 0; k < i; ++k) v -= l_(i, k) * y(k);
      y(i) = v / l_(i, i);
    }
    Vector x;
    for (int i = N - 1; i >= 0; --i) {
      double v = y(i);
      for (int k = i + 1; k < N; ++k) v -= l_(k, i) * x(k);
      x(i) = v / l_(i, i);
    }
    return x;
  }

 private:
  Matrix l_{Matrix::Zero()};
};

}  // namespace rescue::kin
