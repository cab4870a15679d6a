// The reference page's three code examples, verbatim, with only the actor
// set-up added around them; they must compile, run and create constraints
// that step.
#include "test_support.h"

using namespace superdex;
using namespace superdex::test;

TEST_CASE("the reference page's code examples compile and run as written", "[constraints][reference]") {
  Error error;
  std::unique_ptr<Scene> sceneOwner = MakeScene();
  Scene* scene = sceneOwner.get();
  // actor set-up: a soft body with at least 11 nodes, two rigid bodies, a rigid handle
  TetMesh mesh;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.3, 0.1, 0.1), {3, 1, 1}, mesh, error));
  DeformableActorParams softParams;
  softParams.nodes = mesh.nodes;
  softParams.tetrahedra = mesh.tetrahedra;
  DeformableActor* softActor = scene->CreateDeformableActor(softParams, error);
  REQUIRE(softActor);
  REQUIRE(softActor->GetNumNodes() > 10);
  RigidActorParams rigidParams;
  rigidParams.position = Real3(-0.5, 0, 0);
  RigidActor* bodyA = scene->CreateRigidActor(rigidParams, error);
  rigidParams.position = Real3(0.5, 0, 0);
  RigidActor* bodyB = scene->CreateRigidActor(rigidParams, error);
  rigidParams.position = Real3(0.3, 0.2, 0.1);
  RigidActor* rigidActor = scene->CreateRigidActor(rigidParams, error);
  REQUIRE((bodyA && bodyB && rigidActor));

  // ---- the reference page, as written ----
  // Pin a soft-body node (DeformableNodePosition)
  DeformableNodePositionConstraintParams params;
  params.actor = softActor->GetHandle();
  params.nodeIndex = 0;
  params.position = Real3{0_r, 1_r, 0_r};
  params.stiffness = 1e6_r;
  Constraint* c = scene->CreateDeformableNodePositionConstraint(params, error);

  // Ball-and-socket between two rigid bodies (RigidSphericalJoint)
  RigidSphericalJointConstraintParams p;
  p.actorA = bodyA->GetHandle();  p.actorB = bodyB->GetHandle();
  p.localPosA = Real3{0.5_r, 0_r, 0_r};  p.localPosB = Real3{-0.5_r, 0_r, 0_r};
  p.stiffness = 1e6_r;
  Constraint* j = scene->CreateRigidSphericalJointConstraint(p, error);

  // Attach a deformable node to a rigid handle (DeformableNodeToRigid)
  DeformableNodeToRigidConstraintParams a;
  a.deformableActor = softActor->GetHandle();  a.rigidActor = rigidActor->GetHandle();
  a.deformableNodeIndex = 10;  a.fixToDeformablePos = true;  a.stiffness = 1e4_r;
  Constraint* att = scene->CreateDeformableNodeToRigidConstraint(a, error);
  // ---- end of the reference page's code ----

  INFO(error.ToString());
  REQUIRE(c);
  REQUIRE(j);
  REQUIRE(att);
  REQUIRE(c->GetType() == ConstraintType::DeformableNodePosition);
  REQUIRE(j->GetType() == ConstraintType::RigidSphericalJoint);
  REQUIRE(att->GetType() == ConstraintType::DeformableNodeToRigid);
  REQUIRE(ToReal3(att->GetDeviation()).norm() == 0);  // fixToDeformablePos
  real const before = (softActor->GetNodePosition(0) - Real3(0, 1, 0)).norm();
  StepOk(*scene, 1e-3, 20);
  // the pinned node is pulled toward (0, 1, 0)
  REQUIRE((softActor->GetNodePosition(0) - Real3(0, 1, 0)).norm() < 0.9 * before);
}
