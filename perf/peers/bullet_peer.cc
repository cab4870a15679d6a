// Bullet (libbullet-dev 3.24) in perf/peers: btDiscreteDynamicsWorld with
// the default collision configuration, broadphase and sequential impulse
// solver, one internal step of exactly dt per call (stepSimulation(dt, 1, dt)).
//
// Settings that differ from Bullet's defaults, and why:
// - friction √0.5 on each body: Bullet combines two bodies' frictions as
//   their product, so 0.5 on both would be μ = 0.25 at the contact, not the
//   scenes' 0.5 (SuperDex's √(μa μb) and ODE's per-contact μ give 0.5);
// - no deactivation: a body slower than 0.8 m/s for 2 s falls asleep by
//   default, which would stop the sliding box (0.09 m/s² down the slope)
//   and hide any creep behind the sleep heuristic rather than measure it.
// Restitution is 0 (the default) on every body. Continuous collision
// detection is off by default; the bullet-ccd variant turns it on for the
// fast box (motion threshold and swept sphere of the box's half size).
#include <btBulletDynamicsCommon.h>

#include <cmath>

#include "peer_scenes.h"

namespace {

class BulletWorld final : public peers::World {
 public:
  explicit BulletWorld(double dt)
      : dispatcher_(&config_), world_(&dispatcher_, &broadphase_, &solver_, &config_), dt_(dt) {
    world_.setGravity(btVector3(0, -peers::kGravity, 0));
  }

  ~BulletWorld() override {
    // the world refers to the bodies; take them out before they are freed
    for (auto& body : bodies_) world_.removeRigidBody(body.get());
  }

  /// A body of `shape` at `pose` (mass 0: static); friction √μ so that two
  /// bodies' product is μ.
  btRigidBody* Add(std::unique_ptr<btCollisionShape> shape, double mass, peers::Vec3 const& inertia,
                   btTransform const& pose) {
    btRigidBody::btRigidBodyConstructionInfo info(mass, nullptr, shape.get(),
                                                  btVector3(inertia[0], inertia[1], inertia[2]));
    info.m_startWorldTransform = pose;
    info.m_friction = std::sqrt(peers::kFriction);
    info.m_restitution = 0;
    auto body = std::make_unique<btRigidBody>(info);
    body->setActivationState(DISABLE_DEACTIVATION);
    world_.addRigidBody(body.get());
    shapes_.push_back(std::move(shape));
    bodies_.push_back(std::move(body));
    if (mass > 0) boxes_.push_back(bodies_.back().get());
    return bodies_.back().get();
  }

  bool Step(std::string&) override {
    world_.stepSimulation(dt_, 1, dt_);
    return true;
  }

  peers::Pose BoxPose(int i) const override {
    btTransform const& t = boxes_.at(i)->getWorldTransform();
    peers::Pose pose;
    for (int k = 0; k < 3; ++k) pose.position[k] = t.getOrigin()[k];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) pose.rotation[a][b] = t.getBasis()[a][b];
    return pose;
  }

 private:
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_;
  double dt_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<btRigidBody*> boxes_;
};

btTransform At(peers::Vec3 const& p, btQuaternion const& q = btQuaternion::getIdentity()) {
  return btTransform(q, btVector3(p[0], p[1], p[2]));
}

std::unique_ptr<btBoxShape> Box(double half) {
  return std::make_unique<btBoxShape>(btVector3(half, half, half));
}

std::unique_ptr<peers::World> Incline(double tanTheta, double dt) {
  auto world = std::make_unique<BulletWorld>(dt);
  double const theta = std::atan(tanTheta);
  btVector3 const normal(-std::sin(theta), std::cos(theta), 0);  // R_z(θ)·ŷ
  world->Add(std::make_unique<btStaticPlaneShape>(normal, 0), 0, {}, btTransform::getIdentity());
  double const up = peers::kInclineHalf + peers::kInclineGap;
  world->Add(Box(peers::kInclineHalf), 1, peers::BoxInertia(1, {0.1, 0.1, 0.1}),
             At({normal.x() * up, normal.y() * up, 0}, btQuaternion(btVector3(0, 0, 1), theta)));
  return world;
}

std::unique_ptr<peers::World> Stack(double dt) {
  auto world = std::make_unique<BulletWorld>(dt);
  world->Add(std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), 0), 0, {},
             btTransform::getIdentity());
  double const h = peers::kStackHalf;
  for (int i = 0; i < peers::kStackCount; ++i)
    world->Add(Box(h), 1, peers::BoxInertia(1, {h, h, h}), At({0, peers::StackHeight(i), 0}));
  return world;
}

std::unique_ptr<peers::World> FastBox(double dt, bool ccd) {
  auto world = std::make_unique<BulletWorld>(dt);
  auto const& p = peers::kPlateHalf;
  world->Add(std::make_unique<btBoxShape>(btVector3(p[0], p[1], p[2])), 0, {},
             btTransform::getIdentity());
  double const h = peers::kFastHalf;
  btRigidBody* box =
      world->Add(Box(h), 1, peers::BoxInertia(1, {h, h, h}), At({0, peers::kFastHeight, 0}));
  box->setLinearVelocity(btVector3(0, -peers::kFastSpeed, 0));
  if (ccd) {
    // sweep a sphere inside the box whenever it moves more than its half size in a step
    box->setCcdMotionThreshold(h);
    box->setCcdSweptSphereRadius(h);
  }
  return world;
}

}  // namespace

int main(int argc, char** argv) {
#ifdef BT_USE_DOUBLE_PRECISION
  std::string const name = "bullet-f64", precision = "double precision";
#else
  std::string const name = "bullet", precision = "single precision";
#endif
  std::string const note =
      "Bullet " + std::to_string(BT_BULLET_VERSION / 100) + "." +
      std::to_string(BT_BULLET_VERSION % 100) + " " + precision +
      "; stepSimulation(dt 1 dt); SI solver defaults (10 iterations); friction sqrt(0.5) "
      "per body (product 0.5); deactivation off";
  peers::PeerEngine plain;
  plain.name = name;
  plain.note = note;
  plain.incline = [](double tanTheta, double dt, std::string&) { return Incline(tanTheta, dt); };
  plain.stack = [](double dt, std::string&) { return Stack(dt); };
  plain.fastBox = [](double dt, std::string&) { return FastBox(dt, false); };
  // only the fast box differs with CCD on: the other scenes are not run twice
  peers::PeerEngine ccd;
  ccd.name = name + "-ccd";
  ccd.note = note + "; CCD on (motion threshold and swept sphere 0.05 m)";
  ccd.fastBox = [](double dt, std::string&) { return FastBox(dt, true); };
  return peers::RunPeers({plain, ccd}, argc, argv);
}
