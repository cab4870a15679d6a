// Rods (discrete elastic rods, actors/rod_actor.h) in scenes, against
// analytic answers:
//  - a cantilever clamped to a held rigid body sags under its own weight by
//    the Euler–Bernoulli q L⁴ / (8 E I), converging with refinement;
//  - an end-loaded cantilever follows the large-deflection elastica
//    (tests/actors/elastica_reference.h) at α = P L² / (E I) = 1, 2, 5;
//  - a rod clamped between two held bodies, one turned by φ: uniform twist
//    and the clamp reaction torque G J φ / L;
//  - turning a rigid body step by step twists the attached rod, and the
//    rod's torque comes back through the clamp's GetForce;
//  - twist–bend buckling (Greenhill): straight at 0.95 of the critical end
//    torque 2.86 π E I / L, buckled at 1.05.
//
// Static equilibria are reached with backward-Euler steps far longer than the
// structure's periods: the inertia weight m/Δt² of each step is then many
// orders below the stiffnesses, and a few steps leave only the equilibrium
// (each test states the ratio).
//
// Discretization note (measured below, and the reason for the element
// counts): a clamp holds the first element's material frame, which DER
// carries at the element's midpoint, so the clamped rod bends as if it were
// clamped there — a cantilever of effective length L − l/2 (l the element
// length), and a rod clamped at both ends twists over L − l. These are
// first-order (O(l/L)) differences from the continuum answers, so the
// tolerances are met by refinement, not by adjusting the reference.
#include "test_scenes.h"

#include "actors/elastica_reference.h"

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {

/// A rigid body held at its creation pose by stiff constraints, the
/// rotation one kept so that its target can be turned.
struct HeldBody {
  RigidActor* body = nullptr;
  Constraint* rotation = nullptr;  ///< RigidPivotRotation, target world
};

/// Like Anchor (tests/test_scenes.h): RigidPivotToRigidTarget on the body's
/// centre (so turning the body does not move it) plus RigidPivotRotation.
HeldBody MakeHeldBody(Scene& scene, Real3 const& position, real stiffness = 1e9) {
  RigidActorParams p;
  p.mass = 1;
  p.inertia = Real3::Constant(1e-2);
  p.position = position;
  HeldBody held;
  held.body = MakeRigid(scene, p);
  Error error;
  RigidPivotToRigidTargetConstraintParams hold;
  hold.actor = held.body->GetHandle();
  hold.position = position;
  hold.stiffness = stiffness;
  REQUIRE(scene.CreateRigidPivotToRigidTargetConstraint(hold, error));
  RigidPivotRotationConstraintParams rotation;
  rotation.actor = held.body->GetHandle();
  rotation.stiffness = stiffness;
  held.rotation = scene.CreateRigidPivotRotationConstraint(rotation, error);
  INFO(error.ToString());
  REQUIRE(held.rotation);
  return held;
}

/// Turns a held body's rotation target to `angle` about `axis` (world).
void TurnTo(HeldBody const& held, real angle, Real3 const& axis) {
  Error error;
  bool const ok = held.rotation->SetTargetRotation(Quat(Eigen::AngleAxis<real>(angle, axis)), error);
  INFO(error.ToString());
  REQUIRE(ok);
}

/// The torque a RodElementRotationToRigid constraint exerts on its rigid
/// body (world frame): GetForce's entries 0..2.
Real3 TorqueOnBody(Constraint const& clamp) {
  Error error;
  Span<real const> const f = clamp.GetForce(error);
  INFO(error.ToString());
  REQUIRE(f.size() == 11);
  return Real3(f[0], f[1], f[2]);
}

/// Largest distance of a node from the x axis (the straight rods lie on it).
real LateralAmplitude(RodActor const& rod) {
  real amplitude = 0;
  for (int i = 0; i < rod.GetNumNodes(); ++i) {
    Real3 const x = rod.GetNodePosition(i);
    amplitude = std::max(amplitude, std::hypot(x.y(), x.z()));
  }
  return amplitude;
}

/// A circular rod along +x from the origin, clamped at its first node to a
/// held body there.
struct Cantilever {
  std::unique_ptr<Scene> scene;
  HeldBody wall;
  RodActor* rod = nullptr;
};

Cantilever MakeCantilever(SceneParams const& params, real length, int numElements,
                          RodActorParams const& material) {
  Cantilever c;
  c.scene = MakeScene(params);
  c.wall = MakeHeldBody(*c.scene, Real3::Zero());
  c.rod = MakeStraightRod(*c.scene, Real3::Zero(), Real3::UnitX(), length, numElements, material);
  ClampRodEnd(*c.scene, *c.rod, *c.wall.body, false, 1e9, 1e9);
  return c;
}

}  // namespace

