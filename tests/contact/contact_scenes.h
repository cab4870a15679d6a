// The contact scenes of docs/contact.md's table, built for the tests
// (contact_scene_test checks their physics at one time step,
// contact_sweep_test every scene at dt = 1/30, 1/60 and 1/120).
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <superdex/superdex.h>

#include "test_support.h"

namespace superdex::test {

constexpr real kGravity = 9.81;

inline Collider* MakeCollider(Scene& scene, ColliderParams const& params) {
  Error error;
  Collider* collider = scene.CreateCollider(params, error);
  INFO(error.ToString());
  REQUIRE(collider);
  return collider;
}

inline Collider* MakeGround(Scene& scene, real friction = 0.5) {
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  ground.friction = friction;
  return MakeCollider(scene, ground);
}

/// A rigid box of `half` extents and `mass` with its Box collider.
inline RigidActor* MakeRigidBox(Scene& scene, Real3 const& position, Quat const& rotation, Real3 const& half,
                                real mass, real friction = 0.5) {
  RigidActorParams body;
  body.mass = mass;
  Real3 const e = 2 * half;
  body.inertia = mass / 12 * Real3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(),
                                   e.x() * e.x() + e.y() * e.y());
  body.position = position;
  body.rotation = rotation;
  RigidActor* box = MakeRigid(scene, body);
  ColliderParams shape;
  shape.actor = box->GetHandle();
  shape.shape = ShapeType::Box;
  shape.halfExtents = half;
  shape.friction = friction;
  MakeCollider(scene, shape);
  return box;
}

/// The Surface collider of a deformable or rod actor.
inline Collider* MakeSurface(Scene& scene, Actor const& actor, bool selfContact = true) {
  ColliderParams surface;
  surface.actor = actor.GetHandle();
  if (!selfContact) {
    // its own group out of its mask: no pairs within the surface
    surface.group = 2;
    surface.mask = ~2u;
  }
  return MakeCollider(scene, surface);
}

/// A tetrahedral ball: the tets of a grid box whose centroids are within
/// `radius` of the centre, nodes renumbered.
inline DeformableActorParams TetBall(Real3 const& center, real radius, int cells) {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(center - Real3::Constant(radius), Real3::Constant(2 * radius), {cells, cells, cells}, mesh,
                     error));
  DeformableActorParams p;
  std::map<int, int> renumber;
  for (auto const& t : mesh.tetrahedra) {
    Real3 const centroid = 0.25 * (mesh.nodes[t[0]] + mesh.nodes[t[1]] + mesh.nodes[t[2]] + mesh.nodes[t[3]]);
    if ((centroid - center).norm() > radius) continue;
    std::array<int, 4> tet{};
    for (int k = 0; k < 4; ++k) {
      auto [it, inserted] = renumber.try_emplace(t[k], static_cast<int>(p.nodes.size()));
      if (inserted) p.nodes.push_back(mesh.nodes[t[k]]);
      tet[k] = it->second;
    }
    p.tetrahedra.push_back(tet);
  }
  return p;
}

