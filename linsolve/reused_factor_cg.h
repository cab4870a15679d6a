// ReusedFactorCg: conjugate gradients on a symmetric positive definite A,
// preconditioned by the factorization of an earlier matrix of the same
// pattern (Newton's Hessian of an earlier iteration or step).
//
// Within a Newton stage the Hessian H_k changes a little from iteration to
// iteration, and from step to step. With M = L Lᵀ the last factorization,
// M⁻¹ H_k is close to the identity: CG converges in a few iterations, each a
// sparse product H_k p and a pair of triangular solves with L, a small
// fraction of one numeric factorization (docs/linear_solvers.md, "Reused
// factorizations", has the measured ratio). The result is H_k's own Newton
// step to the requested relative residual: the matrix is never approximated,
// only the preconditioner is old.
//
// CG stops with
//   Converged            ‖b − A x‖₂ <= rtol ‖b‖₂, or, given a step
//                        tolerance, maxᵢ sᵢ |zᵢ| <= τ for z = M⁻¹ (b − A x):
//                        the error of x (A⁻¹ r ≈ M⁻¹ r, since M ≈ A) is
//                        below τ in the caller's scaled max-norm
//   NotConverged         not within maxIterations (the caller refactorizes)
//   NonPositiveCurvature pᵀ A p <= 0 for a search direction (A may be
//                        indefinite: the caller refactorizes, and the
//                        factorization says whether it is)
//   PreconditionerFailed the factor's Solve failed (reason in `reason`)
// Allocation: Reserve sizes the workspaces; Solve allocates nothing.
#pragma once

#include <string>

#include <superdex/core/types.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex::internal {

/// y = A x for the symmetric A stored as its upper triangle (CSC, diagonal
/// last in each column). x and y must not overlap.
void MultiplySymmetric(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y);

/// Rows [rowBegin, rowEnd) of y = A x; y's other rows are left as they are.
/// Reads only the entries of A with a row or a column in the range: across
/// MPI ranks the assembler completes exactly those on the rank that owns the
/// rows (HessianAssembler::Analyze), so each rank forms its own rows of the
/// product. x and y must not overlap.
void MultiplySymmetricRows(SparseSymmetricMatrix const& a, int rowBegin, int rowEnd, Span<real const> x,
                           Span<real> y);

/// How ReusedFactorCg forms y = A x. Without one it multiplies the whole
/// stored triangle (MultiplySymmetric); the stage solver across MPI ranks
/// gives one that multiplies the rank's own rows and gathers the rest
/// (docs/distributed.md, "Reused factorizations across ranks"). Every rank
/// must get the same y, bit for bit: CG's decisions are then the same on all.
class MatrixProduct {
 public:
  virtual ~MatrixProduct() = default;
  virtual void Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) = 0;
};

class ReusedFactorCg {
 public:
  enum class Status { Converged, NotConverged, NonPositiveCurvature, PreconditionerFailed };
  struct Result {
    Status status = Status::NotConverged;
    int iterations = 0;          ///< preconditioner applications (= A products)
    real relativeResidual = 0;   ///< ‖b − A x‖₂ / ‖b‖₂ at return
    std::string reason;          ///< PreconditionerFailed: the backend's reason
    /// the factor was applied in reduced precision (LinearSolveResult::reducedPrecision)
    bool reducedPrecision = false;
  };

  /// Converged as well when maxᵢ scales[i] |(M⁻¹ r)ᵢ| <= tolerance.
  struct StepTolerance {
    Span<real const> scales;
    real tolerance = 0;
  };

  void Reserve(int size);

  /// The product CG runs on; null (the default) for MultiplySymmetric. Not
  /// owned: it must outlive the Solve calls.
  void SetProduct(MatrixProduct* product) { product_ = product; }

  /// Solves A x = b, preconditioned by `factor`'s current factorization
  /// (factor.Solve), from x = 0, or with `resume` from the x passed in (a
  /// looser solve continued to a tighter tolerance; the residual is
  /// recomputed, one more product with A). A must have the factorized size.
  /// A zero b gives x = 0, converged, in 0 iterations. With
  /// `reducedPrecision` the factor is applied through
  /// LinearSolver::ApplyPreconditioner in reduced precision where the backend
  /// has it (the preconditioner changes; the residual, and so the answer's
  /// tolerance, stays in double precision). CG then takes the Polak–Ribière
  /// β = rₖ₊₁ᵀ(zₖ₊₁ − zₖ) / rₖᵀzₖ of flexible CG (Notay 2000), robust to a
  /// preconditioner that is not exactly one linear operator (float
  /// arithmetic) and equal to the usual β with one that is.
  Result Solve(SparseSymmetricMatrix const& a, LinearSolver& factor, Span<real const> b, Span<real> x,
               real relativeTolerance, int maxIterations, bool resume = false,
               StepTolerance const* stepTolerance = nullptr, bool reducedPrecision = false);

 private:
  void Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) const;

  MatrixProduct* product_ = nullptr;
  VectorX residual_, preconditioned_, direction_, productVector_;
  VectorX previousPreconditioned_;  ///< reducedPrecision: z of the last iteration
};

}  // namespace superdex::internal