TEST_CASE("a rod cantilever under self weight converges to q L^4 / (8 E I)", "[scene][rod]") {
  // r = 1 cm, ρ = 1000 kg/m³: q = ρ A g = 3.08 N/m; E = 5e10 Pa puts the tip
  // at δ/L ≈ 1e-3, deep in the linear regime (geometric nonlinearity
  // ~ (δ/L)² ≈ 1e-6).
  real const length = 1, radius = 0.01, density = 1000, g = 9.81, youngModulus = 5e10;
  real const area = std::numbers::pi * radius * radius, inertia = area * radius * radius / 4;
  real const q = density * area * g;
  real const expected = q * std::pow(length, 4) / (8 * youngModulus * inertia);
  REQUIRE(std::abs(expected / length / 1e-3 - 1) <= 0.05);
  // Clamp and anchor compliances (stiffnesses 1e9): the root moment q L²/2 =
  // 1.5 N·m turns them by ~1.5e-9 rad (tip: 1.5e-9 m), the shear q L = 3 N
  // moves them by ~3e-9 m — together < 1e-5 of δ.
  // Inertia: the first bending mode, ω ≈ 3.52 √(EI/(ρA L⁴)) ≈ 124 rad/s, sees
  // an inertia weight (ωΔt)⁻² ≈ 6.5e-7 of its stiffness at Δt = 10 s, and
  // the residual contracts by about that factor per step: after 3 steps it
  // is at round-off (measured: a 4th step changes the tip by ~1e-15 m).
  // Newton stops at a step < 1e-10 m/s × 10 s = 1e-9 m (1e-6 of δ), and a
  // linear problem converges in one iteration anyway.
  SceneParams params;
  params.newton.velocityTolerance = 1e-10;
  RodActorParams material;
  material.radius = radius;
  material.youngModulus = youngModulus;
  material.density = density;

  std::printf("rod cantilever under self weight: q L^4 / (8 E I) = %.6e m\n", expected);
  std::printf("%9s %14s %12s %22s\n", "elements", "tip [m]", "rel. error", "q(L-l/2)^4/(8EI) err");
  real previousError = 1;
  real error = 1;
  for (int n : {4, 8, 16, 32, 64, 128, 256}) {
    Cantilever c = MakeCantilever(params, length, n, material);
    StepOk(*c.scene, 10.0, 3);
    real const settled = -c.rod->GetNodePosition(n).y();
    StepOk(*c.scene, 10.0);
    real const tip = -c.rod->GetNodePosition(n).y();
    CAPTURE(n, tip, settled);
    REQUIRE(std::abs(tip - settled) <= 1e-9 * tip);  // static: nothing moves any more
    // the node positions stay on the loaded plane, and the tip sags down
    REQUIRE(std::abs(c.rod->GetNodePosition(n).z()) <= 1e-12);
    REQUIRE(tip > 0);
    error = tip / expected - 1;
    real const clampedAtMidpoint =
        q * std::pow(length - 0.5 * length / n, 4) / (8 * youngModulus * inertia);
    std::printf("%9d %14.6e %12.4e %22.4e\n", n, tip, error, tip / clampedAtMidpoint - 1);
    // convergence: the error never grows with refinement
    REQUIRE(std::abs(error) <= std::abs(previousError));
    previousError = error;
  }
  // finest (256 elements): within 2 % (measured −0.78 %; the error is
  // first-order, ≈ −2 l/L from the clamp acting at the midpoint of the
  // clamped element, halving with each refinement)
  CAPTURE(error);
  REQUIRE(std::abs(error) <= 0.02);
}

