// Articulated links as the rigid body of every rigid constraint type
// (constraints/constraint.h, "Layout"; docs/articulated.md, "Links in
// constraints"): the Jacobian and the curvature over the joint DoFs of the
// link's path against central differences over those DoFs, the DoF lists the
// constraints report, a pendulum on an articulated link against the same body
// built as a RigidActor, bad link arguments, and the constraints' destruction
// with their actor.
#include "constraint_test_util.h"
#include "test_scenes.h"

using namespace superdex;
using namespace superdex::test;

namespace {

/// A floating tree of every joint type with generic offsets and a generic
/// initial configuration: 0 free root; 1 revolute on 0; 2 prismatic on 1;
/// 3 spherical on 2; 4 revolute on 0 (a branch off the path of 3).
ArticulatedActorParams LinkTree() {
  ArticulatedActorParams p;
  auto add = [&](int parent, JointType joint, Real3 const& axis, Real3 const& toJoint, Real3 const& toChild,
                 DynamicArray<real> const& q) {
    ArticulatedLinkParams link;
    link.parent = parent;
    link.joint = joint;
    link.axis = axis.normalized();
    link.parentToJointPosition = toJoint;
    link.parentToJointRotation = QuatOfRotationVector(Real3(0.2, -0.1, 0.3) * (1 + parent));
    link.jointToChildPosition = toChild;
    link.jointToChildRotation = QuatOfRotationVector(Real3(-0.3, 0.25, 0.1));
    link.mass = 1.2;
    link.inertia = Real3(0.1, 0.2, 0.15);
    link.centerOfMass = Real3(0.05, -0.02, 0.1);
    link.initialPosition = q;
    p.links.push_back(link);
  };
  add(-1, JointType::Free, Real3::UnitZ(), Real3(0.1, 0.2, -0.1), Real3(0.05, 0, 0.1), {0.3, -0.2, 0.5, 0.4, 0.7, -0.2});
  add(0, JointType::Revolute, Real3(0.3, 0.5, 0.8), Real3(0.4, 0.1, 0), Real3(0.3, -0.1, 0.2), {0.6});
  add(1, JointType::Prismatic, Real3(0, 0.6, 0.8), Real3(0.2, 0.3, -0.1), Real3(0.1, 0.2, 0), {0.25});
  add(2, JointType::Spherical, Real3::UnitZ(), Real3(0, 0.2, 0.3), Real3(0.1, 0.1, 0.1), {0.3, -0.6, 0.4});
  add(0, JointType::Revolute, Real3::UnitX(), Real3(-0.3, 0, 0.2), Real3(0.2, 0.1, -0.3), {-0.4});
  return p;
}

struct LinkScene {
  std::unique_ptr<Scene> scene;
  ArticulatedActor* tree = nullptr;
  RigidActor* rigid = nullptr;
  DeformableActor* soft = nullptr;
  RodActor* rod = nullptr;
};

LinkScene MakeLinkScene() {
  SceneParams params;
  params.gravity = Real3::Zero();
  LinkScene s;
  s.scene = MakeScene(params);
  Error error;
  s.tree = s.scene->CreateArticulatedActor(LinkTree(), error);
  INFO(error.ToString());
  REQUIRE(s.tree);
  RigidActorParams body;
  body.mass = 1.5;
  body.inertia = Real3(0.2, 0.3, 0.4);
  Pose const pose = RandomPose(0.9, 11);
  body.position = pose.position;
  body.rotation = pose.rotation;
  s.rigid = MakeRigid(*s.scene, body);
  s.soft = MakeBox(*s.scene, Real3(0.5, -0.4, 0.2), Real3(0.2, 0.2, 0.2), {1, 1, 1}, DeformableActorParams{});
  s.rod = MakeStraightRod(*s.scene, Real3(-0.5, 0.3, 0.1), Real3(0.3, 1, -0.2), 0.6, 3, RodActorParams{});
  return s;
}

enum class Kind {
  PivotPosition,
  PivotToRigidTarget,
  PivotRotation,
  SphericalJoint,
  PrismaticJoint,
  RotationRange,
  RotationTracking,
  NodeToRigid,
  RodRotationToRigid,
};

char const* ToString(Kind kind) {
  constexpr char const* kNames[] = {"RigidPivotPosition", "RigidPivotToRigidTarget", "RigidPivotRotation",
                                    "RigidSphericalJoint", "RigidPrismaticJoint", "JointRotationRange",
                                    "JointRotationTracking", "DeformableNodeToRigid", "RodElementRotationToRigid"};
  return kNames[static_cast<int>(kind)];
}

bool IsPair(Kind kind) { return kind >= Kind::SphericalJoint && kind <= Kind::RotationTracking; }
/// g depends on the bodies' rotations only
bool IsRotational(Kind kind) {
  return kind == Kind::PivotRotation || kind == Kind::RotationRange || kind == Kind::RotationTracking ||
         kind == Kind::RodRotationToRigid;
}

/// A pair type between body A (actor `a`, link `linkA`, −1 for a rigid
/// actor) and body B, generic pivots, frames and targets; range components
/// all outside their bounds.
Constraint* MakePair(Scene& scene, Kind kind, ActorHandle a, int linkA, ActorHandle b, int linkB, Error& error) {
  Quat const frame = QuatOfRotationVector(Real3(0.3, -0.5, 0.8));
  switch (kind) {
    case Kind::SphericalJoint: {
      RigidSphericalJointConstraintParams p;
      p.actorA = a;
      p.actorB = b;
      p.linkA = linkA;
      p.linkB = linkB;
      p.localPosA = kPivotA;
      p.localPosB = kPivotB;
      p.stiffness = 1e3;
      return scene.CreateRigidSphericalJointConstraint(p, error);
    }
    case Kind::PrismaticJoint: {
      RigidPrismaticJointConstraintParams p;
      p.actorA = a;
      p.actorB = b;
      p.linkA = linkA;
      p.linkB = linkB;
      p.jointFrame = frame;
      p.offsetAroundRest = false;
      p.referenceOffset = Real3(0.1, -0.2, 0.3);
      p.lowerLimit = p.upperLimit = 5;  // the travel is below: its row is active
      p.stiffness = 1e3;
      return scene.CreateRigidPrismaticJointConstraint(p, error);
    }
    case Kind::RotationRange: {
      JointRotationRangeConstraintParams p;
      p.actorA = a;
      p.actorB = b;
      p.linkA = linkA;
      p.linkB = linkB;
      p.jointFrame = frame;
      p.rangeAroundRest = false;
      p.referenceRotation = QuatOfRotationVector(Real3(0.4, -0.3, 0.5));
      p.lowerLimits = p.upperLimits = Real3::Constant(5);  // every component below: all active
      p.stiffness = 1e3;
      return scene.CreateJointRotationRangeConstraint(p, error);
    }
    case Kind::RotationTracking: {
      JointRotationTrackingConstraintParams p;
      p.actorA = a;
      p.actorB = b;
      p.linkA = linkA;
      p.linkB = linkB;
      p.jointFrame = frame;
      p.stiffness = 1e3;
      Constraint* c = scene.CreateJointRotationTrackingConstraint(p, error);
      if (c) REQUIRE(c->SetTargetRotation(QuatOfRotationVector(Real3(0.4, -0.3, 0.5)), error));
      return c;
    }
    default: return nullptr;
  }
}

/// A constraint of `kind` with `body` (an articulated actor's link `link`,
/// or a rigid actor with link −1) as its rigid body (as body B of a pair type
/// where `linkIsB`, the other body s.rigid), generic pivots, frames and
/// targets; range components all outside their bounds.
Constraint* MakeOnBody(LinkScene& s, Kind kind, ActorHandle body, int link, bool linkIsB, Error& error) {
  ActorHandle const tree = body, rigid = s.rigid->GetHandle();
  ActorHandle const a = linkIsB ? rigid : tree, b = linkIsB ? tree : rigid;
  int const linkA = linkIsB ? -1 : link, linkB = linkIsB ? link : -1;
  Quat const frame = QuatOfRotationVector(Real3(0.3, -0.5, 0.8));
  Scene& scene = *s.scene;
  switch (kind) {
    case Kind::PivotPosition: {
      RigidPivotPositionConstraintParams p;
      p.actor = tree;
      p.link = link;
      p.localPos = kPivotA;
      p.position = kTargetPosition;
      p.stiffness = 1e3;
      return scene.CreateRigidPivotPositionConstraint(p, error);
    }
    case Kind::PivotToRigidTarget: {
      RigidPivotToRigidTargetConstraintParams p;
      p.actor = tree;
      p.link = link;
      p.localPos = kPivotA;
      p.position = kTargetPosition;
      p.rotation = QuatOfRotationVector(Real3(1.1, 0.4, -0.7));
      p.stiffness = 1e3;
      return scene.CreateRigidPivotToRigidTargetConstraint(p, error);
    }
    case Kind::PivotRotation: {
      RigidPivotRotationConstraintParams p;
      p.actor = tree;
      p.link = link;
      p.localRotation = QuatOfRotationVector(Real3(-0.6, 0.2, 0.35));
      p.rotation = QuatOfRotationVector(Real3(0.4, -0.3, 0.5));
      p.stiffness = 1e3;
      return scene.CreateRigidPivotRotationConstraint(p, error);
    }
    case Kind::SphericalJoint:
    case Kind::PrismaticJoint:
    case Kind::RotationRange:
    case Kind::RotationTracking: return MakePair(scene, kind, a, linkA, b, linkB, error);
    case Kind::NodeToRigid: {
      DeformableNodeToRigidConstraintParams p;
      p.deformableActor = s.soft->GetHandle();
      p.deformableNodeIndex = 3;
      p.rigidActor = tree;
      p.rigidLink = link;
      p.fixToDeformablePos = false;
      p.localPos = kPivotB;
      p.stiffness = 1e3;
      return scene.CreateDeformableNodeToRigidConstraint(p, error);
    }
    case Kind::RodRotationToRigid: {
      RodElementRotationToRigidConstraintParams p;
      p.rigidActor = tree;
      p.rigidLink = link;
      p.rodActor = s.rod->GetHandle();
      p.elementIndex = 1;
      p.jointFrame = frame;
      p.stiffness = 1e3;
      Constraint* c = scene.CreateRodElementRotationToRigidConstraint(p, error);
      if (c) REQUIRE(c->SetTargetRotation(QuatOfRotationVector(Real3(0.4, -0.3, 0.5)), error));
      return c;
    }
  }
  return nullptr;
}

Constraint* MakeOnLink(LinkScene& s, Kind kind, int link, bool linkIsB, Error& error) {
  return MakeOnBody(s, kind, s.tree->GetHandle(), link, linkIsB, error);
}

int LinkSlot(Kind kind, bool linkIsB) { return kind == Kind::NodeToRigid || linkIsB ? 1 : 0; }

}  // namespace

