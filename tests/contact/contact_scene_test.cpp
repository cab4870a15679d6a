// Contact scenes against analytic answers (docs/contact.md): a box on an
// incline below and above its friction angle, a soft ball bouncing on the
// ground, a fast box onto a thin plate. Non-penetration is checked on the
// bodies' own geometry (corners against the plane, nodes against the plate),
// not through the barrier's distance.
#include "contact/contact_scenes.h"
#include "scenes/interpenetration.h"
#include "test_scenes.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <random>

#include <superdex/contact/distance.h>
#include <superdex/solver/newton_solver.h>
#include <superdex/superdex.h>

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kG = kGravity;

/// The incline: a static plane through the origin whose normal is y turned
/// by θ about z, so that down the slope is (cos θ, −sin θ, 0)·(−1)… along −x'.
struct Incline {
  std::unique_ptr<Scene> scene;
  RigidActor* box = nullptr;
  Real3 down;  ///< unit vector down the slope
  Real3 normal;
};

constexpr real kHalf = 0.1;  // box half extent [m]

Incline MakeIncline(real tanTheta, real mu) {
  Incline incline;
  SceneParams params;
  params.gravity = Real3(0, -kG, 0);
  incline.scene = MakeScene(params);
  real const theta = std::atan(tanTheta);
  Quat const tilt(Eigen::AngleAxis<real>(theta, Real3::UnitZ()));
  incline.normal = tilt * Real3::UnitY();
  incline.down = tilt * Real3(-1, 0, 0);
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = incline.normal;
  plane.friction = mu;
  MakeCollider(*incline.scene, plane);
  RigidActorParams body;
  body.mass = 1;
  body.inertia = Real3::Constant(body.mass * (2 * kHalf) * (2 * kHalf) / 6);
  body.rotation = tilt;
  // resting at half the activation distance above the plane
  body.position = incline.normal * (kHalf + 0.5 * params.contact.activationDistance);
  incline.box = MakeRigid(*incline.scene, body);
  ColliderParams box;
  box.actor = incline.box->GetHandle();
  box.shape = ShapeType::Box;
  box.halfExtents = Real3::Constant(kHalf);
  box.friction = mu;
  MakeCollider(*incline.scene, box);
  return incline;
}

/// The lowest corner's height above the plane (exact: the box's geometry).
real LowestCorner(RigidActor const& box, Real3 const& normal) {
  real lowest = std::numeric_limits<real>::infinity();
  for (int i = 0; i < 8; ++i) {
    Real3 const corner((i & 1) ? kHalf : -kHalf, (i & 2) ? kHalf : -kHalf, (i & 4) ? kHalf : -kHalf);
    lowest = std::min(lowest, normal.dot(box.TransformPoint(corner)));
  }
  return lowest;
}

}  // namespace

TEST_CASE("a box below its friction angle stays put: no creep", "[contact][friction]") {
  // μ = 0.5, tan θ = 0.49: the friction the box needs, m g sin θ, is 98 % of
  // μ m g cos θ. The stick anchor holds it: after the ramp has taken up the
  // load (within ḡ = 1e-4 m of slip), the box must not move down the slope
  // by more than 1 µm/s over 4 s.
  Incline incline = MakeIncline(0.49, 0.5);
  Error error;
  real const dt = 1.0 / 60;
  for (int s = 0; s < 60; ++s) REQUIRE(incline.scene->Step(dt, error));
  Real3 const start = incline.box->GetPosition();
  for (int s = 0; s < 240; ++s) {
    REQUIRE(incline.scene->Step(dt, error));
    REQUIRE(LowestCorner(*incline.box, incline.normal) > 0);
  }
  real const creep = (incline.box->GetPosition() - start).dot(incline.down) / 4.0;
  INFO("creep " << creep << " m/s");
  CHECK(std::abs(creep) < 1e-6);
  // and what holds it is contact: the box rests on the plane within d̂
  CHECK(incline.scene->GetStats().activeContacts >= 4);
  CHECK(LowestCorner(*incline.box, incline.normal) < incline.scene->GetParams().contact.activationDistance);
}

TEST_CASE("a box above its friction angle slides with a = g (sin θ − μ cos θ)", "[contact][friction]") {
  real const tanTheta = 0.51, mu = 0.5;
  Incline incline = MakeIncline(tanTheta, mu);
  Error error;
  real const dt = 1.0 / 60;
  real const theta = std::atan(tanTheta);
  real const expected = kG * (std::sin(theta) - mu * std::cos(theta));
  for (int s = 0; s < 60; ++s) REQUIRE(incline.scene->Step(dt, error));
  real const v1 = incline.box->GetLinearVelocity().dot(incline.down);
  for (int s = 0; s < 240; ++s) {
    REQUIRE(incline.scene->Step(dt, error));
    REQUIRE(LowestCorner(*incline.box, incline.normal) > 0);
  }
  real const v2 = incline.box->GetLinearVelocity().dot(incline.down);
  real const a = (v2 - v1) / (240 * dt);
  INFO("a = " << a << ", expected " << expected);
  CHECK(std::abs(a - expected) < 0.01 * expected);
}

