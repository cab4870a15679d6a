// The articulated actor's stage potential (link inertia terms through the
// kinematic map, gravity, joint armature and damping): gradient against
// central differences of the energy, exact Hessian against second
// differences of the energy in the increment coordinates Newton uses
// (q ⊕ δ: spherical and free rotations R_j Exp(δ)), on trees with every
// joint type, a branch, and spherical joints turned near π. The projected
// Hessian is PSD and, at the stage start, equals w·M(q) from the composite-
// rigid-body algorithm.
#include "test_support.h"
#include "white_box.h"

#include <numbers>
#include <random>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {

ArticulatedLinkParams Link(int parent, JointType joint, Real3 const& offset, DynamicArray<real> position = {},
                           DynamicArray<real> velocity = {}) {
  ArticulatedLinkParams l;
  l.parent = parent;
  l.joint = joint;
  l.axis = Real3(0.2, 1, -0.3);
  l.parentToJointPosition = offset;
  l.parentToJointRotation = Quat(Eigen::AngleAxis<real>(0.3, Real3(1, 0.5, 0).normalized()));
  l.jointToChildPosition = Real3(0.05, -0.1, 0.02);
  l.jointToChildRotation = Quat(Eigen::AngleAxis<real>(-0.4, Real3(0, 1, 1).normalized()));
  l.mass = 0.7 + 0.1 * parent;
  l.inertia = Real3(0.02, 0.03, 0.015);
  l.centerOfMass = Real3(0.1, 0.02, -0.03);
  l.initialPosition = std::move(position);
  l.initialVelocity = std::move(velocity);
  return l;
}

/// A tree: root (fixed base: revolute; floating: free) → spherical → {revolute
/// with armature and damping, prismatic with armature → fixed → spherical near π}.
ArticulatedActorParams Tree(bool floating, real nearPi) {
  ArticulatedActorParams p;
  if (floating)
    p.links.push_back(Link(-1, JointType::Free, Real3(0.1, 0.2, 0.3), {0.1, -0.2, 0.3, 0.4, -0.5, 0.2},
                           {0.3, 0.1, -0.2, 1.0, -0.5, 0.7}));
  else
    p.links.push_back(Link(-1, JointType::Revolute, Real3(0.1, 0.2, 0.3), {0.4}, {1.3}));
  p.links.push_back(Link(0, JointType::Spherical, Real3(0.3, 0, 0), {0.5, -0.3, 0.8}, {0.7, -1.1, 0.4}));
  p.links.push_back(Link(1, JointType::Revolute, Real3(0.2, 0.1, 0), {-0.6}, {2.0}));
  p.links.back().armature = 0.05;
  p.links.back().damping = 0.3;
  p.links.push_back(Link(1, JointType::Prismatic, Real3(0, 0.25, 0), {0.05}, {-0.4}));
  p.links.back().armature = 0.5;
  p.links.back().damping = 2;
  p.links.push_back(Link(3, JointType::Fixed, Real3(0.1, 0, 0.1)));
  Real3 const axis = Real3(1, 2, -1).normalized();
  p.links.push_back(Link(4, JointType::Spherical, Real3(0.2, 0, 0), {nearPi * axis.x(), nearPi * axis.y(), nearPi * axis.z()},
                         {-0.5, 0.9, 1.5}));
  return p;
}

}  // namespace

