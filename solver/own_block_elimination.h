// OwnBlockElimination: the terms that solve their own block of the Newton
// system (stage/own_block_solve.h: an articulated actor on its tree), seen
// from the Newton solver. At each pattern build it chooses which stay on
// and which link terms they take in; per Newton iteration it factorizes
// their blocks after the assembly, turns the scene's right-hand side into
// the Schur complement's where a block is coupled, and solves their parts of
// the step after the scene's solve.
#pragma once

#include <string>

#include <superdex/linsolve/linear_solver.h>
#include <superdex/solver/stage_problem.h>
#include <superdex/stage/own_block_solve.h>

namespace superdex {
struct SceneStats;
}

namespace superdex::internal {

class OwnBlockElimination {
 public:
  /// At a pattern build, before any stencil: every own block on (in one
  /// process; none across ranks), none holding a folded term.
  void Reset(StageProblem const& problem, bool distributed);
  /// From the stencils of the terms without an own block (termDofs[t], per
  /// term in the problem's order; own-block terms' still empty): an own
  /// block stays on unless a contributor reaches other DoFs or more than one
  /// of its groups (that coupling needs the block in the scene's matrix); a
  /// link term on one of its links is taken in instead (its DoF list
  /// emptied: the own block assembles it, with a Schur complement where it
  /// couples another body).
  void Choose(StageProblem const& problem, DynamicArray<DynamicArray<DynamicArray<int>>>& termDofs);
  /// After the pattern build: the active own blocks and their first
  /// contributors, and the vectors of the solves.
  void Prepare(StageProblem const& problem, bool distributed);

  bool IsEmpty() const { return blocks_.empty(); }
  /// Some own block is coupled with other DoFs (a Schur complement).
  bool IsCoupled() const { return coupled_; }
  /// Every DoF in an own block, none coupled (one process): the scene's
  /// matrix is the identity once the blocks are factorized, and the linear
  /// solver is not called (δ = −∇E, then the blocks' solves).
  bool IsIdentityMatrix() const { return identity_; }

  /// Factorizes every own block after an assembly (timed as factorization
  /// in `stats`); NotPositiveDefinite when one fails.
  LinearSolveResult Factorize(HessianAssembler& assembler, bool project, bool separateCouplings, SceneStats& stats);
  /// Their parts of `delta` from −gradient, after the scene's solve.
  void Solve(Span<real const> gradient, Span<real> delta);
  /// The scene's right-hand side where a block is coupled: −∇E with the
  /// blocks eliminated (natural order), in `rhs`.
  void EliminateFromRhs(Span<real const> gradient, Span<real> rhs);

 private:
  DynamicArray<OwnBlockSolve*> blocks_;  ///< the active own blocks
  DynamicArray<int> firstContributors_;  ///< and their terms' first contributors
  VectorX rhs_;                          ///< −∇E for their solves (natural order)
  bool coupled_ = false;
  bool identity_ = false;
};

}  // namespace superdex::internal
