// ConvergenceTest: when Newton stops (docs/architecture.md, "Newton").
//
// Converged when the step, scaled to the velocity of material points,
// maxⱼ ℓⱼ |δⱼ| / Δtᵢ (ℓⱼ the DoF length scales of StageDofs), is at most
// NewtonParams::velocityTolerance; or at a stall on the round-off floor of
// Eᵢ: the Newton decrement −∇E·δ and the change the last accepted step made
// are both below Eᵢ's resolution, kRoundOffUlps ulps of Σ|terms| plus the
// terms' round-off scales (EnergySum::scale), so that no line search can
// tell the iterate from the minimum. It also measures Eᵢ (Energy), which
// sets the resolution.
#pragma once

#include <cmath>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/solver/collectives.h>
#include <superdex/solver/stage_problem.h>

namespace superdex::internal {

class ConvergenceTest {
 public:
  ConvergenceTest(StageProblem const& problem, HessianAssembler const& assembler, RankGroup& ranks)
      : problem_(problem), assembler_(assembler), ranks_(ranks) {}
  /// At a pattern build.
  void Reserve(int numDofs);
  /// At the stage start: the DoF length scales (ℓⱼ) of the DoF owners, the
  /// tolerance and Δtᵢ.
  void BeginStage(real velocityTolerance, real h);
  Span<real const> GetLengthScales() const { return {lengthScales_.data(), static_cast<std::size_t>(lengthScales_.size())}; }

  /// Eᵢ at the current iterate; records its round-off scale.
  real Energy();
  /// The round-off resolution of Eᵢ: kRoundOffUlps ulps of the scale of the
  /// last Energy.
  real Resolution() const;

  /// The verdict on a step δ from gradient ∇E: its scaled norm and slope
  /// ∇E·δ, converged by the step norm, or stalled at the round-off floor
  /// (the last accepted step changed Eᵢ below `resolution` too).
  struct Verdict {
    real stepNorm = 0, slope = 0;
    bool stepConverged = false, stalled = false;
    bool Converged() const { return stepConverged || stalled; }
  };
  Verdict Judge(VectorX const& gradient, VectorX const& delta, real resolution) const;
  /// After an accepted step that changed Eᵢ from `before` to `after`.
  void RecordChange(real before, real after, real resolution) {
    lastChangeUnresolved_ = std::abs(after - before) <= resolution;
  }

 private:
  StageProblem const& problem_;
  HessianAssembler const& assembler_;
  RankGroup& ranks_;
  VectorX lengthScales_;  ///< ℓⱼ per DoF (StageDofs::WriteDofLengthScales)
  real tolerance_ = 0, duration_ = 1;
  real energyScale_ = 0;  ///< EnergySum::scale at the last Energy
  bool lastChangeUnresolved_ = false;
};

}  // namespace superdex::internal