TEST_CASE("an end-loaded rod cantilever follows the large-deflection elastica", "[long][scene][rod]") {
  real const alpha = GENERATE(1.0, 2.0, 5.0);
  CAPTURE(alpha);
  ElasticaTip const reference = SolveCantileverElastica(alpha);
  // r = 1 cm, E = 1e9 Pa: EI = 7.85 N·m²; the dead load P = α EI / L² is a
  // rigid body of mass P/g hung from the tip node (pivot at its centre, so it
  // puts no moment on the rod). Inextensibility: P/EA = α r²/(4L²) ≤ 1.3e-4.
  real const length = 1, radius = 0.01, g = 9.81, youngModulus = 1e9;
  real const area = std::numbers::pi * radius * radius;
  real const bending = youngModulus * area * radius * radius / 4;
  real const load = alpha * bending / (length * length);
  RodActorParams material;
  material.radius = radius;
  material.youngModulus = youngModulus;
  // self weight 1e-6 of P: its effect on the tip is ~1e-6 relative
  material.density = 1e-6 * load / (area * length * g);
  // Inertia at Δt = 100 s: the hanging mass P/g against the cantilever's
  // lateral stiffness ~3EI/L³ gives a weight ratio ~ 1/(g Δt² α/3 L) < 4e-6,
  // the residual shrinking by that factor per step; 3 steps + 1 to check.
  // Newton's step tolerance: 1e-10 m/s × 100 s = 1e-8 m. Clamp/hook
  // compliance (1e9): the root moment ≤ 40 N·m turns the clamp by ≤ 4e-8 rad.
  SceneParams params;
  params.newton.velocityTolerance = 1e-10;
  // the first step goes from straight to the full load (~22 iterations)
  params.newton.maxIterations = 100;

  std::printf("elastica alpha = %.0f: reference x/L = %.5f, delta/L = %.5f\n", alpha, reference.horizontal,
              reference.vertical);
  real previousWorst = 1;
  real errorX = 1, errorY = 1;
  for (int n : {100, 200}) {
    Cantilever c = MakeCantilever(params, length, n, material);
    RigidActorParams weight;
    weight.mass = load / g;
    weight.inertia = Real3::Constant(1e-4 * weight.mass);
    weight.position = Real3(length, 0, 0);
    RigidActor* hanging = MakeRigid(*c.scene, weight);
    Error err;
    DeformableNodeToRigidConstraintParams hook;
    hook.deformableActor = c.rod->GetHandle();
    hook.rigidActor = hanging->GetHandle();
    hook.deformableNodeIndex = n;
    hook.stiffness = 1e9;
    REQUIRE(c.scene->CreateDeformableNodeToRigidConstraint(hook, err));
    StepOk(*c.scene, 100.0, 3);
    Real3 const settled = c.rod->GetNodePosition(n);
    StepOk(*c.scene, 100.0);
    Real3 const tip = c.rod->GetNodePosition(n) / length;
    CAPTURE(n, tip.transpose());
    real const change = (tip * length - settled).norm();
    REQUIRE(change <= 1e-8 * length);  // static (measured ~1e-10 m)
    REQUIRE(std::abs(tip.z()) <= 1e-12);
    errorX = tip.x() / reference.horizontal - 1;
    errorY = -tip.y() / reference.vertical - 1;
    std::printf("  %4d elements: x/L = %.5f (%+.3e), delta/L = %.5f (%+.3e); last step moved the tip %.1e m\n",
                n, tip.x(), errorX, -tip.y(), errorY, change);
    real const worst = std::max(std::abs(errorX), std::abs(errorY));
    REQUIRE(worst <= previousWorst);  // refinement helps (first order: it halves)
    previousWorst = worst;
  }
  // 200 elements: each component within 1 % of the elastica (measured
  // ≤ 0.66 %; first-order error from the clamp at the clamped element's
  // midpoint, ≈ 1.3 l/L in the deflection)
  CAPTURE(errorX, errorY);
  REQUIRE(std::abs(errorX) <= 0.01);
  REQUIRE(std::abs(errorY) <= 0.01);
}

