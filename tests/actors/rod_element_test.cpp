// The rod's element kernels (actors/rod_element.h) and the rod actor's
// assembled stage derivatives against central differences: stretching,
// bending–twisting (gradient from energy differences, the exact Hessian from
// differences of the analytic gradient), the material frame's angular
// Jacobian and its rigid-rotation twist, on near-straight and strongly bent
// stencils with the stage reference frames held fixed, as the solver holds them.
// The hand-differentiated bending–twisting kernel also against its Jet<8>
// reference (RodBendTwistGradientHessianJet), on those and random stencils.
#include "test_support.h"
#include "white_box.h"

#include <numbers>
#include <random>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {

using Vector11 = internal::Vector11;
using Matrix11 = internal::Matrix11;

/// A reference frame with tangent `tangent` turned by `tilt` about `axis`
/// (the stage-start tangent of an element that has moved since) and director
/// at angle `spin` about it.
internal::RodReferenceFrame TiltedFrame(Real3 const& tangent, Real3 const& axis, real tilt, real spin) {
  Real3 const t = (Eigen::AngleAxis<real>(tilt, axis.normalized()) * tangent.normalized()).normalized();
  Real3 const any = std::abs(t.x()) < 0.9 ? Real3::UnitX() : Real3::UnitY();
  Real3 const u0 = (any - any.dot(t) * t).normalized();
  return {t, Eigen::AngleAxis<real>(spin, t) * u0};
}

struct Stencil {
  char const* name;
  Real3 edgeA, edgeB;
  real thetaA, thetaB;
};

// edge vectors and twists: near-straight (1e-3 rad kink) to a 150° turn
Stencil const kStencils[] = {
    {"straight", Real3(1.0, 0, 0), Real3(0.9, 0, 0), 0, 0},
    {"near-straight", Real3(1.0, 0.0005, -0.0003), Real3(0.9, 0.0011, 0.0007), 0.002, -0.001},
    {"bent 75°", Real3(0.8, 0.1, 0.0), Real3(0.3, 0.8, 0.4), 0.7, -0.4},
    {"bent 150°", Real3(1.1, 0.0, 0.2), Real3(-0.8, 0.5, 0.2), -1.2, 2.1},
};

internal::RodStiffness const kStiffness{50.0, 2.0, 3.5, 1.5};

/// Energy of the stencil as a function of its 11 DoFs [x₀, θ₀, x₁, θ₁, x₂].
struct StencilFunction {
  internal::RodStencilRest rest;
  internal::RodReferenceFrame refA, refB;
  real refTwistStart;
  internal::RodStiffness stiffness = kStiffness;

  static void Split(Vector11 const& q, Real3& edgeA, Real3& edgeB, real& thetaA, real& thetaB) {
    edgeA = q.segment<3>(4) - q.segment<3>(0);
    edgeB = q.segment<3>(8) - q.segment<3>(4);
    thetaA = q[3];
    thetaB = q[7];
  }
  real Energy(Vector11 const& q) const {
    Real3 a, b;
    real ta, tb;
    Split(q, a, b, ta, tb);
    return internal::RodBendTwistEnergy(stiffness, rest, a, b, ta, tb, refA, refB, refTwistStart);
  }
  /// The fast kernel (what the rod actor calls).
  void GradientHessian(Vector11 const& q, Vector11& g, Matrix11& h, bool project) const {
    Real3 a, b;
    real ta, tb;
    Split(q, a, b, ta, tb);
    internal::RodBendTwistGradientHessian(stiffness, rest, a, b, ta, tb, refA, refB, refTwistStart,
                                          g, h, project);
  }
  /// The Jet<8> reference implementation.
  void GradientHessianJet(Vector11 const& q, Vector11& g, Matrix11& h, bool project) const {
    Real3 a, b;
    real ta, tb;
    Split(q, a, b, ta, tb);
    internal::RodBendTwistGradientHessianJet(stiffness, rest, a, b, ta, tb, refA, refB,
                                             refTwistStart, g, h, project);
  }
};

