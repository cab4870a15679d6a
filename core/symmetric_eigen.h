// Eigen decompositions of small symmetric matrices, compiled once.
//
// Eigen::SelfAdjointEigenSolver costs about 9 s of compile time (gcc 12 and
// clang 14 alike, at any -O: template instantiation) for every matrix type in
// every translation unit that instantiates it, and the library, its tests and
// the perf programs instantiated it in 25 places. These functions run the same
// solver (same code, same results) and are instantiated once per type, in
// core/symmetric_eigen.cc, for the types listed there; another type is a link
// error, to be added to that list.
#pragma once

#include <superdex/core/types.h>

namespace superdex {

/// A symmetric matrix of any size up to 6 × 6, stored without allocation
/// (an articulated joint's pivot).
using MatrixUpTo6 = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;

/// The eigenvalues of a symmetric matrix of type Matrix (ascending) and its
/// eigenvectors (columns, in the same order).
template <class Matrix>
struct SymmetricEigen {
  using Values = Eigen::Matrix<real, Matrix::RowsAtCompileTime, 1, 0, Matrix::MaxRowsAtCompileTime, 1>;
  Values values;
  Matrix vectors;
  bool converged = false;  ///< the QL iteration converged (Eigen::Success)
};

/// Eigen::SelfAdjointEigenSolver(a): the eigenvalues and eigenvectors of
/// the symmetric `a` (its lower triangle is read). No allocation for a
/// fixed-size Matrix.
template <class Matrix>
SymmetricEigen<Matrix> ComputeSymmetricEigen(Matrix const& a);

/// Eigen::SelfAdjointEigenSolver(a, EigenvaluesOnly): the eigenvalues alone,
/// ascending.
template <class Matrix>
typename SymmetricEigen<Matrix>::Values SymmetricEigenvalues(Matrix const& a);

}  // namespace superdex
