// Which type-specific runtime methods apply to which constraint type
// (constraints.md, "Runtime interface"), table-driven over the seven rigid
// types × SetTargetPosition, SetTargetRotation, SetTargetTransform,
// SetTargetDof, UpdateOldTarget, GetLimitMinValues, GetLimitMaxValues:
//
//   - a method that does not apply returns false / empty, sets NotSupported
//     with a message naming the method and the type, and changes nothing: the
//     target, the stage-start target and g are bitwise unchanged, and the
//     next step is bitwise that of an identical untouched scene;
//   - a method that applies succeeds with valid input (the limit getters
//     return m values, ±∞ where unbounded);
//   - every setter rejects invalid input with InvalidArgument (NotSupported
//     where it does not apply) and changes nothing;
//   - m, n and the DoF lists of each type match the reference page's table.
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "constraint_test_util.h"

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kInf = std::numeric_limits<real>::infinity();
constexpr real kNaN = std::numeric_limits<real>::quiet_NaN();
constexpr real kDt = 1e-2;

enum class Method {
  SetTargetPosition,
  SetTargetRotation,
  SetTargetTransform,
  SetTargetDof,
  UpdateOldTarget,
  GetLimitMinValues,
  GetLimitMaxValues,
};
constexpr int kNumMethods = 7;

std::string MethodName(Method method) {
  // clang-format off
  switch (method) {
    case Method::SetTargetPosition: return "SetTargetPosition";
    case Method::SetTargetRotation: return "SetTargetRotation";
    case Method::SetTargetTransform: return "SetTargetTransform";
    case Method::SetTargetDof: return "SetTargetDof";
    case Method::UpdateOldTarget: return "UpdateOldTarget";
    case Method::GetLimitMinValues: return "GetLimitMinValues";
    case Method::GetLimitMaxValues: return "GetLimitMaxValues";
  }
  // clang-format on
  return "?";
}

// The expected table: constraints.md's table (m, n, actors) and its runtime
// interface (which type carries which target; only range types report limits —
// RigidPrismaticJoint's travel limits are explicitly not reported).
struct TypeRow {
  ConstraintType type;
  int numActors;
  int dimension;                               // m
  int numDofs;                                 // n
  std::array<DynamicArray<int>, 2> localDofs;  // per actor, in DoF-list order
  bool isRange;
  // indexed by Method: SetTargetPosition, SetTargetRotation, SetTargetTransform,
  // SetTargetDof, UpdateOldTarget, GetLimitMinValues, GetLimitMaxValues
  std::array<bool, kNumMethods> applies;
};

DynamicArray<int> const kAll{0, 1, 2, 3, 4, 5};
DynamicArray<int> const kTranslation{0, 1, 2};
DynamicArray<int> const kRotation{3, 4, 5};
DynamicArray<int> const kNone{};

// clang-format off
TypeRow const kTable[] = {
    //                                   actors m  n   DoFs A, DoFs B   range  Pos    Rot    Trans  Dof    Old    Min    Max
    {ConstraintType::RigidSphericalJoint, 2, 3, 12, {kAll, kAll}, false, {false, false, false, false, false, false, false}},
    {ConstraintType::RigidPrismaticJoint, 2, 3, 9, {kAll, kTranslation}, false, {false, false, false, false, false, false, false}},
    {ConstraintType::JointRotationRange, 2, 3, 6, {kRotation, kRotation}, true, {false, false, false, false, false, true, true}},
    {ConstraintType::JointRotationTracking, 2, 3, 6, {kRotation, kRotation}, false, {false, true, false, false, true, false, false}},
    {ConstraintType::RigidPivotPosition, 1, 3, 6, {kAll, kNone}, false, {true, false, false, false, true, false, false}},
    {ConstraintType::RigidPivotToRigidTarget, 1, 3, 6, {kAll, kNone}, false, {false, false, true, false, true, false, false}},
    {ConstraintType::RigidPivotRotation, 1, 3, 3, {kRotation, kNone}, false, {false, true, false, false, true, false, false}},
};
// clang-format on
constexpr int kNumTypes = static_cast<int>(std::size(kTable));

// JointRotationRange bounds of the scene below: some infinite, and component 0
// violated at rest (l₀ > 0 = r_AB,0), so the constraint is active in a step
Real3 const kRangeLower(0.05, -kInf, -0.1);
Real3 const kRangeUpper(0.4, 0.2, kInf);