Vector11 StencilDofs(Real3 const& x0, Real3 const& edgeA, Real3 const& edgeB, real thetaA,
                     real thetaB) {
  Vector11 q;
  q << x0, thetaA, x0 + edgeA, thetaB, x0 + edgeA + edgeB;
  return q;
}

Vector11 StencilDofs(Stencil const& s) {
  return StencilDofs(Real3(0.1, -0.2, 0.3), s.edgeA, s.edgeB, s.thetaA, s.thetaB);
}

/// One of the fixed stencils as the derivative tests set it up: stage frames
/// tilted 0.15–0.2 rad off the current tangents (the transport term is
/// exercised), with or without natural curvature.
StencilFunction FixedStencilFunction(Stencil const& s, bool naturalCurvature) {
  StencilFunction f;
  f.refA = TiltedFrame(s.edgeA, Real3(0.3, 1, -0.2), 0.2, 0.4);
  f.refB = TiltedFrame(s.edgeB, Real3(-1, 0.2, 0.5), 0.15, -1.1);
  f.refTwistStart = internal::RodReferenceTwist(s.edgeA, s.edgeB, f.refA, f.refB, 0);
  f.rest.voronoiLength = 0.95;
  f.rest.strain = naturalCurvature ? Real3(0.3, -0.2, 0.1) : Real3::Zero();
  return f;
}

/// A random stencil and the point to evaluate it at.
struct RandomStencil {
  StencilFunction f;
  Vector11 q;
  real turn;   ///< angle between the two edges [rad]
  int branch;  ///< refTwistStart's branch, in turns away from atan2's
};

/// Edge lengths 0.3–2 in random directions, the second edge turned by 0–160°
/// from the first (every 8th by less than 10⁻³ rad, every 32nd not at all),
/// twists in [−π, π], stage frames tilted by up to 0.5 rad about random axes and
/// spun at random, stiffnesses 0.2–5, Voronoi length 0.3–2, rest strains in
/// [−1, 1], and the reference twist's stage-start value ±1 rad off a branch
/// k ∈ {−2, …, 2} turns away.
RandomStencil MakeRandomStencil(std::mt19937& rng, int index) {
  std::uniform_real_distribution<real> unit(0, 1), symmetric(-1, 1);
  std::normal_distribution<real> normal;
  auto direction = [&] { return Real3(normal(rng), normal(rng), normal(rng)).normalized(); };
  real const pi = std::numbers::pi_v<real>;
  RandomStencil r;
  Real3 const tA = direction();
  r.turn = index % 32 == 0  ? 0
           : index % 8 == 0 ? 1e-3 * unit(rng)
                            : (160.0 / 180.0) * pi * unit(rng);
  Real3 const tB = Eigen::AngleAxis<real>(r.turn, tA.cross(direction()).normalized()) * tA;
  Real3 const edgeA = (0.3 + 1.7 * unit(rng)) * tA, edgeB = (0.3 + 1.7 * unit(rng)) * tB;
  real const thetaA = pi * symmetric(rng), thetaB = pi * symmetric(rng);
  StencilFunction& f = r.f;
  f.refA = TiltedFrame(edgeA, direction(), 0.5 * unit(rng), pi * symmetric(rng));
  f.refB = TiltedFrame(edgeB, direction(), 0.5 * unit(rng), pi * symmetric(rng));
  f.stiffness = {50.0, 0.2 + 4.8 * unit(rng), 0.2 + 4.8 * unit(rng), 0.2 + 4.8 * unit(rng)};
  f.rest.voronoiLength = 0.3 + 1.7 * unit(rng);
  f.rest.strain = Real3(symmetric(rng), symmetric(rng), symmetric(rng));
  r.branch = std::uniform_int_distribution<int>(-2, 2)(rng);
  f.refTwistStart = internal::RodReferenceTwist(edgeA, edgeB, f.refA, f.refB, 0) +
                    2 * pi * r.branch + symmetric(rng);
  r.q = StencilDofs(Real3(symmetric(rng), symmetric(rng), symmetric(rng)), edgeA, edgeB, thetaA,
                    thetaB);
  return r;
}

