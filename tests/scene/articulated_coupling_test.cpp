// Articulated links coupled through the rigid constraint types, stepped by
// the scene: a pendulum built as an articulated link held by a
// RigidPivotPosition against the same body built as a RigidActor; an
// articulated arm holding a rigid ball by a RigidSphericalJoint converging
// as 1/k to the arm with the ball as a third link on a spherical joint; and
// the constraints on links destroyed with their actor.
#include "test_scenes.h"

#include <cmath>
#include <cstdio>

using namespace superdex;
using namespace superdex::test;

namespace {

SceneParams Tight() {
  SceneParams params;
  params.integrator = IntegratorType::BackwardEuler;
  params.gravity = Real3(0, -9.81, 0);
  params.newton.velocityTolerance = 1e-11;
  return params;
}

}  // namespace

TEST_CASE("a pendulum built as an articulated link held by a RigidPivotPosition moves as the same body built as "
          "a RigidActor",
          "[scene][articulated][rigid]") {
  // one body, its link frame away from its centre of mass: mass 2 kg,
  // principal inertia (0.05, 0.08, 0.11) kg·m², centre of mass c in the link
  // frame, turned by R, pinned at r (link frame) to the world origin
  real const mass = 2;
  Real3 const inertia(0.05, 0.08, 0.11), com(0.1, -0.05, 0.02), pivot(0.05, 0.4, -0.03);
  Quat const rotation(Eigen::AngleAxis<real>(0.8, Real3(0.2, 0.3, 1).normalized()));
  Real3 const origin = -(rotation * pivot);  // the link frame's origin: the pivot at the world origin
  real const k = 1e5;

  auto rigidScene = MakeScene(Tight());
  RigidActorParams body;
  body.mass = mass;
  body.inertia = inertia;
  body.position = origin + rotation * com;  // a rigid actor's frame is its centre of mass
  body.rotation = rotation;
  RigidActor* rigid = MakeRigid(*rigidScene, body);
  Error error;
  RigidPivotPositionConstraintParams pin;
  pin.actor = rigid->GetHandle();
  pin.localPos = pivot - com;
  pin.stiffness = k;
  REQUIRE(rigidScene->CreateRigidPivotPositionConstraint(pin, error));

  // the same body as the free root link of an articulated actor
  auto treeScene = MakeScene(Tight());
  ArticulatedActorParams tree;
  ArticulatedLinkParams link;
  link.parent = -1;
  link.joint = JointType::Free;
  link.mass = mass;
  link.inertia = inertia;
  link.centerOfMass = com;
  Real3 const start = origin;
  Real3 const turn = Eigen::AngleAxis<real>(rotation).angle() * Eigen::AngleAxis<real>(rotation).axis();
  link.initialPosition = {start.x(), start.y(), start.z(), turn.x(), turn.y(), turn.z()};
  tree.links.push_back(link);
  ArticulatedActor* articulated = MakeArticulated(*treeScene, tree);
  int const l = 0;
  pin.actor = articulated->GetHandle();
  pin.link = l;
  pin.localPos = pivot;
  REQUIRE(treeScene->CreateRigidPivotPositionConstraint(pin, error));
  REQUIRE((articulated->GetLinkCenterOfMass(l) - rigid->GetPosition()).norm() <= 1e-15);

  // 1 s at dt = 1/100: a swing of ~0.8 rad
  real worstPosition = 0, worstRotation = 0;
  for (int step = 0; step < 100; ++step) {
    StepOk(*rigidScene, 0.01);
    StepOk(*treeScene, 0.01);
    worstPosition = std::max(worstPosition, (articulated->GetLinkCenterOfMass(l) - rigid->GetPosition()).norm());
    worstRotation =
        std::max(worstRotation, articulated->GetLinkRotation(l).angularDistance(rigid->GetRotation()));
  }
  // a single joint group: the tree recursion solves the actor
  REQUIRE(articulated->IsSolvedOnTree());
  std::printf("pendulum on a free link vs a rigid actor, 1 s at dt = 1/100: largest difference %.2e m, %.2e rad\n",
              worstPosition, worstRotation);
  REQUIRE(rigid->GetPosition().norm() > 0.1);
  // the same incremental potential in two sets of coordinates (a rigid
  // body's world increments, a free joint's local ones): both stages solved
  // to the tight tolerance (velocity 1e-11 m/s), the trajectories agree to a
  // small multiple of it over 100 steps
  REQUIRE(worstPosition <= 1e-8);
  REQUIRE(worstRotation <= 1e-8);
}