TEST_CASE("a fast box does not tunnel through a thin static plate", "[contact][ccd]") {
  // a 0.1 m box at 20 m/s onto a 5 mm plate at dt = 1/60: one free step
  // moves it 0.33 m, 66 plate thicknesses; and so at any CCD cap, down to
  // one distance evaluation per pair (shorter safe steps, never unsafe ones)
  int const cap = GENERATE(10000, 1);
  INFO("ccdMaxIterations " << cap);
  SceneParams params;
  params.contact.ccdMaxIterations = cap;
  auto scene = MakeScene(params);
  ColliderParams plate;
  plate.shape = ShapeType::Box;
  plate.halfExtents = Real3(1, 0.0025, 1);
  MakeCollider(*scene, plate);
  RigidActorParams body;
  body.mass = 1;
  body.inertia = Real3::Constant(1.0 / 600);
  body.position = Real3(0, 0.3, 0);
  body.linearVelocity = Real3(0, -20, 0);
  RigidActor* box = MakeRigid(*scene, body);
  ColliderParams shape;
  shape.actor = box->GetHandle();
  shape.shape = ShapeType::Box;
  shape.halfExtents = Real3::Constant(0.05);
  MakeCollider(*scene, shape);
  Error error;
  for (int s = 0; s < 60; ++s) {
    INFO("step " << s);
    bool const stepped = scene->Step(1.0 / 60, error);
    INFO(error.ToString());
    REQUIRE(stepped);
    // every corner above the plate's top face
    for (int i = 0; i < 8; ++i) {
      Real3 const corner((i & 1) ? 0.05 : -0.05, (i & 2) ? 0.05 : -0.05, (i & 4) ? 0.05 : -0.05);
      REQUIRE(box->TransformPoint(corner).y() > 0.0025);
    }
  }
  CHECK(box->GetPosition().y() < 0.06);  // it landed on the plate
  CHECK(scene->GetStats().patternBuilds == 1);
}


namespace {

/// The ball of scene 3 (scenes::BallParams), REQUIREd to build.
DeformableActorParams SceneBall(real drop) {
  DeformableActorParams ball;
  Error error;
  bool const made = scenes::BallParams(drop, 6, ball, error);
  INFO(error.ToString());
  REQUIRE(made);
  return ball;
}

/// The ball's surface collider without self contact (group 2, a mask
/// without group 2): a solid ball does not fold onto itself, which keeps
/// its candidates to the ground.
void MakeBallSurface(Scene& scene, DeformableActor const& ball) {
  ColliderParams surface;
  surface.actor = ball.GetHandle();
  surface.group = 2;
  surface.mask = ~2u;
  MakeCollider(scene, surface);
}

real LowestNode(DeformableActor const& actor) {
  real y = std::numeric_limits<real>::infinity();
  for (int i = 0; i < actor.GetNumNodes(); ++i) y = std::min(y, actor.GetNodePosition(i).y());
  return y;
}

real FastestNode(DeformableActor const& actor) {
  real v = 0;
  for (int i = 0; i < actor.GetNumNodes(); ++i) v = std::max(v, actor.GetNodeVelocity(i).norm());
  return v;
}

}  // namespace

TEST_CASE("a soft ball dropped on the ground bounces back and never passes through it", "[contact][deformable][long]") {
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  MakeGround(*scene);
  real const drop = 1.0;
  DeformableActor* actor = MakeDeformable(*scene, SceneBall(drop));
  MakeBallSurface(*scene, *actor);
  REQUIRE(LowestNode(*actor) == Approx(drop));
  // the first bounce: the lowest node's highest point between the end of
  // the first contact and the start of the second
  real const dt = 1.0 / 240;
  real peak = 0;
  bool landed = false, leftGround = false;
  int newton = 0, steps = 0;
  Error error;
  for (int s = 0; s < 240 * 2; ++s) {
    bool const stepped = scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    newton += scene->GetStats().newtonIterations;
    ++steps;
    real const y = LowestNode(*actor);
    REQUIRE(y > 0);
    bool const touching = scene->GetStats().activeContacts > 0;
    if (touching && leftGround) break;
    if (touching) landed = true;
    if (landed && !touching) leftGround = true;
    if (leftGround) peak = std::max(peak, y);
  }
  INFO("bounce peak " << peak << " m of " << drop);
  REQUIRE(leftGround);
  // measured 0.930 of the drop (docs/contact.md, "Scene 3: which ball
  // bounces"): the lost 7 % are the vibrations the impact excites, which
  // BDF2 damps; the bar is scene 3's 0.9
  CHECK(peak >= 0.9 * drop);
  CHECK(static_cast<real>(newton) / steps <= 8);
}

TEST_CASE("the soft ball put down on the ground stays at rest", "[contact][deformable][long]") {
  // An undamped elastic ball dropped from 1 m does not come to rest: its
  // slower impacts lose less (docs/contact.md, "Scene 3"). At rest means
  // the ball in its static equilibrium on the ground: found by backward
  // Euler at 1 s steps on a frictionless ground (each step damps what the
  // last left) to a Newton tolerance of 1e-12 m/s, then started there, at
  // rest, in a BDF2 scene on the μ = 0.5 ground.
  real const start = 0.9 * ContactParams{}.activationDistance;
  DynamicArray<Real3> settled;
  {
    SceneParams params;
    params.newton.velocityTolerance = 1e-12;
    params.newton.maxIterations = 200;
    auto scene = MakeScene(params);
    MakeGround(*scene, 0);
    DeformableActor* actor = MakeDeformable(*scene, SceneBall(start));
    MakeBallSurface(*scene, *actor);
    Error error;
    for (int s = 0; s < 12; ++s) REQUIRE(scene->Step(1, error));
    INFO("speed after settling " << FastestNode(*actor));
    REQUIRE(FastestNode(*actor) < 1e-8);
    settled = actor->GetNodePositions();
  }
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  MakeGround(*scene);
  DeformableActorParams ball = SceneBall(start);
  for (std::size_t i = 0; i < ball.nodes.size(); ++i) ball.initialDisplacements.push_back(settled[i] - ball.nodes[i]);
  DeformableActor* actor = MakeDeformable(*scene, ball);
  // the barrier's area weights are the rest shape's: made on the deformed
  // ball, its surface weighs as the settled scene's did (with the deformed
  // shape's areas, this first step moved it at 5e-4 m/s)
  MakeBallSurface(*scene, *actor);
  real fastest = 0;
  Error error;
  for (int s = 0; s < 5 * 240; ++s) {
    REQUIRE(scene->Step(1.0 / 240, error));
    REQUIRE(scene->GetStats().activeContacts > 0);
    fastest = std::max(fastest, FastestNode(*actor));
  }
  // measured 3.0e-10 m/s over the 5 s; the bar is scene 3's
  INFO("fastest node over 5 s: " << fastest << " m/s");
  CHECK(fastest < 1e-6);
  CHECK(scene->GetStats().patternBuilds == 1);
}