// valid inputs of the setters, all different from the creation-time targets
Real3 const kNewPosition(0.3, -0.7, 1.2);
Quat const kNewRotation = QuatOfRotationVector(Real3(0.2, 0.5, -0.4));
real const kNewDof = 0.25;

/// Two moving rigid bodies under gravity and one constraint of `type` between
/// them (or on the first), compliant and damped, with non-trivial parameters.
struct World {
  std::unique_ptr<Scene> scene;
  RigidActor* a = nullptr;
  RigidActor* b = nullptr;
  Constraint* c = nullptr;
};

World MakeWorld(ConstraintType type) {
  World w;
  w.scene = MakeScene();
  RigidActorParams body;
  body.mass = 1.5;
  body.inertia = Real3(0.2, 0.3, 0.4);
  body.position = Real3(0.1, 0.2, -0.3);
  body.rotation = QuatOfRotationVector(Real3(0.3, 0.2, -0.4));
  body.linearVelocity = Real3(0.5, -0.2, 0.1);
  body.angularVelocity = Real3(0.4, -1.0, 0.7);
  w.a = MakeRigid(*w.scene, body);
  body.position = Real3(0.9, -0.1, 0.4);
  body.rotation = QuatOfRotationVector(Real3(-0.5, 0.6, 0.1));
  body.linearVelocity = Real3(-0.3, 0.4, 0.2);
  body.angularVelocity = Real3(-0.6, 0.3, 0.9);
  w.b = MakeRigid(*w.scene, body);

  real const stiffness = 1e3, damping = 5;
  Quat const frame = QuatOfRotationVector(Real3(0.3, -0.5, 0.8));
  Error error;
  switch (type) {
    case ConstraintType::RigidSphericalJoint: {
      RigidSphericalJointConstraintParams p;
      p.actorA = w.a->GetHandle();
      p.actorB = w.b->GetHandle();
      p.localPosA = kPivotA;
      p.localPosB = kPivotB;
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateRigidSphericalJointConstraint(p, error);
      break;
    }
    case ConstraintType::RigidPrismaticJoint: {
      // finite travel limits: they exist, yet GetLimit… must not report them
      RigidPrismaticJointConstraintParams p;
      p.actorA = w.a->GetHandle();
      p.actorB = w.b->GetHandle();
      p.jointFrame = frame;
      p.lowerLimit = -0.2;
      p.upperLimit = 0.1;
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateRigidPrismaticJointConstraint(p, error);
      break;
    }
    case ConstraintType::JointRotationRange: {
      JointRotationRangeConstraintParams p;
      p.actorA = w.a->GetHandle();
      p.actorB = w.b->GetHandle();
      p.jointFrame = frame;
      p.lowerLimits = kRangeLower;
      p.upperLimits = kRangeUpper;
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateJointRotationRangeConstraint(p, error);
      break;
    }
    case ConstraintType::JointRotationTracking: {
      JointRotationTrackingConstraintParams p;
      p.actorA = w.a->GetHandle();
      p.actorB = w.b->GetHandle();
      p.jointFrame = frame;
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateJointRotationTrackingConstraint(p, error);
      break;
    }
    case ConstraintType::RigidPivotPosition: {
      RigidPivotPositionConstraintParams p;
      p.actor = w.a->GetHandle();
      p.localPos = kPivotA;
      p.position = kTargetPosition;
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateRigidPivotPositionConstraint(p, error);
      break;
    }
    case ConstraintType::RigidPivotToRigidTarget: {
      RigidPivotToRigidTargetConstraintParams p;
      p.actor = w.a->GetHandle();
      p.localPos = kPivotA;
      p.position = kTargetPosition;
      p.rotation = QuatOfRotationVector(Real3(1.1, 0.4, -0.7));
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateRigidPivotToRigidTargetConstraint(p, error);
      break;
    }
    case ConstraintType::RigidPivotRotation: {
      RigidPivotRotationConstraintParams p;
      p.actor = w.a->GetHandle();
      p.localRotation = QuatOfRotationVector(Real3(-0.6, 0.2, 0.35));
      p.rotation = QuatOfRotationVector(Real3(0.7, -0.1, 0.3));
      p.stiffness = stiffness;
      p.damping = damping;
      w.c = w.scene->CreateRigidPivotRotationConstraint(p, error);
      break;
    }
    default:
      FAIL("not one of the seven rigid types");
  }
  INFO(error.ToString());
  REQUIRE(w.c);
  REQUIRE(w.c->GetType() == type);
  return w;
}

