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

#include <memory>

#include <limits>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

class ArticulatedActor;

struct ArticulatedSingleDofTargetConstraintParams {
  ActorHandle actor;        ///< an articulated actor
  int jointIndex = 0;       ///< the joint of link jointIndex
  int dofIndex = 0;         ///< 0, or 0..2 for a free joint's translation
  real target = 0;          ///< θ̂ [rad or m]
  real stiffness = 0;       ///< k >= 0
  real damping = 0;         ///< d >= 0
  real saturation = -1;     ///< ḡ; <= 0 disables
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = θ - θ̂ (m = 1, n = 1): θ a revolute angle, a prismatic offset or a free joint's translation component. Spherical joints and free-joint rotations: use the 3D types.";
  static constexpr auto Fields() {
    using P = ArticulatedSingleDofTargetConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "an articulated actor"},
        internal::ParamsField<P>{"jointIndex", &P::jointIndex, "the joint of link joint_index"},
        internal::ParamsField<P>{"dofIndex", &P::dofIndex, "0, or 0..2 for a free joint's translation"},
        internal::ParamsField<P>{"target", &P::target, "θ̂ [rad or m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad or N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad or N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad or m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
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
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = max(θ - u, l - θ, 0) (m = 1, n = 1): mechanical joint limits.";
  static constexpr auto Fields() {
    using P = ArticulatedSingleDofRangeConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "an articulated actor"},
        internal::ParamsField<P>{"jointIndex", &P::jointIndex, "the joint of link joint_index"},
        internal::ParamsField<P>{"dofIndex", &P::dofIndex, "0, or 0..2 for a free joint's translation"},
        internal::ParamsField<P>{"lowerLimit", &P::lowerLimit, "l, <= upper_limit, default -inf"},
        internal::ParamsField<P>{"upperLimit", &P::upperLimit, "u, default +inf"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad or N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad or N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad or m]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

struct Articulated3dRotationTargetConstraintParams {
  ActorHandle actor;
  int jointIndex = 0;                 ///< a spherical or free joint
  bool targetFromCurrent = true;      ///< R̂ = the creation-time R_j
  Quat rotation = Quat::Identity();   ///< R̂ when !targetFromCurrent (joint frame, rest = identity)
  real stiffness = 0;                 ///< [N·m/rad]
  real damping = 0;
  real saturation = -1;
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "g = Log(R_j R̂⁻¹) (m = 3, n = 3) on a spherical or free joint; the target is in the joint's frame relative to its rest orientation (identity = rest).";
  static constexpr auto Fields() {
    using P = Articulated3dRotationTargetConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "an articulated actor"},
        internal::ParamsField<P>{"jointIndex", &P::jointIndex, "a spherical or free joint"},
        internal::ParamsField<P>{"targetFromCurrent", &P::targetFromCurrent, "R̂ = the creation-time R_j (default True)"},
        internal::ParamsField<P>{"rotation", &P::rotation, "R̂ when not target_from_current [w, x, y, z]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

struct Articulated3dRotationRangeConstraintParams {
  ActorHandle actor;
  int jointIndex = 0;  ///< a spherical or free joint
  Real3 lowerLimits = Real3::Constant(-std::numeric_limits<real>::infinity());  ///< on Log(R_j) [rad]
  Real3 upperLimits = Real3::Constant(std::numeric_limits<real>::infinity());
  real stiffness = 0;
  real damping = 0;
  real saturation = -1;
  /// One line on the type, and the fields with their documentation: mochi's
  /// params class, the API fuzzer and the docs table come from them.
  static constexpr std::string_view kSummary = "Independent bounds on each component of Log(R_j) (m = 3, n = 3), one-sided violation.";
  static constexpr auto Fields() {
    using P = Articulated3dRotationRangeConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "an articulated actor"},
        internal::ParamsField<P>{"jointIndex", &P::jointIndex, "a spherical or free joint"},
        internal::ParamsField<P>{"lowerLimits", &P::lowerLimits, "on Log(R_j) [rad], -inf for no bound"},
        internal::ParamsField<P>{"upperLimits", &P::upperLimits, "[rad], +inf for no bound"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N·m/rad], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·m·s/rad], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation ḡ [rad]: the elastic force is capped at k·ḡ; <= 0 (default -1) disables it"}};
  }
};

/// ArticulatedSingleDofTarget and ArticulatedSingleDofRange.
class ArticulatedSingleDofConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, ArticulatedSingleDofRangeConstraintParams const& params,
                                            Error& error);
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, ArticulatedSingleDofTargetConstraintParams const& params,
                                            Error& error);
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
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, Articulated3dRotationRangeConstraintParams const& params,
                                            Error& error);
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene, Articulated3dRotationTargetConstraintParams const& params,
                                            Error& error);
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
