// The four constraint types on an articulated actor's reduced pose
// (constraints.md, "Articulated constraints"; no world frames). Each acts on
// one joint — the joint that attaches link `jointIndex` to its parent — of
// one ArticulatedActor; they share that lookup, hence one header.
//
// ArticulatedSingleDofTarget   g = θ − θ̂                        m = 1, n = 1
// ArticulatedSingleDofRange    g = max(θ − u, l − θ, 0)          m = 1, n = 1
//   θ a revolute angle [rad], a prismatic offset [m] or one component of a
//   free joint's translation [m] (dofIndex 0..2); J = ±1. Spherical joints
//   and free-joint rotations are refused (InvalidArgument): use the 3D types.
// Articulated3dRotationTarget  g = Log(R_j R̂⁻¹)                  m = 3, n = 3
//   J = J_l⁻¹(g) R_j for the joint's local increments R_j ← R_j Exp(δ).
//   The target R̂ is in the joint's frame relative to its rest orientation
//   (identity = rest pose); it starts at the creation-time R_j.
// Articulated3dRotationRange   gₖ = max(φₖ − uₖ, lₖ − φₖ, 0), φ = Log(R_j)
//   m = 3, n = 3; row k of J = ±(J_r⁻¹(φ))ₖ.
//   The 3D types accept spherical joints and free joints' rotations.
// Units: rad or m; stiffness N·m/rad or N/m.
#pragma once

#include <limits>

#include <superdex/constraints/constraint.h>

namespace superdex {

class ArticulatedActor;

struct ArticulatedSingleDofTargetConstraintParams {
  ActorHandle actor;        ///< an articulated actor
  int jointIndex = 0;       ///< the joint of link jointIndex
  int dofIndex = 0;         ///< 0, or 0..2 for a free joint's translation
  real target = 0;          ///< θ̂ [rad or m]
  real stiffness = 0;       ///< k >= 0
  real damping = 0;         ///< d >= 0
  real saturation = -1;     ///< ḡ; <= 0 disables
};

struct ArticulatedSingleDofRangeConstraintParams {
  ActorHandle actor;
  int jointIndex = 0;
  int dofIndex = 0;
  real lowerLimit = -std::numeric_limits<real>::infinity();  ///< l, <= upperLimit
  real upperLimit = std::numeric_limits<real>::infinity();   ///< u
  real stiffness = 0;
  real damping = 0;
  real saturation = -1;
};

struct Articulated3dRotationTargetConstraintParams {
  ActorHandle actor;
  int jointIndex = 0;                 ///< a spherical or free joint
  bool targetFromCurrent = true;      ///< R̂ = the creation-time R_j
  Quat rotation = Quat::Identity();   ///< R̂ when !targetFromCurrent (joint frame, rest = identity)
  real stiffness = 0;                 ///< [N·m/rad]
  real damping = 0;
  real saturation = -1;
};

struct Articulated3dRotationRangeConstraintParams {
  ActorHandle actor;
  int jointIndex = 0;  ///< a spherical or free joint
  Real3 lowerLimits = Real3::Constant(-std::numeric_limits<real>::infinity());  ///< on Log(R_j) [rad]
  Real3 upperLimits = Real3::Constant(std::numeric_limits<real>::infinity());
  real stiffness = 0;
  real damping = 0;
  real saturation = -1;
};

/// ArticulatedSingleDofTarget and ArticulatedSingleDofRange.
class ArticulatedSingleDofConstraint final : public Constraint {
 public:
  ArticulatedSingleDofConstraint(ArticulatedActor* actor, ArticulatedSingleDofTargetConstraintParams const& params);
  ArticulatedSingleDofConstraint(ArticulatedActor* actor, ArticulatedSingleDofRangeConstraintParams const& params);
  /// θ now.
  real GetCoordinate() const;

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const override;

  ArticulatedActor* actor_;
  int joint_, dof_;
  real lower_ = 0, upper_ = 0;
};

/// Articulated3dRotationTarget and Articulated3dRotationRange.
class Articulated3dRotationConstraint final : public Constraint {
 public:
  Articulated3dRotationConstraint(ArticulatedActor* actor, Articulated3dRotationTargetConstraintParams const& params);
  Articulated3dRotationConstraint(ArticulatedActor* actor, Articulated3dRotationRangeConstraintParams const& params);
  /// φ = Log(R_j) now.
  Real3 GetJointRotationVector() const;

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;
  void DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const override;

  ArticulatedActor* actor_;
  int joint_;
  Real3 lower_ = Real3::Zero(), upper_ = Real3::Zero();
};

}  // namespace superdex