namespace {

// two uniform rods of length L hinged about z, released along +x, and a ball
// of mass m_b at the tip of the second
constexpr real kLength = 0.5, kRodMass = 1.0, kBallMass = 0.5;
Real3 const kBallInertia(0.004, 0.005, 0.006);

ArticulatedActorParams Arm(bool withBall) {
  ArticulatedActorParams p = TwoRevoluteLinks(kLength, kRodMass);
  if (withBall) {
    ArticulatedLinkParams ball;
    ball.parent = 1;
    ball.joint = JointType::Spherical;
    ball.parentToJointPosition = Real3(kLength, 0, 0);
    ball.mass = kBallMass;
    ball.inertia = kBallInertia;
    p.links.push_back(ball);
  }
  return p;
}

/// A rigid ball at the arm's tip held by a RigidSphericalJoint of stiffness
/// k on link 1.
Constraint* HoldBall(Scene& scene, ArticulatedActor& arm, RigidActor& ball, real k) {
  RigidSphericalJointConstraintParams joint;
  joint.actorA = arm.GetHandle();
  joint.linkA = 1;
  joint.localPosA = Real3(kLength, 0, 0);
  joint.actorB = ball.GetHandle();
  joint.stiffness = k;
  Error error;
  Constraint* c = scene.CreateRigidSphericalJointConstraint(joint, error);
  INFO(error.ToString());
  REQUIRE(c);
  return c;
}

}  // namespace

TEST_CASE("an articulated arm holding a rigid ball by a RigidSphericalJoint on its link converges as 1/k to the "
          "ball as a third link",
          "[scene][articulated][rigid]") {
  real const dt = 1.0 / 400, endTime = 0.5;
  int const steps = static_cast<int>(std::lround(endTime / dt));
  Error error;
  auto referenceScene = MakeScene(Tight());
  ArticulatedActor* reference = MakeArticulated(*referenceScene, Arm(true));
  StepOk(*referenceScene, dt, steps);
  Real3 const expected = reference->GetLinkCenterOfMass(2);
  std::printf("arm + rigid ball on a RigidSphericalJoint vs the ball as a spherical link, t = %.1f s, dt = 1/400:\n",
              endTime);
  DynamicArray<real> stiffnesses, errors;
  for (real k : {1e4, 1e5, 1e6, 1e7}) {
    auto scene = MakeScene(Tight());
    ArticulatedActor* arm = MakeArticulated(*scene, Arm(false));
    RigidActorParams body;
    body.mass = kBallMass;
    body.inertia = kBallInertia;
    body.position = Real3(2 * kLength, 0, 0);
    RigidActor* ball = MakeRigid(*scene, body);
    HoldBall(*scene, *arm, *ball, k);
    StepOk(*scene, dt, steps);
    // the joint couples the arm with another actor: the tree, coupled by
    // its Schur complement over the ball's six DoFs
    REQUIRE(arm->IsSolvedOnTree());
    REQUIRE(arm->GetNumCoupledDofs() == 6);
    real const e = (ball->GetPosition() - expected).norm();
    stiffnesses.push_back(k);
    errors.push_back(e);
    std::printf("  k = %.0e N/m: ball position error %.3e m\n", k, e);
  }
  real const power = FitOrder(stiffnesses, errors);
  std::printf("  fitted power of k: %.3f\n", power);
  CAPTURE(power);
  REQUIRE(expected.norm() > 0.5);
  // error ∝ 1/k over three decades (the compliant joint's stretch under the
  // ball's load), the stiffest within 1e-5 m of the rigid answer
  REQUIRE(std::abs(power + 1) <= 0.15);
  REQUIRE(errors.back() <= 1e-5);
}

