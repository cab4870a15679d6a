// GCC 12 reports a false -Wmaybe-uninitialized inside Eigen 3.4's
// self-adjoint matrix-vector product (instantiated by the fixed-size
// SelfAdjointEigenSolver: the stack buffer it flags is unused when the
// destination has direct access). Silenced for Eigen's headers only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <superdex/core/symmetric_eigen.h>

#include <Eigen/Eigenvalues>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace superdex {

template <class Matrix>
SymmetricEigen<Matrix> ComputeSymmetricEigen(Matrix const& a) {
  Eigen::SelfAdjointEigenSolver<Matrix> const solver(a);
  return {solver.eigenvalues(), solver.eigenvectors(), solver.info() == Eigen::Success};
}

template <class Matrix>
typename SymmetricEigen<Matrix>::Values SymmetricEigenvalues(Matrix const& a) {
  return Eigen::SelfAdjointEigenSolver<Matrix>(a, Eigen::EigenvaluesOnly).eigenvalues();
}

template <int n>
using Square = Eigen::Matrix<real, n, n>;

// The types in use: the contact barrier's 2 × 2 friction block and its 6, 9
// and 12 coordinates; the rigid inertia's 3 × 3; the shell's 6 × 6, the
// rod's 8 × 8, the tet's 9 × 9; the articulated solve's joint pivots (1, 3, 6
// or any size up to 6 without allocation); dynamic size for the tests.
#define SUPERDEX_SYMMETRIC_EIGEN(Matrix)                                          \
  template SymmetricEigen<Matrix> ComputeSymmetricEigen<Matrix>(Matrix const&); \
  template SymmetricEigen<Matrix>::Values SymmetricEigenvalues<Matrix>(Matrix const&);
SUPERDEX_SYMMETRIC_EIGEN(Square<1>)
SUPERDEX_SYMMETRIC_EIGEN(Square<2>)
SUPERDEX_SYMMETRIC_EIGEN(Square<3>)
SUPERDEX_SYMMETRIC_EIGEN(Square<6>)
SUPERDEX_SYMMETRIC_EIGEN(Square<8>)
SUPERDEX_SYMMETRIC_EIGEN(Square<9>)
SUPERDEX_SYMMETRIC_EIGEN(Square<12>)
SUPERDEX_SYMMETRIC_EIGEN(MatrixUpTo6)
SUPERDEX_SYMMETRIC_EIGEN(MatrixX)
#undef SUPERDEX_SYMMETRIC_EIGEN

}  // namespace superdex