/// What a call returned: the bool of a setter, or the values of a getter
/// (ok = non-empty).
struct CallResult {
  bool ok = false;
  DynamicArray<real> values;
};

CallResult Call(Constraint& c, Method method, Error& error) {
  CallResult r;
  switch (method) {
    case Method::SetTargetPosition:
      r.ok = c.SetTargetPosition(kNewPosition, error);
      break;
    case Method::SetTargetRotation:
      r.ok = c.SetTargetRotation(kNewRotation, error);
      break;
    case Method::SetTargetTransform:
      r.ok = c.SetTargetTransform(kNewPosition, kNewRotation, error);
      break;
    case Method::SetTargetDof:
      r.ok = c.SetTargetDof(kNewDof, error);
      break;
    case Method::UpdateOldTarget:
      r.ok = c.UpdateOldTarget(error);
      break;
    case Method::GetLimitMinValues:
      r.values = c.GetLimitMinValues(error);
      r.ok = !r.values.empty();
      break;
    case Method::GetLimitMaxValues:
      r.values = c.GetLimitMaxValues(error);
      r.ok = !r.values.empty();
      break;
  }
  return r;
}

/// Everything a call could change in a constraint: the target, the
/// stage-start target and g (compared bitwise).
struct ConstraintState {
  DynamicArray<real> target, oldTarget, deviation;
  bool operator==(ConstraintState const&) const = default;
};

ConstraintState StateOf(Constraint const& c) {
  Span<real const> target = ConstraintTestAccess::Target(c);
  Span<real const> oldTarget = ConstraintTestAccess::OldTarget(c);
  return {DynamicArray<real>(target.begin(), target.end()),
          DynamicArray<real>(oldTarget.begin(), oldTarget.end()), c.GetDeviation()};
}

/// Bitwise equality of the two bodies' states and of g.
bool SameWorld(World const& w, World const& twin) {
  bool same = w.c->GetDeviation() == twin.c->GetDeviation();
  for (auto [x, y] : {std::pair{w.a, twin.a}, std::pair{w.b, twin.b}}) {
    same = same && x->GetPosition() == y->GetPosition() &&
           x->GetRotation().coeffs() == y->GetRotation().coeffs() &&
           x->GetLinearVelocity() == y->GetLinearVelocity() &&
           x->GetAngularVelocity() == y->GetAngularVelocity();
  }
  return same;
}

/// Moves the target of a target-bearing type with the setter that applies.
void MoveTarget(Constraint& c) {
  Error error;
  bool ok = false;
  switch (c.GetType()) {
    case ConstraintType::RigidPivotPosition:
      ok = c.SetTargetPosition(kNewPosition, error);
      break;
    case ConstraintType::RigidPivotToRigidTarget:
      ok = c.SetTargetTransform(kNewPosition, kNewRotation, error);
      break;
    case ConstraintType::RigidPivotRotation:
    case ConstraintType::JointRotationTracking:
      ok = c.SetTargetRotation(kNewRotation, error);
      break;
    default:
      FAIL("not a target-bearing type");
  }
  INFO(error.ToString());
  REQUIRE(ok);
}

DynamicArray<real> ToArray(Span<real const> s) {
  return DynamicArray<real>(s.begin(), s.end());
}

}  // namespace

TEST_CASE("m, n and the DoF lists of each type match the reference table",
          "[constraints][interface]") {
  int const typeIndex = GENERATE(range(0, kNumTypes));
  TypeRow const& row = kTable[typeIndex];
  CAPTURE(ToString(row.type));
  World w = MakeWorld(row.type);
  Constraint const& c = *w.c;
  REQUIRE(c.GetDimension() == row.dimension);
  REQUIRE(c.GetDimension() == 3);
  REQUIRE(c.GetNumDofs() == row.numDofs);
  REQUIRE(c.GetNumActors() == row.numActors);
  REQUIRE(c.IsRange() == row.isRange);
  int total = 0;
  for (int i = 0; i < 2; ++i) {
    CAPTURE(i);
    Span<int const> indices = c.GetDofIndicesForActor(i);
    if (i >= row.numActors) {
      REQUIRE(indices.empty());
      REQUIRE(c.GetActor(i) == nullptr);
      continue;
    }
    REQUIRE(c.GetActor(i) == (i == 0 ? static_cast<Actor*>(w.a) : static_cast<Actor*>(w.b)));
    // global index = the actor's DoF offset + the local DoF of the table
    DynamicArray<int> expected;
    for (int local : row.localDofs[i]) expected.push_back(c.GetActor(i)->GetDofOffset() + local);
    REQUIRE(DynamicArray<int>(indices.begin(), indices.end()) == expected);
    total += static_cast<int>(indices.size());
  }
  REQUIRE(total == c.GetNumDofs());
}

