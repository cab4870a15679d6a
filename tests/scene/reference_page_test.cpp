// The reference page's code compiles as written and runs: every code block of
// the original page the project's spec/constraints.md was taken from,
// verbatim between the BEGIN/END markers, with only the actors it names set
// up before and its results checked after. (The spec's own block, the three
// creation examples in one scope, was tests/constraints/reference_examples_test;
// its checks are in the first case below.)
#include "test_scenes.h"

// the page's snippets name results they do not use
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wunused-parameter"

using namespace superdex;
using namespace superdex::test;

namespace {

/// The names the page's snippets use: `scene` (a pointer-like owner),
/// `error`, and the actors softActor, bodyA, bodyB, rigidActor.
struct PageSetUp {
  std::unique_ptr<Scene> scene = MakeScene();
  Error error;
  DeformableActor* softActor = nullptr;
  RigidActor *bodyA = nullptr, *bodyB = nullptr, *rigidActor = nullptr;

  PageSetUp() {
    softActor = MakeBox(*scene, Real3(0, 1, 0), Real3(0.2, 0.1, 0.1), {2, 1, 1}, {});  // 12 nodes
    RigidActorParams body;
    body.position = Real3(0, 0, 0);
    bodyA = MakeRigid(*scene, body);
    body.position = Real3(1, 0, 0);
    bodyB = MakeRigid(*scene, body);
    body.position = Real3(0.2, 1.05, 0.05);
    rigidActor = MakeRigid(*scene, body);
  }
};

/// The page's "Connecting Two Rigid Bodies" block, for the runtime blocks
/// that start from a `constraint`.
Constraint* MakeJoint(PageSetUp& s) {
  RigidSphericalJointConstraintParams params;
  params.actorA = s.bodyA->GetHandle();
  params.actorB = s.bodyB->GetHandle();
  params.localPosA = Real3{0.5_r, 0_r, 0_r};
  params.localPosB = Real3{-0.5_r, 0_r, 0_r};
  params.stiffness = 1e6_r;
  Constraint* c = s.scene->CreateRigidSphericalJointConstraint(params, s.error);
  REQUIRE(c);
  return c;
}

}  // namespace

TEST_CASE("the original page: the three creation examples", "[scene][reference_page]") {
  PageSetUp s;
  auto& scene = s.scene;
  Error& error = s.error;
  DeformableActor* softActor = s.softActor;
  RigidActor *bodyA = s.bodyA, *bodyB = s.bodyB, *rigidActor = s.rigidActor;
  {
    // BEGIN "Pinning a Soft Body Node (DeformableNodePosition)"
    DeformableNodePositionConstraintParams params;
    params.actor = softActor->GetHandle();
    params.nodeIndex = 0; // pin the first node
    params.position = Real3{0_r, 1_r, 0_r}; // target world position
    params.stiffness = 1e6_r; // penalty stiffness
    Constraint* constraint = scene->CreateDeformableNodePositionConstraint(params, error);
    // END
    REQUIRE(constraint);
    REQUIRE(constraint->GetType() == ConstraintType::DeformableNodePosition);
  }
  {
    // BEGIN "Connecting Two Rigid Bodies (RigidSphericalJoint)"
    RigidSphericalJointConstraintParams params;
    params.actorA = bodyA->GetHandle();
    params.actorB = bodyB->GetHandle();
    params.localPosA = Real3{0.5_r, 0_r, 0_r}; // pivot on body A
    params.localPosB = Real3{-0.5_r, 0_r, 0_r}; // pivot on body B
    params.stiffness = 1e6_r;
    Constraint* constraint = scene->CreateRigidSphericalJointConstraint(params, error);
    // END
    REQUIRE(constraint);
    REQUIRE(constraint->GetType() == ConstraintType::RigidSphericalJoint);
  }
  {
    // BEGIN "Attaching a Deformable Actor to a Rigid Body (DeformableNodeToRigid)"
    DeformableNodeToRigidConstraintParams params;
    params.deformableActor = softActor->GetHandle();
    params.rigidActor = rigidActor->GetHandle();
    params.deformableNodeIndex = 10; // which deformable-actor node
    params.fixToDeformablePos = true; // use the node's current position
    params.stiffness = 1e4_r;
    Constraint* constraint = scene->CreateDeformableNodeToRigidConstraint(params, error);
    // END
    REQUIRE(constraint);
    REQUIRE(constraint->GetType() == ConstraintType::DeformableNodeToRigid);
    REQUIRE(ToReal3(constraint->GetDeviation()).norm() == 0);  // fixToDeformablePos
  }
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(scene->GetNumConstraints() == 3);
  // the constraints act: over 20 ms under gravity the jointed bodies fall
  // ~2 mm, the pinned node stays at (0, 1, 0) (its weight, ~1.6 N, over k =
  // 1e6 N/m: ~2e-6 m) and the joint holds its pivots together
  real const startY = bodyA->GetPosition().y();
  StepOk(*scene, 1e-3, 20);
  REQUIRE(bodyA->GetPosition().y() < startY - 1e-3);
  REQUIRE((softActor->GetNodePosition(0) - Real3(0, 1, 0)).norm() < 1e-4);
}