TEST_CASE("a rod clamped between two bodies, one turned by phi: uniform twist and torque G J phi / L",
          "[scene][rod]") {
  real const phi = GENERATE(1.0, -0.6);
  CAPTURE(phi);
  // r = 1 cm, E = 1e9, ν = 0.5: GJ = 5.24 N·m²; 200 elements (the twist acts
  // between the clamped elements' midpoints, L − l: +0.5 % on the torque).
  real const length = 1;
  int const n = 200;
  real const elementLength = length / n;
  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-12;
  auto scene = MakeScene(params);
  HeldBody left = MakeHeldBody(*scene, Real3::Zero());
  HeldBody right = MakeHeldBody(*scene, Real3(length, 0, 0));
  RodActorParams material;
  material.radius = 0.01;
  material.youngModulus = 1e9;
  RodActor* rod = MakeStraightRod(*scene, Real3::Zero(), Real3::UnitX(), length, n, material);
  // angular clamp stiffness 1e7 N·m/rad: the torque ~5 N·m leaves ≤ 1e-6 rad
  // in the two clamps (and 1e-8 in the anchors) of φ
  RodClamp const clampLeft = ClampRodEnd(*scene, *rod, *left.body, false, 1e9, 1e7);
  RodClamp const clampRight = ClampRodEnd(*scene, *rod, *right.body, true, 1e9, 1e7);
  TurnTo(right, phi, Real3::UnitX());
  // static: the first torsion mode, ω ≈ (π/2) √(GJ / (ρ(I₁+I₂)L²)) ≈ 900
  // rad/s, sees an inertia weight (ωΔt)⁻² ≈ 1e-8 at Δt = 10 s; two steps
  StepOk(*scene, 10.0, 2);

  real const GJ = rod->GetStiffness().twist;
  real const expected = GJ * phi / length;
  Real3 const onLeft = TorqueOnBody(*clampLeft.rotation);
  Real3 const onRight = TorqueOnBody(*clampRight.rotation);
  real minTwist = 1e300, maxTwist = -1e300, totalTwist = 0;
  for (int i = 1; i < n; ++i) {
    real const m = rod->GetStrain(i)[2];
    minTwist = std::min(minTwist, m);
    maxTwist = std::max(maxTwist, m);
    totalTwist += m;
  }
  std::printf("torsion phi = %+.2f rad, %d elements: GJ phi / L = %+.6f N m, torque on the turned body %+.6f, "
              "on the other %+.6f (ratio %.5f; vs GJ phi / (L - l): %.7f); twist per node in [%.10e, %.10e], "
              "total %.8f rad\n",
              phi, n, expected, onRight.x(), onLeft.x(), onLeft.x() / expected,
              onLeft.x() / (GJ * phi / (length - elementLength)), minTwist, maxTwist, totalTwist);
  CAPTURE(onLeft.transpose(), onRight.transpose(), expected, minTwist, maxTwist, totalTwist);
  // the rod resists: the turned body is pulled back (torque −GJφ/L about x),
  // the other one is turned along with it (+GJφ/L); within 1 % (measured
  // 0.5 %, the L − l of the note at the top)
  REQUIRE(std::abs(-onRight.x() / expected - 1) <= 0.01);
  REQUIRE(std::abs(onLeft.x() / expected - 1) <= 0.01);
  // equal and opposite, and about the rod's axis only
  REQUIRE((onLeft + onRight).norm() <= 1e-6 * std::abs(expected));
  REQUIRE(onLeft.tail<2>().norm() <= 1e-6 * std::abs(expected));
  // the discrete rod's exact answer: twist over L − l, up to the clamps'
  // compliance (~1e-6 relative)
  REQUIRE(std::abs(onLeft.x() / (GJ * phi / (length - elementLength)) - 1) <= 1e-5);
  // uniform twist (measured spread 1.5e-8 of the twist: the inertia residual
  // above), and all of φ (less the compliances) in the rod
  REQUIRE(maxTwist - minTwist <= 1e-6 * std::abs(phi) / (n - 1));
  REQUIRE(std::abs(totalTwist - phi) <= 1e-5 * std::abs(phi));
  // the rod stays straight
  REQUIRE(LateralAmplitude(*rod) <= 1e-12);
}