TEST_CASE("articulated potential: gradient and exact Hessian match differences of the energy",
          "[actors][articulated][derivatives]") {
  bool const floating = GENERATE(false, true);
  real const nearPi = GENERATE(0.7, std::numbers::pi - 0.05);
  bool const bdf2 = GENERATE(false, true);
  CAPTURE(floating, nearPi, bdf2);
  SceneParams sceneParams;
  auto scene = MakeScene(sceneParams);
  Error error;
  ArticulatedActor* actor = scene->CreateArticulatedActor(Tree(floating, nearPi), error);
  INFO(error.ToString());
  REQUIRE(actor);
  int const n = actor->GetNumDofs();
  REQUIRE(n == (floating ? 6 : 1) + 3 + 1 + 1 + 3);

  real const h = 0.01;
  Real3 const gravity(0, -9.81, 0);
  ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::BackwardEuler, h, false), gravity);
  if (bdf2) {
    ActorTestAccess::EndStage(*actor);
    ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::Bdf2, h, true), gravity);
  }
  // at Newton's first iterate, the projected Hessian is PSD; away from the
  // stage start it is w·M(q) only up to J_l⁻¹(φ) — checked at the start below
  DynamicArray<real> offset(n);
  for (int k = 0; k < n; ++k) offset[k] = 0.05 * std::sin(1.3 * k + 0.4);
  ActorTestAccess::SaveIterate(*actor);
  ActorTestAccess::ApplyIncrementFromSaved(*actor, offset, 1);

  ActorDerivatives const exact = AssembleActor(*actor, false);
  MatrixX const& hessian = exact.hessian;

  ActorTestAccess::SaveIterate(*actor);
  auto energyAt = [&](VectorX const& d) {
    ActorTestAccess::ApplyIncrementFromSaved(*actor, Span<real const>(d.data(), n), 1);
    return ActorTestAccess::Energy(*actor);
  };
  real const eps = 1e-6, eps2 = 1e-4;
  VectorX fdGradient(n);
  MatrixX fdHessian(n, n);
  for (int j = 0; j < n; ++j) {
    VectorX e = VectorX::Zero(n);
    e[j] = eps;
    fdGradient[j] = (energyAt(e) - energyAt(-e)) / (2 * eps);
    for (int i = 0; i < n; ++i) {
      VectorX a = VectorX::Zero(n), b = VectorX::Zero(n);
      a[i] = eps2;
      b[j] = eps2;
      fdHessian(i, j) = (energyAt(a + b) - energyAt(a - b) - energyAt(b - a) + energyAt(-a - b)) / (4 * eps2 * eps2);
    }
  }
  ActorTestAccess::RestoreIterate(*actor);
  VectorX const& analytic = exact.gradient;
  real const gScale = analytic.lpNorm<Eigen::Infinity>(), hScale = hessian.lpNorm<Eigen::Infinity>();
  CAPTURE(gScale, hScale);
  REQUIRE(gScale > 1);
  REQUIRE(hScale > 100);
  // central differences ε = 1e-6: ~1e-9 relative; second differences ε = 1e-4:
  // truncation ε² E⁗ and round-off 1e-16 E/ε² both ~1e-8 of the entries
  CAPTURE((analytic - fdGradient).transpose());
  REQUIRE((analytic - fdGradient).lpNorm<Eigen::Infinity>() <= 1e-6 * gScale);
  CAPTURE(MatrixX(hessian - fdHessian));
  REQUIRE((hessian - fdHessian).lpNorm<Eigen::Infinity>() <= 1e-5 * hScale);
  // the projected Hessian is the exact one made positive definite by a
  // modified Cholesky (pivoted LDLᵀ, |D|): positive definite, and equal to
  // the exact one where that is positive definite already
  MatrixX const projected = AssembleActor(*actor, true).hessian;
  real const smallestExact = SymmetricEigenvalues(hessian).minCoeff();
  CAPTURE(smallestExact);
  REQUIRE(SymmetricEigenvalues(projected).minCoeff() > 0);
  if (smallestExact > 1e-8 * hScale)
    REQUIRE((projected - hessian).lpNorm<Eigen::Infinity>() <= 1e-9 * hScale);
  else
    REQUIRE((projected - hessian).lpNorm<Eigen::Infinity>() > 1e-3 * hScale);
}