/// Central differences of the stencil at q: the gradient from energy
/// differences, the Hessian from differences of the (fast) analytic gradient.
void CentralDifferences(StencilFunction const& f, Vector11 const& q, Vector11& fdGradient,
                        Matrix11& fdHessian) {
  real const eps = 1e-6;
  for (int j = 0; j < 11; ++j) {
    Vector11 plus = q, minus = q;
    plus[j] += eps;
    minus[j] -= eps;
    fdGradient[j] = (f.Energy(plus) - f.Energy(minus)) / (2 * eps);
    Vector11 gPlus, gMinus;
    Matrix11 unused;
    f.GradientHessian(plus, gPlus, unused, false);
    f.GradientHessian(minus, gMinus, unused, false);
    fdHessian.col(j) = (gPlus - gMinus) / (2 * eps);
  }
}

/// The fast kernel against the Jet<8> reference at q: the largest gradient
/// difference relative to max(‖g_ref‖∞, 1) and the largest Hessian difference
/// relative to ‖H_ref‖∞ (the largest entry; REQUIREd > 0.05 so the ratio is
/// not vacuous: every stencil's GJ/l̄ is at least 0.1).
struct Deviation {
  real gradient = 0, hessian = 0;
};
Deviation DeviationFromJet(StencilFunction const& f, Vector11 const& q, bool project) {
  Vector11 g, gRef;
  Matrix11 h, hRef;
  f.GradientHessian(q, g, h, project);
  f.GradientHessianJet(q, gRef, hRef, project);
  real const hScale = hRef.lpNorm<Eigen::Infinity>();
  REQUIRE(hScale > 0.05);
  return {(g - gRef).lpNorm<Eigen::Infinity>() / std::max<real>(gRef.lpNorm<Eigen::Infinity>(), 1),
          (h - hRef).lpNorm<Eigen::Infinity>() / hScale};
}

}  // namespace

