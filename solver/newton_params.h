// Newton's options for every stage (SceneParams::newton; docs/architecture.md,
// "Newton").
#pragma once

#include <string_view>

#include <superdex/core/types.h>
#include <superdex/stage/constraint_hessian.h>

namespace superdex {

/// How Newton treats element Hessians that are not positive semi-definite
/// (hyperelastic tetrahedra and membranes under compression).
enum class HessianProjection {
  /// Exact element Hessians while the assembled matrix is positive definite
  /// (the inertia term usually makes it so); a Newton iteration whose matrix
  /// the linear solver reports not positive definite (or whose step is not a
  /// descent direction) is re-assembled with projected Hessians, and the next
  /// iteration tries the exact ones again. Near a minimum the exact Hessian is
  /// positive semi-definite, so Newton ends quadratically.
  WhenIndefinite,
  /// Every element Hessian projected to PSD (negative eigenvalues clamped):
  /// always a descent direction, but only linear convergence where elements
  /// are compressed (the projection drops curvature the solution needs).
  Always,
};

std::string_view ToString(HessianProjection projection);

/// Newton's method on each stage's incremental potential.
struct NewtonParams {
  int maxIterations = 50;        ///< > 0
  /// Converged when the step, scaled to the velocity of material points, is
  /// small: maxⱼ ℓⱼ |δqⱼ| / Δtᵢ <= velocityTolerance [m/s], with ℓⱼ = 1 m
  /// for translations (and every DoF of deformables, rods and articulated
  /// actors) and a rigid body's rms radius √(tr I_b / 2m) for its rotations
  /// (the rms motion of its mass per radian). > 0. Also converged when the
  /// Newton decrement −∇E·δ is below the round-off resolution of the
  /// incremental potential (counted in SceneStats::roundOffConvergences).
  real velocityTolerance = 1e-6;
  int maxLineSearchSteps = 40;   ///< backtracking halvings before failure, > 0
  HessianProjection hessianProjection = HessianProjection::WhenIndefinite;
  /// The constraint blocks of the Newton Hessian, for every constraint whose
  /// own choice is ConstraintHessian::SceneDefault (not allowed here).
  ConstraintHessian constraintHessian = ConstraintHessian::GeometricStiffness;
  /// The near-rigid cap β (off when 0, the default; finite and >= 0). With
  /// β > 0, every constraint whose k + d/Δtᵢ exceeds 4π²/(β² Δtᵢ² w) — w its
  /// inverse effective mass, the largest diagonal entry of J diag(M)⁻¹ Jᵀ at
  /// the stage start — has k and d scaled down to that bound for the stage
  /// (d/k kept; a saturated constraint keeps its force cap k ḡ), so that no
  /// constraint oscillates with a period below β Δtᵢ: the Newton Hessian stays
  /// well-conditioned for PCG, and the answer changes (a softer constraint),
  /// which is why it is opt-in. β = 1 is Drake SAP's near-rigid threshold;
  /// smaller β caps less. SceneStats::nearRigidConstraints counts the capped
  /// constraints; docs/constraints.md "Near-rigid constraints (opt-in)".
  real nearRigidBeta = 0;
  /// Direct linear solvers (CHOLMOD, dense): a Newton iteration first solves
  /// its own Hessian's system by conjugate gradients preconditioned with the
  /// last numeric factorization (of an earlier iteration or step, same
  /// pattern), to the relative residual `factorReuseTolerance`, and
  /// refactorizes only when that CG meets negative curvature or needs more
  /// iterations than one factorization costs (the cap comes from the factor's
  /// flop counts, docs/linear_solvers.md "Reused factorizations"). The step
  /// is the current Hessian's Newton step to that residual, so Newton
  /// converges to the same state. Off: every iteration refactorizes.
  /// SceneStats::factorizations and reusedFactorSolves count both kinds.
  bool reuseFactorization = true;
  real factorReuseTolerance = 1e-6;  ///< in (0, 1)
  /// With reuseFactorization: each reused-factor CG stops at the inexact-
  /// Newton forcing term of its iteration (Eisenstat–Walker choice 2, in
  /// [factorReuseTolerance, 0.1]: loose while Newton is far from the
  /// minimum, tight near it) instead of factorReuseTolerance, or once its
  /// estimated error, scaled like the Newton step, is a tenth of
  /// velocityTolerance. A step that meets the Newton tolerance from a looser
  /// solve is continued to one of those before Newton may stop, so the
  /// converged state stays within the tolerance of full Newton's. Off: every
  /// reused-factor solve goes to factorReuseTolerance.
  bool reuseForcingTerms = true;
  /// With reuseFactorization: the reused-factor CG applies a supernodal
  /// CHOLMOD factor from a copy of L rounded to single precision (half the
  /// memory traffic of its triangular solves, which run at memory speed), the
  /// arithmetic and CG's residual staying in double. The preconditioner is
  /// then L̃L̃ᵀ with L̃ = L rounded, still symmetric positive definite, and
  /// each Newton step is still the current Hessian's to the same tolerance.
  /// Skipped per factorization when L's diagonal spread says the Hessian is
  /// too ill-conditioned for single precision to pay (or a value does not fit
  /// a float); simplicial and dense factors always solve in double
  /// (docs/linear_solvers.md "Reused factorizations"). Off: double always.
  bool singlePrecisionReusedFactor = true;
};

}  // namespace superdex