TEST_CASE("articulated: at the stage start the projected Hessian is w M(q) from the composite-rigid-body algorithm",
          "[actors][articulated]") {
  bool const floating = GENERATE(false, true);
  CAPTURE(floating);
  auto scene = MakeScene();
  Error error;
  ArticulatedActorParams params = Tree(floating, 2.0);
  for (auto& link : params.links) link.initialVelocity.clear();  // Newton starts at the stage start
  ArticulatedActor* actor = scene->CreateArticulatedActor(params, error);
  REQUIRE(actor);
  real const h = 0.02;
  ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::BackwardEuler, h, false), Real3::Zero());
  MatrixX hessian = AssembleActor(*actor, true).hessian;
  // damping d/h on the revolute (DoF after the root's and the spherical's) and prismatic joints
  int const first = floating ? 6 : 1;
  hessian(first + 3, first + 3) -= 0.3 / h;
  hessian(first + 4, first + 4) -= 2 / h;
  MatrixX const mass = actor->ComputeMassMatrix();
  real const w = 1 / (h * h);
  CAPTURE(hessian, w * mass);
  REQUIRE((hessian - w * mass).lpNorm<Eigen::Infinity>() <= 1e-10 * w * mass.lpNorm<Eigen::Infinity>());
  REQUIRE((mass - mass.transpose()).lpNorm<Eigen::Infinity>() <= 1e-14 * mass.lpNorm<Eigen::Infinity>());
  REQUIRE(SymmetricEigenvalues(mass).minCoeff() > 0);
}

namespace {

/// A random tree of `numLinks` links: shape 0 a chain, 1 random parents; the
/// root free (floating) or revolute, the others revolute, prismatic,
/// spherical or fixed, at random poses and velocities.
ArticulatedActorParams RandomTree(int numLinks, int shape, bool floating, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<real> uniform(-1, 1);
  ArticulatedActorParams p;
  JointType const types[] = {JointType::Revolute, JointType::Prismatic, JointType::Spherical, JointType::Fixed};
  for (int i = 0; i < numLinks; ++i) {
    int const parent = i == 0 ? -1 : shape == 0 ? i - 1 : static_cast<int>(random() % static_cast<unsigned>(i));
    JointType const joint = i == 0 ? (floating ? JointType::Free : JointType::Revolute) : types[random() % 4];
    DynamicArray<real> position, velocity;
    for (int k = 0; k < JointDofs(joint); ++k) {
      position.push_back(0.8 * uniform(random));
      velocity.push_back(uniform(random));
    }
    ArticulatedLinkParams l = Link(parent, joint, Real3(0.3, 0.1 * uniform(random), 0.1 * uniform(random)),
                                   std::move(position), std::move(velocity));
    l.axis = Real3(uniform(random), uniform(random), 1);
    l.mass = 0.5 + 0.5 * (1 + uniform(random));
    l.armature = i % 3 == 0 ? 0.02 : 0;
    l.damping = i % 4 == 1 ? 0.5 : 0;
    p.links.push_back(std::move(l));
  }
  return p;
}

}  // namespace

