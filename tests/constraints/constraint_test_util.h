// Shared fixtures of the constraint derivative tests: a scene of rigid bodies
// at chosen poses, constraints made through the public Scene API, and central
// differences over a constraint's DoFs in the tangent increments of
// docs/design.md §3 (t ± ε e_j; R ← Exp(±ε e_j) R).
#pragma once

#include "test_support.h"
#include "white_box.h"

#include <algorithm>
#include <limits>
#include <numbers>
#include <random>
#include <type_traits>

namespace superdex::test {

using internal::ActorTestAccess;
using internal::ConstraintTestAccess;

struct Pose {
  Real3 position;
  Quat rotation;
};

/// A pose with rotation `angle` about a random axis and a random position in
/// [−1, 1]³, both from `seed` (the axis is built with Eigen's AngleAxis, not
/// superdex::Exp).
inline Pose RandomPose(real angle, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<real> normal;
  std::uniform_real_distribution<real> uniform(-1, 1);
  Real3 axis(normal(rng), normal(rng), normal(rng));
  axis.normalize();
  Real3 const position(uniform(rng), uniform(rng), uniform(rng));
  return {position, Quat(Eigen::AngleAxis<real>(angle, axis))};
}

/// A scene (gravity irrelevant, zero) with two rigid bodies of generic mass
/// properties at the given poses.
struct RigidPair {
  std::unique_ptr<Scene> scene;
  RigidActor* a = nullptr;
  RigidActor* b = nullptr;
};

inline RigidPair MakeRigidPair(Pose const& poseA, Pose const& poseB) {
  SceneParams params;
  params.gravity = Real3::Zero();
  RigidPair pair;
  pair.scene = MakeScene(params);
  RigidActorParams body;
  body.mass = 1.5;
  body.inertia = Real3(0.2, 0.3, 0.4);
  body.position = poseA.position;
  body.rotation = poseA.rotation;
  pair.a = MakeRigid(*pair.scene, body);
  body.position = poseB.position;
  body.rotation = poseB.rotation;
  pair.b = MakeRigid(*pair.scene, body);
  return pair;
}

// non-zero, non-axis-aligned pivots, so that every rotation column of J is
// non-zero
inline Real3 const kPivotA{0.3, -0.2, 0.5};
inline Real3 const kPivotB{-0.4, 0.1, 0.25};
inline Real3 const kTargetPosition{1.0, 2.0, -0.5};

inline Constraint* MakeSphericalJoint(RigidPair& pair, internal::CompliantParams const& compliance) {
  RigidSphericalJointConstraintParams p;
  p.actorA = pair.a->GetHandle();
  p.actorB = pair.b->GetHandle();
  p.localPosA = kPivotA;
  p.localPosB = kPivotB;
  p.stiffness = compliance.stiffness;
  p.damping = compliance.damping;
  p.saturation = compliance.saturation;
  Error error;
  Constraint* c = pair.scene->CreateRigidSphericalJointConstraint(p, error);
  INFO(error.ToString());
  REQUIRE(c);
  return c;
}

inline Constraint* MakePivotPosition(RigidPair& pair, internal::CompliantParams const& compliance) {
  RigidPivotPositionConstraintParams p;
  p.actor = pair.a->GetHandle();
  p.localPos = kPivotA;
  p.position = kTargetPosition;
  p.stiffness = compliance.stiffness;
  p.damping = compliance.damping;
  p.saturation = compliance.saturation;
  Error error;
  Constraint* c = pair.scene->CreateRigidPivotPositionConstraint(p, error);
  INFO(error.ToString());
  REQUIRE(c);
  return c;
}

// ---- test-side rotation maps (Eigen only: independent of superdex::Exp/Log) ----

/// Unit quaternion of the rotation vector φ, through Eigen::AngleAxis.
inline Quat QuatOfRotationVector(Real3 const& phi) {
  real const angle = phi.norm();
  if (angle == 0) return Quat::Identity();
  return Quat(Eigen::AngleAxis<real>(angle, phi / angle));
}

/// The reference Log: rotation vector angle·axis of a rotation matrix through
/// Eigen::AngleAxis (angle ∈ [0, π]), not superdex::Log.
inline Real3 ReferenceLog(Real33 const& rotation) {
  Eigen::AngleAxis<real> const angleAxis(rotation);
  return angleAxis.angle() * angleAxis.axis();
}

// ---- range bounds placed around a measured value ----

/// Where a bounded component sits relative to its bounds l <= u.
enum class RangeRegion { BelowLower, Inside, AboveUpper };

inline char const* ToString(RangeRegion region) {
  switch (region) {
    case RangeRegion::BelowLower: return "below lower";
    case RangeRegion::Inside: return "inside";
    case RangeRegion::AboveUpper: return "above upper";
  }
  return "?";
}

struct Bounds {
  real lower, upper;
};

/// Bounds that put the measured value x in `region`, `margin` away from the
/// nearest bound. `oneSided` makes the bound on the far side infinite (inside:
/// the lower one); otherwise the far bound is 3·margin away.
inline Bounds BoundsPlacing(real x, RangeRegion region, real margin, bool oneSided) {
  real const inf = std::numeric_limits<real>::infinity();
  switch (region) {
    case RangeRegion::BelowLower: return {x + margin, oneSided ? inf : x + 3 * margin};
    case RangeRegion::AboveUpper: return {oneSided ? -inf : x - 3 * margin, x - margin};
    case RangeRegion::Inside: return {oneSided ? -inf : x - margin, x + margin};
  }
  return {-inf, inf};
}

/// The reference page's one-sided violation max(x − u, l − x, 0).
inline real ReferenceViolation(real x, Bounds const& bounds) {
  return std::max({x - bounds.upper, bounds.lower - x, real(0)});
}

inline RigidActor& RigidOf(Constraint const& c, int actorIndex) {
  auto* body = dynamic_cast<RigidActor*>(c.GetActor(actorIndex));
  REQUIRE(body);
  return *body;
}

inline VectorX Deviation(Constraint const& c) {
  DynamicArray<real> const g = c.GetDeviation();
  return Eigen::Map<VectorX const>(g.data(), static_cast<Eigen::Index>(g.size()));
}

/// Central differences of f() over the constraint's DoFs, columns in DoF-list
/// order: column j = (f(q + ε e_j) − f(q − ε e_j)) / 2ε. f returns a vector
/// (the result has its size in rows) or a real (one row). Every body is put
/// back at its pose afterwards.
template <class F>
MatrixX CentralDifferenceOverDofs(Constraint const& c, real epsilon, F const& f) {
  int const n = c.GetNumDofs();
  MatrixX result;
  int column = 0;
  for (int a = 0; a < c.GetNumActors(); ++a) {
    RigidActor& body = RigidOf(c, a);
    Pose const base{body.GetPosition(), body.GetRotation()};
    for (int local : ConstraintTestAccess::LocalDofs(c, a)) {
      SetPerturbedPose(body, base.position, base.rotation, local, +epsilon);
      auto const plus = f();
      SetPerturbedPose(body, base.position, base.rotation, local, -epsilon);
      auto const minus = f();
      if constexpr (std::is_arithmetic_v<std::decay_t<decltype(plus)>>) {
        if (column == 0) result.resize(1, n);
        result(0, column++) = (plus - minus) / (2 * epsilon);
      } else {
        if (column == 0) result.resize(plus.size(), n);
        result.col(column++) = (plus - minus) / (2 * epsilon);
      }
    }
    // back to the pose it had
    Error error;
    REQUIRE(body.SetPose(base.position, base.rotation, error));
  }
  REQUIRE(column == n);
  return result;
}

/// Central differences of f() over the constraint's global DoFs in the
/// tangent increments the stage solver applies (Actor::ApplyIncrementFromSaved),
/// columns in DoF-list order: column j = (f(q ⊕ ε e_j) − f(q ⊕ −ε e_j)) / 2ε.
template <class F>
MatrixX CentralDifferenceOverIncrements(Constraint const& c, real eps, F const& f) {
  int const n = c.GetNumDofs();
  DynamicArray<int> const& dofs = ConstraintTestAccess::Dofs(c);
  int numDofs = 0;
  for (int a = 0; a < c.GetNumActors(); ++a)
    numDofs = std::max(numDofs, c.GetActor(a)->GetDofOffset() + c.GetActor(a)->GetNumDofs());
  DynamicArray<real> delta(numDofs, 0);
  MatrixX fd;
  for (int j = 0; j < n; ++j) {
    Actor* owner = nullptr;
    for (int a = 0; a < c.GetNumActors(); ++a) {
      Actor* actor = c.GetActor(a);
      if (dofs[j] >= actor->GetDofOffset() && dofs[j] < actor->GetDofOffset() + actor->GetNumDofs())
        owner = actor;
    }
    REQUIRE(owner);
    ActorTestAccess::SaveIterate(*owner);
    delta[dofs[j]] = eps;
    ActorTestAccess::ApplyIncrementFromSaved(*owner, delta, 1);
    VectorX const plus = f();
    ActorTestAccess::ApplyIncrementFromSaved(*owner, delta, -1);
    VectorX const minus = f();
    ActorTestAccess::RestoreIterate(*owner);
    delta[dofs[j]] = 0;
    if (j == 0) fd.resize(plus.size(), n);
    fd.col(j) = (plus - minus) / (2 * eps);
  }
  return fd;
}

/// J against central differences over the constraint's global DoFs; the
/// columns in `zeroColumns` must vanish (DoFs listed but not acting), every
/// other one must not
inline void CheckJacobian(Scene& /*scene*/, Constraint& c, DynamicArray<int> const& zeroColumns = {},
                          real tolerance = 1e-6) {
  int const m = c.GetDimension(), n = c.GetNumDofs();
  internal::TermWorkspace ws;
  ws.Reserve(m, n);
  ConstraintTestAccess::EvaluateCurrent(c, ws);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);
  real const eps = 1e-6;
  MatrixX const fd = CentralDifferenceOverIncrements(c, eps, [&] { return Deviation(c); });
  for (int j = 0; j < n; ++j) {
    CAPTURE(j);
    bool const zero = std::find(zeroColumns.begin(), zeroColumns.end(), j) != zeroColumns.end();
    if (zero) {
      REQUIRE(fd.col(j).norm() <= 1e-9);
      REQUIRE(jacobian.col(j).isZero());
    } else {
      REQUIRE(fd.col(j).norm() > 0.05);
    }
  }
  CAPTURE(jacobian, fd);
  // smooth g: ε = 1e-6 gives ~1e-10 error against O(1) entries
  REQUIRE((jacobian - fd).cwiseAbs().maxCoeff() <= tolerance);
}
/// The geometric-stiffness term G = Σᵢ wᵢ ∂²gᵢ/∂q² (Constraint::DoAddCurvature)
/// against central differences of the analytic gradient Jᵀw over the
/// constraint's DoFs, for fixed weights w. For rotation increments the
/// difference of a gradient taken at R and at Exp(ε eⱼ) R carries an extra
/// antisymmetric term ½ ∇·(eᵢ × eⱼ) (the increments do not commute), so G is
/// compared with the symmetric part of the difference matrix. `curved`: the
/// curvature of g is non-zero here (G must not vanish, and the type must
/// report HasCurvature; otherwise both G and the differences must vanish).
inline void CheckCurvature(Constraint const& c, bool curved, real tolerance = 1e-6) {
  int const m = c.GetDimension(), n = c.GetNumDofs();
  VectorX weights(m);
  for (int i = 0; i < m; ++i) weights[i] = std::array<real, 3>{0.7, -1.3, 0.45}[i % 3] * (1 + i / 3);
  MatrixX const curvature = ConstraintTestAccess::Curvature(c, weights);
  internal::TermWorkspace ws;
  ws.Reserve(m, n);
  auto gradient = [&] {
    ConstraintTestAccess::EvaluateCurrent(c, ws);
    return VectorX(ws.jacobian.topLeftCorner(m, n).transpose() * weights);
  };
  MatrixX const fd = CentralDifferenceOverIncrements(c, 1e-6, gradient);
  MatrixX const symmetric = 0.5 * (fd + fd.transpose());
  CAPTURE(curvature, symmetric);
  if (curved) {
    REQUIRE(c.HasCurvature());
    REQUIRE(symmetric.cwiseAbs().maxCoeff() > 1e-3);
  } else {
    REQUIRE(symmetric.cwiseAbs().maxCoeff() <= 1e-8);
  }
  REQUIRE(curvature.isApprox(curvature.transpose(), 1e-12));
  // ε = 1e-6 central differences: ~1e-10 against O(1) entries
  REQUIRE((curvature - symmetric).cwiseAbs().maxCoeff() <=
          tolerance * std::max<real>(1, symmetric.cwiseAbs().maxCoeff()));
}

}  // namespace superdex::test