TEST_CASE("turning a rigid body twists the attached rod and its torque comes back through GetForce",
          "[scene][rod]") {
  // A rod clamped between two held bodies; the right body's rotation target
  // is turned about the rod's axis by π/8 per step, to 2.5π in all (1.25
  // turns, past the ±π range of one rotation target: the increments are
  // small, and the rod's twist is tracked continuously).
  // Circular, ν = 0.5: Greenhill's φ_cr = 2.86π EI/GJ = 13.5 rad > 2.5π.
  real const length = 1;
  int const n = 50;
  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-12;
  auto scene = MakeScene(params);
  HeldBody left = MakeHeldBody(*scene, Real3::Zero());
  HeldBody right = MakeHeldBody(*scene, Real3(length, 0, 0));
  RodActorParams material;
  material.radius = 0.01;
  material.youngModulus = 1e9;
  RodActor* rod = MakeStraightRod(*scene, Real3::Zero(), Real3::UnitX(), length, n, material);
  real const GJ = rod->GetStiffness().twist;
  // 1e8 N·m/rad: at the largest torque (~42 N·m) the clamps give ≤ 1e-6 rad
  RodClamp const clampLeft = ClampRodEnd(*scene, *rod, *left.body, false, 1e9, 1e8);
  RodClamp const clampRight = ClampRodEnd(*scene, *rod, *right.body, true, 1e9, 1e8);
  Real33 const lastFrameAtRest = rod->GetMaterialFrame(n - 1);

  int const increments = 20;
  real worstTorque = 0, worstTwist = 0, worstFrame = 0;
  for (int k = 1; k <= increments; ++k) {
    real const phi = k * std::numbers::pi / 8;
    TurnTo(right, phi, Real3::UnitX());
    // quasi-static: at Δt = 10 s the rod's twist inertia weighs (ωΔt)⁻² ≈
    // 1e-8 against its torsional stiffness (first torsion mode ω ≈ 900 rad/s;
    // at Δt = 1 s it left a measured 1.5e-6 torque mismatch), the bodies'
    // inertia 1e-4 N·m/rad against 1e9
    StepOk(*scene, 10.0);
    CAPTURE(k, phi);
    // the body turned to its target (world rotation about x by φ)
    Eigen::AngleAxis<real> const bodyTurn(right.body->GetRotation());
    real const bodyAngle = bodyTurn.angle() * bodyTurn.axis().x();
    CAPTURE(bodyAngle);
    REQUIRE(std::abs(std::remainder(bodyAngle - phi, 2 * std::numbers::pi)) <= 1e-6);
    // the rod's twist follows: the total twist Σ mᵢ is φ itself (not φ mod
    // 2π), and the last element's material frame is the rest one turned by φ
    real totalTwist = 0;
    for (int i = 1; i < n; ++i) totalTwist += rod->GetStrain(i)[2];
    worstTwist = std::max(worstTwist, std::abs(totalTwist - phi));
    Real33 const turned = Eigen::AngleAxis<real>(phi, Real3::UnitX()).toRotationMatrix() * lastFrameAtRest;
    worstFrame = std::max(worstFrame, (rod->GetMaterialFrame(n - 1) - turned).norm());
    // GetForce's torque on the body is the rod's own torque GJ m/l̄ (twist
    // per length from the rod's state), at every interior node
    Real3 const onRight = TorqueOnBody(*clampRight.rotation);
    Real3 const onLeft = TorqueOnBody(*clampLeft.rotation);
    for (int i = 1; i < n; ++i) {
      real const voronoiLength = 0.5 * (rod->GetRestLength(i - 1) + rod->GetRestLength(i));
      real const rodTorque = GJ * rod->GetStrain(i)[2] / voronoiLength;
      worstTorque = std::max(
          {worstTorque, std::abs(-onRight.x() / rodTorque - 1), std::abs(onLeft.x() / rodTorque - 1)});
    }
    REQUIRE(onRight.tail<2>().norm() <= 1e-6 * std::abs(onRight.x()));
    REQUIRE(LateralAmplitude(*rod) <= 1e-12);
  }
  std::printf("turning a body through 2.5 pi in %d steps: torque %+.4f N m (GJ phi / (L - l) = %.4f); worst "
              "|sum m - phi| %.2e rad, worst frame error %.2e, worst relative torque mismatch %.2e\n",
              increments, TorqueOnBody(*clampRight.rotation).x(),
              GJ * increments * std::numbers::pi / 8 / (length - length / n), worstTwist, worstFrame, worstTorque);
  CAPTURE(worstTwist, worstFrame, worstTorque);
  // the clamps' compliance (≤ 1e-6 rad) bounds the twist and frame errors
  REQUIRE(worstTwist <= 1e-5);
  REQUIRE(worstFrame <= 1e-5);
  // torque balance of the end element: only the rod's twist inertia (~1e-8)
  // and Newton's last step stand between the two
  REQUIRE(worstTorque <= 1e-6);
}

