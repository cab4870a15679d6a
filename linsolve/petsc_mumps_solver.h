// PetscMumpsSolver: the LinearSolver backend on MUMPS, the multifrontal
// direct solver, through PETSc's interface to it (MATSOLVERMUMPS) — the
// direct solver that runs across MPI ranks: on one (PETSC_COMM_SELF) by
// default, so that the harness can compare it with CHOLMOD on the same
// matrices, and on the ranks SetDistribution gives (below).
//
// Analyze (once per pattern) creates the SeqSBAIJ matrix of A's upper
// triangle (block size 1: MUMPS takes symmetric matrices as triples of one
// triangle), PETSc's own arrays, the map from A's upper CSC entries to its
// row-wise value array, and runs MUMPS's analysis on the pattern (its own
// fill-reducing ordering, ICNTL(7) automatic, of the plain graph, ICNTL(12)
// = 1, on the METIS-ordered A). Factorize (every Newton iteration) writes
// A's values in place and runs the numeric factorization; Solve runs
// MatSolve.
//
// Positive definiteness. MUMPS factors A as LDLᵀ with pivoting (SYM = 2):
// the Newton Hessian may be indefinite with exact element Hessians, and a
// factorization that assumes SPD (SYM = 1) would not say so. The inertia of
// the factor (MatGetInertia: negative pivots, INFOG(12); null pivots,
// ICNTL(24) = 1) decides: any negative or null pivot is NotPositiveDefinite,
// as CHOLMOD's failed Cholesky is — without a failing column (-1), which
// pivoting leaves undefined.
//
// Across R > 1 ranks (SetDistribution; docs/linear_solvers.md "Across MPI
// ranks"): the matrix is the MPIAIJ of the owned rows, both triangles
// (PetscDistributedMatrix, shared with the PCG backend; PETSc's MUMPS
// interface extracts the upper triangle for the LDLᵀ factor), its values
// set in place by MatUpdateMPIAIJWithArray at each Factorize. The analysis is the
// same, plus ICNTL(13) = 1 (no ScaLAPACK on the root front, so that INFOG(12)
// counts every negative pivot). INFOG and the inertia are global, so every
// rank returns the same status (any rank's PETSc error is agreed on too);
// Solve takes b's owned entries and gathers all of x onto every rank.
// GetDescription ends in "on R ranks".
//
// Allocation: Analyze allocates the PETSc objects; MUMPS allocates its
// frontal matrices and factor inside each numeric factorization (Fortran
// allocatable arrays), as CHOLMOD allocates temporaries; SuperDex's own
// code allocates nothing per iteration.
#pragma once

#include <memory>
#include <string>

#include <superdex/linsolve/linear_solver.h>

namespace superdex::internal {

class PetscMumpsSolver final : public LinearSolver {
 public:
  /// PETSc must be initialized (EnsurePetscInitialized); CreateLinearSolver
  /// does it.
  PetscMumpsSolver();
  /// Destroys the PETSc objects (unless PETSc was already finalized).
  ~PetscMumpsSolver() override;
  PetscMumpsSolver(PetscMumpsSolver const&) = delete;
  PetscMumpsSolver& operator=(PetscMumpsSolver const&) = delete;

  LinearSolverType GetType() const override { return LinearSolverType::PetscMumps; }
  /// E.g. "PETSc 3.18.5 MUMPS 5.5.1 LDLᵀ (ordering METIS)".
  std::string GetDescription() const override;
  /// MUMPS's estimate after its analysis (INFOG(20)); -1 before Analyze.
  double GetFactorNonzeros() const override;
  /// MUMPS's estimate of the elimination's flops (RINFOG(1)); -1 before.
  double GetFactorFlops() const override;
  std::int64_t GetNumObjectBuilds() const override { return numObjectBuilds_; }

 protected:
  LinearSolveResult DoAnalyze(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoFactorize(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoSolve(Span<real const> b, Span<real> x) override;
  /// Stores the ranks and rows for the next Analyze; always accepted.
  bool DoSetDistribution(Communicator const& communicator, int rowBegin, int rowEnd) override;

 private:
  struct Impl;  // the PETSc objects (petsc_mumps_solver.cc)
  std::unique_ptr<Impl> impl_;
  std::int64_t numObjectBuilds_ = 0;
};

}  // namespace superdex::internal