TEST_CASE("type-specific methods apply exactly where the reference page says",
          "[constraints][interface]") {
  int const typeIndex = GENERATE(range(0, kNumTypes));
  int const methodIndex = GENERATE(range(0, kNumMethods));
  TypeRow const& row = kTable[typeIndex];
  Method const method = static_cast<Method>(methodIndex);
  bool const applies = row.applies[methodIndex];
  std::string const typeName(ToString(row.type));
  CAPTURE(typeName, MethodName(method), applies);

  World w = MakeWorld(row.type);
  World twin = MakeWorld(row.type);  // identical, never touched
  Constraint& c = *w.c;
  REQUIRE(StateOf(c) == StateOf(*twin.c));

  if (!applies) {
    ConstraintState const before = StateOf(c);
    Error error;
    CallResult const result = Call(c, method, error);
    REQUIRE_FALSE(result.ok);
    REQUIRE(result.values.empty());
    REQUIRE(error.GetCode() == ErrorCode::NotSupported);
    CAPTURE(error.GetMessage());
    REQUIRE(error.GetMessage().find(MethodName(method)) != std::string::npos);
    REQUIRE(error.GetMessage().find(typeName) != std::string::npos);
    // nothing changed: target, stage-start target and g bitwise, and the next
    // steps are bitwise those of the untouched twin
    REQUIRE(StateOf(c) == before);
    StepOk(*w.scene, kDt, 2);
    StepOk(*twin.scene, kDt, 2);
    REQUIRE(SameWorld(w, twin));
    return;
  }

  switch (method) {
    case Method::GetLimitMinValues:
    case Method::GetLimitMaxValues: {
      Error error;
      CallResult const result = Call(c, method, error);
      INFO(error.ToString());
      REQUIRE_FALSE(error);
      REQUIRE(result.ok);
      // m values, ±∞ where unbounded
      Real3 const& expected = method == Method::GetLimitMinValues ? kRangeLower : kRangeUpper;
      REQUIRE(static_cast<int>(result.values.size()) == c.GetDimension());
      for (int j = 0; j < 3; ++j) {
        CAPTURE(j, result.values[j], expected[j]);
        REQUIRE(result.values[j] == expected[j]);
      }
      REQUIRE(std::isinf(result.values[method == Method::GetLimitMinValues ? 1 : 2]));
      REQUIRE(StateOf(c) == StateOf(*twin.c));  // a getter changes nothing
      break;
    }
    case Method::UpdateOldTarget: {
      // move the target in both worlds; only `w` resets its stage-start target
      MoveTarget(c);
      MoveTarget(*twin.c);
      REQUIRE(ToArray(ConstraintTestAccess::OldTarget(c)) !=
              ToArray(ConstraintTestAccess::Target(c)));
      Error error;
      REQUIRE(Call(c, method, error).ok);
      INFO(error.ToString());
      REQUIRE_FALSE(error);
      REQUIRE(ToArray(ConstraintTestAccess::OldTarget(c)) ==
              ToArray(ConstraintTestAccess::Target(c)));
      REQUIRE(c.GetDeviation() == twin.c->GetDeviation());  // g does not see p̂⁰
      // the teleport removed the damping transient the twin still has
      StepOk(*w.scene, kDt);
      StepOk(*twin.scene, kDt);
      REQUIRE_FALSE(SameWorld(w, twin));
      break;
    }
    default: {  // a target setter that applies
      ConstraintState const before = StateOf(c);
      Error error;
      REQUIRE(Call(c, method, error).ok);
      INFO(error.ToString());
      REQUIRE_FALSE(error);
      ConstraintState const after = StateOf(c);
      // the target is the new value; the stage-start target is left for the
      // damping term to difference against
      DynamicArray<real> expectedTarget;
      if (method == Method::SetTargetPosition || method == Method::SetTargetTransform)
        expectedTarget.insert(expectedTarget.end(), kNewPosition.begin(), kNewPosition.end());
      if (method == Method::SetTargetRotation || method == Method::SetTargetTransform)
        expectedTarget.insert(expectedTarget.end(), {kNewRotation.w(), kNewRotation.x(),
                                                     kNewRotation.y(), kNewRotation.z()});
      // (a rotation is stored normalized: equal to within rounding)
      for (std::size_t i = 0; i < expectedTarget.size(); ++i) {
        CAPTURE(i, after.target[i], expectedTarget[i]);
        REQUIRE(std::abs(after.target[i] - expectedTarget[i]) <= 1e-15);
      }
      REQUIRE(after.oldTarget == before.oldTarget);
      REQUIRE(after.deviation != before.deviation);
      break;
    }
  }
}