TEST_CASE("rod bending-twisting energy: gradient and exact Hessian match central differences",
          "[actors][rod][derivatives]") {
  Stencil const s = GENERATE(from_range(std::begin(kStencils), std::end(kStencils)));
  bool const naturalCurvature = GENERATE(false, true);
  CAPTURE(s.name, naturalCurvature);
  StencilFunction const f = FixedStencilFunction(s, naturalCurvature);
  Vector11 const q = StencilDofs(s);

  Vector11 g;
  Matrix11 h;
  f.GradientHessian(q, g, h, false);
  REQUIRE(std::abs(f.Energy(q) - internal::RodBendTwistEnergy(kStiffness, f.rest, s.edgeA, s.edgeB,
                                                              s.thetaA, s.thetaB, f.refA, f.refB,
                                                              f.refTwistStart)) <=
          1e-14 * std::max<real>(f.Energy(q), 1));

  Vector11 fdGradient;
  Matrix11 fdHessian;
  CentralDifferences(f, q, fdGradient, fdHessian);
  real const gScale = g.lpNorm<Eigen::Infinity>(), hScale = h.lpNorm<Eigen::Infinity>();
  CAPTURE(gScale, hScale);
  // the check is not vacuous: the gradient vanishes only in the straight,
  // untwisted stencil without natural curvature; the Hessian never does
  if (naturalCurvature || std::string(s.name) != "straight") REQUIRE(gScale > 1e-3);
  REQUIRE(hScale > 1);
  // central differences: truncation ε²·E‴ ~ 1e-12·O(1e2), round-off 1e-16·E/ε ~ 1e-9
  REQUIRE((g - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-6 * std::max<real>(gScale, 1));
  REQUIRE((h - fdHessian).lpNorm<Eigen::Infinity>() <= 1e-6 * hScale);
  REQUIRE((h - h.transpose()).lpNorm<Eigen::Infinity>() <= 1e-12 * hScale);
  // translation invariance: the gradient has no net force
  REQUIRE((g.segment<3>(0) + g.segment<3>(4) + g.segment<3>(8)).norm() <= 1e-12 * std::max<real>(gScale, 1));

  // the projected Hessian is PSD and equals the exact one where that is PSD
  Vector11 gp;
  Matrix11 hp;
  f.GradientHessian(q, gp, hp, true);
  REQUIRE(gp == g);
  VectorX const projected = SymmetricEigenvalues<MatrixX>(hp), exact = SymmetricEigenvalues<MatrixX>(h);
  CAPTURE(exact.transpose());
  REQUIRE(projected.minCoeff() >= -1e-12 * hScale);
  if (exact.minCoeff() >= 0) REQUIRE((hp - h).lpNorm<Eigen::Infinity>() <= 1e-10 * hScale);
}

TEST_CASE("rod bending-twisting energy on random stencils: derivatives match central differences",
          "[actors][rod][derivatives]") {
  // random geometry, frames, twists, stiffness, rest strain and twist branch
  // (MakeRandomStencil); the same tolerances as on the fixed stencils
  std::mt19937 rng(11);
  int numBent = 0;
  for (int i = 0; i < 40; ++i) {
    RandomStencil const r = MakeRandomStencil(rng, i);
    CAPTURE(i, r.turn, r.branch);
    Vector11 g;
    Matrix11 h;
    r.f.GradientHessian(r.q, g, h, false);
    Vector11 fdGradient;
    Matrix11 fdHessian;
    CentralDifferences(r.f, r.q, fdGradient, fdHessian);
    real const gScale = g.lpNorm<Eigen::Infinity>(), hScale = h.lpNorm<Eigen::Infinity>();
    CAPTURE(gScale, hScale);
    // random twists and rest strains leave every stencil off its rest state
    REQUIRE(gScale > 1e-2);
    REQUIRE(hScale > 0.05);
    REQUIRE((g - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-6 * std::max<real>(gScale, 1));
    REQUIRE((h - fdHessian).lpNorm<Eigen::Infinity>() <= 1e-6 * hScale);
    if (r.turn > 0.5) ++numBent;
  }
  REQUIRE(numBent >= 20);
}

TEST_CASE("rod bending-twisting stencil: the fast gradient and Hessian equal the Jet<8> reference",
          "[actors][rod][derivatives]") {
  // the same function differentiated two ways: they differ by round-off only,
  // relative to the largest entry (DeviationFromJet)
  static constexpr real kTolerance = 1e-12;
  bool const project = GENERATE(false, true);
  CAPTURE(project);
  auto record = [](Deviation const& d) {
    CAPTURE(d.gradient, d.hessian);
    REQUIRE(d.gradient <= kTolerance);
    REQUIRE(d.hessian <= kTolerance);
  };
  for (Stencil const& s : kStencils) {
    for (bool const naturalCurvature : {false, true}) {
      CAPTURE(s.name, naturalCurvature);
      record(DeviationFromJet(FixedStencilFunction(s, naturalCurvature), StencilDofs(s), project));
    }
  }
  std::mt19937 rng(7);
  int numOffBranch = 0;
  for (int i = 0; i < 400; ++i) {
    RandomStencil const r = MakeRandomStencil(rng, i);
    CAPTURE(i, r.turn, r.branch);
    record(DeviationFromJet(r.f, r.q, project));
    if (r.branch != 0) ++numOffBranch;
  }
  // the reference twist's branch was exercised: a wrong branch changes m by 2πk
  REQUIRE(numOffBranch >= 200);
}

TEST_CASE("rod stretching: gradient and Hessian match central differences", "[actors][rod][derivatives]") {
  real const stretch = GENERATE(0.7, 1.0, 1.3);  // compressed, at rest length, stretched
  CAPTURE(stretch);
  real const restLength = 0.8, stiffness = 40;
  Real3 const xa(0.2, -0.1, 0.4), direction = Real3(0.3, -0.5, 0.8).normalized();
  internal::Vector6 q;
  q << xa, xa + stretch * restLength * direction;
  auto energy = [&](internal::Vector6 const& x) {
    return internal::RodStretchEnergy(stiffness, restLength, x.tail<3>() - x.head<3>());
  };
  internal::Vector6 g;
  internal::Matrix6 h;
  internal::RodStretchGradientHessian(stiffness, restLength, q.tail<3>() - q.head<3>(), g, h, false);
  real const eps = 1e-6;
  internal::Vector6 fdGradient;
  internal::Matrix6 fdHessian;
  for (int j = 0; j < 6; ++j) {
    internal::Vector6 plus = q, minus = q;
    plus[j] += eps;
    minus[j] -= eps;
    fdGradient[j] = (energy(plus) - energy(minus)) / (2 * eps);
    internal::Vector6 gp, gm;
    internal::Matrix6 unused;
    internal::RodStretchGradientHessian(stiffness, restLength, plus.tail<3>() - plus.head<3>(), gp, unused, false);
    internal::RodStretchGradientHessian(stiffness, restLength, minus.tail<3>() - minus.head<3>(), gm, unused, false);
    fdHessian.col(j) = (gp - gm) / (2 * eps);
  }
  real const hScale = h.lpNorm<Eigen::Infinity>();
  REQUIRE(hScale > 1);
  REQUIRE((g - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-7 * std::max<real>(g.lpNorm<Eigen::Infinity>(), 1));
  REQUIRE((h - fdHessian).lpNorm<Eigen::Infinity>() <= 1e-7 * hScale);
  if (stretch != 1) REQUIRE(g.norm() > 1);
  internal::Matrix6 hp;
  internal::RodStretchGradientHessian(stiffness, restLength, q.tail<3>() - q.head<3>(), g, hp, true);
  REQUIRE(SymmetricEigenvalues(hp).minCoeff() >= -1e-12 * hScale);
}

TEST_CASE("rod material frame: orthonormal, angular Jacobian matches central differences",
          "[actors][rod][derivatives]") {
  Stencil const s = GENERATE(from_range(std::begin(kStencils), std::end(kStencils)));
  CAPTURE(s.name);
  internal::RodReferenceFrame const ref = TiltedFrame(s.edgeB, Real3(0.2, -0.4, 1), 0.3, 0.8);
  Real3 const xa(0.3, 0.1, -0.2);
  Eigen::Matrix<real, 8, 1> q;
  q << xa, s.thetaA, xa + s.edgeB, 0.9;  // the second twist must not act
  auto frame = [&](Eigen::Matrix<real, 8, 1> const& x) {
    return internal::RodMaterialFrame(x.segment<3>(4) - x.segment<3>(0), ref, x[3]);
  };
  Real33 const r = frame(q);
  REQUIRE((r.transpose() * r - Real33::Identity()).norm() < 1e-14);
  REQUIRE(std::abs(r.determinant() - 1) < 1e-14);
  REQUIRE((r.col(2) - s.edgeB.normalized()).norm() < 1e-15);

  internal::Matrix38 const jacobian = internal::RodMaterialFrameJacobian(s.edgeB, ref);
  real const eps = 1e-6;
  internal::Matrix38 fd;
  for (int j = 0; j < 8; ++j) {
    Eigen::Matrix<real, 8, 1> plus = q, minus = q;
    plus[j] += eps;
    minus[j] -= eps;
    // R(q + ε e_j) R(q − ε e_j)ᵀ = Exp(2ε ω_j) + O(ε³)
    fd.col(j) = Log(Quat(frame(plus) * frame(minus).transpose())) / (2 * eps);
  }
  CAPTURE(jacobian, fd);
  REQUIRE(jacobian.lpNorm<Eigen::Infinity>() > 0.5);
  REQUIRE((jacobian - fd).lpNorm<Eigen::Infinity>() <= 1e-8);
  REQUIRE(jacobian.col(7).isZero());

  // a rigid rotation ω of the element turns its material frame by ω when the
  // twist changes by RodTwistUnderRotation
  Real3 const omega(0.3, -0.7, 0.5);
  real const twistRate = internal::RodTwistUnderRotation(s.edgeB, ref, omega);
  Real3 const rotated = Log(Quat(internal::RodMaterialFrame(Exp(eps * omega) * s.edgeB, ref, s.thetaA + eps * twistRate) *
                                 internal::RodMaterialFrame(Exp(-eps * omega) * s.edgeB, ref, s.thetaA - eps * twistRate)
                                     .transpose())) /
                        (2 * eps);
  REQUIRE((rotated - omega).norm() <= 1e-8);
}

TEST_CASE("parallel transport of a director: unit, normal to the new tangent, identity for no turn",
          "[actors][rod]") {
  Real3 const a = Real3(0.2, 0.9, -0.3).normalized();
  Real3 const u = (Real3::UnitX() - Real3::UnitX().dot(a) * a).normalized();
  for (Real3 const& bRaw : {Real3(0.2, 0.9, -0.3), Real3(1, 0, 0), Real3(-0.5, 0.1, 0.9), Real3(0.1, -0.8, 0.5)}) {
    Real3 const b = bRaw.normalized();
    Real3 const moved = internal::TransportDirector(a, b, u);
    REQUIRE(std::abs(moved.norm() - 1) < 1e-14);
    REQUIRE(std::abs(moved.dot(b)) < 1e-14);
    // the rotation about a × b: the component along a × b is unchanged
    Real3 const axis = a.cross(b);
    if (axis.norm() > 1e-12) REQUIRE(std::abs(moved.dot(axis) - u.dot(axis)) < 1e-14);
  }
  REQUIRE((internal::TransportDirector(a, a, u) - u).norm() < 1e-15);
}

TEST_CASE("the rod actor's assembled stage gradient and Hessian match finite differences",
          "[actors][rod][derivatives]") {
  // a helix-like polyline with natural curvature and twist, moving, displaced
  // and twisted off its stage start; reference frames one step old
  RodActorParams p;
  int const numNodes = 9;
  for (int i = 0; i < numNodes; ++i)
    p.nodes.push_back(Real3(0.3 * std::cos(0.5 * i), 0.3 * std::sin(0.5 * i), 0.12 * i));
  p.radius = 0.05;
  p.youngModulus = 1e5;
  p.poissonRatio = 0.3;
  p.density = 500;
  std::mt19937 rng(3);
  std::uniform_real_distribution<real> jitter(-1, 1);
  for (int i = 0; i < numNodes; ++i) p.initialVelocities.push_back(Real3(jitter(rng), jitter(rng), jitter(rng)));
  for (int e = 0; e + 1 < numNodes; ++e) p.materialDirectors.push_back(Real3(jitter(rng), jitter(rng), jitter(rng)));
  SceneParams sceneParams;
  auto scene = MakeScene(sceneParams);
  Error error;
  RodActor* rod = scene->CreateRodActor(p, error);
  INFO(error.ToString());
  REQUIRE(rod);
  int const n = rod->GetNumDofs();
  REQUIRE(n == 4 * numNodes);

  real const h = 1e-2;
  // one stage moves the frames on (they are transported at its end)
  ActorTestAccess::BeginStage(*rod, internal::MakeStage(IntegratorType::BackwardEuler, h, false), Real3(0, 0, -9.81));
  ActorTestAccess::EndStage(*rod);
  ActorTestAccess::BeginStage(*rod, internal::MakeStage(IntegratorType::Bdf2, h, true), Real3(0, 0, -9.81));
  DynamicArray<real> offset(n);
  for (real& v : offset) v = 0.02 * jitter(rng);
  ActorTestAccess::SaveIterate(*rod);
  ActorTestAccess::ApplyIncrementFromSaved(*rod, offset, 1);

  DynamicArray<int> blocks;
  ActorTestAccess::AppendDofBlockSizes(*rod, blocks);
  REQUIRE(blocks == DynamicArray<int>(numNodes, 4));
  ActorDerivatives const analytic = AssembleActor(*rod, false, OrderingMethod::Metis);
  MatrixX const& hessian = analytic.hessian;

  real const eps = 1e-6;
  ActorTestAccess::SaveIterate(*rod);
  DynamicArray<real> delta(n, 0);
  VectorX fdGradient(n);
  MatrixX fdHessian(n, n);
  for (int j = 0; j < n; ++j) {
    delta[j] = eps;
    ActorTestAccess::ApplyIncrementFromSaved(*rod, delta, 1);
    real const plus = ActorTestAccess::Energy(*rod);
    VectorX const gPlus = AssembleActor(*rod, false).gradient;
    ActorTestAccess::ApplyIncrementFromSaved(*rod, delta, -1);
    real const minus = ActorTestAccess::Energy(*rod);
    VectorX const gMinus = AssembleActor(*rod, false).gradient;
    delta[j] = 0;
    fdGradient[j] = (plus - minus) / (2 * eps);
    fdHessian.col(j) = (gPlus - gMinus) / (2 * eps);
  }
  ActorTestAccess::RestoreIterate(*rod);
  real const gScale = analytic.gradient.lpNorm<Eigen::Infinity>(), hScale = hessian.lpNorm<Eigen::Infinity>();
  CAPTURE(gScale, hScale);
  REQUIRE(gScale > 1e-2);
  REQUIRE((analytic.gradient - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-6 * gScale);
  REQUIRE((hessian - fdHessian).lpNorm<Eigen::Infinity>() <= 1e-6 * hScale);
  // the twist DoFs are coupled to the positions (bending–twisting stencils)
  REQUIRE(std::abs(hessian(3, 4)) + std::abs(hessian(3, 8)) > 0);
}

TEST_CASE("the rod's rigid-body modes span the null space of its elastic Hessian at rest",
          "[actors][rod]") {
  // a helix with natural twist at rest: its elastic energy is zero and
  // stationary, so H·(rigid motion) = 0 (with dt = 1e6 s the inertia term's
  // weight 1/dt² = 1e-12 is negligible)
  RodActorParams p;
  for (int i = 0; i < 8; ++i) p.nodes.push_back(Real3(0.3 * std::cos(0.6 * i), 0.3 * std::sin(0.6 * i), 0.1 * i));
  for (int e = 0; e < 7; ++e) p.materialDirectors.push_back(Real3(std::sin(1.3 * e), 1, std::cos(0.7 * e)));
  p.radius = 0.02;
  p.youngModulus = 1e6;
  SceneParams sceneParams;
  sceneParams.gravity = Real3::Zero();
  auto scene = MakeScene(sceneParams);
  Error error;
  RodActor* rod = scene->CreateRodActor(p, error);
  REQUIRE(rod);
  int const n = rod->GetNumDofs();
  ActorTestAccess::BeginStage(*rod, internal::MakeStage(IntegratorType::BackwardEuler, 1e6, false), Real3::Zero());
  MatrixX const hessian = AssembleActor(*rod, false).hessian;
  MatrixX modes = MatrixX::Zero(n, 6);
  ActorTestAccess::WriteRigidBodyModes(*rod, modes);
  // rotations turn the twists too (a twist-free mode would not be in the null space)
  REQUIRE(modes.bottomRows(n - 4).col(3).cwiseAbs().maxCoeff() > 0);
  real const scale = hessian.lpNorm<Eigen::Infinity>() * modes.lpNorm<Eigen::Infinity>();
  REQUIRE(scale > 1);
  CAPTURE((hessian * modes).lpNorm<Eigen::Infinity>() / scale);
  REQUIRE((hessian * modes).lpNorm<Eigen::Infinity>() <= 1e-9 * scale);
  // and without the twist rows the rotations are not null motions
  MatrixX withoutTwist = modes;
  for (int i = 0; i < rod->GetNumNodes(); ++i) withoutTwist.row(4 * i + 3).setZero();
  REQUIRE((hessian * withoutTwist).rightCols<3>().lpNorm<Eigen::Infinity>() > 1e-5 * scale);
}