TEST_CASE("every rigid constraint type on an articulated link: g, J and the curvature over the path's joint DoFs "
          "match central differences",
          "[constraints][derivatives][articulated]") {
  Kind const kind = static_cast<Kind>(GENERATE(range(0, 9)));
  // the link as body B only for the pair types
  bool const linkIsB = GENERATE_COPY(from_range(IsPair(kind) ? std::vector<int>{0, 1} : std::vector<int>{0})) != 0;
  int const link = GENERATE(3, 4);
  CAPTURE(ToString(kind), linkIsB, link);
  LinkScene s = MakeLinkScene();
  Error error;
  Constraint* c = MakeOnLink(s, kind, link, linkIsB, error);
  INFO(error.ToString());
  REQUIRE(c);

  // the constraint's DoFs on the tree: the joints from the root to the link
  // (3: free 0..5, revolute 6, prismatic 7, spherical 8..10; 4: free 0..5
  // and its own revolute joint 11)
  int const slot = LinkSlot(kind, linkIsB);
  REQUIRE(c->GetActor(slot) == s.tree);
  DynamicArray<int> expected;
  DynamicArray<int> const local = link == 3 ? DynamicArray<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}
                                            : DynamicArray<int>{0, 1, 2, 3, 4, 5, 11};
  for (int d : local) expected.push_back(s.tree->GetDofOffset() + d);
  Span<int const> const reported = c->GetDofIndicesForActor(slot);
  REQUIRE(DynamicArray<int>(reported.begin(), reported.end()) == expected);

  // columns of DoFs that do not turn the link vanish for rotational types
  internal::LinkPath const path = s.tree->GetLinkPath(link);
  DynamicArray<int> zeroColumns;
  int const offset = slot == 0 ? 0 : static_cast<int>(c->GetDofIndicesForActor(0).size());
  if (IsRotational(kind))
    for (std::size_t i = 0; i < path.dofRotates.size(); ++i)
      if (!path.dofRotates[i]) zeroColumns.push_back(offset + static_cast<int>(i));
  // the element's frame does not depend on the next node's twist (rod DoF 7)
  if (kind == Kind::RodRotationToRigid) zeroColumns.push_back(static_cast<int>(path.dofs.size()) + 7);
  CheckJacobian(*s.scene, *c, zeroColumns);
  CheckCurvature(*c, true);
}

