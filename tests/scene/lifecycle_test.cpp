// Lifecycle: destroying an actor destroys exactly its constraints; handles of
// destroyed constraints give Errors; ForEachConstraint visits each live
// constraint once; the pattern is rebuilt once per step that follows a
// topology change, and never otherwise.
#include "test_scenes.h"

#include <map>

using namespace superdex;
using namespace superdex::test;

TEST_CASE("destroying an actor destroys exactly its constraints", "[scene][lifecycle]") {
  Chain chain = MakeChain(4);  // pin on 0, joints 0-1, 1-2, 2-3
  Scene& scene = *chain.scene;
  Error error;
  RigidPivotPositionConstraintParams extra;
  extra.actor = chain.bodies[3]->GetHandle();
  extra.position = chain.bodies[3]->GetPosition();
  extra.stiffness = 10;
  REQUIRE(scene.CreateRigidPivotPositionConstraint(extra, error));
  REQUIRE(scene.GetNumConstraints() == 5);
  StepOk(scene, 1e-3);
  REQUIRE(scene.GetStats().patternBuilds == 1);

  // which constraints touch body 1
  DynamicArray<ConstraintHandle> onBody1, others;
  scene.ForEachConstraint([&](Constraint& c) {
    bool touches = false;
    for (int i = 0; i < c.GetNumActors(); ++i) touches |= c.GetActor(i) == chain.bodies[1];
    (touches ? onBody1 : others).push_back(c.GetHandle());
  });
  REQUIRE(onBody1.size() == 2);
  REQUIRE(others.size() == 3);

  REQUIRE(scene.DestroyActor(chain.bodies[1]->GetHandle(), error));
  REQUIRE(scene.GetNumActors() == 3);
  REQUIRE(scene.GetNumConstraints() == 3);
  for (ConstraintHandle h : onBody1) {
    REQUIRE(scene.GetConstraint(h) == nullptr);
    error.Clear();
    REQUIRE_FALSE(scene.DestroyConstraint(h, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  }
  for (ConstraintHandle h : others) REQUIRE(scene.GetConstraint(h) != nullptr);

  // each live constraint exactly once
  std::map<std::uint32_t, int> visits;
  scene.ForEachConstraint([&](Constraint& c) { ++visits[c.GetHandle().index]; });
  REQUIRE(visits.size() == 3);
  for (auto const& [index, count] : visits) REQUIRE(count == 1);

  // one rebuild per step after a change, none otherwise
  StepOk(scene, 1e-3);
  REQUIRE(scene.GetStats().patternBuilds == 2);
  REQUIRE(scene.GetStats().symbolicAnalyses == 2);
  StepOk(scene, 1e-3, 3);
  REQUIRE(scene.GetStats().patternBuilds == 2);
  REQUIRE(scene.DestroyConstraint(others.front(), error));
  StepOk(scene, 1e-3);
  REQUIRE(scene.GetStats().patternBuilds == 3);
  REQUIRE(scene.GetStats().symbolicAnalyses == 3);
  // the remaining DoF indices follow the renumbered actors
  scene.ForEachConstraint([&](Constraint& c) {
    for (int i = 0; i < c.GetNumActors(); ++i) {
      Span<int const> dofs = c.GetDofIndicesForActor(i);
      REQUIRE(dofs.front() >= c.GetActor(i)->GetDofOffset());
      REQUIRE(dofs.back() < c.GetActor(i)->GetDofOffset() + c.GetActor(i)->GetNumDofs());
    }
  });
}
