// The four articulated constraint types: g against reference formulas
// (Eigen's AngleAxis for rotations) and J against central differences over
// the joint's DoFs in their increment coordinates, with spherical joints
// turned near π, range components below, inside and above their bounds;
// which joints each type refuses.
#include "constraint_test_util.h"

#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {

/// Root free joint → revolute → prismatic → spherical, every joint displaced.
ArticulatedActor* MakeTree(Scene& scene, real sphericalAngle) {
  ArticulatedActorParams p;
  Real3 const axis = Real3(1, -2, 0.5).normalized();
  auto link = [](int parent, JointType joint, DynamicArray<real> position) {
    ArticulatedLinkParams l;
    l.parent = parent;
    l.joint = joint;
    l.axis = Real3(0.3, 1, 0.2);
    l.parentToJointPosition = Real3(0.2, 0.1, 0);
    l.centerOfMass = Real3(0.1, 0, 0);
    l.initialPosition = std::move(position);
    return l;
  };
  p.links.push_back(link(-1, JointType::Free, {0.1, 0.2, -0.3, 0.4, 0.9, -0.2}));
  p.links.push_back(link(0, JointType::Revolute, {0.7}));
  p.links.push_back(link(1, JointType::Prismatic, {0.05}));
  p.links.push_back(link(2, JointType::Spherical,
                         {sphericalAngle * axis.x(), sphericalAngle * axis.y(), sphericalAngle * axis.z()}));
  Error error;
  ArticulatedActor* actor = scene.CreateArticulatedActor(p, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}

}  // namespace

TEST_CASE("articulated single-DoF types: g and J", "[constraints][articulated][derivatives]") {
  auto scene = MakeScene();
  ArticulatedActor* tree = MakeTree(*scene, 1.0);
  Error error;
  struct Case {
    int joint, dof;
    real value;
  };
  for (Case const c : {Case{1, 0, 0.7}, Case{2, 0, 0.05}, Case{0, 1, 0.2}}) {
    CAPTURE(c.joint, c.dof);
    ArticulatedSingleDofTargetConstraintParams target;
    target.actor = tree->GetHandle();
    target.jointIndex = c.joint;
    target.dofIndex = c.dof;
    target.target = 0.3;
    target.stiffness = 10;
    Constraint* t = scene->CreateArticulatedSingleDofTargetConstraint(target, error);
    INFO(error.ToString());
    REQUIRE(t);
    REQUIRE(t->GetDimension() == 1);
    REQUIRE(t->GetNumDofs() == 1);
    REQUIRE(t->GetDofIndicesForActor(0)[0] == tree->GetDofOffset() + tree->GetJointDofOffset(c.joint) + c.dof);
    REQUIRE(std::abs(Deviation(*t)[0] - (c.value - 0.3)) <= 1e-14);
    CheckJacobian(*scene, *t);
    REQUIRE(!t->HasCurvature());  // g linear in the joint coordinate
    CheckCurvature(*t, false);
    REQUIRE(t->SetTargetDof(c.value + 0.1, error));
    REQUIRE(std::abs(Deviation(*t)[0] + 0.1) <= 1e-14);
    for (RangeRegion region : {RangeRegion::BelowLower, RangeRegion::Inside, RangeRegion::AboveUpper}) {
      Bounds const bounds = BoundsPlacing(c.value, region, 0.02, false);
      ArticulatedSingleDofRangeConstraintParams range;
      range.actor = tree->GetHandle();
      range.jointIndex = c.joint;
      range.dofIndex = c.dof;
      range.lowerLimit = bounds.lower;
      range.upperLimit = bounds.upper;
      range.stiffness = 10;
      Constraint* r = scene->CreateArticulatedSingleDofRangeConstraint(range, error);
      REQUIRE(r);
      REQUIRE(r->IsRange());
      REQUIRE(std::abs(Deviation(*r)[0] - ReferenceViolation(c.value, bounds)) <= 1e-14);
      REQUIRE(r->GetLimitMinValues(error) == DynamicArray<real>{bounds.lower});
      REQUIRE(r->GetLimitMaxValues(error) == DynamicArray<real>{bounds.upper});
      if (region != RangeRegion::Inside) {
        CheckJacobian(*scene, *r);
        REQUIRE(!r->HasCurvature());  // g linear in the joint coordinate
        CheckCurvature(*r, false);
      }
    }
  }
}

