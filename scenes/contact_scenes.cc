// The contact scenes (contact_scenes.h).
#include "scenes/contact_scenes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace superdex::scenes {

Builder::Builder(SceneParams const& params) {
  owned_ = Scene::Create(params, error_);
  scene_ = owned_.get();
  ok_ = scene_ != nullptr;
}

bool Builder::Fail(Error const& error) {
  if (ok_) error_ = error;
  ok_ = false;
  return false;
}

Collider* Builder::AddCollider(ColliderParams const& params) {
  if (!ok_) return nullptr;
  Error error;
  return Check(scene_->CreateCollider(params, error), error);
}

Collider* Builder::AddGround(real friction) {
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  ground.friction = friction;
  return AddCollider(ground);
}

RigidActor* Builder::AddRigid(RigidActorParams const& params) {
  if (!ok_) return nullptr;
  Error error;
  return Check(scene_->CreateRigidActor(params, error), error);
}

RigidActor* Builder::AddRigidBox(Real3 const& position, Quat const& rotation, Real3 const& half, real mass,
                                 real friction) {
  RigidActorParams body;
  body.mass = mass;
  Real3 const e = 2 * half;
  body.inertia = mass / 12 * Real3(e.y() * e.y() + e.z() * e.z(), e.x() * e.x() + e.z() * e.z(),
                                   e.x() * e.x() + e.y() * e.y());
  body.position = position;
  body.rotation = rotation;
  RigidActor* box = AddRigid(body);
  if (!box) return nullptr;
  ColliderParams shape;
  shape.actor = box->GetHandle();
  shape.shape = ShapeType::Box;
  shape.halfExtents = half;
  shape.friction = friction;
  return AddCollider(shape) ? box : nullptr;
}

DeformableActor* Builder::AddDeformable(DeformableActorParams const& params) {
  if (!ok_) return nullptr;
  Error error;
  return Check(scene_->CreateDeformableActor(params, error), error);
}

RodActor* Builder::AddRod(RodActorParams const& params) {
  if (!ok_) return nullptr;
  Error error;
  return Check(scene_->CreateRodActor(params, error), error);
}

ArticulatedActor* Builder::AddArticulated(ArticulatedActorParams const& params) {
  if (!ok_) return nullptr;
  Error error;
  return Check(scene_->CreateArticulatedActor(params, error), error);
}

Constraint* Builder::AddJointTarget(ArticulatedActor const& arm, int joint, real target, real stiffness,
                                    real damping) {
  if (!ok_) return nullptr;
  ArticulatedSingleDofTargetConstraintParams params;
  params.actor = arm.GetHandle();
  params.jointIndex = joint;
  params.target = target;
  params.stiffness = stiffness;
  params.damping = damping;
  Error error;
  return Check(scene_->CreateArticulatedSingleDofTargetConstraint(params, error), error);
}

Collider* Builder::AddSurface(Actor const* actor, bool selfContact) {
  if (!ok_ || !actor) return nullptr;
  ColliderParams surface;
  surface.actor = actor->GetHandle();
  if (!selfContact) {
    // its own group out of its mask: no pairs within the surface
    surface.group = 2;
    surface.mask = ~2u;
  }
  return AddCollider(surface);
}

bool Builder::MakeBox(Real3 const& lower, Real3 const& size, std::array<int, 3> const& cells,
                      DeformableActorParams& params) {
  if (!ok_) return false;
  TetMesh mesh;
  Error error;
  if (!MakeTetBox(lower, size, cells, mesh, error)) return Fail(error);
  params.nodes = std::move(mesh.nodes);
  params.tetrahedra = std::move(mesh.tetrahedra);
  return true;
}

DeformableActor* Builder::AddCloth(int n, real size, real y, Quat const& rotation, MembraneModel membrane) {
  if (!ok_) return nullptr;
  TriangleMesh mesh;
  Error error;
  if (!MakeTriangleGrid(Real3(-0.5 * size, 0, -0.5 * size), size, size, n - 1, n - 1, mesh, error)) {
    Fail(error);
    return nullptr;
  }
  DeformableActorParams cloth;
  for (Real3 const& p : mesh.nodes) cloth.nodes.push_back(Real3(0, y, 0) + rotation * p);
  cloth.triangles = mesh.triangles;
  cloth.youngModulus = 1e6;
  cloth.poissonRatio = 0.3;
  cloth.thickness = 1e-3;
  cloth.density = 300;
  cloth.membrane = membrane;
  DeformableActor* actor = AddDeformable(cloth);
  return AddSurface(actor) ? actor : nullptr;
}