TEST_CASE("a pair type between two links of one tree (a kinematic loop): its DoFs are the union of the two paths, "
          "J and the curvature match central differences",
          "[constraints][derivatives][articulated]") {
  // links 3 and 4 share the free root's six DoFs: each appears once, its
  // column the sum of the two links' (translations of the root move both
  // bodies alike and leave relative measures unchanged: zero columns)
  Kind const kind = static_cast<Kind>(GENERATE(range(static_cast<int>(Kind::SphericalJoint),
                                                     static_cast<int>(Kind::RotationTracking) + 1)));
  bool const swapped = GENERATE(false, true);
  CAPTURE(ToString(kind), swapped);
  LinkScene s = MakeLinkScene();
  Error error;
  int const linkA = swapped ? 4 : 3, linkB = swapped ? 3 : 4;
  ActorHandle const tree = s.tree->GetHandle();
  Constraint* c = MakePair(*s.scene, kind, tree, linkA, tree, linkB, error);
  INFO(error.ToString());
  REQUIRE(c);
  // the DoF list: link A's path, then link B's own joints (3: 0..10; 4: 0..5, 11)
  DynamicArray<int> const pathA = linkA == 3 ? DynamicArray<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}
                                             : DynamicArray<int>{0, 1, 2, 3, 4, 5, 11};
  DynamicArray<int> const pathB = linkB == 3 ? DynamicArray<int>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}
                                             : DynamicArray<int>{0, 1, 2, 3, 4, 5, 11};
  DynamicArray<int> expected;
  for (int d : pathA) expected.push_back(s.tree->GetDofOffset() + d);
  for (int d : pathB)
    if (std::find(pathA.begin(), pathA.end(), d) == pathA.end()) expected.push_back(s.tree->GetDofOffset() + d);
  REQUIRE(ConstraintTestAccess::Dofs(*c) == expected);
  Span<int const> const reportedB = c->GetDofIndicesForActor(1);
  REQUIRE(static_cast<int>(reportedB.size()) == static_cast<int>(pathB.size()));
  REQUIRE(c->GetNumDofs() == 12);
  // relative measures: the root's translation (columns 0..2) moves both
  // frames alike; measures in frame A (the prismatic joint's) and relative
  // rotations also ignore the root's rotation (3..5: R_Aᵀ R_B and R_Aᵀ
  // (t_B − t_A) unchanged), which turns the spherical joint's world
  // separation; rotational types ignore the prismatic joint too (it moves
  // only link 3's position)
  DynamicArray<int> zeroColumns = {0, 1, 2};
  if (kind != Kind::SphericalJoint) zeroColumns.insert(zeroColumns.end(), {3, 4, 5});
  if (IsRotational(kind)) {
    int const prismatic = static_cast<int>(std::find(expected.begin(), expected.end(), s.tree->GetDofOffset() + 7) -
                                           expected.begin());
    zeroColumns.push_back(prismatic);
  }
  CheckJacobian(*s.scene, *c, zeroColumns);
  CheckCurvature(*c, true);
}

