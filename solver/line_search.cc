#include <superdex/solver/line_search.h>

#include <cmath>
#include <limits>

#include <superdex/solver/newton_params.h>
#include <superdex/solver/scene_stats.h>

namespace superdex::internal {

namespace {
/// Doublings of a projected step on a concave ray (at most 2²⁰ times the step)
constexpr int kMaxExpansions = 20;
/// Chord iterations of a second-order correction
constexpr int kMaxCorrections = 4;

/// Armijo's sufficient decrease (c = 1e-4) for a step of α along a direction
/// of slope ∇E·δ, with a round-off allowance of 1e-12 |E| plus the
/// resolution of Eᵢ: a full Newton step near the minimum, whose decrease is
/// below what Eᵢ resolves, is taken rather than halved on round-off until it
/// no longer moves the iterate
bool SufficientDecrease(real energy, real trialEnergy, real alpha, real slope, real resolution) {
  real const allowance = 1e-12 * std::max(std::abs(energy), std::abs(trialEnergy)) + resolution;
  return std::isfinite(trialEnergy) && trialEnergy <= energy + 1e-4 * alpha * slope + allowance;
}
}  // namespace

void LineSearch::Reserve(int numDofs) {
  newtonStep_.setZero(numDofs);
  correctedStep_.setZero(numDofs);
}

void LineSearch::TakeWhole() {
  Span<real const> const delta(delta_->data(), delta_->size());
  problem_.ApplyIncrementFromSaved(delta, problem_.BoundsSteps() ? problem_.LargestSafeStep(delta, 1) : 1);
}

bool LineSearch::Search(NewtonParams const& newton, bool projected, real slope, real& energy, SceneStats& stats) {
  Span<real const> const delta(delta_->data(), delta_->size());
  // the safe step along δ, asked once at the saved iterate: no trial below
  // goes past it (the backtracking's first, the expansion's last)
  safeAlpha_ = problem_.BoundsSteps() ? problem_.LargestSafeStep(delta, std::ldexp(real(1), kMaxExpansions))
                                      : std::numeric_limits<real>::infinity();
  real alpha = std::min(real(1), safeAlpha_);
  bool accepted = false, corrected = false;
  real trialEnergy = energy;
  for (int k = 0; k <= newton.maxLineSearchSteps; ++k, alpha *= 0.5) {
    problem_.ApplyIncrementFromSaved(delta, alpha);
    trialEnergy = convergence_.Energy();
    if (SufficientDecrease(energy, trialEnergy, alpha, slope, convergence_.Resolution())) {
      accepted = true;
      break;
    }
    // a rejected full step first tries its second-order correction
    // (the curvature of constraints, docs/architecture.md)
    if (k == 0 && alpha == 1 && problem_.HasSecondOrderCorrection() &&
        SecondOrderCorrection(energy, slope, stats, trialEnergy)) {
      accepted = corrected = true;
      break;
    }
  }
  if (!accepted) {
    problem_.RestoreIterate();
    return false;
  }
  // cut short (a contact stopping a few vertices stops the whole step
  // along δ): the step limited per DoF share may go further
  if (problem_.BoundsSteps() && !corrected && alpha < 0.5 && TryLimitedStep(energy, alpha, trialEnergy, stats)) {
    energy = trialEnergy;
    return true;
  }
  // Expansion: a projected Hessian overestimates the curvature
  // (H_p − H ⪰ 0). Where the full step decreased Eᵢ by more than 3/4 of the
  // slope (1.5 × the decrease the model predicts, ½|∇E·δ|), the true
  // curvature along δ is below half the model's or negative: near a saddle
  // of a folding cloth the projected steps are then a small fraction of the
  // way down and Newton crawls away from it by a constant factor per
  // iteration (docs/architecture.md, measurements).
  if (projected && !corrected && alpha == 1 && std::isfinite(trialEnergy) && trialEnergy < energy + 0.75 * slope)
    alpha = Expand(trialEnergy, stats);
  // the terms' force estimates follow the accepted step
  if (corrected)
    problem_.AcceptStep({Span<real const>(newtonStep_.data(), newtonStep_.size()), 1, true});
  else
    problem_.AcceptStep({delta, alpha, false});
  energy = trialEnergy;
  return true;
}

bool LineSearch::TryLimitedStep(real energy, real alpha, real& trialEnergy, SceneStats& stats) {
  Span<real const> const delta(delta_->data(), delta_->size());
  correctedStep_ = *delta_;
  problem_.LimitStepPerDof(Span<real>(correctedStep_.data(), correctedStep_.size()));
  real const slope = gradient_->dot(correctedStep_);
  if (!(slope < 0)) return false;  // not a descent direction: δ's point stays
  Span<real const> const limited(correctedStep_.data(), correctedStep_.size());
  real beta = std::min(real(1), problem_.LargestSafeStep(limited, 1));
  constexpr int kMaxHalvings = 10;
  for (int k = 0; k <= kMaxHalvings; ++k, beta *= 0.5) {
    problem_.ApplyIncrementFromSaved(limited, beta);
    real const limitedEnergy = convergence_.Energy();
    if (!SufficientDecrease(energy, limitedEnergy, beta, slope, convergence_.Resolution())) continue;
    if (!(limitedEnergy < trialEnergy)) break;
    *delta_ = correctedStep_;
    problem_.AcceptStep({delta, beta, false});
    trialEnergy = limitedEnergy;
    ++stats.limitedSteps;
    return true;
  }
  problem_.ApplyIncrementFromSaved(delta, alpha);
  return false;
}

real LineSearch::Expand(real& trialEnergy, SceneStats& stats) {
  Span<real const> const delta(delta_->data(), delta_->size());
  real alpha = 1;
  for (int k = 0; k < kMaxExpansions; ++k) {
    if (2 * alpha > safeAlpha_) break;
    problem_.ApplyIncrementFromSaved(delta, 2 * alpha);
    real const expandedEnergy = convergence_.Energy();
    if (!(expandedEnergy < trialEnergy)) break;
    alpha *= 2;
    trialEnergy = expandedEnergy;
  }
  problem_.ApplyIncrementFromSaved(delta, alpha);
  if (alpha > 1) ++stats.lineSearchExpansions;
  return alpha;
}

bool LineSearch::SecondOrderCorrection(real energy, real slope, SceneStats& stats, real& trialEnergy) {
  // the actors are at q + δ, δ in delta_; each correction's right-hand side
  // goes to gradient_ and its solution to delta_
  newtonStep_ = *delta_;
  correctedStep_ = *delta_;
  // ∇E is put back on every exit: the limited step after a failed
  // correction takes its slope from it (with the correction's force there,
  // its slope was the force's, and across ranks, where that force is
  // assembled in each rank's own rows only, the ranks disagreed)
  newtonGradient_ = *gradient_;
  struct Restore {
    VectorX& to;
    VectorX const& from;
    ~Restore() { to = from; }
  } const restore{*gradient_, newtonGradient_};
  Span<real const> const step(newtonStep_.data(), newtonStep_.size());
  Span<real> const gradient(gradient_->data(), gradient_->size());
  Span<real const> const corrected(correctedStep_.data(), correctedStep_.size());
  real previousEnergy = trialEnergy;
  for (int c = 0; c < kMaxCorrections; ++c) {
    gradient_->setZero();
    problem_.AddCorrectionForce(step, gradient);
    if (!linear_.SolveWithCurrentMatrix(stats).Ok()) break;
    correctedStep_ += *delta_;
    if (problem_.BoundsSteps()) {
      // asked from the saved iterate, as every safe step
      problem_.RestoreIterate();
      if (problem_.LargestSafeStep(corrected, 1) < 1) break;
    }
    problem_.ApplyIncrementFromSaved(corrected, 1);
    real const correctedEnergy = convergence_.Energy();
    if (SufficientDecrease(energy, correctedEnergy, 1, slope, convergence_.Resolution())) {
      trialEnergy = correctedEnergy;
      ++stats.secondOrderCorrections;
      newtonStep_ = *delta_;  // the last δc
      *delta_ = correctedStep_;
      return true;
    }
    if (!(correctedEnergy < previousEnergy)) break;
    previousEnergy = correctedEnergy;
  }
  *delta_ = newtonStep_;
  return false;
}

}  // namespace superdex::internal