inline DeformableActor* MakeDeformable(Scene& scene, DeformableActorParams const& params) {
  Error error;
  DeformableActor* actor = scene.CreateDeformableActor(params, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}

/// A contact scene and how long it runs [s].
struct ContactScene {
  std::unique_ptr<Scene> scene;
  real seconds = 1;
  /// Called before each step with the time at its start [s] (targets that
  /// drive the scene); none: nothing to drive.
  std::function<void(real)> drive;
};

/// 1. A 0.2 m rigid box at rest on a plane incline of slope tan θ, μ = 0.5
/// (it sticks at tan θ = 0.49).
inline ContactScene InclineScene(SceneParams params, real tanTheta = 0.49) {
  params.gravity = Real3(0, -kGravity, 0);
  ContactScene out{MakeScene(params), 2, {}};
  Quat const tilt(Eigen::AngleAxis<real>(std::atan(tanTheta), Real3::UnitZ()));
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = tilt * Real3::UnitY();
  MakeCollider(*out.scene, plane);
  MakeRigidBox(*out.scene, plane.normal * (0.1 + 0.5 * params.contact.activationDistance), tilt,
               Real3::Constant(0.1), 1);
  return out;
}

/// 2. A solid sphere (r = 0.1 m) rolling from rest down a 15° incline.
inline ContactScene RollingScene(SceneParams params) {
  ContactScene out{MakeScene(params), 1, {}};
  Quat const tilt(Eigen::AngleAxis<real>(15 * M_PI / 180, Real3::UnitZ()));
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = tilt * Real3::UnitY();
  MakeCollider(*out.scene, plane);
  RigidActorParams body;
  body.inertia = Real3::Constant(0.4 * 0.1 * 0.1);
  body.position = plane.normal * (0.1 + 0.9 * params.contact.activationDistance);
  RigidActor* sphere = MakeRigid(*out.scene, body);
  ColliderParams shape;
  shape.actor = sphere->GetHandle();
  shape.shape = ShapeType::Sphere;
  shape.radius = 0.1;
  MakeCollider(*out.scene, shape);
  return out;
}

/// 3. An undamped Neo-Hookean tet ball (r = 0.1 m, E = 1e5 Pa, 1000 kg/m³)
/// dropped from `drop` m onto the ground; without self contact (a solid
/// ball does not fold onto itself).
inline ContactScene BallDropScene(SceneParams params, real drop = 1, int cells = 6) {
  ContactScene out{MakeScene(params), 1, {}};
  MakeGround(*out.scene);
  DeformableActorParams ball = TetBall(Real3(0, drop + 0.1, 0), 0.1, cells);
  ball.material = TetMaterialModel::StableNeoHookean;
  ball.youngModulus = 1e5;
  ball.density = 1000;
  MakeSurface(*out.scene, *MakeDeformable(*out.scene, ball), false);
  return out;
}

/// 4a. A stack of `count` 0.2 m rigid boxes (1 kg), each started 0.9 d̂
/// above the one below (near where the barrier carries them: started at
/// 0.5 d̂ the barrier's stored energy launches them, docs/contact.md).
inline ContactScene BoxStackScene(SceneParams params, int count = 5) {
  ContactScene out{MakeScene(params), 2, {}};
  MakeGround(*out.scene);
  real const half = 0.1, gap = 0.9 * params.contact.activationDistance;
  for (int i = 0; i < count; ++i)
    MakeRigidBox(*out.scene, Real3(0, gap + half + i * (2 * half + gap), 0), Quat::Identity(),
                 Real3::Constant(half), 1);
  return out;
}

/// 4b. A stack of `count` tet cubes (0.1 m, 2×2×2 cells of 6 tets, E = 1e6 Pa,
/// 1000 kg/m³), each started 0.9 d̂ above the one below.
inline ContactScene CubeStackScene(SceneParams params, int count = 5) {
  ContactScene out{MakeScene(params), 2, {}};
  MakeGround(*out.scene);
  real const side = 0.1, gap = 0.9 * params.contact.activationDistance;
  for (int i = 0; i < count; ++i) {
    TetMesh mesh;
    Error error;
    REQUIRE(MakeTetBox(Real3(-0.5 * side, gap + i * (side + gap), -0.5 * side), Real3::Constant(side), {2, 2, 2},
                       mesh, error));
    DeformableActorParams cube;
    cube.nodes = mesh.nodes;
    cube.tetrahedra = mesh.tetrahedra;
    cube.material = TetMaterialModel::StableNeoHookean;
    cube.youngModulus = 1e6;
    cube.density = 1000;
    MakeSurface(*out.scene, *MakeDeformable(*out.scene, cube), false);
  }
  return out;
}

/// A square cloth of n × n nodes, `size` m wide, in the x–z plane at height
/// y centred on the y axis, turned by `rotation` about its centre: the perf
/// harness's cloth (hinge bending, E = 1e6 Pa, ν = 0.3, h = 1 mm,
/// 300 kg/m³), with its self contact; its membrane the tension field (a
/// cloth pressed into folds wrinkles; with StVK the compressed membrane's
/// saddles cost Newton far more iterations, docs/contact.md "Measured").
inline DeformableActor* MakeCloth(Scene& scene, int n, real size, real y, Quat const& rotation,
                                  MembraneModel membrane = MembraneModel::TensionField) {
  TriangleMesh mesh;
  Error error;
  REQUIRE(MakeTriangleGrid(Real3(-0.5 * size, 0, -0.5 * size), size, size, n - 1, n - 1, mesh, error));
  DeformableActorParams cloth;
  for (Real3 const& p : mesh.nodes) cloth.nodes.push_back(Real3(0, y, 0) + rotation * p);
  cloth.triangles = mesh.triangles;
  cloth.youngModulus = 1e6;
  cloth.poissonRatio = 0.3;
  cloth.thickness = 1e-3;
  cloth.density = 300;
  cloth.membrane = membrane;
  DeformableActor* actor = MakeDeformable(scene, cloth);
  MakeSurface(scene, *actor);
  return actor;
}

/// 5a. A 32 × 32 cloth (0.6 m) dropped from 5 cm above a static sphere
/// (r = 0.2 m) resting on the ground: it drapes over it.
inline ContactScene ClothOnSphereScene(SceneParams params, int n = 32) {
  ContactScene out{MakeScene(params), 1.5, {}};
  MakeGround(*out.scene);
  ColliderParams sphere;
  sphere.shape = ShapeType::Sphere;
  sphere.position = Real3(0, 0.2, 0);
  sphere.radius = 0.2;
  MakeCollider(*out.scene, sphere);
  MakeCloth(*out.scene, n, 0.6, 0.45, Quat::Identity());
  return out;
}

/// 5b. A cloth (n × n, 0.4 m) falling edge-first, tilted 80° from the
/// ground: it lands, buckles and folds onto itself.
inline ContactScene ClothFoldScene(SceneParams params, int n = 24) {
  ContactScene out{MakeScene(params), 1.5, {}};
  MakeGround(*out.scene);
  Quat const tilt(Eigen::AngleAxis<real>(80 * M_PI / 180, Real3::UnitX()));
  MakeCloth(*out.scene, n, 0.4, 0.21, tilt);
  return out;
}

/// 6. A rod of `n` nodes (r = 4 mm, E = 1e7 Pa) in a helix of radius 5 cm and
/// pitch 2 cm, dropped onto the ground: the upper turns pile onto the lower.
inline ContactScene RodCoilScene(SceneParams params, int n = 100) {
  ContactScene out{MakeScene(params), 1, {}};
  MakeGround(*out.scene);
  RodActorParams rod;
  rod.radius = 0.004;
  rod.youngModulus = 1e7;
  rod.density = 1000;
  real const turns = 3;
  for (int i = 0; i < n; ++i) {
    real const a = 2 * M_PI * turns * i / (n - 1);
    rod.nodes.push_back(Real3(0.05 * std::cos(a), 0.02 + 0.02 * a / (2 * M_PI), 0.05 * std::sin(a)));
  }
  Error error;
  RodActor* actor = out.scene->CreateRodActor(rod, error);
  INFO(error.ToString());
  REQUIRE(actor);
  MakeSurface(*out.scene, *actor);
  return out;
}

/// 7. A 0.1 m rigid box at 20 m/s onto a static 5 mm plate.
inline ContactScene FastBoxScene(SceneParams params) {
  ContactScene out{MakeScene(params), 0.5, {}};
  ColliderParams plate;
  plate.shape = ShapeType::Box;
  plate.halfExtents = Real3(1, 0.0025, 1);
  MakeCollider(*out.scene, plate);
  RigidActor* box = MakeRigidBox(*out.scene, Real3(0, 0.3, 0), Quat::Identity(), Real3::Constant(0.05), 1);
  Error error;
  REQUIRE(box->SetVelocity(Real3(0, -20, 0), Real3::Zero(), error));
  return out;
}

/// 8. A 5-link arm pushes a 1 kg, 0.2 m rigid box across the ground (μ =
/// 0.3): a carriage (link 0, prismatic along x, 0.55 m up) from which four
/// 0.1 m links hang on revolute joints about z, each with a capsule collider
/// (r = 15 mm) along its axis. Targets drive it: the carriage's position
/// moves at `speed` (it starts 0.15 m behind the box's face), the hanging
/// joints are held at 0 (stiffness 100 N·m/rad); the lowest capsule meets
/// the box's side.
struct ArmPush {
  ArticulatedActor* arm = nullptr;
  RigidActor* box = nullptr;
  Constraint* carriage = nullptr;
  real speed = 0.3;       ///< of the carriage's target [m/s]
  real start = 0;         ///< the carriage's target at t = 0 [m]
};

constexpr real kArmLink = 0.1;      ///< hanging link length [m]
constexpr real kArmRadius = 0.015;  ///< capsule radius [m]

/// The arm with its carriage at `carriage` [m].
inline ArticulatedActorParams ArmParams(real carriage) {
  ArticulatedActorParams p;
  p.blockSolve = ArticulatedBlockSolve::Dense;
  for (int i = 0; i < 5; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    if (i == 0) {
      link.joint = JointType::Prismatic;
      link.axis = Real3::UnitX();
      link.parentToJointPosition = Real3(0, 0.55, 0);
      link.mass = 2;
      link.inertia = Real3::Constant(0.01);
      link.initialPosition = {carriage};
    } else {
      link.joint = JointType::Revolute;
      link.axis = Real3::UnitZ();
      link.parentToJointPosition = i == 1 ? Real3::Zero() : Real3(0, -kArmLink, 0);
      link.mass = 0.2;
      link.centerOfMass = Real3(0, -kArmLink / 2, 0);
      real const across = link.mass * kArmLink * kArmLink / 12;
      link.inertia = Real3(across, 1e-5, across);
    }
    p.links.push_back(link);
  }
  return p;
}

/// The capsule of hanging link `link` (1..4): along the link's −y, between
/// 10 mm and 90 mm below its joint.
inline ColliderParams ArmCapsule(ArticulatedActor const& arm, int link) {
  ColliderParams capsule;
  capsule.actor = arm.GetHandle();
  capsule.link = link;
  capsule.shape = ShapeType::Capsule;
  capsule.position = Real3(0, -kArmLink / 2, 0);
  capsule.rotation = Quat(Eigen::AngleAxis<real>(-M_PI / 2, Real3::UnitX()));  // local z along y
  capsule.radius = kArmRadius;
  capsule.halfLength = 0.04;
  capsule.friction = 0.3;
  return capsule;
}

inline ArmPush MakeArmPush(Scene& scene, real speed = 0.3) {
  ArmPush out;
  out.speed = speed;
  MakeGround(scene, 0.3);
  real const dhat = scene.GetParams().contact.activationDistance;
  out.box = MakeRigidBox(scene, Real3(0.3, 0.1 + 0.5 * dhat, 0), Quat::Identity(), Real3::Constant(0.1), 1, 0.3);
  // the carriage 0.15 m behind the box's face (at x = 0.2) with the capsule
  out.start = 0.2 - kArmRadius - 0.15;
  out.arm = MakeArticulated(scene, ArmParams(out.start));
  for (int link = 1; link < 5; ++link) MakeCollider(scene, ArmCapsule(*out.arm, link));
  Error error;
  for (int link = 0; link < 5; ++link) {
    ArticulatedSingleDofTargetConstraintParams target;
    target.actor = out.arm->GetHandle();
    target.jointIndex = link;
    target.target = link == 0 ? out.start : 0;
    target.stiffness = link == 0 ? 1e4 : 100;
    target.damping = link == 0 ? 100 : 1;
    Constraint* c = scene.CreateArticulatedSingleDofTargetConstraint(target, error);
    INFO(error.ToString());
    REQUIRE(c);
    if (link == 0) out.carriage = c;
  }
  return out;
}

inline ContactScene ArmPushScene(SceneParams params) {
  params.gravity = Real3(0, -kGravity, 0);
  ContactScene out{MakeScene(params), 2, {}};
  ArmPush const push = MakeArmPush(*out.scene);
  out.drive = [push](real time) {
    Error error;
    REQUIRE(push.carriage->SetTargetDof(push.start + push.speed * time, error));
  };
  return out;
}

}  // namespace superdex::test