TEST_CASE("a constraint on a link sees the link frame: its g equals the same constraint's on a rigid body at that "
          "frame",
          "[constraints][articulated]") {
  Kind const kind = static_cast<Kind>(GENERATE(range(0, 9)));
  // the link as body B only for the pair types
  bool const linkIsB = GENERATE_COPY(from_range(IsPair(kind) ? std::vector<int>{0, 1} : std::vector<int>{0})) != 0;
  CAPTURE(ToString(kind), linkIsB);
  LinkScene s = MakeLinkScene();
  // a rigid body at the frame of link 3 (GetLinkPosition/GetLinkRotation:
  // the link frame, not the centre of mass)
  RigidActorParams body;
  body.position = s.tree->GetLinkPosition(3);
  body.rotation = s.tree->GetLinkRotation(3);
  RigidActor* copy = MakeRigid(*s.scene, body);
  Error error;
  Constraint* onLink = MakeOnLink(s, kind, 3, linkIsB, error);
  INFO(error.ToString());
  REQUIRE(onLink);
  Constraint* onCopy = MakeOnBody(s, kind, copy->GetHandle(), -1, linkIsB, error);
  REQUIRE(onCopy);
  VectorX const g = Deviation(*onLink), reference = Deviation(*onCopy);
  CAPTURE(g.transpose(), reference.transpose());
  REQUIRE(g.norm() > 0.05);
  // the same few operations on a pose from two kinematic routes (the actor's
  // quaternion products, the copy's stored pose): round-off only
  REQUIRE((g - reference).cwiseAbs().maxCoeff() <= 1e-12);
}

