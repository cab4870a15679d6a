// A step that fails leaves every actor bit-identical to before and returns an
// Error naming the stage and the cause.
#include "test_scenes.h"

#include <superdex/solver/newton_solver.h>

#include <cstring>

using namespace superdex;
using namespace superdex::test;

namespace {
struct BodyState {
  Real3 position, linearVelocity, angularVelocity;
  Quat rotation;
};

DynamicArray<BodyState> Capture(Chain const& chain) {
  DynamicArray<BodyState> states;
  for (RigidActor* b : chain.bodies)
    states.push_back({b->GetPosition(), b->GetLinearVelocity(), b->GetAngularVelocity(), b->GetRotation()});
  return states;
}

bool BitIdentical(DynamicArray<BodyState> const& a, DynamicArray<BodyState> const& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(a[i].position.data(), b[i].position.data(), sizeof(Real3)) != 0 ||
        std::memcmp(a[i].linearVelocity.data(), b[i].linearVelocity.data(), sizeof(Real3)) != 0 ||
        std::memcmp(a[i].angularVelocity.data(), b[i].angularVelocity.data(), sizeof(Real3)) != 0 ||
        std::memcmp(a[i].rotation.coeffs().data(), b[i].rotation.coeffs().data(), 4 * sizeof(real)) != 0)
      return false;
  }
  return true;
}

}  // namespace

TEST_CASE("a failed step changes nothing and says which stage failed and why", "[scene][transaction]") {
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  Chain chain = MakeChain(6, params);
  Scene& scene = *chain.scene;
  StepOk(scene, 1e-3, 10);  // the chain is moving, with integrator history
  DynamicArray<BodyState> const before = Capture(chain);
  real const timeBefore = scene.GetTime();
  Error error;

  SECTION("a linear-solver failure") {
    internal::SetFaultInjectionForTesting(scene, {.failLinearSolveAtIteration = 2});
    REQUIRE_FALSE(scene.Step(1e-3, error));
    CAPTURE(error.ToString());
    REQUIRE(error.GetCode() == ErrorCode::LinearSolverFailed);
    REQUIRE(Contains(error.GetMessage(), "stage 0"));
    REQUIRE(Contains(error.GetMessage(), "Newton iteration 2"));
    REQUIRE(Contains(error.GetMessage(), "linear solver"));
    // after the fault is cleared the same step succeeds
    internal::SetFaultInjectionForTesting(scene, {});
    REQUIRE(BitIdentical(before, Capture(chain)));
    StepOk(scene, 1e-3);
  }
  SECTION("a Newton failure") {
    // one Newton iteration cannot converge this nonlinear stage
    Chain tight = MakeChain(6, [] {
      SceneParams p;
      p.newton.maxIterations = 1;
      p.newton.velocityTolerance = 1e-14;
      return p;
    }());
    DynamicArray<BodyState> const start = Capture(tight);
    REQUIRE_FALSE(tight.scene->Step(1e-2, error));
    CAPTURE(error.ToString());
    REQUIRE(error.GetCode() == ErrorCode::NewtonFailed);
    REQUIRE(Contains(error.GetMessage(), "stage 0"));
    REQUIRE(Contains(error.GetMessage(), "did not converge"));
    REQUIRE(BitIdentical(start, Capture(tight)));
    REQUIRE(tight.scene->GetTime() == 0);
  }
  SECTION("a non-finite state") {
    // a finite but enormous velocity overflows the incremental potential
    REQUIRE(chain.bodies[3]->SetVelocity(Real3(1e300, 0, 0), Real3::Zero(), error));
    DynamicArray<BodyState> const huge = Capture(chain);
    REQUIRE_FALSE(scene.Step(1e-3, error));
    CAPTURE(error.ToString());
    REQUIRE(error.GetCode() == ErrorCode::NonFiniteState);
    REQUIRE(Contains(error.GetMessage(), "stage 0"));
    REQUIRE(Contains(error.GetMessage(), "not finite"));
    REQUIRE(BitIdentical(huge, Capture(chain)));
    return;
  }
  REQUIRE(scene.GetTime() >= timeBefore);
}

TEST_CASE("a failed step keeps constraint targets and forces as they were", "[scene][transaction]") {
  Chain chain = MakeChain(4);
  Scene& scene = *chain.scene;
  Error error;
  Constraint* pin = nullptr;
  scene.ForEachConstraint([&](Constraint& c) {
    if (c.GetType() == ConstraintType::RigidPivotPosition) pin = &c;
  });
  REQUIRE(pin);
  REQUIRE(pin->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(scene, 1e-3, 5);
  DynamicArray<real> const force(pin->GetForce(error).begin(), pin->GetForce(error).end());
  REQUIRE(Real3(force[0], force[1], force[2]).norm() > 0);
  internal::SetFaultInjectionForTesting(scene, {.failLinearSolveAtIteration = 1});
  REQUIRE_FALSE(scene.Step(1e-3, error));
  Span<real const> after = pin->GetForce(error);
  REQUIRE(DynamicArray<real>(after.begin(), after.end()) == force);
}
