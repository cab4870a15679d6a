// Time integrators as stage generators (docs/architecture.md, "The stage").
//
// A step of size h is a sequence of implicit stages. Every integrator here
// writes its stage in one form, for any DoF in tangent coordinates relative
// to the stage start q⁰ = qⁿ (Δ = q ⊖ qⁿ, Δₚ = qⁿ⁻¹ ⊖ qⁿ):
//
//   inertial target   Δ̂ = c·Δₚ + β h (a vⁿ + b vⁿ⁻¹)
//   inertia term      ½ w ‖Δ − Δ̂‖²_M,   w = 1/(β h)²
//   velocity update   vⁿ⁺¹ = (Δ − c Δₚ)/(β h)
//
//   backward Euler:  β = 1,   c = 0,    a = 1,   b = 0          (1st order)
//   BDF2:            β = 2/3, c = −1/3, a = 4/3, b = −1/3       (2nd order;
//                    its first step, with no history, is backward Euler)
//
// The stage duration Δtᵢ used by constraint damping (constraints.md) is h.
#pragma once

#include <string_view>

#include <superdex/core/types.h>

namespace superdex {

enum class IntegratorType { BackwardEuler, Bdf2 };

std::string_view ToString(IntegratorType type);

namespace internal {

struct StageCoefficients {
  real duration = 0;      ///< Δtᵢ = h
  real beta = 1;          ///< velocity scale β
  real cPrevious = 0;     ///< c, weight of Δₚ in the target
  real aVelocity = 1;     ///< a, weight of vⁿ
  real bVelocity = 0;     ///< b, weight of vⁿ⁻¹
  bool usesHistory = false;

  /// w = 1/(β h)²
  real InertiaWeight() const { return 1 / ((beta * duration) * (beta * duration)); }

  /// The coefficients a body with or without a history of its own uses in
  /// this stage: these, or, for a body without history (its first step, or
  /// one created or teleported since the last step) where these use it,
  /// backward Euler's over the same duration.
  StageCoefficients ForBody(bool hasHistory) const;
};

/// The single stage of one step of `type`; `hasHistory` is false on a first
/// step (BDF2 then falls back to backward Euler).
StageCoefficients MakeStage(IntegratorType type, real dt, bool hasHistory);

/// Relative difference under which two step sizes count as equal for the
/// history (round-off in a caller's dt, e.g. differences of frame times).
inline constexpr real kHistoryStepTolerance = 1e-9;

/// Whether the history recorded by a step of `historyStep` (0: no step yet)
/// may be used by a step of `dt`. The BDF2 coefficients above are those of
/// equal steps (Δₚ spans h): with a history over another step size the
/// velocity update is inconsistent (after a step of h/2, a body in free
/// fall gains (5/6) g h instead of g h), so the step then restarts as
/// backward Euler; the history it records serves the next step of its size.
bool IsHistoryUsable(real historyStep, real dt);

}  // namespace internal
}  // namespace superdex
