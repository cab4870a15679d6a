// With saturation ḡ the constraint force magnitude never exceeds k ḡ.
#include "test_support.h"

using namespace superdex;
using namespace superdex::test;

TEST_CASE("a saturated pivot never pulls harder than k times saturation", "[scene][saturation]") {
  // gravity m g = 19.62 N exceeds the cap k ḡ = 5 N, so the body slips away
  // from the target while the pivot keeps pulling at (nearly) the cap
  real const stiffness = 1e4, saturation = 5e-4;
  real const cap = stiffness * saturation;
  auto scene = MakeScene();
  RigidActorParams body;
  body.mass = 2;
  RigidActor* actor = MakeRigid(*scene, body);
  RigidPivotPositionConstraintParams p;
  p.actor = actor->GetHandle();
  p.localPos = Real3(0.1, 0.2, 0);
  p.position = actor->TransformPoint(p.localPos);
  p.stiffness = stiffness;
  p.saturation = saturation;
  Error error;
  Constraint* pivot = scene->CreateRigidPivotPositionConstraint(p, error);
  REQUIRE(pivot);
  REQUIRE(pivot->RegisterQuery(QueryType::ConstraintForce, error));

  real largest = 0;
  for (int step = 0; step < 300; ++step) {
    StepOk(*scene, 1e-3);
    Span<real const> force = pivot->GetForce(error);
    REQUIRE(force.size() == 6);
    real const magnitude = Real3(force[0], force[1], force[2]).norm();
    CAPTURE(step, magnitude, cap);
    REQUIRE(magnitude <= cap * (1 + 1e-12));
    largest = std::max(largest, magnitude);
  }
  // the cap is reached (the check above is not vacuous) and the body fell
  REQUIRE(largest >= 0.999 * cap);
  REQUIRE(ToReal3(pivot->GetDeviation()).norm() > 10 * saturation);
}