TEST_CASE("the tree recursion solves the actor's Newton system as the dense block does",
          "[actors][articulated][tree]") {
  int const numLinks = GENERATE(1, 3, 12, 30);
  int const shape = GENERATE(0, 1);
  bool const floating = GENERATE(false, true);
  real const h = GENERATE(0.005, 0.2);
  unsigned const seed = GENERATE(1u, 2u);
  CAPTURE(numLinks, shape, floating, h, seed);
  auto scene = MakeScene();
  Error error;
  ArticulatedActor* actor = scene->CreateArticulatedActor(RandomTree(numLinks, shape, floating, seed), error);
  INFO(error.ToString());
  REQUIRE(actor);
  int const n = actor->GetNumDofs();
  ActorTestAccess::BeginStage(*actor, internal::MakeStage(IntegratorType::BackwardEuler, h, false), Real3(0, -9.81, 0));
  DynamicArray<real> offset(n);
  for (int k = 0; k < n; ++k) offset[k] = 0.1 * std::sin(1.7 * k + seed);
  ActorTestAccess::SaveIterate(*actor);
  ActorTestAccess::ApplyIncrementFromSaved(*actor, offset, 1);

  // the dense block (exact, and its modified Cholesky)
  ActorTestAccess::SetSolvesOwnBlock(*actor, false);
  ActorDerivatives const dense = AssembleActor(*actor, false);
  MatrixX const projected = AssembleActor(*actor, true).hessian;
  VectorX const rhs = -dense.gradient;
  real const scale = dense.hessian.lpNorm<Eigen::Infinity>();
  real const smallest = SymmetricEigenvalues(dense.hessian).minCoeff();
  CAPTURE(n, scale, smallest);

  // the tree: one contributor per joint, the rest kept by the actor
  ActorTestAccess::SetSolvesOwnBlock(*actor, true);
  DynamicArray<DynamicArray<int>> contributors;
  DynamicArray<int> blocks;
  ActorTestAccess::AppendContributorDofs(*actor, contributors);
  ActorTestAccess::AppendDofBlockSizes(*actor, blocks);
  int numJointsWithDofs = 0;
  for (int i = 0; i < actor->GetNumLinks(); ++i) numJointsWithDofs += actor->GetJointNumDofs(i) > 0;
  REQUIRE(static_cast<int>(contributors.size()) == numJointsWithDofs);
  internal::HessianAssembler assembler;
  REQUIRE(assembler.Analyze(n, blocks, contributors, OrderingMethod::Natural, error));
  // the assembled matrix is block-diagonal by joint: n(n+1)/2 entries at most per joint
  REQUIRE(assembler.GetMatrix().values.size() <= static_cast<std::size_t>(6 * n));
  auto solveOnTree = [&](bool project, VectorX& x) {
    DynamicArray<real> gradient(n, 0);
    assembler.ZeroValues();
    ActorTestAccess::AddGradientAndHessian(*actor, gradient, assembler, 0, project);
    // the gradient is the dense one, term for term
    CHECK((Eigen::Map<VectorX const>(gradient.data(), n) - dense.gradient).lpNorm<Eigen::Infinity>() <=
          1e-14 * dense.gradient.lpNorm<Eigen::Infinity>());
    std::string reason;
    if (!ActorTestAccess::FactorizeOwnBlock(*actor, assembler, 0, project, reason)) return false;
    // the joints' blocks in the scene's matrix are now the identity
    CHECK(DenseNaturalHessian(assembler).isIdentity(0));
    x = VectorX::Constant(n, 99.0);
    ActorTestAccess::SolveOwnBlock(*actor, Span<real const>(rhs.data(), n), Span<real>(x.data(), n));
    return true;
  };
  VectorX x(n);
  if (smallest > 1e-8 * scale) {
    // positive definite: the dense Cholesky's solution within 1e-10
    VectorX const expected = Eigen::LLT<MatrixX>(dense.hessian).solve(rhs);
    REQUIRE(solveOnTree(false, x));
    CHECK((x - expected).norm() <= 1e-10 * expected.norm());
    CHECK((dense.hessian * x - rhs).norm() <= 1e-10 * scale * expected.norm());
  }
  // indefinite: the exact block Cholesky fails and the actor modifies the
  // tree at once, the step the projected factorization gives
  long const modifiedBefore = actor->GetNumModifiedTreeFactorizations();
  VectorX exact(n);
  REQUIRE(solveOnTree(false, exact));
  if (smallest > 1e-8 * scale) CHECK(actor->GetNumModifiedTreeFactorizations() == modifiedBefore);
  if (smallest < -1e-8 * scale) CHECK(actor->GetNumModifiedTreeFactorizations() == modifiedBefore + 1);
  // the modified factorization: a descent direction, and the exact step
  // where the block is positive definite, as the dense modified Cholesky
  REQUIRE(solveOnTree(true, x));
  if (smallest < -1e-8 * scale) CHECK(exact == x);
  CHECK(dense.gradient.dot(x) < 0);
  if (smallest > 1e-8 * scale) {
    VectorX const expected = Eigen::LLT<MatrixX>(projected).solve(rhs);
    CHECK((x - expected).norm() <= 1e-9 * expected.norm());
  }
}