TEST_CASE("constraints on an articulated actor's links are destroyed with it", "[scene][articulated]") {
  auto scene = MakeScene(Tight());
  Error error;
  ArticulatedActor* arm = MakeArticulated(*scene, Arm(false));
  RigidActorParams body;
  body.position = Real3(2 * kLength, 0, 0);
  RigidActor* ball = MakeRigid(*scene, body);
  Constraint* held = HoldBall(*scene, *arm, *ball, 1e5);
  RigidPivotPositionConstraintParams pin;
  pin.actor = arm->GetHandle();
  pin.link = 0;
  pin.stiffness = 1e5;
  Constraint* pinned = scene->CreateRigidPivotPositionConstraint(pin, error);
  REQUIRE(pinned);
  ConstraintHandle const heldHandle = held->GetHandle(), pinnedHandle = pinned->GetHandle();
  StepOk(*scene, 0.01, 3);
  REQUIRE(scene->DestroyActor(arm->GetHandle(), error));
  REQUIRE(scene->GetConstraint(heldHandle) == nullptr);
  REQUIRE(scene->GetConstraint(pinnedHandle) == nullptr);
  REQUIRE(scene->GetNumConstraints() == 0);
  // the ball falls freely now
  real const y = ball->GetPosition().y();
  StepOk(*scene, 0.01, 3);
  REQUIRE(ball->GetPosition().y() < y);
}

TEST_CASE("single-body constraints on links are folded into the tree: the same trajectory as the dense block",
          "[scene][articulated][tree]") {
  // a branched tree of every joint type (floating or fixed base), a
  // RigidPivotPosition on a deep link with a moving target, a
  // RigidPivotRotation and a RigidPivotToRigidTarget on two others, gravity,
  // 0.5 s of BDF2 at dt = 1/100, exact Hessians (the geometric stiffness,
  // with the link frames' curvature). The tree takes the constraints as
  // wrenches and stiffnesses at their links, the dense block as blocks over
  // their paths; both take the same exact Newton steps and converge to the
  // tight tolerance, so the trajectories agree far below the integrator's
  // error. (With the Gauss–Newton or diagonal blocks Newton converges only
  // linearly here, and not to 1e-10 in 50 iterations, on either solve.)
  bool const floating = GENERATE(false, true);
  CAPTURE(floating);
  auto run = [&](ArticulatedBlockSolve solve, DynamicArray<real>& positions, SceneStats& stats, int& iterations) {
    SceneParams params = Tight();
    params.integrator = IntegratorType::Bdf2;
    params.newton.velocityTolerance = 1e-10;
    auto scene = MakeScene(params);
    ArticulatedActorParams const p = BranchedTree(floating, solve);
    Error error;
    ArticulatedActor* actor = MakeArticulated(*scene, p);
    RigidPivotPositionConstraintParams pin;
    pin.actor = actor->GetHandle();
    pin.link = 6;
    pin.localPos = Real3(0.1, 0.05, 0);
    pin.position = actor->GetLinkPosition(6) + actor->GetLinkRotation(6) * pin.localPos;
    pin.stiffness = 2e3;
    pin.damping = 5;
    Constraint* moving = scene->CreateRigidPivotPositionConstraint(pin, error);
    REQUIRE(moving);
    RigidPivotRotationConstraintParams turn;
    turn.actor = actor->GetHandle();
    turn.link = 7;
    turn.rotation = actor->GetLinkRotation(7) * Quat(Eigen::AngleAxis<real>(0.4, Real3(0, 0, 1)));
    turn.stiffness = 20;
    turn.damping = 0.1;
    REQUIRE(scene->CreateRigidPivotRotationConstraint(turn, error));
    RigidPivotToRigidTargetConstraintParams carried;
    carried.actor = actor->GetHandle();
    carried.link = 5;
    carried.localPos = Real3(0.05, 0, 0.02);
    carried.position = Real3(0.1, -0.1, 0.05);
    carried.rotation = Quat(Eigen::AngleAxis<real>(0.3, Real3(1, 0, 0)));
    carried.stiffness = 500;
    REQUIRE(scene->CreateRigidPivotToRigidTargetConstraint(carried, error));
    for (int step = 0; step < 50; ++step) {
      REQUIRE(moving->SetTargetPosition(pin.position + Real3(0, 0.2 * std::sin(0.2 * step), 0), error));
      StepOk(*scene, 1.0 / 100);
      iterations += scene->GetStats().newtonIterations;
    }
    REQUIRE(actor->IsSolvedOnTree() == (solve == ArticulatedBlockSolve::Tree));
    positions = actor->GetJointPositions();
    stats = scene->GetStats();
  };
  DynamicArray<real> tree, dense;
  SceneStats treeStats, denseStats;
  int treeIterations = 0, denseIterations = 0;
  run(ArticulatedBlockSolve::Tree, tree, treeStats, treeIterations);
  run(ArticulatedBlockSolve::Dense, dense, denseStats, denseIterations);
  real difference = 0, size = 0;
  for (std::size_t k = 0; k < tree.size(); ++k) {
    difference = std::max(difference, std::abs(tree[k] - dense[k]));
    size = std::max(size, std::abs(dense[k]));
  }
  std::printf("links' constraints folded into the tree vs the dense block (%s base): largest joint "
              "coordinate difference %.2e after 0.5 s; Newton iterations %d and %d\n",
              floating ? "floating" : "fixed", difference, treeIterations, denseIterations);
  REQUIRE(size > 0.1);
  CHECK(difference <= 1e-9);
  // the same exact Newton steps where the Hessian is positive definite (the
  // two modify indefinite ones differently): about as many iterations
  // (measured 259 / 254 fixed, 281 / 271 floating). Without the link
  // frames' curvature in the tree it took 505 / 257 and a step failed
  CHECK(treeIterations <= 1.2 * denseIterations);
  // the scene's matrix holds the joints' diagonal blocks only: no block over
  // a constraint's path
  int const n = static_cast<int>(tree.size());
  CHECK(treeStats.hessianNonzeros < 3 * n);
}