TEST_CASE("the original page: lifecycle and identity", "[scene][reference_page]") {
  PageSetUp s;
  auto& scene = s.scene;
  Constraint* constraint = MakeJoint(s);
  int visited = 0;
  // BEGIN "Lifecycle and Identity"
  ConstraintHandle handle = constraint->GetHandle();
  Constraint* same = scene->GetConstraint(handle); // look up by handle
  scene->ForEachConstraint([](Constraint* c) { /* ... */ }); // enumerate
  scene->DestroyConstraint(handle); // explicit removal
  // scene->DestroyActor(actorHandle) also removes every constraint on that actor
  // END
  scene->ForEachConstraint([&](Constraint* c) { visited += c != nullptr; });
  REQUIRE(same == constraint);
  REQUIRE(scene->GetConstraint(handle) == nullptr);
  REQUIRE(visited == 0);
}

TEST_CASE("the original page: introspection, parameters, targets, diagnostics", "[scene][reference_page]") {
  PageSetUp s;
  auto& scene = s.scene;
  Error& error = s.error;
  Constraint* constraint = MakeJoint(s);
  {
    // BEGIN "Introspection"
    ConstraintType type = constraint->GetType();
    int numActors = constraint->GetNumActors();
    for (int i = 0; i < numActors; ++i) {
    Actor* actor = constraint->GetActor(i);
    Span<int const> dofs = constraint->GetDofIndicesForActor(i); // affected DoFs
    }
    // END
    REQUIRE(type == ConstraintType::RigidSphericalJoint);
    REQUIRE(numActors == 2);
    REQUIRE(constraint->GetDofIndicesForActor(1).size() == 6);
  }
  // BEGIN "Parameters"
  constraint->SetStiffness(1e5_r, error);   // [N/m] (or [N*m/rad] for rotational constraints)
  constraint->SetDamping(20_r, error); // [N*s/m] (or [N*m*s/rad])
  constraint->SetSaturation(-1_r, error); // force cap = stiffness * saturation; negative disables
  // END
  REQUIRE_FALSE(error);
  REQUIRE(constraint->GetStiffness() == 1e5);
  REQUIRE(constraint->GetDamping() == 20);
  {
    RigidPivotPositionConstraintParams pin;
    pin.actor = s.bodyA->GetHandle();
    pin.position = s.bodyA->GetPosition();
    pin.stiffness = 1e6;
    Constraint* pivot = scene->CreateRigidPivotPositionConstraint(pin, error);
    REQUIRE(pivot);
    real const x = 0, y = 0.01, z = 0;
    // BEGIN "Kinematic Targets"
    pivot->SetTargetPosition(Real3{x, y, z}, error);  // RigidPivotPosition
    // SetTargetRotation / SetTargetDof apply to rotation- / DoF-target constraints
    // END
    REQUIRE_FALSE(error);
  }
  real const dt = 1e-3;
  // BEGIN "Diagnostics and Queries"
  constraint->RegisterQuery(QueryType::ConstraintForce, error);  // once, before Step
  scene->Step(dt, error);
  DynamicArray<real> deviation = constraint->GetDeviation(); // constraint value g
  Span<real const> force = constraint->GetForce(error); // needs the query above
  // END
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(deviation.size() == 3);
  REQUIRE(force.size() == 12);  // −Jᵀ(...) on both bodies' 6 DoFs
  REQUIRE(scene->GetTime() == dt);
}
