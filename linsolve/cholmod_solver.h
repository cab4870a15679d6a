// CholmodSolver: the LinearSolver backend on SuiteSparse CHOLMOD's sparse
// Cholesky factorization: supernodal A = P' L L' P where the factor has dense
// blocks for BLAS to work on, simplicial A = P' L D L' P where it has not
// (chains, rods: CholmodFactorKind).
//
// Analyze runs cholmod_analyze on A's pattern (the caller's upper-triangle CSC
// arrays, wrapped without copying). By default the ordering is CHOLMOD's
// natural ordering, because the assembler has already applied a
// fill-reducing (METIS) ordering; CHOLMOD may still follow it with a
// postorder of the elimination tree, so P is a postorder and not always the
// identity. Factorize runs cholmod_factorize on the same symbolic factor;
// Solve runs cholmod_solve2 with workspaces kept in the solver.
//
// Reported as CHOLMOD reports it: nnz(L) and the factorization flop count
// are CHOLMOD's own analysis statistics (Common->lnz, Common->fl), and
// GetDescription names the CHOLMOD version, factor kind and ordering that ran.
//
// Allocation: Analyze allocates the symbolic factor; the first Solve after an
// Analyze allocates the solve workspaces; later Solves allocate nothing.
// cholmod_factorize itself allocates two short-lived temporaries per call
// (the transpose of A and the supernode update matrix); this class adds none.
//
// CHOLMOD is linked privately: this header does not include cholmod.h.
#pragma once

#include <superdex/linsolve/linear_solver.h>

#include <memory>
#include <string>

namespace superdex::internal {

/// Factorizations of at least this many flops run OpenBLAS on all its
/// threads, smaller ones on one (measured, docs/linear_solvers.md).
inline constexpr double kParallelBlasFlops = 2e8;

/// The ordering cholmod_analyze uses.
enum class CholmodOrdering {
  Given,           ///< natural: trust the caller's (already fill-reducing) column order
  /// the caller's order or AMD's, whichever CHOLMOD's analysis finds the
  /// better factor for (nested dissection suits meshes; on chains and rods
  /// AMD finds the fill-free order that nested dissection misses)
  GivenOrAmd,
  CholmodDefault,  ///< CHOLMOD's own choice (AMD, then METIS/NESDIS if AMD is poor)
};

/// The numeric factorization cholmod_analyze prepares.
enum class CholmodFactorKind {
  /// CHOLMOD's own rule: simplicial when flops / nnz(L) < 40 (few flops per
  /// entry of L: chains, rods, thin shells, where supernodes are one or two
  /// columns wide and BLAS calls cost more than their arithmetic),
  /// supernodal otherwise (volumetric meshes)
  Auto,
  Supernodal,  ///< always supernodal LLᵀ (BLAS-3 on dense supernodes)
  Simplicial,  ///< always simplicial LDLᵀ (column by column, no BLAS)
};

class CholmodSolver final : public LinearSolver {
 public:
  /// Starts a cholmod_common for this solver (cholmod_start).
  explicit CholmodSolver(CholmodOrdering ordering = CholmodOrdering::Given,
                         CholmodFactorKind kind = CholmodFactorKind::Auto);
  /// Frees the factor and workspaces and ends the cholmod_common (cholmod_finish).
  ~CholmodSolver() override;

  CholmodSolver(CholmodSolver const&) = delete;
  CholmodSolver& operator=(CholmodSolver const&) = delete;

  LinearSolverType GetType() const override { return LinearSolverType::Cholmod; }
  /// E.g. "CHOLMOD 3.0.14 supernodal LL', ordering natural+postorder"; before
  /// Analyze only the version and "not analyzed".
  std::string GetDescription() const override;
  /// The single-precision preconditioner solve runs on these threads.
  void SetParallelExecutor(ParallelExecutor const* executor) override;
  /// Nonzeros of L from CHOLMOD's analysis (Common->lnz), without the explicit
  /// zeros that supernode amalgamation adds; -1 before Analyze.
  double GetFactorNonzeros() const override;
  /// Flops of one numeric factorization from CHOLMOD's analysis (Common->fl);
  /// -1 before Analyze.
  double GetFactorFlops() const override;

  CholmodOrdering GetOrdering() const { return ordering_; }
  CholmodFactorKind GetFactorKind() const { return kind_; }
  /// Whether the current analysis is supernodal (false before Analyze).
  bool IsSupernodal() const;
  /// Entries stored for L (supernodal: L->xsize, nnz(L) plus amalgamation
  /// zeros; simplicial: nnz(L)); -1 before Analyze.
  double GetFactorStoredEntries() const;
  /// The permutation CHOLMOD factors in: entry k is the caller's column that
  /// is the k-th column of L (L->Perm). Empty before Analyze. For tests and
  /// diagnostics; allocates.
  DynamicArray<int> GetFactorPermutation() const;
  /// Whether ApplyPreconditioner with reducedPrecision uses a single-precision
  /// copy of the current factorization's L (SinglePrecisionFactor): only for
  /// a supernodal factor whose values fit a float and whose diagonal spread
  /// is below SinglePrecisionFactor::kMaxDiagonalSpread. Makes the copy if
  /// this factorization has none yet (once per Factorize); false before one.
  bool UsesSinglePrecisionPreconditioner();

 protected:
  LinearSolveResult DoAnalyze(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoFactorize(SparseSymmetricMatrix const& a) override;
  LinearSolveResult DoSolve(Span<real const> b, Span<real> x) override;
  /// reducedPrecision and a usable single-precision copy: its solve;
  /// otherwise DoSolve.
  LinearSolveResult DoApplyPreconditioner(Span<real const> b, Span<real> x,
                                          bool reducedPrecision) override;

 private:
  /// After a simplicial analysis in a permuted order: analyzes the permuted
  /// matrix itself instead (Impl::folded), so that Factorize does not
  /// transpose A twice per call.
  LinearSolveResult FoldOrder(SparseSymmetricMatrix const& a);

  struct Impl;  // the cholmod_common, factor and workspaces (cholmod_solver.cc)

  CholmodOrdering ordering_;
  CholmodFactorKind kind_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace superdex::internal