TEST_CASE("colliders are validated and a bad one changes nothing", "[contact][errors]") {
  auto scene = MakeScene();
  Error error;
  ColliderParams sphere;
  sphere.shape = ShapeType::Sphere;
  sphere.radius = 0;
  CHECK_FALSE(scene->CreateCollider(sphere, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Mentions(error, "radius"));
  sphere.radius = 0.1;
  sphere.position = Real3(0, std::nan(""), 0);
  CHECK_FALSE(scene->CreateCollider(sphere, error));
  CHECK(Mentions(error, "position"));
  ColliderParams mesh;
  mesh.shape = ShapeType::TriangleMesh;
  mesh.vertices = {Real3(0, 0, 0), Real3(1, 0, 0), Real3(2, 0, 0)};
  mesh.triangles = {{0, 1, 2}};
  CHECK_FALSE(scene->CreateCollider(mesh, error));
  CHECK(Mentions(error, "triangles[0]"));
  mesh.triangles = {{0, 1, 3}};
  CHECK_FALSE(scene->CreateCollider(mesh, error));
  CHECK(Mentions(error, "out of range"));
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = Real3::Zero();
  CHECK_FALSE(scene->CreateCollider(plane, error));
  CHECK(Mentions(error, "normal"));
  // shapes too small to touch anything (a primitive's area weight not a
  // normal double): a capsule 1e-323 m long was invisible to contact, and
  // two of them at one place passed the creation check and a step
  ColliderParams tiny;
  tiny.shape = ShapeType::Capsule;
  tiny.radius = 0.16;
  tiny.halfLength = 5e-324;
  CHECK_FALSE(scene->CreateCollider(tiny, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Mentions(error, "halfLength"));
  CHECK(Mentions(error, "too small to touch anything"));
  tiny.shape = ShapeType::Sphere;
  tiny.radius = 1e-200;
  CHECK_FALSE(scene->CreateCollider(tiny, error));
  CHECK(Mentions(error, "radius"));
  tiny.radius = 1e-150;  // π r² = 3e-300: a normal double
  CHECK(MakeScene()->CreateCollider(tiny, error));
  // geometry beyond the contact range (kMaxContactCoordinate = 1e9 m): a
  // capsule 1e300 m long made every distance to it NaN
  ColliderParams capsule;
  capsule.shape = ShapeType::Capsule;
  capsule.radius = 0.1;
  capsule.halfLength = 1e300;
  CHECK_FALSE(scene->CreateCollider(capsule, error));
  CHECK(Mentions(error, "halfLength must be finite and within ±1000000000"));
  capsule.halfLength = 0.1;
  capsule.position = Real3(0, 2e9, 0);
  CHECK_FALSE(scene->CreateCollider(capsule, error));
  CHECK(Mentions(error, "position must be finite and within"));
  RigidActorParams far;
  far.position = Real3(0, 0, -5e9);  // a valid body, too far for contact
  RigidActor* farBody = MakeRigid(*scene, far);
  ColliderParams farShape;
  farShape.actor = farBody->GetHandle();
  farShape.shape = ShapeType::Sphere;
  farShape.radius = 0.1;
  CHECK_FALSE(scene->CreateCollider(farShape, error));
  CHECK(Mentions(error, "CreateCollider: the Sphere's vertex 0 (world) must be finite and within"));
  CHECK(scene->GetNumColliders() == 0);
  REQUIRE(scene->DestroyActor(farBody->GetHandle(), error));
  // a rod's Surface takes the rod's radius as its thickness: in range too
  RodActorParams thick;
  thick.nodes = {Real3(0, 5, 0), Real3(1, 5, 0)};
  thick.radius = 2e9;
  RodActor* rod = scene->CreateRodActor(thick, error);
  INFO(error.ToString());
  REQUIRE(rod);
  ColliderParams surface;
  surface.actor = rod->GetHandle();
  CHECK_FALSE(scene->CreateCollider(surface, error));
  CHECK(Mentions(error, "thickness must be finite and within ±1000000000"));
  CHECK(scene->GetNumColliders() == 0);
  REQUIRE(scene->DestroyActor(rod->GetHandle(), error));
  // a box that starts through the ground is refused, naming both colliders
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  REQUIRE(scene->CreateCollider(ground, error));
  RigidActorParams body;
  body.position = Real3(0, 0.05, 0);
  RigidActor* box = MakeRigid(*scene, body);
  ColliderParams shape;
  shape.actor = box->GetHandle();
  shape.shape = ShapeType::Box;
  shape.halfExtents = Real3::Constant(0.1);
  CHECK_FALSE(scene->CreateCollider(shape, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Mentions(error, "intersects collider 0 (Plane)"));
  CHECK(scene->GetNumColliders() == 1);
  body.position = Real3(0, 0.2, 0);
  REQUIRE(box->SetPose(body.position, Quat::Identity(), error));
  CHECK(scene->CreateCollider(shape, error));
  SceneParams bad;
  bad.contact.activationDistance = -1;
  CHECK_FALSE(Scene::Create(bad, error));
  CHECK(Mentions(error, "contact.activationDistance"));
  bad = SceneParams();
  bad.contact.ccdMaxIterations = 0;
  CHECK_FALSE(Scene::Create(bad, error));
  CHECK(Mentions(error, "contact.ccdMaxIterations must be in [1, 100000000], got 0"));
}

namespace {
/// A solid sphere rolling from rest down a 15° incline (μ = 0.5, well above
/// the 2/7 tan θ = 0.077 that rolling needs): after dropping a height h its
/// speed is √(10 g h / 7) (energy, with I = 2/5 m r² and no slip). Returns
/// the relative error of the speed after `seconds`.
real RollingSpeedError(IntegratorType integrator, real dt, real seconds) {
  SceneParams params;
  params.integrator = integrator;
  params.newton.velocityTolerance = 1e-9;
  auto scene = MakeScene(params);
  real const theta = 15 * M_PI / 180, r = 0.1, m = 1;
  Quat const tilt(Eigen::AngleAxis<real>(theta, Real3::UnitZ()));
  Real3 const normal = tilt * Real3::UnitY();
  ColliderParams plane;
  plane.shape = ShapeType::Plane;
  plane.normal = normal;
  MakeCollider(*scene, plane);
  RigidActorParams body;
  body.mass = m;
  body.inertia = Real3::Constant(0.4 * m * r * r);
  // resting on the barrier's equilibrium gap: the first steps barely bounce
  body.position = normal * (r + 0.9 * params.contact.activationDistance);
  RigidActor* sphere = MakeRigid(*scene, body);
  ColliderParams shape;
  shape.actor = sphere->GetHandle();
  shape.shape = ShapeType::Sphere;
  shape.radius = r;
  MakeCollider(*scene, shape);
  Real3 const start = sphere->GetPosition();
  Error error;
  int const steps = static_cast<int>(std::lround(seconds / dt));
  for (int s = 0; s < steps; ++s) {
    bool const stepped = scene->Step(dt, error);
    INFO(error.ToString());
    REQUIRE(stepped);
  }
  real const h = start.y() - sphere->GetPosition().y();
  real const speed = sphere->GetLinearVelocity().norm();
  real const expected = std::sqrt(10 * kG * h / 7);
  INFO("dt " << dt << ": h " << h << " m, speed " << speed << " m/s, expected " << expected);
  REQUIRE(h > 0.1);
  return std::abs(speed - expected) / expected;
}
}  // namespace

TEST_CASE("a sphere rolls down an incline at the speed of rolling without slip", "[contact][friction]") {
  // the speed's error against √(10 g h / 7): BDF2 at dt = 1e-2 within 1e-3,
  // backward Euler at dt = 1e-3 within 5.5e-4
  CHECK(RollingSpeedError(IntegratorType::Bdf2, 1e-2, 1.0) < 1e-3);
  CHECK(RollingSpeedError(IntegratorType::BackwardEuler, 1e-3, 1.0) < 5.5e-4);
}

/// What a contact scene did, step by step: each step's counts (Newton
/// iterations, candidates, active contacts), its smallest gap and every
/// collider's world vertices, for bit-for-bit comparisons; `touched`: the
/// steps that ended with active contacts.
DynamicArray<real> ContactTrace(ContactScene const& scene, real dt, int steps, int& touched) {
  touched = 0;
  DynamicArray<real> trace;
  DynamicArray<Real3> vertices;
  for (int s = 0; s < steps; ++s) {
    Drive(scene, s * dt, (s + 1) * dt);
    Error error;
    bool const stepped = scene.scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    SceneStats const& stats = scene.scene->GetStats();
    touched += stats.activeContacts > 0;
    trace.insert(trace.end(), {static_cast<real>(stats.newtonIterations), static_cast<real>(stats.contactCandidates),
                               static_cast<real>(stats.activeContacts), stats.minContactDistance});
    for (int id = 0; id < scene.scene->GetNumColliders(); ++id) {
      scene.scene->GetCollider(id)->GetWorldVertices(vertices);
      for (Real3 const& v : vertices) trace.insert(trace.end(), {v.x(), v.y(), v.z()});
    }
  }
  return trace;
}

/// A contact scene to step on several thread counts.
struct ThreadCase {
  std::string name;
  std::function<ContactScene(SceneParams)> make;
  real dt;
  int steps;
};

/// The builder `make(params, error)` as a ThreadCase's, its build REQUIREd.
template <class Make>
std::function<ContactScene(SceneParams)> BuiltBy(Make make) {
  return [make](SceneParams params) {
    Error error;
    return Built(make(params, error), error);
  };
}

/// Steps each case on 1 and 4 threads: every step's counts and every
/// collider's vertices the same bit for bit, most of the run in contact.
void RequireSameOnThreads(DynamicArray<ThreadCase> const& cases) {
  for (ThreadCase const& c : cases) {
    DYNAMIC_SECTION(c.name) {
      int touched = 0;
      auto run = [&](int threads) {
        SceneParams params;
        params.gravity = Real3(0, -kGravity, 0);
        params.numThreads = threads;
        return ContactTrace(c.make(params), c.dt, c.steps, touched);
      };
      DynamicArray<real> const one = run(1);
      REQUIRE(one.size() > static_cast<std::size_t>(4 * c.steps));
      REQUIRE(touched > c.steps / 3);
      DynamicArray<real> const four = run(4);
      REQUIRE(four.size() == one.size());
      std::size_t first = 0;
      while (first < one.size() && std::memcmp(&one[first], &four[first], sizeof(real)) == 0) ++first;
      INFO("4 threads: the first difference at entry " << first << " of " << one.size());
      CHECK(first == one.size());
    }
  }
}

TEST_CASE("contact scenes step bit-identically on 1 and 4 threads", "[contact][parallel]") {
  // the candidate search, the barrier and friction energies, the contact
  // assembly and the CCD run on the stage's threads (docs/contact.md,
  // "Threads"); every kind of body: a soft ball landing (a solid's surface
  // and its self contact against a plane), a 5-box stack (rigid body-body
  // pairs, the rigid CCD), a rod coiling on the ground (segments and their
  // self contact), the 5-link arm pushing a box (link capsules), an arm
  // folding onto itself (two links' pair over their shared joints) and the
  // gripper (kinematic obstacles dragging a soft cube); the cloth below
  RequireSameOnThreads({
      {"ball", BuiltBy([](SceneParams p, Error& e) { return scenes::BallDropScene(p, 0.05, 4, e); }), 1.0 / 120, 40},
      {"box stack", BuiltBy([](SceneParams p, Error& e) { return scenes::BoxStackScene(p, 5, e); }), 1.0 / 60, 30},
      {"rod coil", BuiltBy([](SceneParams p, Error& e) { return scenes::RodCoilScene(p, 100, e); }), 1.0 / 60, 40},
      {"arm push", BuiltBy([](SceneParams p, Error& e) { return scenes::ArmPushScene(p, e); }), 1.0 / 60, 40},
      {"arm fold", BuiltBy([](SceneParams p, Error& e) { return scenes::FoldingArmScene(p, e); }), 1.0 / 60, 40},
      {"gripper",
       [](SceneParams params) {
         params.newton.maxIterations = 100;
         scenes::Builder b(params);
         scenes::Grasp const grasp = scenes::AddGrasp(b, 2);
         real const dhat = b.ActivationDistance();
         Error error;
         ContactScene scene = Built(scenes::Finish(b, 1.5, error), error);
         scene.drive = [grasp, dhat](real, real to, Error& driveError) {
           return scenes::DriveGrasp(grasp, dhat, to, driveError);
         };
         return scene;
       },
       1.0 / 60, 24},
  });
}

TEST_CASE("a cloth folding onto itself steps bit-identically on 1 and 4 threads", "[contact][parallel][long]") {
  // a shell's edge-edge and point-triangle self pairs, tens of thousands of
  // candidates in chunks on the threads ([long]: 4 minutes under the
  // sanitizers, whose build runs the case above)
  RequireSameOnThreads(
      {{"cloth fold", BuiltBy([](SceneParams p, Error& e) { return scenes::ClothFoldScene(p, 12, e); }), 1.0 / 30, 45}});
}

TEST_CASE("a stack of rigid boxes rests on the ground: body-body contact", "[contact][stack]") {
  // three 0.2 m boxes, each started 0.5 d̂ above the one below; their pairs
  // join two bodies' blocks: the pattern grows in its kept order once
  SceneParams params;
  auto scene = MakeScene(params);
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  MakeCollider(*scene, ground);
  real const half = 0.1, gap = 0.5 * params.contact.activationDistance;
  DynamicArray<RigidActor*> boxes;
  for (int i = 0; i < 3; ++i) {
    RigidActorParams body;
    body.mass = 1;
    body.inertia = Real3::Constant(body.mass * (2 * half) * (2 * half) / 6);
    body.position = Real3(0, gap + half + i * (2 * half + gap), 0);
    boxes.push_back(MakeRigid(*scene, body));
    ColliderParams shape;
    shape.actor = boxes.back()->GetHandle();
    shape.shape = ShapeType::Box;
    shape.halfExtents = Real3::Constant(half);
    MakeCollider(*scene, shape);
  }
  Error error;
  real const dt = 1.0 / 60;
  Real3 top = Real3::Zero();  // set at step 59
  std::int64_t buildsAtRest = 0;
  for (int s = 0; s < 120; ++s) {
    bool const stepped = scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    if (s == 59) {
      top = boxes[2]->GetPosition();
      buildsAtRest = scene->GetStats().patternBuilds + scene->GetStats().patternGrowths;
    }
    // exact geometry: each box's lowest corner above the top face of the one below
    for (int i = 0; i < 3; ++i) {
      real lowest = std::numeric_limits<real>::infinity();
      for (int c = 0; c < 8; ++c) {
        Real3 const corner((c & 1) ? half : -half, (c & 2) ? half : -half, (c & 4) ? half : -half);
        lowest = std::min(lowest, boxes[i]->TransformPoint(corner).y());
      }
      real const below = i == 0 ? 0 : boxes[i - 1]->GetPosition().y() + half;
      REQUIRE(lowest > below - 1e-9);
    }
  }
  // at rest: the top box moved less than 1e-4 m over the last second
  INFO("top box drift " << (boxes[2]->GetPosition() - top).norm() << " m");
  CHECK((boxes[2]->GetPosition() - top).norm() < 1e-4);
  // the contacts between the boxes changed the pattern (a growth, or with
  // three bodies a new ordering: their block pairs are more than
  // kReorderFraction of the graph's), and once resting, nothing more
  SceneStats const& stats = scene->GetStats();
  CHECK(stats.contactPatternBuilds >= 1);
  CHECK(stats.patternBuilds + stats.patternGrowths == buildsAtRest);
  CHECK(stats.activeContacts >= 12);
}

TEST_CASE("stacks of 5 rigid boxes and of 5 tet cubes rest for 10 s: no drift, no penetration",
          "[contact][stack][long]") {
  // docs/contact.md scene 4: each stack settles into the barrier's layer in
  // its first second (the boxes sink from 0.9 d̂ to their resting gaps, the
  // cubes compress under the ones above), then must stay put: every point of
  // every body within 1e-4 m of where it was at t = 1 s until t = 10 s, and no
  // two colliders interpenetrating at any step end (the exact check)
  real const dt = 1.0 / 60;
  for (bool const rigid : {true, false}) {
    SceneParams params;
    scenes::Builder b(params);
    DynamicArray<RigidActor*> boxes;
    DynamicArray<DeformableActor*> cubes;
    if (rigid)
      boxes = scenes::AddBoxStack(b, 5);
    else
      cubes = scenes::AddCubeStack(b, 5, 2);
    std::unique_ptr<Scene> scene = b.TakeScene();
    INFO((rigid ? "boxes: " : "cubes: ") << b.GetError().ToString());
    REQUIRE(scene);
    // the points watched: each box's corners, each cube's nodes
    auto points = [&] {
      DynamicArray<Real3> at;
      for (RigidActor const* box : boxes)
        for (int c = 0; c < 8; ++c)
          at.push_back(box->TransformPoint(Real3((c & 1) ? 0.1 : -0.1, (c & 2) ? 0.1 : -0.1, (c & 4) ? 0.1 : -0.1)));
      for (DeformableActor const* cube : cubes)
        for (int i = 0; i < cube->GetNumNodes(); ++i) at.push_back(cube->GetNodePosition(i));
      return at;
    };
    InterpenetrationCheck check(params.contact.activationDistance);
    REQUIRE(check.Find(*scene).empty());
    DynamicArray<Real3> settled;
    real drift = 0;
    long newton = 0;
    int const steps = static_cast<int>(std::lround(10 / dt));
    for (int s = 0; s < steps; ++s) {
      StepChecked(*scene, dt, s, check, newton);
      if (s + 1 == static_cast<int>(std::lround(1 / dt))) settled = points();
      if (settled.empty()) continue;
      DynamicArray<Real3> const now = points();
      for (std::size_t i = 0; i < now.size(); ++i) drift = std::max(drift, (now[i] - settled[i]).norm());
    }
    INFO((rigid ? "boxes" : "cubes") << ": largest drift over [1, 10] s " << drift << " m, "
                                     << static_cast<real>(newton) / steps << " Newton/step");
    std::printf("10 s stack of 5 %s: drift %.3g m, smallest gap %.3g m, %.2f Newton/step\n", rigid ? "boxes" : "cubes",
                drift, check.GetMinGap(), static_cast<real>(newton) / steps);
    CHECK(drift < 1e-4);
    CHECK(scene->GetStats().activeContacts > 0);
  }
}

TEST_CASE("a rod coil dropped on the ground piles onto itself without crossing", "[contact][rod][self][long]") {
  // a two-turn helix (radius 5 cm, pitch 2 cm, rod radius 4 mm): the upper
  // turn lands on the lower one. Checked on the rod's own geometry: every
  // two segments apart by two or more keep their axes at least a diameter
  // apart (the gap of the barrier, thicknesses included, stays positive)
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  ColliderParams ground;
  ground.shape = ShapeType::Plane;
  MakeCollider(*scene, ground);
  RodActorParams rod;
  real const r = 0.004;
  rod.radius = r;
  rod.youngModulus = 1e7;
  rod.density = 1000;
  int const n = 60;
  for (int i = 0; i < n; ++i) {
    real const a = 4 * M_PI * i / (n - 1);
    rod.nodes.push_back(Real3(0.05 * std::cos(a), 0.02 + 0.02 * a / (2 * M_PI), 0.05 * std::sin(a)));
  }
  Error error;
  RodActor* actor = scene->CreateRodActor(rod, error);
  INFO(error.ToString());
  REQUIRE(actor);
  ColliderParams surface;
  surface.actor = actor->GetHandle();
  MakeCollider(*scene, surface);
  int newton = 0, selfContacts = 0;
  real const dt = 1.0 / 120;
  for (int s = 0; s < 120; ++s) {
    bool const stepped = scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    newton += scene->GetStats().newtonIterations;
    DynamicArray<ContactInfo> contacts;
    scene->GetContacts(contacts);
    for (ContactInfo const& c : contacts) selfContacts += c.colliderA == c.colliderB;
    for (int i = 0; i + 1 < n; ++i) {
      REQUIRE(actor->GetNodePosition(i).y() > r);
      for (int j = i + 2; j + 1 < n; ++j) {
        real const d = std::sqrt(contact::EdgeEdgeDistance2(actor->GetNodePosition(i), actor->GetNodePosition(i + 1),
                                                            actor->GetNodePosition(j), actor->GetNodePosition(j + 1)));
        INFO("segments " << i << ", " << j);
        REQUIRE(d > 2 * r);
      }
    }
  }
  CHECK(selfContacts > 0);  // the turns did touch
  CHECK(static_cast<real>(newton) / 120 <= 8);
}

namespace {
/// A box resting on the ground (μ = 0.3) and a static Box obstacle, a
/// paddle 0.4 m tall, 5 cm to its left.
struct Paddle {
  std::unique_ptr<Scene> scene;
  RigidActor* box = nullptr;
  Collider* paddle = nullptr;
};

Paddle MakePaddle() {
  Paddle out;
  SceneParams params;
  out.scene = MakeScene(params);
  MakeGround(*out.scene, 0.3);
  out.box = MakeRigidBox(*out.scene, Real3(0, 0.1 + 0.5 * params.contact.activationDistance, 0), Quat::Identity(),
                         Real3::Constant(0.1), 1, 0.3);
  ColliderParams paddle;
  paddle.shape = ShapeType::Box;
  paddle.halfExtents = Real3(0.02, 0.2, 0.3);
  paddle.position = Real3(-0.17, 0.25, 0);
  out.paddle = MakeCollider(*out.scene, paddle);
  return out;
}
}  // namespace

TEST_CASE("a kinematic paddle pushes a box across the ground and never passes into it", "[contact][kinematic]") {
  // the paddle moves at 0.5 m/s along +x by a target per step: it reaches
  // the box after 0.1 s and pushes it (μ = 0.3 against the ground) at its
  // own speed; the contact touches only the box's own block: no pattern
  // build after the first step
  Paddle p = MakePaddle();
  InterpenetrationCheck check(p.scene->GetParams().contact.activationDistance);
  real const dt = 1.0 / 60, speed = 0.5;
  Error error;
  int newton = 0;
  std::int64_t buildsAfterFirst = 0;
  int const steps = 60;
  for (int s = 0; s < steps; ++s) {
    Real3 const target = p.paddle->GetPosition() + Real3(speed * dt, 0, 0);
    REQUIRE(p.paddle->SetTargetTransform(target, Quat::Identity(), error));
    bool const stepped = p.scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    REQUIRE(p.paddle->GetPosition() == target);  // it got there
    newton += p.scene->GetStats().newtonIterations;
    if (s == 0) buildsAfterFirst = p.scene->GetStats().patternBuilds;
    std::string const found = check.Find(*p.scene);
    INFO(found);
    REQUIRE(found.empty());
  }
  SceneStats const& stats = p.scene->GetStats();
  INFO("box at x = " << p.box->GetPosition().x() << ", vx = " << p.box->GetLinearVelocity().x() << ", "
                     << static_cast<real>(newton) / steps << " Newton iterations per step");
  // pushed along at the paddle's speed, its left face just ahead of the paddle's right one
  CHECK(p.box->GetLinearVelocity().x() == Approx(speed).epsilon(0.02));
  real const paddleFace = p.paddle->GetPosition().x() + 0.02, boxFace = p.box->GetPosition().x() - 0.1;
  CHECK(boxFace > paddleFace);
  CHECK(boxFace - paddleFace < p.scene->GetParams().contact.activationDistance);
  CHECK(stats.patternBuilds == buildsAfterFirst);
  CHECK(stats.contactPatternBuilds == 0);
  CHECK(static_cast<real>(newton) / steps <= 8);
}

TEST_CASE("a rising kinematic ground lifts a resting box", "[contact][kinematic]") {
  // the ground plane rises at 0.2 m/s: the box rides on it at that speed
  SceneParams params;
  auto scene = MakeScene(params);
  Collider* ground = MakeGround(*scene);
  RigidActor* box = MakeRigidBox(*scene, Real3(0, 0.1 + 0.5 * params.contact.activationDistance, 0),
                                 Quat::Identity(), Real3::Constant(0.1), 1);
  InterpenetrationCheck check(params.contact.activationDistance);
  real const dt = 1.0 / 60;
  Error error;
  for (int s = 0; s < 60; ++s) {
    REQUIRE(ground->SetTargetTransform(ground->GetPosition() + Real3(0, 0.2 * dt, 0), Quat::Identity(), error));
    bool const stepped = scene->Step(dt, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    REQUIRE(check.Find(*scene).empty());
  }
  CHECK(ground->GetPosition().y() == Approx(0.2).epsilon(1e-12));
  CHECK(box->GetLinearVelocity().y() == Approx(0.2).epsilon(0.01));
  CHECK(box->GetPosition().y() - 0.1 - ground->GetPosition().y() > 0);
}

TEST_CASE("moving a static obstacle: bad poses, a body's collider and a teleport into a body are refused",
          "[contact][kinematic][errors]") {
  Paddle p = MakePaddle();
  Error error;
  Real3 const start = p.paddle->GetPosition();
  CHECK_FALSE(p.paddle->SetTargetTransform(Real3(0, std::nan(""), 0), Quat::Identity(), error));
  CHECK(Mentions(error, "position"));
  CHECK_FALSE(p.paddle->SetTransform(start, Quat(2, 0, 0, 0), error));
  CHECK(Mentions(error, "rotation"));
  // beyond the contact range: the pose itself, or a vertex of the shape there
  CHECK_FALSE(p.paddle->SetTargetTransform(Real3(1e10, 0, 0), Quat::Identity(), error));
  CHECK(Mentions(error, "SetTargetTransform: position must be finite and within ±1000000000"));
  CHECK_FALSE(p.paddle->SetTransform(Real3(kMaxContactCoordinate, 0, 0), Quat::Identity(), error));
  CHECK(Mentions(error, "SetTransform: collider 2's vertex 1 (world) must be finite and within"));
  CHECK(p.paddle->GetPosition() == start);
  Collider* boxShape = p.scene->GetCollider(1);
  REQUIRE(boxShape);
  REQUIRE(boxShape->Moves());
  CHECK_FALSE(boxShape->SetTargetTransform(Real3::Zero(), Quat::Identity(), error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Mentions(error, "carried by an actor"));
  // a teleport into the box: refused, naming both colliders; nothing moved
  CHECK_FALSE(p.paddle->SetTransform(Real3(-0.05, 0.25, 0), Quat::Identity(), error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Mentions(error, "SetTransform: collider 2 (Box) intersects collider 1 (Box)"));
  CHECK(p.paddle->GetPosition() == start);
  InterpenetrationCheck check(p.scene->GetParams().contact.activationDistance);
  CHECK(check.Find(*p.scene).empty());
  // a teleport clear of it is taken
  REQUIRE(p.paddle->SetTransform(Real3(-0.5, 0.25, 0), Quat::Identity(), error));
  CHECK(p.paddle->GetPosition() == Real3(-0.5, 0.25, 0));
}

TEST_CASE("a failed step leaves a kinematic obstacle where it was, its target pending", "[contact][kinematic]") {
  Paddle p = MakePaddle();
  Error error;
  Real3 const start = p.paddle->GetPosition(), target = start + Real3(0.01, 0, 0);
  REQUIRE(p.paddle->SetTargetTransform(target, Quat::Identity(), error));
  internal::SetFaultInjectionForTesting(*p.scene, {.failLinearSolveAtIteration = 1});
  CHECK_FALSE(p.scene->Step(1.0 / 60, error));
  CHECK(p.paddle->GetPosition() == start);
  internal::SetFaultInjectionForTesting(*p.scene, {});
  REQUIRE(p.scene->Step(1.0 / 60, error));
  CHECK(p.paddle->GetPosition() == target);
  // and a step without a new target leaves it there
  REQUIRE(p.scene->Step(1.0 / 60, error));
  CHECK(p.paddle->GetPosition() == target);
}

TEST_CASE("the exact check's point-triangle distance: the library's on random triangles, finite on a sliver",
          "[contact][check]") {
  // the independent check (scenes/interpenetration.h) against the
  // library's classified distance: they agree to 1e-12 of the O(1) scale on
  // random triangles and points near them
  std::mt19937 rng(5);
  std::uniform_real_distribution<real> unit(-1, 1);
  auto random = [&] { return Real3(unit(rng), unit(rng), unit(rng)); };
  for (int k = 0; k < 2000; ++k) {
    Real3 const a = random(), b = random(), c = random(), p = random();
    auto const type = contact::PointTriangleDistanceType(p, a, b, c);
    real const library = std::sqrt(contact::PointTriangleDistance2(p, a, b, c, type));
    CAPTURE(k);
    REQUIRE(InterpenetrationCheck::PointTriangleDistance(p, a, b, c) == Approx(library).margin(1e-12));
  }
  // a Box face of edges ~1e9 m and 0.3 m passing 0.02 m from the point
  // (fuzz_contact, tests/fuzz/corpus/contact/nan_gap_body_inside_huge_box.bin):
  // Ericson's barycentric differences of ~1e18 cancelled to 0/0 there
  Real3 const p(0.1, 0.48450156249999998, -0.20000000000000001);
  Real3 const a(-2216160.9397460758, 798001470.76195347, 602651424.96314514);
  Real3 const b(2216160.8934969711, -798001471.81688321, -602651425.69425714);
  Real3 const c(2216161.0162475649, -798001471.9947623, -602651425.45826709);
  real const check = InterpenetrationCheck::PointTriangleDistance(p, a, b, c);
  REQUIRE(std::isfinite(check));
  // the distance to the triangle's plane (in long double) bounds it from
  // below, an edge's distance from above
  using Long3 = Eigen::Matrix<long double, 3, 1>;
  Long3 const la = a.cast<long double>(), lb = b.cast<long double>(), lc = c.cast<long double>();
  Long3 const normal = (lc - lb).cross(la - lb).normalized();
  real const toPlane = static_cast<real>(std::abs(normal.dot(p.cast<long double>() - lb)));
  CHECK(check <= InterpenetrationCheck::PointSegmentDistance(p, b, c));
  CHECK(check >= toPlane - 1e-6);  // round-off of coordinates ~1e9 m: ~1e-7 m
  std::printf("sliver: check %.9g m, plane %.9g m\n", check, toPlane);
  // the library's distance of the same pair is finite too
  auto const type = contact::PointTriangleDistanceType(p, a, b, c);
  CHECK(std::isfinite(contact::PointTriangleDistance2(p, a, b, c, type)));
}

TEST_CASE("a cloth landing edge first outruns its stage's self bound: the candidates are found again mid-stage",
          "[contact][deformable][self]") {
  // dt = 1/30: the landed edge stops while the rest of the cloth falls on,
  // further relative to the cloth's mean than the self bound the stage
  // start's uniform fall gave (~1.2 cm). Without the mid-stage search
  // Newton stalled at the bound's edge (the safe step 0 from the 5th
  // iteration on: NewtonFailed after any number of iterations). The cap is
  // raised: the crawl of a cloth folding at this dt is docs/contact.md's open
  // case; here the stall is the point
  SceneParams params;
  params.newton.maxIterations = 400;
  ContactScene scene = ClothFoldScene(params, 12);
  InterpenetrationCheck check(params.contact.activationDistance);
  int recentered = 0;
  for (int s = 0; s < 2; ++s) {  // the landing is the second step
    Error error;
    bool const stepped = scene.scene->Step(1.0 / 30, error);
    INFO("step " << s << ": " << error.ToString());
    REQUIRE(stepped);
    std::string const found = check.Find(*scene.scene);
    INFO(found);
    REQUIRE(found.empty());
    recentered += scene.scene->GetStats().contactRecenterings;
    std::printf("cloth landing edge first, step %d: %d Newton iterations, %d recenterings\n", s,
                scene.scene->GetStats().newtonIterations, scene.scene->GetStats().contactRecenterings);
  }
  CHECK(recentered > 0);
  CHECK(scene.scene->GetStats().activeContacts > 0);
  // the contact phases of the landing step: each ran, they are parts of the
  // step, and the contact assembly is part of the assembly (docs/contact.md,
  // "Costs")
  SceneStats const& stats = scene.scene->GetStats();
  CHECK(stats.contactBroadPhaseSeconds > 0);
  CHECK(stats.contactNarrowPhaseSeconds > 0);
  CHECK(stats.contactCcdSeconds > 0);
  CHECK(stats.contactAssemblySeconds > 0);
  CHECK(stats.contactAssemblySeconds <= stats.assemblySeconds);
  CHECK(stats.contactBroadPhaseSeconds + stats.contactNarrowPhaseSeconds + stats.contactCcdSeconds +
            stats.contactAssemblySeconds <=
        stats.stepSeconds);
}

TEST_CASE("a kinematic gripper lifts a soft cube against gravity and holds it without creep",
          "[contact][kinematic][friction]") {
  // scenes::GraspScene: two static box paddles, moved by targets, squeeze a
  // 1 kg soft cube 1.5 mm a side, lift it 0.1 m and hold still; friction
  // alone carries its weight. The stick anchors keep it where the lift
  // left it (the creep the engines users compare with show under a load
  // below the friction limit)
  SceneParams params;
  params.gravity = Real3(0, -scenes::kGravity, 0);
  // the lift's steps take up to 44 Newton iterations (below): a cap with room
  params.newton.maxIterations = 100;
  scenes::Builder b(params);
  scenes::Grasp const grasp = scenes::AddGrasp(b, 3);
  INFO(b.GetError().ToString());
  REQUIRE(b.Ok());
  std::unique_ptr<Scene> scene = b.TakeScene();
  real const dhat = params.contact.activationDistance;
  InterpenetrationCheck check(dhat);
  real const dt = 1.0 / 60;
  int const steps = 90;  // 1.5 s: closed at 0.25 s, lifted at 0.5 s, then held
  auto centroid = [&] {
    Real3 sum = Real3::Zero();
    for (Real3 const& p : grasp.cube->GetNodePositions()) sum += p;
    return Real3(sum / grasp.cube->GetNumNodes());
  };
  Real3 const start = centroid();
  Real3 held;  // where the cube is half way through the hold
  int const holdFrom = static_cast<int>(std::lround(1.0 / dt));
  Error error;
  long newton = 0;
  for (int s = 0; s < steps; ++s) {
    REQUIRE(scenes::DriveGrasp(grasp, dhat, (s + 1) * dt, error));
    StepChecked(*scene, dt, s, check, newton);
    if (s + 1 == holdFrom) held = centroid();
  }
  Real3 const end = centroid();
  real const creep = (end - held).norm() / ((steps - holdFrom) * dt);
  INFO("lifted " << end.y() - start.y() << " m, creep " << creep * 1e6 << " um/s over the last "
                 << (steps - holdFrom) * dt << " s, " << static_cast<real>(newton) / steps << " Newton/step");
  // lifted with the paddles (less the cube's sag and its slip while the
  // lift accelerated it: within 5 mm), held without creep (measured: lifted
  // 0.0995 m, creep 1e-18 m/s: the stick anchors hold it)
  CHECK(end.y() - start.y() == Approx(scenes::kGraspLift).margin(0.005));
  CHECK(creep < 1e-6);
  // Newton: 8.2 iterations per step over the run, but 20–44 in each step
  // of the lift (docs/contact.md, "Not met yet": a kinematic obstacle that
  // drags a body by friction advances with Newton's step, and a sliding
  // contact's friction has no stiffness along its slip)
  CHECK(static_cast<real>(newton) / steps <= 10);
}
