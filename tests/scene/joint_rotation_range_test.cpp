// JointRotationRange on a hinge: a rod hinged to a fixed body (two spherical
// joints on the hinge axis z) swings down under gravity until the range's
// lower bound on the z component stops it; inside the bounds the range
// contributes exactly nothing to the residual and the Hessian.
#include "test_scenes.h"
#include "white_box.h"

#include <iostream>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kMass = 1.2, kHalfLength = 0.5;
constexpr real kLower = -0.6, kUpper = 0.6;
constexpr real kRangeStiffness = 1e4;  // [N·m/rad]

struct Hinge {
  std::unique_ptr<Scene> scene;
  RigidActor* base;
  RigidActor* rod;
  JointRotationRangeConstraint* range;
};

Hinge MakeHinge(Scene& scene) {
  Hinge h;
  RigidActorParams base;
  base.mass = 3;
  h.base = MakeRigid(scene, base);
  Anchor(scene, *h.base);
  RigidActorParams rod;
  rod.mass = kMass;
  rod.inertia = Real3(0.01, kMass * 4 * kHalfLength * kHalfLength / 12, kMass * 4 * kHalfLength * kHalfLength / 12);
  rod.position = Real3(kHalfLength, 0, 0);  // horizontal, hinge at the origin
  h.rod = MakeRigid(scene, rod);
  Error error;
  for (real z : {-0.25, 0.25}) {
    RigidSphericalJointConstraintParams j;
    j.actorA = h.base->GetHandle();
    j.actorB = h.rod->GetHandle();
    j.localPosA = Real3(0, 0, z);
    j.localPosB = Real3(-kHalfLength, 0, z);
    j.stiffness = 1e7;
    REQUIRE(scene.CreateRigidSphericalJointConstraint(j, error));
  }
  JointRotationRangeConstraintParams r;
  r.actorA = h.base->GetHandle();
  r.actorB = h.rod->GetHandle();
  r.lowerLimits = Real3(-std::numeric_limits<real>::infinity(), -std::numeric_limits<real>::infinity(), kLower);
  r.upperLimits = Real3(std::numeric_limits<real>::infinity(), std::numeric_limits<real>::infinity(), kUpper);
  r.stiffness = kRangeStiffness;
  r.damping = 50;
  Constraint* c = scene.CreateJointRotationRangeConstraint(r, error);
  REQUIRE(c);
  h.range = static_cast<JointRotationRangeConstraint*>(c);
  return h;
}
}  // namespace

TEST_CASE("a hinge driven past its bound stops at the bound", "[long][scene][range]") {
  auto scene = MakeScene();
  Hinge h = MakeHinge(*scene);
  Error error;
  DynamicArray<real> const lower = h.range->GetLimitMinValues(error);
  DynamicArray<real> const upper = h.range->GetLimitMaxValues(error);
  REQUIRE(lower == DynamicArray<real>{-INFINITY, -INFINITY, kLower});
  REQUIRE(upper == DynamicArray<real>{INFINITY, INFINITY, kUpper});

  // it swings freely (range inactive) until it reaches the bound
  real minimumAngle = 0;
  for (int step = 0; step < 3000; ++step) {
    StepOk(*scene, 1e-3);
    minimumAngle = std::min(minimumAngle, h.range->GetRelativeRotation().z());
  }
  real const angle = h.range->GetRelativeRotation().z();
  // at rest the range's torque k·(l − θ) balances gravity's m g L cos θ
  real const torque = kMass * 9.81 * kHalfLength * std::cos(angle);
  real const expectedViolation = torque / kRangeStiffness;
  Real3 const g = ToReal3(h.range->GetDeviation());
  std::cout << "hinge: at rest at " << angle << " rad (bound " << kLower << "), violation " << g.z()
            << " (expected " << expectedViolation << "), deepest " << minimumAngle << "\n";
  CAPTURE(angle, g.transpose(), expectedViolation, minimumAngle);
  REQUIRE(h.rod->GetAngularVelocity().norm() <= 1e-5);
  REQUIRE(std::abs(g.z() - expectedViolation) <= 0.01 * expectedViolation);
  REQUIRE(std::abs(angle - (kLower - expectedViolation)) <= 1e-3 * expectedViolation);
  // without the range it would hang at −π/2; it never went far past the bound
  REQUIRE(minimumAngle > kLower - 0.1);
}

TEST_CASE("inside its bounds a range contributes exactly zero", "[scene][range]") {
  auto scene = MakeScene();
  Hinge h = MakeHinge(*scene);
  // a pose inside the bounds, now and at the stage start
  REQUIRE(h.range->GetRelativeRotation().norm() < 1e-12);
  internal::TermWorkspace ws;
  ws.Reserve(3, 6);
  internal::ConstraintTestAccess::BeginStage(*h.range, ws);
  REQUIRE(internal::ConstraintTestAccess::StageStartValue(*h.range).isZero(0));

  // assemble only this constraint into a pattern over all scene DoFs
  int const numDofs = scene->GetNumDofs();
  internal::HessianAssembler assembler;
  Error error;
  DynamicArray<int> blocks(scene->GetNumActors(), 6);
  REQUIRE(assembler.Analyze(numDofs, blocks, {internal::ConstraintTestAccess::Dofs(*h.range)},
                            OrderingMethod::Natural, error));
  DynamicArray<real> gradient(numDofs, 0);
  assembler.ZeroValues();
  internal::ConstraintTestAccess::AddGradientAndHessian(*h.range, 1e-3, gradient, assembler, 0, ws);
  for (real v : gradient) REQUIRE(v == 0);
  for (real v : assembler.GetMatrix().values) REQUIRE(v == 0);
  REQUIRE(internal::ConstraintTestAccess::Energy(*h.range, 1e-3, ws) == 0);

  // the same calls outside the bounds do contribute (the check is not vacuous)
  Quat const turned(Eigen::AngleAxis<real>(kUpper + 0.2, Real3::UnitZ()));
  REQUIRE(h.rod->SetPose(h.rod->GetPosition(), turned, error));
  assembler.ZeroValues();
  internal::ConstraintTestAccess::AddGradientAndHessian(*h.range, 1e-3, gradient, assembler, 0, ws);
  real largest = 0;
  for (real v : assembler.GetMatrix().values) largest = std::max(largest, std::abs(v));
  REQUIRE(largest > 0);
}
