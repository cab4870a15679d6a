// Scene builders shared by several suites.
#pragma once

#include "test_support.h"

#include <functional>

namespace superdex::test {

/// A chain of `numBodies` rods (0.1 m long boxes, 1 kg) along +x, joined end
/// to end by spherical joints, the first one pinned to the world at its left
/// end by a RigidPivotPosition.
struct Chain {
  std::unique_ptr<Scene> scene;
  DynamicArray<RigidActor*> bodies;
};

inline Chain MakeChain(int numBodies, SceneParams const& params = {}, real stiffness = 1e6) {
  real const length = 0.1;
  Chain chain;
  chain.scene = MakeScene(params);
  Error error;
  for (int i = 0; i < numBodies; ++i) {
    RigidActorParams body;
    body.mass = 1;
    body.inertia = Real3(1e-4, 1e-3, 1e-3);
    body.position = Real3((i + 0.5) * length, 0, 0);
    chain.bodies.push_back(MakeRigid(*chain.scene, body));
  }
  RigidPivotPositionConstraintParams pin;
  pin.actor = chain.bodies[0]->GetHandle();
  pin.localPos = Real3(-length / 2, 0, 0);
  pin.position = Real3::Zero();
  pin.stiffness = stiffness;
  REQUIRE(chain.scene->CreateRigidPivotPositionConstraint(pin, error));
  for (int i = 0; i + 1 < numBodies; ++i) {
    RigidSphericalJointConstraintParams joint;
    joint.actorA = chain.bodies[i]->GetHandle();
    joint.actorB = chain.bodies[i + 1]->GetHandle();
    joint.localPosA = Real3(length / 2, 0, 0);
    joint.localPosB = Real3(-length / 2, 0, 0);
    joint.stiffness = stiffness;
    REQUIRE(chain.scene->CreateRigidSphericalJointConstraint(joint, error));
  }
  return chain;
}

/// Holds `body` at its current pose with stiff RigidPivotToRigidTarget and
/// RigidPivotRotation constraints: a fixed body up to a compliance of
/// 1/stiffness.
inline void Anchor(Scene& scene, RigidActor& body, real stiffness = 1e9) {
  Error error;
  RigidPivotToRigidTargetConstraintParams position;
  position.actor = body.GetHandle();
  position.position = body.GetPosition();
  position.rotation = body.GetRotation();
  position.stiffness = stiffness;
  REQUIRE(scene.CreateRigidPivotToRigidTargetConstraint(position, error));
  RigidPivotRotationConstraintParams rotation;
  rotation.actor = body.GetHandle();
  rotation.rotation = body.GetRotation();
  rotation.stiffness = stiffness;
  REQUIRE(scene.CreateRigidPivotRotationConstraint(rotation, error));
}

/// A tetrahedral box (MakeTetBox) of `cells` as a deformable actor with the
/// material of `p`.
inline DeformableActor* MakeBox(Scene& scene, Real3 const& origin, Real3 const& size, std::array<int, 3> cells,
                         DeformableActorParams p) {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(origin, size, cells, mesh, error));
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  DeformableActor* actor = scene.CreateDeformableActor(p, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}

// pins every node with `select(X)` true to its current position; returns the pins
inline DynamicArray<Constraint*> PinNodes(Scene& scene, DeformableActor& actor, real stiffness,
                                   std::function<bool(Real3 const&)> const& select,
                                   std::function<Real3(Real3 const&)> const& target = {}) {
  DynamicArray<Constraint*> pins;
  Error error;
  for (int i = 0; i < actor.GetNumNodes(); ++i) {
    Real3 const x = actor.GetNodeReferencePosition(i);
    if (!select(x)) continue;
    DeformableNodePositionConstraintParams p;
    p.actor = actor.GetHandle();
    p.nodeIndex = i;
    p.position = target ? target(x) : actor.GetNodePosition(i);
    p.stiffness = stiffness;
    Constraint* c = scene.CreateDeformableNodePositionConstraint(p, error);
    REQUIRE(c);
    REQUIRE(c->RegisterQuery(QueryType::ConstraintForce, error));
    pins.push_back(c);
  }
  return pins;
}

}  // namespace superdex::test