TEST_CASE("links coupled with other bodies through the tree's Schur complement step as the dense block",
          "[scene][articulated][tree]") {
  // a 12-link spherical chain carrying, on its tip link, a rigid ball (a
  // RigidSphericalJoint, and a JointRotationTracking with the link as body
  // B), a tet block by two
  // DeformableNodeToRigid holds and a rod clamped by its first node and
  // element; a RigidPivotPosition on a middle link (folded). Gravity along
  // the chain (hanging: the exact Hessian stays positive definite, so both
  // solves take exact Newton steps), BDF2, exact Hessians with the geometric
  // stiffness, 0.4 s at dt = 1/100. The tree solves its block by the
  // recursion and the scene's matrix holds only the other bodies' coupled
  // DoFs' block −C A⁻¹ Cᵀ; the dense block holds every path. Same Newton
  // steps: trajectories equal far below the integrator's error.
  auto run = [&](ArticulatedBlockSolve solve, DynamicArray<real>& positions, Real3& ballPosition,
                 SceneStats& stats, int& iterations) {
    CAPTURE(static_cast<int>(solve));
    SceneParams params;
    params.integrator = IntegratorType::Bdf2;
    params.gravity = Real3(9.81, 0, 0);
    params.newton.velocityTolerance = 1e-8;
    params.newton.constraintHessian = ConstraintHessian::GeometricStiffness;
    auto scene = MakeScene(params);
    int const n = 12;
    Error error;
    // a sideways push: the chain swings
    ArticulatedActorParams chain = SphericalChain(n, solve);
    for (ArticulatedLinkParams& link : chain.links) link.initialVelocity = {0, 0.3, 0.3};
    ArticulatedActor* actor = MakeArticulated(*scene, chain);
    RigidActorParams body;
    body.position = Real3(0.1 * n + 0.2, 0, 0);
    body.mass = 0.5;
    RigidActor* ball = MakeRigid(*scene, body);
    RigidSphericalJointConstraintParams joint;
    joint.actorA = actor->GetHandle();
    joint.linkA = n - 1;
    joint.localPosA = Real3(0.2, 0, 0);
    joint.actorB = ball->GetHandle();
    joint.localPosB = Real3(-0.1, 0, 0);
    joint.stiffness = 1e4;
    REQUIRE(scene->CreateRigidSphericalJointConstraint(joint, error));
    // the ball's rotation tracks the link's (the link as body B)
    JointRotationTrackingConstraintParams weld;
    weld.actorA = ball->GetHandle();
    weld.actorB = actor->GetHandle();
    weld.linkB = n - 1;
    weld.stiffness = 50;
    REQUIRE(scene->CreateJointRotationTrackingConstraint(weld, error));
    // a node of a tet block or a rod held on the tip link
    auto hold = [&](ActorHandle body, int node) {
      DeformableNodeToRigidConstraintParams params;
      params.deformableActor = body;
      params.deformableNodeIndex = node;
      params.rigidActor = actor->GetHandle();
      params.rigidLink = n - 1;
      params.stiffness = 1e4;
      REQUIRE(scene->CreateDeformableNodeToRigidConstraint(params, error));
    };
    DeformableActor* block = MakeBox(*scene, Real3(0.1 * n, 0.05, -0.05), Real3(0.1, 0.1, 0.1), {1, 1, 1},
                                     DeformableActorParams{});
    for (int node : {0, 4}) hold(block->GetHandle(), node);
    RodActorParams rodParams;
    rodParams.radius = 0.005;
    RodActor* rod = MakeStraightRod(*scene, Real3(0.1 * n, -0.05, 0), Real3(0, -1, 0), 0.15, 3, rodParams);
    hold(rod->GetHandle(), 0);
    RodElementRotationToRigidConstraintParams twist;
    twist.rigidActor = actor->GetHandle();
    twist.rigidLink = n - 1;
    twist.rodActor = rod->GetHandle();
    twist.stiffness = 10;
    REQUIRE(scene->CreateRodElementRotationToRigidConstraint(twist, error));
    RigidPivotPositionConstraintParams pin;
    pin.actor = actor->GetHandle();
    pin.link = n / 2;
    pin.position = actor->GetLinkPosition(n / 2);
    pin.stiffness = 100;
    REQUIRE(scene->CreateRigidPivotPositionConstraint(pin, error));
    for (int step = 0; step < 40; ++step) {
      StepOk(*scene, 1.0 / 100);
      iterations += scene->GetStats().newtonIterations;
    }
    REQUIRE(actor->IsSolvedOnTree() == (solve == ArticulatedBlockSolve::Tree));
    if (solve == ArticulatedBlockSolve::Tree) {
      REQUIRE(actor->GetNumCoupledConstraints() == 6);
      // the ball's 6, two block nodes' 6, the rod's first node and element (8)
      REQUIRE(actor->GetNumCoupledDofs() == 20);
    }
    positions = actor->GetJointPositions();
    ballPosition = ball->GetPosition();
    stats = scene->GetStats();
  };
  DynamicArray<real> tree, dense;
  Real3 treeBall, denseBall;
  SceneStats treeStats, denseStats;
  int treeIterations = 0, denseIterations = 0;
  run(ArticulatedBlockSolve::Dense, dense, denseBall, denseStats, denseIterations);
  run(ArticulatedBlockSolve::Tree, tree, treeBall, treeStats, treeIterations);
  real difference = 0, size = 0;
  for (std::size_t k = 0; k < tree.size(); ++k) {
    difference = std::max(difference, std::abs(tree[k] - dense[k]));
    size = std::max(size, std::abs(dense[k]));
  }
  real const ballDifference = (treeBall - denseBall).norm();
  std::printf("links coupled by the Schur complement vs the dense block: largest joint coordinate difference "
              "%.2e, ball %.2e m after 0.4 s; Newton iterations %d and %d; Hessian entries %lld and %lld\n",
              difference, ballDifference, treeIterations, denseIterations,
              static_cast<long long>(treeStats.hessianNonzeros), static_cast<long long>(denseStats.hessianNonzeros));
  REQUIRE(size > 0.05);
  CHECK(difference <= 1e-9);
  CHECK(ballDifference <= 1e-9);
  // the same exact Newton steps where the Hessian is positive definite (the
  // two would modify an indefinite one differently): as many iterations
  // (measured 237 and 237)
  CHECK(treeIterations <= 1.1 * denseIterations);
  // no block over the paths (36 DoFs, 666 upper entries on the dense block)
  CHECK(treeStats.hessianNonzeros < denseStats.hessianNonzeros - 500);
}