TEST_CASE("a link argument that names no rigid body is refused with an error naming the field", "[constraints][articulated]") {
  LinkScene s = MakeLinkScene();
  Error error;
  RigidPivotPositionConstraintParams pin;
  pin.stiffness = 1;
  auto refused = [&](auto const& params, ErrorCode code, std::string const& mention) {
    Error e;
    int const before = s.scene->GetNumConstraints();
    REQUIRE(s.scene->CreateRigidPivotPositionConstraint(params, e) == nullptr);
    int const after = s.scene->GetNumConstraints();
    CAPTURE(e.ToString());
    REQUIRE(e.GetCode() == code);
    REQUIRE(Mentions(e, mention));
    REQUIRE(before == after);
  };
  // an articulated actor needs a link in range
  pin.actor = s.tree->GetHandle();
  for (int link : {-1, 5, 1 << 30}) {
    pin.link = link;
    refused(pin, ErrorCode::InvalidArgument, "RigidPivotPositionConstraintParams.link must be a link");
  }
  // a rigid actor takes no link
  pin.actor = s.rigid->GetHandle();
  pin.link = 0;
  refused(pin, ErrorCode::InvalidArgument, "RigidPivotPositionConstraintParams.link must be -1");
  // neither a deformable nor a rod actor is a rigid body
  pin.link = -1;
  pin.actor = s.soft->GetHandle();
  refused(pin, ErrorCode::InvalidHandle, "expected a Rigid actor or an Articulated actor's link");
  // one link twice is refused for a pair type (two links of one tree close
  // a loop: "... kinematic loop" above)
  RigidSphericalJointConstraintParams joint;
  joint.actorA = joint.actorB = s.tree->GetHandle();
  joint.linkA = joint.linkB = 3;
  REQUIRE(s.scene->CreateRigidSphericalJointConstraint(joint, error) == nullptr);
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "RigidSphericalJointConstraintParams.linkB must differ from linkA"));
  joint.linkB = 4;
  // the field names of the other types
  DeformableNodeToRigidConstraintParams node;
  node.deformableActor = s.soft->GetHandle();
  node.rigidActor = s.tree->GetHandle();
  node.rigidLink = 9;
  REQUIRE(s.scene->CreateDeformableNodeToRigidConstraint(node, error) == nullptr);
  REQUIRE(Mentions(error, "DeformableNodeToRigidConstraintParams.rigidLink must be a link of the Articulated actor"));
  joint.actorB = s.rigid->GetHandle();
  joint.linkB = 2;
  REQUIRE(s.scene->CreateRigidSphericalJointConstraint(joint, error) == nullptr);
  REQUIRE(Mentions(error, "RigidSphericalJointConstraintParams.linkB must be -1"));
}