bool TetBall(Real3 const& center, real radius, int cells, DeformableActorParams& ball, Error& error) {
  TetMesh mesh;
  if (!MakeTetBox(center - Real3::Constant(radius), Real3::Constant(2 * radius), {cells, cells, cells}, mesh,
                  error))
    return false;
  // each node moved along its ray from the centre by |d|∞ / |d|₂: the box's
  // nested cube shells become spheres, its faces the ball's surface
  ball.nodes.clear();
  for (Real3 const& p : mesh.nodes) {
    Real3 const d = p - center;
    real const length = d.norm();
    ball.nodes.push_back(length > 0 ? center + d * (d.cwiseAbs().maxCoeff() / length) : p);
  }
  ball.tetrahedra = mesh.tetrahedra;
  return true;
}

ContactScene Finish(Builder& builder, real seconds, Error& error) {
  ContactScene out;
  out.seconds = seconds;
  if (!builder.Ok()) {
    error = builder.GetError();
    return out;
  }
  out.scene = builder.TakeScene();
  return out;
}

namespace {

/// A static plane through the origin with normal `normal`.
ColliderParams PlaneThroughOrigin(Real3 const& normal) {
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = normal;
  return plane;
}

}  // namespace

ContactScene InclineScene(SceneParams params, real tanTheta, Error& error) {
  params.gravity = Real3(0, -kGravity, 0);
  Builder b(params);
  Quat const tilt(Eigen::AngleAxis<real>(std::atan(tanTheta), Real3::UnitZ()));
  Real3 const normal = tilt * Real3::UnitY();
  b.AddCollider(PlaneThroughOrigin(normal));
  b.AddRigidBox(normal * (0.1 + 0.5 * params.contact.activationDistance), tilt, Real3::Constant(0.1), 1);
  return Finish(b, 2, error);
}

ContactScene RollingScene(SceneParams params, Error& error) {
  Builder b(params);
  Quat const tilt(Eigen::AngleAxis<real>(15 * std::numbers::pi / 180, Real3::UnitZ()));
  Real3 const normal = tilt * Real3::UnitY();
  b.AddCollider(PlaneThroughOrigin(normal));
  RigidActorParams body;
  body.inertia = Real3::Constant(0.4 * 0.1 * 0.1);
  body.position = normal * (0.1 + 0.9 * params.contact.activationDistance);
  RigidActor* sphere = b.AddRigid(body);
  if (sphere) {
    ColliderParams shape;
    shape.actor = sphere->GetHandle();
    shape.shape = ShapeType::Sphere;
    shape.radius = 0.1;
    b.AddCollider(shape);
  }
  return Finish(b, 1, error);
}

bool BallParams(real drop, int cells, DeformableActorParams& ball, Error& error) {
  if (!TetBall(Real3(0, drop + kBallRadius, 0), kBallRadius, cells, ball, error)) return false;
  ball.material = TetMaterialModel::StableNeoHookean;
  ball.youngModulus = kBallYoungModulus;
  ball.poissonRatio = 0.3;
  ball.density = 1000;
  return true;
}

ContactScene BallDropScene(SceneParams params, real drop, int cells, Error& error) {
  Builder b(params);
  b.AddGround();
  DeformableActorParams ball;
  if (!BallParams(drop, cells, ball, error)) return {};
  b.AddSurface(b.AddDeformable(ball), false);
  return Finish(b, 1, error);
}

real Builder::ActivationDistance() const {
  return scene_ ? scene_->GetParams().contact.activationDistance : 0;
}

DynamicArray<RigidActor*> AddBoxStack(Builder& b, int count) {
  b.AddGround();
  real const half = 0.1, gap = 0.9 * b.ActivationDistance();
  DynamicArray<RigidActor*> boxes;
  for (int i = 0; i < count; ++i)
    boxes.push_back(
        b.AddRigidBox(Real3(0, gap + half + i * (2 * half + gap), 0), Quat::Identity(), Real3::Constant(half), 1));
  return boxes;
}

