#include <superdex/constraints/rigid_center_on_plane.h>

#include <superdex/constraints/constraint_validation.h>

namespace superdex {

RigidCenterOnPlaneConstraint::RigidCenterOnPlaneConstraint(internal::RigidBodySlot body,
                                                           RigidCenterOnPlaneConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidCenterOnPlane,
                        .dimension = 1,
                        .actors = {body.actor, nullptr},
                        .links = {body.link, -1},
                        .localDofs = {DynamicArray<int>{0, 1, 2}, DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      normal_(params.normal.normalized()),
      offset_(params.offset) {}

void RigidCenterOnPlaneConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                              Eigen::Ref<MatrixX> jacobian) const {
  g[0] = normal_.dot(BodyPosition(0)) - offset_;
  jacobian.row(0) = normal_.transpose();
}

std::unique_ptr<Constraint> RigidCenterOnPlaneConstraint::Create(internal::ActorLookup const& scene,
                                                                 RigidCenterOnPlaneConstraintParams const& p,
                                                                 Error& error) {
  constexpr std::string_view kParams = "RigidCenterOnPlaneConstraintParams";
  internal::RigidBodySlot body;
  if (!internal::GetRigidBody(scene, p.actor, p.link, kParams, "actor", "link", body, error) ||
      !internal::CheckField(p.normal, kParams, "normal", error) ||
      !internal::CheckFinite(p.offset, std::string(kParams) + ".offset", error) ||
      !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  if (!(p.normal.norm() > 0)) {
    error.Set(ErrorCode::InvalidArgument, std::string(kParams) + ".normal must not be zero");
    return nullptr;
  }
  return std::make_unique<RigidCenterOnPlaneConstraint>(body, p);
}

}  // namespace superdex
