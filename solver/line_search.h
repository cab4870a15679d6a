// LineSearch: how far Newton moves along its step δ (docs/architecture.md,
// "Newton"). Backtracking (halving) from the largest safe step with Armijo's
// sufficient decrease on Eᵢ plus a round-off allowance; a rejected full step
// first tries a second-order correction (terms with curvature: constraints);
// a projected step on a concave ray is lengthened while Eᵢ keeps falling.
// A step cut to less than half also tries the direction in which each DoF
// share is limited on its own (StageTerm::LimitStepPerDof), and keeps the
// lower Eᵢ of the two.
//
// The safe-step hook: every trial step is bounded by StageTerm::
// LargestSafeStep over the terms that bound steps (collision detection will
// answer it, so that no trial configuration lets surfaces pass through each
// other), asked at the saved iterate; without such terms nothing changes.
#pragma once

#include <superdex/solver/convergence_test.h>
#include <superdex/solver/linear_step.h>
#include <superdex/solver/stage_problem.h>

namespace superdex {
struct NewtonParams;
struct SceneStats;
}  // namespace superdex

namespace superdex::internal {

class LineSearch {
 public:
  LineSearch(StageProblem& problem, ConvergenceTest& convergence, LinearStep& linear)
      : problem_(problem), convergence_(convergence), linear_(linear) {}
  /// The Newton solver's gradient and step (a second-order correction uses
  /// both: its right-hand side in the gradient, its solves in the step).
  void Bind(VectorX* gradient, VectorX* delta) {
    gradient_ = gradient;
    delta_ = delta;
  }
  /// At a pattern build.
  void Reserve(int numDofs);

  /// Takes a converged step whole (at most the safe step).
  void TakeWhole();
  /// From the saved iterate along δ with slope ∇E·δ < 0 at energy E: moves to
  /// the accepted point and sets `energy` to Eᵢ there (the terms are told:
  /// StageTerm::AcceptStep). False, with the iterate restored, when no step
  /// decreases Eᵢ within NewtonParams::maxLineSearchSteps halvings.
  bool Search(NewtonParams const& newton, bool projected, real slope, real& energy, SceneStats& stats);

 private:
  /// The actors at q + δ, E(q + δ) rejected: tries q + δ + Σ δc, each δc
  /// solving H δc = −Σ Jᵀ (f(g(q + d)) − f(g + J δ)) with the factorization
  /// of H (a chord iteration back to the linearized constraint values). On
  /// success δ holds d and newtonStep_ the last δc.
  bool SecondOrderCorrection(real energy, real slope, SceneStats& stats, real& trialEnergy);
  /// Doubles a projected full step while each doubling decreases Eᵢ further.
  real Expand(real& trialEnergy, SceneStats& stats);
  /// The actors at q + α δ with Eᵢ = trialEnergy there, α < ½: tries δ
  /// limited per DoF share (StageTerm::LimitStepPerDof) with its own safe
  /// step and backtracking; true, with the actors there, the terms told and
  /// `trialEnergy` lowered, where it decreases Eᵢ sufficiently and below
  /// trialEnergy (δ then holds it); false with the actors back at q + α δ.
  bool TryLimitedStep(real energy, real alpha, real& trialEnergy, SceneStats& stats);

  StageProblem& problem_;
  ConvergenceTest& convergence_;
  LinearStep& linear_;
  VectorX* gradient_ = nullptr;
  VectorX* delta_ = nullptr;
  VectorX newtonStep_, correctedStep_;  ///< δ and δ + Σ δc in a second-order correction; the limited step
  VectorX newtonGradient_;  ///< ∇E, kept while a second-order correction uses the gradient for its force
  real safeAlpha_ = 1;  ///< the terms' safe step along this iteration's δ
};

}  // namespace superdex::internal