TEST_CASE("setters reject invalid input and change nothing", "[constraints][interface]") {
  int const typeIndex = GENERATE(range(0, kNumTypes));
  TypeRow const& row = kTable[typeIndex];
  std::string const typeName(ToString(row.type));
  CAPTURE(typeName);
  World w = MakeWorld(row.type);
  Constraint& c = *w.c;
  ConstraintState const before = StateOf(c);

  Real3 const nanPosition(kNaN, 0, 0);
  Real3 const infinitePosition(0, kInf, 0);
  Quat const nonUnit(2, 0, 0, 0);
  Quat const slightlyNonUnit(1 + 1e-4, 0, 0, 0);  // beyond the 1e-6 unit tolerance
  Quat const zero(0, 0, 0, 0);
  Quat const nanRotation(kNaN, 0, 0, 0);

  struct Invalid {
    Method method;
    char const* what;
    char const* field;  // the field the InvalidArgument message must name
    std::function<bool(Error&)> call;
  };
  Invalid const calls[] = {
      {Method::SetTargetPosition, "NaN position", "position",
       [&](Error& e) { return c.SetTargetPosition(nanPosition, e); }},
      {Method::SetTargetPosition, "infinite position", "position",
       [&](Error& e) { return c.SetTargetPosition(infinitePosition, e); }},
      {Method::SetTargetRotation, "non-unit quaternion", "rotation",
       [&](Error& e) { return c.SetTargetRotation(nonUnit, e); }},
      {Method::SetTargetRotation, "slightly non-unit quaternion", "rotation",
       [&](Error& e) { return c.SetTargetRotation(slightlyNonUnit, e); }},
      {Method::SetTargetRotation, "zero quaternion", "rotation",
       [&](Error& e) { return c.SetTargetRotation(zero, e); }},
      {Method::SetTargetRotation, "NaN quaternion", "rotation",
       [&](Error& e) { return c.SetTargetRotation(nanRotation, e); }},
      {Method::SetTargetTransform, "NaN position, valid rotation", "position",
       [&](Error& e) { return c.SetTargetTransform(nanPosition, kNewRotation, e); }},
      {Method::SetTargetTransform, "valid position, non-unit rotation", "rotation",
       [&](Error& e) { return c.SetTargetTransform(kNewPosition, nonUnit, e); }},
      {Method::SetTargetTransform, "valid position, NaN rotation", "rotation",
       [&](Error& e) { return c.SetTargetTransform(kNewPosition, nanRotation, e); }},
      {Method::SetTargetDof, "NaN dof", "value", [&](Error& e) { return c.SetTargetDof(kNaN, e); }},
      {Method::SetTargetDof, "infinite dof", "value",
       [&](Error& e) { return c.SetTargetDof(kInf, e); }},
  };
  int rejectedAsInvalid = 0;
  for (Invalid const& invalid : calls) {
    bool const applies = row.applies[static_cast<int>(invalid.method)];
    CAPTURE(MethodName(invalid.method), invalid.what, applies);
    Error error;
    REQUIRE_FALSE(invalid.call(error));
    CAPTURE(error.GetMessage());
    if (applies) {
      // the setter applies: the input is what is wrong
      REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
      REQUIRE(error.GetMessage().find(invalid.field) != std::string::npos);
      ++rejectedAsInvalid;
    } else {
      // applicability is checked first: NotSupported whatever the input
      REQUIRE(error.GetCode() == ErrorCode::NotSupported);
      REQUIRE(error.GetMessage().find(MethodName(invalid.method)) != std::string::npos);
      REQUIRE(error.GetMessage().find(typeName) != std::string::npos);
    }
    // target, stage-start target and g bitwise unchanged
    REQUIRE(StateOf(c) == before);
  }
  // every target-bearing type had its own setter exercised with bad input
  // (SetTargetDof applies to none of these seven types: its InvalidArgument
  // path belongs to the articulated types)
  bool const hasTarget = row.applies[static_cast<int>(Method::UpdateOldTarget)];
  REQUIRE((rejectedAsInvalid > 0) == hasTarget);
}
