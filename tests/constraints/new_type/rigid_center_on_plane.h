// RigidCenterOnPlane — holds a rigid body's centre on a plane.
//
//   g = n̂ · t − d                                                m = 1, n = 3
//   J = n̂ᵀ (the body's translation DoFs)
// n̂ the unit normal (the given normal, normalized), d the plane's offset
// along it [m]; g is linear: no curvature. Units: g in m, stiffness N/m.
//
// The example type of docs/extending.md: tests/constraints/add_type_test.sh
// adds it to a copy of the tree by the checklist — these two files, one line
// in constraints/constraint_types.h — and checks that the factory, its
// validation, mochi's binding and the docs table come with it.
#pragma once

#include <memory>

#include <superdex/constraints/constraint.h>

namespace superdex {

namespace internal {
class ActorLookup;
}

struct RigidCenterOnPlaneConstraintParams {
  ActorHandle actor;                 ///< a rigid actor, or an articulated actor with `link`
  int link = -1;                     ///< the articulated actor's link (−1: a rigid actor)
  Real3 normal = Real3::UnitY();     ///< the plane's normal, world (not zero)
  real offset = 0;                   ///< d: the plane is n̂ · x = d [m]
  real stiffness = 0;                ///< k >= 0 [N/m]
  real damping = 0;                  ///< d >= 0 [N·s/m]
  real saturation = -1;              ///< ḡ [m]; <= 0 disables

  static constexpr std::string_view kSummary = "Holds a rigid body's centre on a plane: g = n·t - d (m = 1, n = 3).";
  static constexpr auto Fields() {
    using P = RigidCenterOnPlaneConstraintParams;
    return std::array{
        internal::ParamsField<P>{"actor", &P::actor, "a rigid actor, or an articulated actor with link"},
        internal::ParamsField<P>{"link", &P::link, "the articulated actor's link (-1: a rigid actor)"},
        internal::ParamsField<P>{"normal", &P::normal, "the plane's normal, world (not zero)"},
        internal::ParamsField<P>{"offset", &P::offset, "d: the plane is n·x = d [m]"},
        internal::ParamsField<P>{"stiffness", &P::stiffness, "stiffness k >= 0 [N/m], default 0"},
        internal::ParamsField<P>{"damping", &P::damping, "damping d >= 0 [N·s/m], default 0"},
        internal::ParamsField<P>{"saturation", &P::saturation, "saturation [m]; <= 0 (default -1) disables it"}};
  }
};

class RigidCenterOnPlaneConstraint final : public Constraint {
 public:
  /// Validates `params` against the scene's actors and creates the
  /// constraint; nullptr and `error` naming the field on bad input.
  static std::unique_ptr<Constraint> Create(internal::ActorLookup const& scene,
                                            RigidCenterOnPlaneConstraintParams const& params, Error& error);
  RigidCenterOnPlaneConstraint(internal::RigidBodySlot body, RigidCenterOnPlaneConstraintParams const& params);

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g, Eigen::Ref<MatrixX> jacobian) const override;

  Real3 normal_;
  real offset_;
};

}  // namespace superdex
