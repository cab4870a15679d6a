// PetscPcgSolver: the LinearSolver backend on PETSc's preconditioned
// conjugate gradients (KSPCG), for the SPD Newton Hessian.
//
// Analyze (once per pattern) creates everything: the full-storage SeqAIJ
// matrix of the symmetric A (both triangles, PETSc's own arrays, with A's
// DoF block sizes), the KSP with its preconditioner, tolerances and the
// user's PETSc options, and the map from A's upper-triangle CSC entries to
// the AIJ value array. Factorize (every Newton iteration) writes A's values
// into the AIJ array in place (MatSeqAIJGetArrayWrite: no Mat or KSP
// re-creation) and sets the preconditioner up (KSPSetUp); Solve runs KSPSolve
// from a zero initial guess. GetNumObjectBuilds counts Mat+KSP creations.
//
// Convergence: ‖b − A x‖₂ <= max(rtol ‖b‖₂, atol) on the UNPRECONDITIONED
// residual (KSP_NORM_UNPRECONDITIONED), so the tolerance means the same for
// every preconditioner. Non-convergence (iteration cap, indefinite matrix or
// preconditioner, preconditioner set-up failure) is NotConverged with
// PETSc's reason (KSPConvergedReasons, PCFailedReasons), the iteration count
// and the relative residual.
//
// Preconditioners (PcgPreconditioner): Jacobi; point-block Jacobi on A's DoF
// blocks (PCVPBJACOBI); block Jacobi with IC(k) blocks and IC(k), both
// SuperDex's own IncompleteCholesky in a shell PC (incomplete_cholesky.h:
// Jacobi-scaled, RCM order, bounded diagonal shifts); GAMG with the
// near-null space the caller passes (SetNearNullSpace, orthonormalized
// here), with the block size of the matrix set to the gcd of the DoF block
// sizes (3 for nodes and rigid bodies); hypre BoomerAMG (strong threshold
// 0.5, hypre's recommendation for 3-D). PcgParams::options are inserted into
// PETSc's options database under this solver's own prefix and applied last;
// an option PETSc did not use by the first set-up is reported as
// InvalidInput.
//
// Across R > 1 ranks (SetDistribution; docs/linear_solvers.md "Across MPI
// ranks"): the matrix is the MPIAIJ of the owned rows (PetscDistributedMatrix:
// preallocated from the owned rows' CSR once per pattern, values set in
// place by MatUpdateMPIAIJWithArray at each Factorize), KSPCG runs on the communicator with
// the same tolerances, norm and options; Solve takes b's owned entries (and
// Resume x's, as the initial guess) and gathers all of x onto every rank.
// Jacobi, point-block Jacobi (the owned DoF blocks), GAMG (the near-null
// space's owned rows, orthonormalized with global dot products) and
// BoomerAMG run as PETSc runs them in parallel; block Jacobi is the same IC(k)
// shell applied by each rank to its own rows (the diagonal block of the
// owned rows, in that rank's share of max(blockJacobiBlocks, R) groups);
// Icc, IC of the whole matrix, is refused (InvalidInput). A failure known
// to one rank (IC factor, preconditioner set-up, a PETSc error in the solve)
// is reported by every rank. GetDescription ends in "on R ranks".
//
// Allocation: Analyze allocates the PETSc objects; the preconditioner set-up
// allocates inside PETSc (AMG hierarchies), as CHOLMOD's
// factorization does; SuperDex's own code allocates nothing per iteration.
#pragma once

#include <memory>
#include <string>

#include <superdex/linsolve/linear_solver.h>

namespace superdex::internal {

class IncompleteCholesky;

class PetscPcgSolver final : public LinearSolver {
 public:
  /// `params` must have passed ValidatePcgParams, and PETSc must be
  /// initialized (EnsurePetscInitialized); CreateLinearSolver does both.
  explicit PetscPcgSolver(PcgParams const& params);
  /// Destroys the PETSc objects (unless PETSc was already finalized) and
  /// removes this solver's options from PETSc's database.
  ~PetscPcgSolver() override;

  PetscPcgSolver(PetscPcgSolver const&) = delete;
  PetscPcgSolver& operator=(PetscPcgSolver const&) = delete;

  LinearSolverType GetType() const override { return LinearSolverType::PetscPcg; }
  /// E.g. "PETSc 3.18.5 CG + GAMG (rigid-body near-null space), rtol 1e-08".
  std::string GetDescription() const override;
  double GetFactorNonzeros() const override { return -1; }
  double GetFactorFlops() const override { return -1; }
  bool IsIterative() const override { return true; }
  void SetRelativeTolerance(real relativeTolerance) override;
  bool WantsNearNullSpace() const override;
  void SetNearNullSpace(MatrixX const& modes) override;
  std::int64_t GetNumObjectBuilds() const override { return numObjectBuilds_; }

  PcgParams const& GetParams() const { return params_; }
  /// Icc and BlockJacobi: the incomplete factor (after Analyze); else nullptr.
  IncompleteCholesky const* GetIncompleteFactor() const;

 protected:
  LinearSolveResult DoAnalyze(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoFactorize(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoSolve(Span<real const> b, Span<real> x) override;
  LinearSolveResult DoResume(Span<real const> b, Span<real> x) override;
  /// Stores the ranks and rows for the next Analyze; always accepted.
  bool DoSetDistribution(Communicator const& communicator, int rowBegin, int rowEnd) override;

 private:
  struct Impl;  // the PETSc objects (petsc_pcg_solver.cc)

  PcgParams params_;
  std::unique_ptr<Impl> impl_;
  std::int64_t numObjectBuilds_ = 0;
};

}  // namespace superdex::internal
