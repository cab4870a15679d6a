// The Hessian pattern, ordering and symbolic analysis are built once and
// reused across steps; only topology changes rebuild them.
#include "test_scenes.h"

using namespace superdex;
using namespace superdex::test;

TEST_CASE("a 20-body chain builds its pattern once over 200 steps", "[scene][assembly]") {
  LinearSolverType const solver = GENERATE(LinearSolverType::Auto, LinearSolverType::Cholmod,
                                           LinearSolverType::Dense);
  CAPTURE(ToString(solver));
  SceneParams params;
  params.linearSolver = solver;
  Chain chain = MakeChain(20, params);
  Scene& scene = *chain.scene;
  Error error;

  StepOk(scene, 1e-3, 200);
  REQUIRE(scene.GetStats().steps == 200);
  REQUIRE(scene.GetStats().patternBuilds == 1);
  REQUIRE(scene.GetStats().symbolicAnalyses == 1);
  REQUIRE(scene.GetStats().newtonIterations >= 1);

  // parameter and target changes are not topology changes
  Constraint* first = nullptr;
  scene.ForEachConstraint([&](Constraint& c) {
    if (!first) first = &c;
  });
  REQUIRE(first->SetStiffness(2e6, error));
  REQUIRE(first->SetTargetPosition(Real3(0, 0.01, 0), error));
  StepOk(scene, 1e-3, 5);
  REQUIRE(scene.GetStats().patternBuilds == 1);
  REQUIRE(scene.GetStats().symbolicAnalyses == 1);

  // adding one constraint: exactly one more of each
  RigidPivotPositionConstraintParams pin;
  pin.actor = chain.bodies.back()->GetHandle();
  pin.position = chain.bodies.back()->GetPosition();
  pin.stiffness = 1e3;
  REQUIRE(scene.CreateRigidPivotPositionConstraint(pin, error));
  StepOk(scene, 1e-3, 50);
  REQUIRE(scene.GetStats().patternBuilds == 2);
  REQUIRE(scene.GetStats().symbolicAnalyses == 2);
}

TEST_CASE("switching the linear solver re-analyzes without rebuilding the pattern",
          "[scene][assembly]") {
  Chain chain = MakeChain(20);
  Scene& scene = *chain.scene;
  Error error;
  REQUIRE(scene.SetLinearSolver(LinearSolverType::Cholmod, error));
  StepOk(scene, 1e-3, 3);
  REQUIRE(scene.GetStats().linearSolver.find("CHOLMOD") != std::string::npos);
  REQUIRE(scene.SetLinearSolver(LinearSolverType::Dense, error));
  StepOk(scene, 1e-3, 3);
  REQUIRE(scene.GetStats().patternBuilds == 1);
  REQUIRE(scene.GetStats().symbolicAnalyses == 2);
  REQUIRE(scene.GetStats().linearSolver.find("CHOLMOD") == std::string::npos);
}