ContactScene BoxStackScene(SceneParams params, int count, Error& error) {
  Builder b(params);
  AddBoxStack(b, count);
  return Finish(b, 2, error);
}

DynamicArray<DeformableActor*> AddCubeStack(Builder& b, int count, int cells) {
  b.AddGround();
  real const side = 0.1, gap = 0.9 * b.ActivationDistance();
  DynamicArray<DeformableActor*> cubes;
  for (int i = 0; i < count; ++i) {
    DeformableActorParams cube;
    b.MakeBox(Real3(-0.5 * side, gap + i * (side + gap), -0.5 * side), Real3::Constant(side), {cells, cells, cells},
              cube);
    cube.material = TetMaterialModel::StableNeoHookean;
    cube.youngModulus = 1e6;
    cube.density = 1000;
    DeformableActor* actor = b.AddDeformable(cube);
    b.AddSurface(actor, false);
    cubes.push_back(actor);
  }
  return cubes;
}

ContactScene CubeStackScene(SceneParams params, int count, int cells, Error& error) {
  Builder b(params);
  AddCubeStack(b, count, cells);
  return Finish(b, 2, error);
}

DeformableActor* AddClothOnSphere(Builder& b, int n) {
  b.AddGround();
  ColliderParams sphere;
  sphere.shape = ShapeType::Sphere;
  sphere.position = Real3(0, 0.2, 0);
  sphere.radius = 0.2;
  b.AddCollider(sphere);
  return b.AddCloth(n, 0.6, 0.45, Quat::Identity());
}

ContactScene ClothOnSphereScene(SceneParams params, int n, Error& error) {
  Builder b(params);
  AddClothOnSphere(b, n);
  return Finish(b, 1.5, error);
}

DynamicArray<RodActor*> AddRodPile(Builder& b, int rods, int nodes) {
  // the bin: the ground and four static walls (2 cm thick, 0.3 m high)
  // around a 0.6 m square floor
  b.AddGround();
  real const half = 0.3, wall = 0.01, height = 0.15;
  for (int side = 0; side < 4; ++side) {
    ColliderParams w;
    w.shape = ShapeType::Box;
    Real3 const out = side < 2 ? Real3((side == 0 ? -1 : 1) * (half + wall), height, 0)
                               : Real3(0, height, (side == 2 ? -1 : 1) * (half + wall));
    w.position = out;
    w.halfExtents = side < 2 ? Real3(wall, height, half + 2 * wall) : Real3(half, height, wall);
    b.AddCollider(w);
  }
  // straight rods 0.5 m long in layers 2 cm apart from 3 cm up, 10 per
  // layer 3 cm apart, each layer turned 100° from the one below (they
  // cross); a layer's corners stay within 0.284 m of the centre, clear of
  // the walls at any turn
  constexpr real kLength = 0.5, kPitch = 0.03, kLayerGap = 0.02;
  constexpr int perLayer = 10;
  DynamicArray<RodActor*> out;
  for (int r = 0; r < rods; ++r) {
    int const layer = r / perLayer, slot = r % perLayer;
    real const angle = layer * 100 * std::numbers::pi / 180;
    Real3 const along(std::cos(angle), 0, std::sin(angle)), across(-std::sin(angle), 0, std::cos(angle));
    Real3 const center = Real3(0, 0.03 + layer * kLayerGap, 0) + (slot - 0.5 * (perLayer - 1)) * kPitch * across;
    RodActorParams rod;
    rod.radius = 0.004;
    rod.youngModulus = 1e7;
    rod.density = 1000;
    for (int i = 0; i < nodes; ++i)
      rod.nodes.push_back(center + (static_cast<real>(i) / (nodes - 1) - 0.5) * kLength * along);
    RodActor* actor = b.AddRod(rod);
    b.AddSurface(actor, false);
    out.push_back(actor);
  }
  return out;
}

ContactScene RodPileScene(SceneParams params, int rods, int nodes, Error& error) {
  Builder b(params);
  AddRodPile(b, rods, nodes);
  return Finish(b, 1, error);
}

ContactScene ClothFoldScene(SceneParams params, int n, Error& error) {
  Builder b(params);
  b.AddGround();
  Quat const tilt(Eigen::AngleAxis<real>(80 * std::numbers::pi / 180, Real3::UnitX()));
  b.AddCloth(n, 0.4, 0.21, tilt);
  return Finish(b, 1.5, error);
}

