// Scene builders shared by several suites.
#pragma once

#include "test_support.h"

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

}  // namespace superdex::test
