// ConstraintHessian: how a constraint's block of the Newton Hessian is formed
// (a Newton option of the scene and of each constraint; docs/constraints.md
// "The constraint Hessian" has the measurements behind the default).
#pragma once

#include <string_view>

#include <superdex/core/error.h>

namespace superdex {

/// How a constraint's block of the Newton Hessian is formed (the gradient,
/// and so the minimizer of every stage, is the same whichever is chosen).
/// With the force coefficients f = κ g + d/Δtᵢ Δg and the curvature
/// G = Σᵢ fᵢ ∂²gᵢ/∂q² (the term the reference page drops):
enum class ConstraintHessian {
  /// Per constraint: use the scene's choice (SceneParams::constraintHessian).
  SceneDefault,
  /// The reference page's Gauss–Newton block (κ + d/Δtᵢ) JᵀJ.
  GaussNewton,
  /// Geometric stiffness: (κ + d/Δtᵢ) JᵀJ + G, exact while Newton tries
  /// exact Hessians (HessianProjection::WhenIndefinite: the assembled matrix
  /// is positive definite and the step a descent direction); in projected
  /// iterations G is replaced by its diagonal form (below), PSD.
  GeometricStiffness,
  /// (κ + d/Δtᵢ) JᵀJ + diag(‖G e_j‖): G replaced by the diagonal of its
  /// column norms (Andrews, Teichmann & Kry 2017), PSD by construction.
  GeometricStiffnessDiagonal,
};

std::string_view ToString(ConstraintHessian hessian);

namespace internal {
/// True when `hessian` is a ConstraintHessian value (SceneDefault only where
/// `allowSceneDefault`); otherwise an InvalidArgument Error naming `field`.
bool CheckConstraintHessian(ConstraintHessian hessian, std::string_view field, bool allowSceneDefault,
                            Error& error);
}  // namespace internal

}  // namespace superdex