TEST_CASE("articulated 3D rotation types: g and J, spherical joints near pi", "[constraints][articulated][derivatives]") {
  real const angle = GENERATE(0.3, 2.0, std::numbers::pi - 0.05);
  int const joint = GENERATE(0, 3);  // the free root's rotation, the spherical joint
  CAPTURE(angle, joint);
  auto scene = MakeScene();
  ArticulatedActor* tree = MakeTree(*scene, angle);
  Error error;
  Quat const rotation = tree->GetJointRotation(joint);
  Articulated3dRotationTargetConstraintParams target;
  target.actor = tree->GetHandle();
  target.jointIndex = joint;
  target.stiffness = 10;
  Constraint* t = scene->CreateArticulated3dRotationTargetConstraint(target, error);
  INFO(error.ToString());
  REQUIRE(t);
  REQUIRE(t->GetNumDofs() == 3);
  int const first = tree->GetDofOffset() + tree->GetJointDofOffset(joint) + (joint == 0 ? 3 : 0);
  for (int k = 0; k < 3; ++k) REQUIRE(t->GetDofIndicesForActor(0)[k] == first + k);
  REQUIRE(Deviation(*t).norm() <= 1e-12);  // starts at the current rotation
  // a target 0.4 rad away: g = Log(R_j R̂⁻¹)
  Quat const targetRotation = (Quat(Eigen::AngleAxis<real>(0.4, Real3(0.2, 0.4, 1).normalized())) * rotation).normalized();
  REQUIRE(t->SetTargetRotation(targetRotation, error));
  REQUIRE((Deviation(*t) - ReferenceLog((rotation * targetRotation.conjugate()).toRotationMatrix())).norm() <= 1e-12);
  CheckJacobian(*scene, *t, {}, 1e-5);
  CheckCurvature(*t, true, 1e-5);
  // the range type on each component of Log(R_j), a region per component
  Real3 const phi = ReferenceLog(rotation.toRotationMatrix());
  RangeRegion const regions[3] = {RangeRegion::BelowLower, RangeRegion::AboveUpper, RangeRegion::BelowLower};
  Articulated3dRotationRangeConstraintParams range;
  range.actor = tree->GetHandle();
  range.jointIndex = joint;
  range.stiffness = 10;
  Real3 expected;
  for (int k = 0; k < 3; ++k) {
    Bounds const b = BoundsPlacing(phi[k], regions[k], 0.05, false);
    range.lowerLimits[k] = b.lower;
    range.upperLimits[k] = b.upper;
    expected[k] = ReferenceViolation(phi[k], b);
  }
  Constraint* r = scene->CreateArticulated3dRotationRangeConstraint(range, error);
  REQUIRE(r);
  REQUIRE((Deviation(*r) - expected).norm() <= 1e-12);
  CheckJacobian(*scene, *r, {}, 1e-5);
  CheckCurvature(*r, true, 1e-5);
  DynamicArray<real> const lower = r->GetLimitMinValues(error);
  REQUIRE(lower == DynamicArray<real>(range.lowerLimits.begin(), range.lowerLimits.end()));
}

TEST_CASE("articulated constraint types refuse the joints they do not act on", "[constraints][articulated][input]") {
  auto scene = MakeScene();
  ArticulatedActor* tree = MakeTree(*scene, 1.0);
  RigidActor* body = MakeRigid(*scene, RigidActorParams{});
  Error error;
  ArticulatedSingleDofTargetConstraintParams single;
  single.actor = tree->GetHandle();
  single.jointIndex = 3;  // spherical
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofTargetConstraint(single, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("Spherical") && Catch::Contains("Articulated3dRotationTarget"));
  single.jointIndex = 0;  // free: rotations refused
  single.dofIndex = 4;
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofTargetConstraint(single, error));
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("dofIndex") && Catch::Contains("rotation"));
  single.jointIndex = 1;
  single.dofIndex = 1;  // a revolute joint has one DoF
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofTargetConstraint(single, error));
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("dofIndex must be in [0, 1)"));
  single.jointIndex = 7;
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofTargetConstraint(single, error));
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("jointIndex must be in [0, 4)"));
  single.actor = body->GetHandle();
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofTargetConstraint(single, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  ArticulatedSingleDofRangeConstraintParams range;
  range.actor = tree->GetHandle();
  range.jointIndex = 1;
  range.lowerLimit = 1;
  range.upperLimit = 0;
  REQUIRE_FALSE(scene->CreateArticulatedSingleDofRangeConstraint(range, error));
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("lowerLimit"));
  Articulated3dRotationTargetConstraintParams rotation;
  rotation.actor = tree->GetHandle();
  rotation.jointIndex = 1;  // revolute
  REQUIRE_FALSE(scene->CreateArticulated3dRotationTargetConstraint(rotation, error));
  REQUIRE_THAT(error.GetMessage(), Catch::Contains("Revolute") && Catch::Contains("spherical"));
  Articulated3dRotationRangeConstraintParams rotationRange;
  rotationRange.actor = tree->GetHandle();
  rotationRange.jointIndex = 2;  // prismatic
  REQUIRE_FALSE(scene->CreateArticulated3dRotationRangeConstraint(rotationRange, error));
  REQUIRE(scene->GetNumConstraints() == 0);
}