ContactScene RodCoilScene(SceneParams params, int n, Error& error) {
  Builder b(params);
  b.AddGround();
  RodActorParams rod;
  rod.radius = 0.004;
  rod.youngModulus = 1e7;
  rod.density = 1000;
  real const turns = 3;
  for (int i = 0; i < n; ++i) {
    real const a = 2 * std::numbers::pi * turns * i / (n - 1);
    rod.nodes.push_back(Real3(0.05 * std::cos(a), 0.02 + 0.02 * a / (2 * std::numbers::pi), 0.05 * std::sin(a)));
  }
  b.AddSurface(b.AddRod(rod));
  return Finish(b, 1, error);
}

ContactScene FastBoxScene(SceneParams params, Error& error) {
  Builder b(params);
  ColliderParams plate;
  plate.shape = ShapeType::Box;
  plate.halfExtents = Real3(1, 0.0025, 1);
  b.AddCollider(plate);
  RigidActor* box = b.AddRigidBox(Real3(0, 0.3, 0), Quat::Identity(), Real3::Constant(0.05), 1);
  if (box && !box->SetVelocity(Real3(0, -20, 0), Real3::Zero(), error)) return {};
  return Finish(b, 0.5, error);
}

ArticulatedActorParams ArmParams(real carriage) {
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

ColliderParams ArmCapsule(ArticulatedActor const& arm, int link) {
  ColliderParams capsule;
  capsule.actor = arm.GetHandle();
  capsule.link = link;
  capsule.shape = ShapeType::Capsule;
  capsule.position = Real3(0, -kArmLink / 2, 0);
  capsule.rotation = Quat(Eigen::AngleAxis<real>(-std::numbers::pi / 2, Real3::UnitX()));  // local z along y
  capsule.radius = kArmRadius;
  capsule.halfLength = 0.04;
  capsule.friction = 0.3;
  return capsule;
}

ArmPush AddArmPush(Builder& b, real speed) {
  ArmPush out;
  out.speed = speed;
  b.AddGround(0.3);
  if (!b.Ok()) return out;
  real const dhat = b.GetScene()->GetParams().contact.activationDistance;
  out.box = b.AddRigidBox(Real3(0.3, 0.1 + 0.5 * dhat, 0), Quat::Identity(), Real3::Constant(0.1), 1, 0.3);
  // the carriage 0.15 m behind the box's face (at x = 0.2) with the capsule
  out.start = 0.2 - kArmRadius - 0.15;
  out.arm = b.AddArticulated(ArmParams(out.start));
  if (!out.arm) return out;
  for (int link = 1; link < 5; ++link) b.AddCollider(ArmCapsule(*out.arm, link));
  out.carriage = b.AddJointTarget(*out.arm, 0, out.start, 1e4, 100);
  for (int link = 1; link < 5; ++link) b.AddJointTarget(*out.arm, link, 0, 100, 1);
  return out;
}

ContactScene ArmPushScene(SceneParams params, Error& error) {
  params.gravity = Real3(0, -kGravity, 0);
  Builder b(params);
  ArmPush const push = AddArmPush(b, 0.3);
  ContactScene out = Finish(b, 2, error);
  out.drive = [push](real from, real, Error& driveError) {
    return push.carriage->SetTargetDof(push.start + push.speed * from, driveError);
  };
  return out;
}

FoldingArm AddFoldingArm(Builder& b) {
  // link lengths 0.4, 0.1 m (link 2 reaches 0.35 m), each link's frame at its
  // joint with its axis along local x
  constexpr real kLengths[] = {0.4, 0.1, 0.36};
  constexpr real kStart[] = {0, std::numbers::pi / 2, std::numbers::pi / 2};
  ArticulatedActorParams p;
  p.blockSolve = ArticulatedBlockSolve::Dense;
  for (int i = 0; i < 3; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = JointType::Revolute;
    link.axis = Real3::UnitZ();
    link.parentToJointPosition = i == 0 ? Real3(0, 0.5, 0) : Real3(kLengths[i - 1], 0, 0);
    link.mass = 0.2;
    link.centerOfMass = Real3(kLengths[i] / 2, 0, 0);
    real const across = link.mass * kLengths[i] * kLengths[i] / 12;
    link.inertia = Real3(1e-5, across, across);
    link.initialPosition = {kStart[i]};
    p.links.push_back(link);
  }
  FoldingArm out;
  out.arm = b.AddArticulated(p);
  if (!out.arm) return out;
  // capsules along each link's x, 20 mm (link 2: 50 mm) clear of its joints
  constexpr real kFrom[] = {0.02, 0.02, 0.05}, kTo[] = {0.38, 0.08, 0.35};
  for (int i = 0; i < 3; ++i) {
    ColliderParams capsule;
    capsule.actor = out.arm->GetHandle();
    capsule.link = i;
    capsule.shape = ShapeType::Capsule;
    capsule.position = Real3(0.5 * (kFrom[i] + kTo[i]), 0, 0);
    capsule.rotation = Quat(Eigen::AngleAxis<real>(std::numbers::pi / 2, Real3::UnitY()));  // local z along x
    capsule.radius = kArmRadius;
    capsule.halfLength = 0.5 * (kTo[i] - kFrom[i]);
    capsule.friction = 0.3;
    b.AddCollider(capsule);
  }
  b.AddJointTarget(*out.arm, 0, kStart[0], 100, 1);
  b.AddJointTarget(*out.arm, 1, kStart[1], 100, 1);
  out.fold = b.AddJointTarget(*out.arm, 2, kStart[2], 2, 0.05);
  return out;
}

ContactScene FoldingArmScene(SceneParams params, Error& error) {
  params.gravity = Real3::Zero();
  Builder b(params);
  FoldingArm const fold = AddFoldingArm(b);
  ContactScene out = Finish(b, 1, error);
  out.drive = [fold](real, real to, Error& driveError) { return DriveFoldingArm(fold, to, driveError); };
  return out;
}

bool DriveFoldingArm(FoldingArm const& fold, real to, Error& error) {
  real const turned = std::min(to / kFoldSeconds, real(1));
  return fold.fold->SetTargetDof(std::numbers::pi / 2 + turned * (kFoldTarget - std::numbers::pi / 2), error);
}

namespace {
constexpr real kGraspCube = 0.1;                       // edge [m]
constexpr real kGraspStartGap = 0.003, kGraspSqueeze = 0.0015;  // per side [m]
constexpr real kGraspPaddleHalfWidth = 0.01;
}  // namespace

Real3 GraspPaddlePosition(int side, real time, real activationDistance) {
  real const closing = std::clamp(time / kGraspClosed, real(0), real(1));
  real const lifting = std::clamp((time - kGraspClosed) / (kGraspLifted - kGraspClosed), real(0), real(1));
  real const face = 0.5 * kGraspCube + kGraspStartGap - closing * (kGraspStartGap + kGraspSqueeze);
  real const x = (side == 0 ? -1 : 1) * (face + kGraspPaddleHalfWidth);
  // at the cube's mid-height (it starts 0.9 d̂ above the ground)
  return Real3(x, 0.5 * kGraspCube + 0.9 * activationDistance + lifting * kGraspLift, 0);
}

Grasp AddGrasp(Builder& b, int cells) {
  Grasp out;
  b.AddGround();
  real const dhat = b.ActivationDistance();
  DeformableActorParams cube;
  b.MakeBox(Real3(-0.5 * kGraspCube, 0.9 * dhat, -0.5 * kGraspCube), Real3::Constant(kGraspCube),
            {cells, cells, cells}, cube);
  cube.material = TetMaterialModel::StableNeoHookean;
  cube.youngModulus = 1e5;
  cube.density = 1000;
  out.cube = b.AddDeformable(cube);
  b.AddSurface(out.cube, false);
  for (int side = 0; side < 2; ++side) {
    ColliderParams paddle;
    paddle.shape = ShapeType::Box;
    paddle.halfExtents = Real3(kGraspPaddleHalfWidth, 0.04, 0.08);
    paddle.position = GraspPaddlePosition(side, 0, dhat);
    paddle.friction = 0.8;
    out.paddles[side] = b.AddCollider(paddle);
  }
  return out;
}

bool DriveGrasp(Grasp const& grasp, real activationDistance, real to, Error& error) {
  for (int side = 0; side < 2; ++side)
    if (!grasp.paddles[side]->SetTargetTransform(GraspPaddlePosition(side, to, activationDistance),
                                                 Quat::Identity(), error))
      return false;
  return true;
}

}  // namespace superdex::scenes