TEST_CASE("a parallelogram four-bar closed by a RigidSphericalJoint between two links of one actor swings as its "
          "one-DoF pendulum",
          "[scene][articulated]") {
  // a fixed ground link; crank (link 1) and rocker (link 3) of length L
  // hinged about z at (0, 0, 0) and (d, 0, 0); the coupler (link 2, length
  // d) hinged on the crank's tip, its far end joined to the rocker's tip by
  // a RigidSphericalJoint (a kinematic loop in one actor). Released at θ₀
  // from hanging, the coupler translates without turning and θ follows
  // (2 m L²/3 + m_c L²) θ̈ = −(m + m_c) g L sin θ (uniform rods m, coupler m_c)
  real const L = 0.5, d = 0.8, m = 1, mc = 0.6, g = 9.81, theta0 = 0.7;
  ArticulatedBlockSolve const solve = GENERATE(ArticulatedBlockSolve::Tree, ArticulatedBlockSolve::Dense);
  CAPTURE(static_cast<int>(solve));
  ArticulatedActorParams p;
  p.blockSolve = solve;
  ArticulatedLinkParams ground;
  ground.joint = JointType::Fixed;
  p.links.push_back(ground);
  auto bar = [&](int parent, Real3 const& at, real angle) {
    ArticulatedLinkParams link;
    link.parent = parent;
    link.joint = JointType::Revolute;
    link.axis = Real3::UnitZ();
    link.parentToJointPosition = at;
    link.mass = m;
    link.centerOfMass = Real3(0, -L / 2, 0);
    link.inertia = Real3(m * L * L / 12, 1e-4, m * L * L / 12);
    link.initialPosition = {angle};
    return link;
  };
  p.links.push_back(bar(0, Real3::Zero(), theta0));  // crank
  ArticulatedLinkParams coupler = bar(1, Real3(0, -L, 0), -theta0);
  coupler.mass = mc;
  coupler.centerOfMass = Real3(d / 2, 0, 0);
  coupler.inertia = Real3(1e-4, mc * d * d / 12, mc * d * d / 12);
  p.links.push_back(coupler);
  p.links.push_back(bar(0, Real3(d, 0, 0), theta0));  // rocker
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.gravity = Real3(0, -g, 0);
  params.newton.velocityTolerance = 1e-9;
  auto scene = MakeScene(params);
  ArticulatedActor* actor = MakeArticulated(*scene, p);
  RigidSphericalJointConstraintParams close;
  close.actorA = close.actorB = actor->GetHandle();
  close.linkA = 2;
  close.localPosA = Real3(d, 0, 0);
  close.linkB = 3;
  close.localPosB = Real3(0, -L, 0);
  close.stiffness = 1e7;
  Error error;
  Constraint* loop = scene->CreateRigidSphericalJointConstraint(close, error);
  INFO(error.ToString());
  REQUIRE(loop);
  for (real value : loop->GetDeviation()) REQUIRE(std::abs(value) <= 1e-14);
  // its DoFs: the crank's and the coupler's joints, then the rocker's
  REQUIRE(loop->GetNumDofs() == 3);

  // the reference: RK4 on the pendulum at 1e-5 s
  real const omega2 = g * (m + mc) / (L * (2 * m / 3 + mc));
  real theta = theta0, rate = 0;
  real const h = 1e-5, dt = 1e-3, endTime = 1.0;
  int const substeps = static_cast<int>(std::lround(dt / h));
  real worstAngle = 0, worstTurn = 0, worstRocker = 0;
  for (int step = 0; step < static_cast<int>(std::lround(endTime / dt)); ++step) {
    for (int k = 0; k < substeps; ++k) {
      auto f = [&](real x) { return -omega2 * std::sin(x); };
      real const k1x = rate, k1v = f(theta);
      real const k2x = rate + 0.5 * h * k1v, k2v = f(theta + 0.5 * h * k1x);
      real const k3x = rate + 0.5 * h * k2v, k3v = f(theta + 0.5 * h * k2x);
      real const k4x = rate + h * k3v, k4v = f(theta + h * k3x);
      theta += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      rate += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
    StepOk(*scene, dt);
    DynamicArray<real> const q = actor->GetJointPositions();
    worstAngle = std::max(worstAngle, std::abs(q[0] - theta));
    worstTurn = std::max(worstTurn, std::abs(q[0] + q[1]));    // the coupler's world angle
    worstRocker = std::max(worstRocker, std::abs(q[2] - q[0]));  // the rocker turns with the crank
  }
  // the loop reaches two joints of the actor: the dense block
  REQUIRE_FALSE(actor->IsSolvedOnTree());
  std::printf("parallelogram four-bar closed in one actor, 1 s at dt = 1e-3 (BDF2): crank angle vs the pendulum "
              "%.2e rad, coupler turn %.2e rad, rocker - crank %.2e rad\n",
              worstAngle, worstTurn, worstRocker);
  // BDF2's phase error at ω dt ≈ 5e-3 over ~0.7 periods (~ω³ dt² t ≈ 1e-4
  // rad) and the joint's stretch under the ~20 N loads over k = 1e7 N/m
  // (~1e-5 rad): measured 4.2e-5 rad against the pendulum, 5.9e-7 coupler
  // turn, 5.3e-7 between rocker and crank
  REQUIRE(std::abs(theta - theta0) > 0.5);
  CHECK(worstAngle <= 2e-4);
  CHECK(worstTurn <= 1e-5);
  CHECK(worstRocker <= 1e-5);
}