TEST_CASE("a twisted rod clamped at both ends buckles at Greenhill's torque 2.86 pi E I / L", "[scene][rod]") {
  // Explicit section with GJ = 4 EI, so that the critical end rotation
  // φ_cr = M_cr L / GJ = 2.86π EI/GJ = 2.25 rad stays below π (the turned
  // body's rotation target is still ramped in 10 increments). EA L²/EI = 1e4:
  // with both ends held at their distance the buckled rod must stretch, which
  // bounds the post-buckling amplitude (≈ 8 mm at 1.05 M_cr).
  real const ratio = GENERATE(0.95, 1.05);
  CAPTURE(ratio);
  real const length = 1, youngModulus = 1e7, inertia = 1e-7, area = 1e-3;
  real const shearModulus = 5e6, torsionConstant = 8e-7;
  int const n = 80;
  real const EI = youngModulus * inertia, GJ = shearModulus * torsionConstant;
  real const criticalTorque = 2.86 * std::numbers::pi * EI / length;
  real const phi = ratio * criticalTorque * length / GJ;  // M = GJφ/L = ratio · M_cr

  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-9;
  params.newton.maxIterations = 100;
  auto scene = MakeScene(params);
  HeldBody left = MakeHeldBody(*scene, Real3::Zero());
  HeldBody right = MakeHeldBody(*scene, Real3(length, 0, 0));
  RodActorParams material;
  material.sectionArea = area;
  material.secondMomentOfArea1 = material.secondMomentOfArea2 = inertia;
  material.torsionConstant = torsionConstant;
  material.youngModulus = youngModulus;
  material.shearModulus = shearModulus;
  material.density = 1000;
  RodActor* rod = MakeStraightRod(*scene, Real3::Zero(), Real3::UnitX(), length, n, material);
  REQUIRE(std::abs(rod->GetStiffness().twist / rod->GetStiffness().bend1 - 4) <= 1e-12);
  ClampRodEnd(*scene, *rod, *left.body, false, 1e9, 1e8);
  RodClamp const clampRight = ClampRodEnd(*scene, *rod, *right.body, true, 1e9, 1e8);
  // the perturbation: a spring on the middle node toward a point ε off the
  // axis, on for one step only
  real const epsilon = 1e-4 * length;
  Error error;
  DeformableNodePositionConstraintParams pokeParams;
  pokeParams.actor = rod->GetHandle();
  pokeParams.nodeIndex = n / 2;
  pokeParams.position = rod->GetNodePosition(n / 2) + Real3(0, epsilon, 0);
  pokeParams.stiffness = 0;
  Constraint* poke = scene->CreateDeformableNodePositionConstraint(pokeParams, error);
  REQUIRE(poke);

  // 1. twist the straight rod quasi-statically (Δt = 10 s: the first bending
  //    mode, ω ≈ 22 rad/s, sees an inertia weight 2e-5); it stays straight
  int const increments = 10;
  for (int k = 1; k <= increments; ++k) {
    TurnTo(right, phi * k / increments, Real3::UnitX());
    StepOk(*scene, 10.0);
  }
  real const straight = LateralAmplitude(*rod);
  real const torque = -TorqueOnBody(*clampRight.rotation).x();
  CAPTURE(straight, torque);
  REQUIRE(straight <= 1e-12);
  // the straight rod's torque is GJφ/(L − l) (see the torsion test): +1.3 %
  // on GJφ/L at 80 elements
  REQUIRE(std::abs(torque / (GJ * phi / (length - length / n)) - 1) <= 1e-5);
  // 2. push the middle sideways (static step with the spring, k = 1e3 N/m,
  //    well above the rod's lateral stiffness ~200 N/m, so the pushed state
  //    is stable on either side of M_cr)
  REQUIRE(poke->SetStiffness(1e3, error));
  StepOk(*scene, 10.0);
  real const pushed = LateralAmplitude(*rod);
  CAPTURE(pushed);
  REQUIRE(pushed >= 0.5 * epsilon);
  REQUIRE(pushed <= 2 * epsilon);
  // 3. let go and follow the motion with Δt = 0.1 s. Within ±5 % of M_cr the
  //    critical mode's frequency (below) or growth rate (above) is about
  //    √0.1 of the first bending frequency, ~7 s⁻¹: backward Euler at this
  //    step damps the stable mode (measured: by 1e7 in 60 steps) and lets the
  //    unstable one grow ~1.5x per step until it settles on the buckled
  //    equilibrium (measured: within ~25 steps)
  REQUIRE(poke->SetStiffness(0, error));
  int const steps = 60;
  real previous = pushed, amplitude = pushed;
  for (int s = 1; s <= steps; ++s) {
    StepOk(*scene, 0.1);
    previous = amplitude;
    amplitude = LateralAmplitude(*rod);
  }
  std::printf("Greenhill, %d elements: M = GJ phi / L = %.2f M_cr (phi = %.4f rad, clamp torque %.4f N m = %.4f "
              "M_cr): lateral amplitude straight %.1e, pushed %.3e, after %d steps of 0.1 s %.3e m\n",
              n, ratio, phi, torque, torque / criticalTorque, straight, pushed, steps, amplitude);
  CAPTURE(amplitude, previous);
  if (ratio < 1) {
    // stable: the perturbation has died out (measured: 1e-4 m → 7e-12 m)
    REQUIRE(amplitude <= 1e-4 * epsilon);
  } else {
    // buckled: a finite lateral deflection, ~80 ε (8 mm at L = 1 m), and at
    // rest on the buckled equilibrium (it no longer changes)
    REQUIRE(amplitude >= 10 * epsilon);
    REQUIRE(std::abs(amplitude - previous) <= 1e-6 * amplitude);
    // the buckled shape is spatial, as Greenhill's mode is (measured: max |z|
    // ≈ 0.41 max |y|; y symmetric and z antisymmetric about the middle, the
    // symmetry of the clamped rod and the push)
    real maxY = 0, maxZ = 0;
    for (int i = 0; i <= n; ++i) {
      maxY = std::max(maxY, std::abs(rod->GetNodePosition(i).y()));
      maxZ = std::max(maxZ, std::abs(rod->GetNodePosition(i).z()));
    }
    CAPTURE(maxY, maxZ);
    REQUIRE(maxZ >= 0.2 * maxY);
  }
}
