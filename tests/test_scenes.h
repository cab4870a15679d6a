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
  DynamicArray<Constraint*> constraints;  ///< the pin, then the joints in order
};

/// Principal moments of a box of mass m, `length` along x and `side` × `side`
/// across.
inline Real3 BoxInertia(real mass, real length, real side) {
  real const side2 = side * side, length2 = length * length;
  return mass / 12 * Real3(2 * side2, length2 + side2, length2 + side2);
}

inline Chain MakeChain(int numBodies, SceneParams const& params = {}, real stiffness = 1e6,
                       Real3 const& inertia = Real3(1e-4, 1e-3, 1e-3)) {
  real const length = 0.1;
  Chain chain;
  chain.scene = MakeScene(params);
  Error error;
  for (int i = 0; i < numBodies; ++i) {
    RigidActorParams body;
    body.mass = 1;
    body.inertia = inertia;
    body.position = Real3((i + 0.5) * length, 0, 0);
    chain.bodies.push_back(MakeRigid(*chain.scene, body));
  }
  RigidPivotPositionConstraintParams pin;
  pin.actor = chain.bodies[0]->GetHandle();
  pin.localPos = Real3(-length / 2, 0, 0);
  pin.position = Real3::Zero();
  pin.stiffness = stiffness;
  chain.constraints.push_back(chain.scene->CreateRigidPivotPositionConstraint(pin, error));
  REQUIRE(chain.constraints.back());
  for (int i = 0; i + 1 < numBodies; ++i) {
    RigidSphericalJointConstraintParams joint;
    joint.actorA = chain.bodies[i]->GetHandle();
    joint.actorB = chain.bodies[i + 1]->GetHandle();
    joint.localPosA = Real3(length / 2, 0, 0);
    joint.localPosB = Real3(-length / 2, 0, 0);
    joint.stiffness = stiffness;
    chain.constraints.push_back(chain.scene->CreateRigidSphericalJointConstraint(joint, error));
    REQUIRE(chain.constraints.back());
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

/// A straight rod of `numElements` elements from `start` along `direction`
/// (length `length`), with the section and material of `p` (nodes replaced).
inline RodActor* MakeStraightRod(Scene& scene, Real3 const& start, Real3 const& direction, real length,
                                 int numElements, RodActorParams p) {
  p.nodes.clear();
  for (int i = 0; i <= numElements; ++i)
    p.nodes.push_back(start + (length * i / numElements) * direction.normalized());
  Error error;
  RodActor* rod = scene.CreateRodActor(p, error);
  INFO(error.ToString());
  REQUIRE(rod);
  return rod;
}

/// The two constraints of a rod end clamped to a rigid body.
struct RodClamp {
  Constraint* position = nullptr;  ///< DeformableNodeToRigid on the end node
  Constraint* rotation = nullptr;  ///< RodElementRotationToRigid on the end element
};

/// Clamps the rod's first (`atEnd` false) or last end to `body` at their
/// current relative pose: DeformableNodeToRigid on the end node plus
/// RodElementRotationToRigid on the end element, stiffnesses `linear` [N/m]
/// and `angular` [N·m/rad]; both register the ConstraintForce query.
inline RodClamp ClampRodEnd(Scene& scene, RodActor& rod, RigidActor& body, bool atEnd, real linear,
                            real angular) {
  Error error;
  RodClamp clamp;
  DeformableNodeToRigidConstraintParams node;
  node.deformableActor = rod.GetHandle();
  node.rigidActor = body.GetHandle();
  node.deformableNodeIndex = atEnd ? rod.GetNumNodes() - 1 : 0;
  node.stiffness = linear;
  clamp.position = scene.CreateDeformableNodeToRigidConstraint(node, error);
  INFO(error.ToString());
  REQUIRE(clamp.position);
  RodElementRotationToRigidConstraintParams frame;
  frame.rigidActor = body.GetHandle();
  frame.rodActor = rod.GetHandle();
  frame.elementIndex = atEnd ? rod.GetNumElements() - 1 : 0;
  frame.stiffness = angular;
  clamp.rotation = scene.CreateRodElementRotationToRigidConstraint(frame, error);
  INFO(error.ToString());
  REQUIRE(clamp.rotation);
  REQUIRE(clamp.position->RegisterQuery(QueryType::ConstraintForce, error));
  REQUIRE(clamp.rotation->RegisterQuery(QueryType::ConstraintForce, error));
  return clamp;
}

/// A compound pendulum: one rigid body hanging from a RigidPivotPosition at
/// the world origin, the pivot `arm` above the centre of mass in the body
/// frame, the body turned by `angle` about z.
struct Pendulum {
  std::unique_ptr<Scene> scene;
  RigidActor* body = nullptr;
  Constraint* pin = nullptr;
};

inline Pendulum MakePendulum(SceneParams const& params, real mass, Real3 const& inertia, real arm,
                             real stiffness, real angle) {
  Pendulum p;
  p.scene = MakeScene(params);
  Quat const rotation(Eigen::AngleAxis<real>(angle, Real3::UnitZ()));
  Real3 const localPivot(0, arm, 0);
  RigidActorParams body;
  body.mass = mass;
  body.inertia = inertia;
  body.rotation = rotation;
  body.position = -(rotation * localPivot);
  p.body = MakeRigid(*p.scene, body);
  RigidPivotPositionConstraintParams pin;
  pin.actor = p.body->GetHandle();
  pin.localPos = localPivot;
  pin.position = Real3::Zero();
  pin.stiffness = stiffness;
  Error error;
  p.pin = p.scene->CreateRigidPivotPositionConstraint(pin, error);
  INFO(error.ToString());
  REQUIRE(p.pin);
  return p;
}

/// Two uniform rods of length `length` and mass `mass` hinged about z, the
/// first at the origin, end to end along +x (principal inertia 1e-4 about
/// the rod, m L²/12 across it).
inline ArticulatedActorParams TwoRevoluteLinks(real length, real mass) {
  ArticulatedActorParams p;
  for (int i = 0; i < 2; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = JointType::Revolute;
    link.axis = Real3::UnitZ();
    link.parentToJointPosition = i == 0 ? Real3::Zero() : Real3(length, 0, 0);
    link.mass = mass;
    link.inertia = Real3(1e-4, mass * length * length / 12, mass * length * length / 12);
    link.centerOfMass = Real3(length / 2, 0, 0);
    p.links.push_back(link);
  }
  return p;
}

/// A branched tree of eight links with every joint type (the root free or
/// revolute), generic axes, offsets, armature on link 2 and damping on
/// link 4 (docs/articulated.md's tree-against-dense checks).
inline ArticulatedActorParams BranchedTree(bool floating, ArticulatedBlockSolve solve) {
  ArticulatedActorParams p;
  p.blockSolve = solve;
  JointType const types[] = {JointType::Spherical, JointType::Revolute, JointType::Prismatic,
                             JointType::Fixed,     JointType::Revolute, JointType::Spherical};
  int const parents[] = {-1, 0, 1, 1, 3, 2, 5, 4};
  for (int i = 0; i < 8; ++i) {
    ArticulatedLinkParams link;
    link.parent = parents[i];
    link.joint = i == 0 ? (floating ? JointType::Free : JointType::Revolute) : types[(i - 1) % 6];
    link.axis = Real3(0.3 * i, 1, 0.5);
    link.parentToJointPosition = i == 0 ? Real3::Zero() : Real3(0.2, 0.05 * i, 0);
    link.jointToChildPosition = Real3(0.02, 0.03, -0.01);
    link.mass = 0.5 + 0.1 * i;
    link.inertia = Real3(2e-3, 3e-3, 4e-3);
    link.centerOfMass = Real3(0.1, 0, 0);
    link.armature = i == 2 ? 0.01 : 0;
    link.damping = i == 4 ? 0.05 : 0;
    p.links.push_back(link);
  }
  return p;
}

/// A chain of n spherical joints, 0.1 m apart along +x (light links).
inline ArticulatedActorParams SphericalChain(int n, ArticulatedBlockSolve solve = ArticulatedBlockSolve::Tree) {
  ArticulatedActorParams chain;
  chain.blockSolve = solve;
  for (int i = 0; i < n; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = JointType::Spherical;
    link.parentToJointPosition = i == 0 ? Real3::Zero() : Real3(0.1, 0, 0);
    link.inertia = Real3(1e-4, 1e-3, 1e-3);
    link.centerOfMass = Real3(0.05, 0, 0);
    chain.links.push_back(link);
  }
  return chain;
}

}  // namespace superdex::test
