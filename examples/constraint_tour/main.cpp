// SuperDex constraint tour: the runtime interface of constraints, exercised
// on a small scene with every call checked. docs/constraints.md quotes this
// file; keep the two in sync.
//
//   superdex_constraint_tour
//
// The scene (y is up, gravity (0, −9.81, 0)):
//   base      held at the origin by a RigidPivotPosition (its centre) and a
//             RigidPivotRotation (its orientation);
//   arm       hangs from the base's right end by a RigidSphericalJoint, its
//             swing limited by a JointRotationRange;
//   carriage  slides along the vertical axis through the base
//             (RigidPrismaticJoint + JointRotationTracking);
//   tool      one of its points follows a prescribed rigid motion
//             (RigidPivotToRigidTarget).
// Prints what each call returns. Exits 1 when any call or value is not what
// the documentation says it is.
#include <superdex/superdex.h>

#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <memory>
#include <string>

using namespace superdex;

namespace {

int failures = 0;

std::string Str(Span<real const> values) {
  std::string s = "[";
  char buffer[32];
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::snprintf(buffer, sizeof buffer, "%s%.4g", i ? ", " : "", values[i]);
    s += buffer;
  }
  return s + "]";
}

std::string Str(Span<int const> values) {
  std::string s = "{";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) s += ',';
    s += std::to_string(values[i]);
  }
  return s + "}";
}

// A call that must succeed.
void Ok(std::string const& what, bool ok, Error& error) {
  if (ok && !error) {
    std::printf("  ok      %s\n", what.c_str());
  } else {
    std::printf("  FAILED  %s: %s\n", what.c_str(), error.ToString().c_str());
    ++failures;
  }
  error.Clear();
}

// A call that must fail with `code`; prints the library's message.
void Fails(std::string const& what, bool ok, Error& error, ErrorCode code) {
  if (!ok && error.GetCode() == code) {
    std::printf("  error   %s -> %s\n", what.c_str(), error.ToString().c_str());
  } else {
    std::printf("  FAILED  %s: expected %s, got %s\n", what.c_str(),
                std::string(ToString(code)).c_str(), ok ? "success" : error.ToString().c_str());
    ++failures;
  }
  error.Clear();
}

// A value that must hold.
void Check(std::string const& what, bool condition) {
  std::printf("  %s %s\n", condition ? "check  " : "FAILED ", what.c_str());
  if (!condition) ++failures;
}

bool Near(Span<real const> a, std::initializer_list<real> b, real tolerance = 1e-9) {
  if (a.size() != b.size()) return false;
  std::size_t i = 0;
  for (real expected : b)
    if (!(std::abs(a[i++] - expected) <= tolerance)) return false;
  return true;
}

Quat AboutZ(real angle) {
  return Quat(Eigen::AngleAxis<real>(angle, Real3::UnitZ()));
}

}  // namespace

int main() {
  constexpr real kInf = std::numeric_limits<real>::infinity();
  Error error;

  // ---- 1. scene and bodies ----
  std::printf("1. scene and bodies\n");
  std::unique_ptr<Scene> scene = Scene::Create(SceneParams{}, error);
  Ok("Scene::Create", scene != nullptr, error);
  if (!scene) return 1;

  auto makeBody = [&](char const* name, Real3 const& position) {
    RigidActorParams p;  // 1 kg, inertia (1, 1, 1) kg·m², at rest
    p.position = position;
    RigidActor* body = scene->CreateRigidActor(p, error);
    Ok(std::string("CreateRigidActor(") + name + ")", body != nullptr, error);
    return body;
  };
  RigidActor* base = makeBody("base", {0, 0, 0});
  RigidActor* arm = makeBody("arm", {1, 0, 0});
  RigidActor* carriage = makeBody("carriage", {0, -1, 0});
  RigidActor* tool = makeBody("tool", {2, 0, 0});
  if (failures) return 1;

  // ---- 2. constraints, one factory each ----
  std::printf("2. constraints\n");
  // hold the base: its centre at the origin, its orientation at identity
  RigidPivotPositionConstraintParams pinParams;
  pinParams.actor = base->GetHandle();
  pinParams.localPos = {0, 0, 0};  // pivot in the body frame [m]
  pinParams.position = {0, 0, 0};  // target, world [m]
  pinParams.stiffness = 1e5;       // N/m
  pinParams.damping = 10;          // N·s/m
  Constraint* pin = scene->CreateRigidPivotPositionConstraint(pinParams, error);
  Ok("CreateRigidPivotPositionConstraint", pin != nullptr, error);

  RigidPivotRotationConstraintParams holdParams;
  holdParams.actor = base->GetHandle();
  holdParams.rotation = Quat::Identity();  // target, world
  holdParams.stiffness = 1e4;              // N·m/rad
  holdParams.damping = 1;                  // N·m·s/rad
  Constraint* hold = scene->CreateRigidPivotRotationConstraint(holdParams, error);
  Ok("CreateRigidPivotRotationConstraint", hold != nullptr, error);

  // the arm hangs from the base's right end (0.5, 0, 0) by its left end
  RigidSphericalJointConstraintParams shoulderParams;
  shoulderParams.actorA = base->GetHandle();
  shoulderParams.actorB = arm->GetHandle();
  shoulderParams.localPosA = {0.5, 0, 0};
  shoulderParams.localPosB = {-0.5, 0, 0};
  shoulderParams.stiffness = 1e5;
  Constraint* shoulder = scene->CreateRigidSphericalJointConstraint(shoulderParams, error);
  Ok("CreateRigidSphericalJointConstraint", shoulder != nullptr, error);

  // its swing in the x–y plane (z component of the relative rotation vector)
  // stays within ±0.5 rad of the rest pose; the other two components are free
  JointRotationRangeConstraintParams rangeParams;
  rangeParams.actorA = base->GetHandle();
  rangeParams.actorB = arm->GetHandle();
  rangeParams.lowerLimits = {-kInf, -kInf, -0.5};  // rad
  rangeParams.upperLimits = {kInf, kInf, 0.5};
  rangeParams.stiffness = 1e3;  // N·m/rad
  Constraint* range = scene->CreateJointRotationRangeConstraint(rangeParams, error);
  Ok("CreateJointRotationRangeConstraint", range != nullptr, error);

  // the carriage slides along world y (the joint frame's z axis), ±0.2 m
  // around where it starts; the prismatic joint leaves rotation free, so a
  // JointRotationTracking keeps the carriage's orientation relative to the base
  RigidPrismaticJointConstraintParams slideParams;
  slideParams.actorA = base->GetHandle();
  slideParams.actorB = carriage->GetHandle();
  slideParams.jointFrame = Quat::FromTwoVectors(Real3::UnitZ(), Real3::UnitY());
  slideParams.lowerLimit = -0.2;  // m
  slideParams.upperLimit = 0.2;
  slideParams.stiffness = 1e4;
  Constraint* slide = scene->CreateRigidPrismaticJointConstraint(slideParams, error);
  Ok("CreateRigidPrismaticJointConstraint", slide != nullptr, error);

  JointRotationTrackingConstraintParams lockParams;
  lockParams.actorA = base->GetHandle();
  lockParams.actorB = carriage->GetHandle();
  lockParams.stiffness = 1e3;  // N·m/rad
  lockParams.damping = 1;
  Constraint* lock = scene->CreateJointRotationTrackingConstraint(lockParams, error);
  Ok("CreateJointRotationTrackingConstraint", lock != nullptr, error);

  // the tool's point (0.1, 0, 0) follows the prescribed transform T̂
  RigidPivotToRigidTargetConstraintParams gripParams;
  gripParams.actor = tool->GetHandle();
  gripParams.localPos = {0.1, 0, 0};
  gripParams.position = {2, 0, 0};         // T̂: translation ...
  gripParams.rotation = Quat::Identity();  // ... and rotation
  gripParams.stiffness = 1e4;
  Constraint* grip = scene->CreateRigidPivotToRigidTargetConstraint(gripParams, error);
  Ok("CreateRigidPivotToRigidTargetConstraint", grip != nullptr, error);
  if (failures) return 1;

  // bad parameters are reported and create nothing
  RigidSphericalJointConstraintParams bad = shoulderParams;
  bad.actorB = base->GetHandle();  // the same body twice
  Fails("CreateRigidSphericalJointConstraint(actorA == actorB)",
        scene->CreateRigidSphericalJointConstraint(bad, error) != nullptr, error,
        ErrorCode::InvalidArgument);
  Check("7 constraints", scene->GetNumConstraints() == 7);

  // ---- 3. handles and introspection ----
  std::printf("3. handles and introspection\n");
  ConstraintHandle const shoulderHandle = shoulder->GetHandle();
  Check("GetConstraint(shoulder->GetHandle()) == shoulder",
        scene->GetConstraint(shoulderHandle) == shoulder);
  scene->ForEachConstraint([](Constraint& c) {
    std::printf("          %-24s actors %d  m %d  n %2d  dofs",
                std::string(ToString(c.GetType())).c_str(), c.GetNumActors(), c.GetDimension(),
                c.GetNumDofs());
    for (int i = 0; i < c.GetNumActors(); ++i)
      std::printf(" %s", Str(c.GetDofIndicesForActor(i)).c_str());
    std::printf("\n");
  });
  Check("slide->GetActor(1) == carriage", slide->GetActor(1) == carriage);
  Check("slide->GetActor(2) == nullptr (out of range)", slide->GetActor(2) == nullptr);
  Check("slide->GetType() == RigidPrismaticJoint",
        slide->GetType() == ConstraintType::RigidPrismaticJoint);
  Check("range touches the arm's rotation DoFs {9,10,11}",
        Str(range->GetDofIndicesForActor(1)) == "{9,10,11}");

  // ---- 4. stiffness, damping, saturation ----
  std::printf("4. parameters\n");
  Ok("pin->SetStiffness(2e5)", pin->SetStiffness(2e5, error), error);
  Ok("pin->SetDamping(20)", pin->SetDamping(20, error), error);
  Ok("pin->SetSaturation(0.01)   force cap 2e5 * 0.01 = 2000 N", pin->SetSaturation(0.01, error),
     error);
  Ok("pin->SetSaturation(-1)     disabled again", pin->SetSaturation(-1, error), error);
  Fails("pin->SetStiffness(-1)", pin->SetStiffness(-1, error), error, ErrorCode::InvalidArgument);
  Check("the failed call changed nothing: stiffness 2e5", pin->GetStiffness() == 2e5);
  Check("GetDamping() == 20, GetSaturation() == -1",
        pin->GetDamping() == 20 && pin->GetSaturation() == -1);

  // ---- 5. targets ----
  std::printf("5. targets\n");
  // teleport the pin's target 5 cm up: UpdateOldTarget, so the jump is not
  // read as a velocity by the damping term
  Ok("pin->SetTargetPosition({0, 0.05, 0})", pin->SetTargetPosition({0, 0.05, 0}, error), error);
  Ok("pin->UpdateOldTarget()", pin->UpdateOldTarget(error), error);
  DynamicArray<real> g = pin->GetDeviation();
  std::printf("          pin g = %s m\n", Str(g).c_str());
  Check("pin g = T(r) - p = (0, -0.05, 0)", Near(g, {0, -0.05, 0}));

  // turn the base's target 0.1 rad about z without UpdateOldTarget: the
  // damping term reads the change as the target moving during the next step
  Ok("hold->SetTargetRotation(0.1 rad about z)", hold->SetTargetRotation(AboutZ(0.1), error),
     error);
  g = hold->GetDeviation();
  std::printf("          hold g = %s rad\n", Str(g).c_str());
  Check("hold g = Log(R R^-1) = (0, 0, -0.1)", Near(g, {0, 0, -0.1}));

  Ok("lock->SetTargetRotation(identity)", lock->SetTargetRotation(Quat::Identity(), error), error);
  Check("lock g = 0 (the bodies are aligned)", Near(lock->GetDeviation(), {0, 0, 0}));

  Ok("grip->SetTargetTransform({2, 0, 0}, 0.2 rad about z)",
     grip->SetTargetTransform({2, 0, 0}, AboutZ(0.2), error), error);
  g = grip->GetDeviation();
  std::printf("          grip g = %s m\n", Str(g).c_str());
  Check("grip g = T(r) - T^(r)", Near(g, {0.1 * (1 - std::cos(0.2)), -0.1 * std::sin(0.2), 0}));

  // ---- 6. methods that do not apply ----
  std::printf("6. methods that do not apply\n");
  Fails("pin->SetTargetDof(0.3)", pin->SetTargetDof(0.3, error), error, ErrorCode::NotSupported);
  Fails("hold->SetTargetPosition(...)", hold->SetTargetPosition({0, 0, 0}, error), error,
        ErrorCode::NotSupported);
  Fails("shoulder->UpdateOldTarget()", shoulder->UpdateOldTarget(error), error,
        ErrorCode::NotSupported);
  Fails("slide->GetLimitMinValues()", !slide->GetLimitMinValues(error).empty(), error,
        ErrorCode::NotSupported);

  // ---- 7. limits of a range type ----
  std::printf("7. limits\n");
  DynamicArray<real> const lower = range->GetLimitMinValues(error);
  Ok("range->GetLimitMinValues() = " + Str(lower), !lower.empty(), error);
  DynamicArray<real> const upper = range->GetLimitMaxValues(error);
  Ok("range->GetLimitMaxValues() = " + Str(upper), !upper.empty(), error);
  Check("unbounded components report -inf / +inf",
        lower.size() == 3 && upper.size() == 3 && lower[0] == -kInf && lower[1] == -kInf &&
            lower[2] == -0.5 && upper[0] == kInf && upper[1] == kInf && upper[2] == 0.5);
  Check("range g = 0 inside its bounds", Near(range->GetDeviation(), {0, 0, 0}));
  Check("range->IsRange(), !slide->IsRange()", range->IsRange() && !slide->IsRange());

  // ---- 8. force queries ----
  std::printf("8. force queries\n");
  Check("pin->IsQuerySupported(ConstraintForce)",
        pin->IsQuerySupported(QueryType::ConstraintForce));
  Fails("pin->GetForce() before RegisterQuery", !pin->GetForce(error).empty(), error,
        ErrorCode::InvalidState);
  Ok("pin->RegisterQuery(ConstraintForce)", pin->RegisterQuery(QueryType::ConstraintForce, error),
     error);
  Ok("shoulder->RegisterQuery(ConstraintForce)",
     shoulder->RegisterQuery(QueryType::ConstraintForce, error), error);
  Fails("pin->GetForce() before a step", !pin->GetForce(error).empty(), error,
        ErrorCode::InvalidState);
  Ok("scene->Step(0.01)", scene->Step(0.01, error), error);
  Span<real const> const pinForce = pin->GetForce(error);
  Ok("pin->GetForce() = " + Str(pinForce) + "  (N on the base, then N·m)", pinForce.size() == 6,
     error);
  Span<real const> const jointForce = shoulder->GetForce(error);
  Ok("shoulder->GetForce() = " + Str(jointForce), jointForce.size() == 12, error);
  Check("the joint pulls the two bodies with opposite forces",
        jointForce.size() == 12 && std::abs(jointForce[0] + jointForce[6]) < 1e-9 &&
            std::abs(jointForce[1] + jointForce[7]) < 1e-9 &&
            std::abs(jointForce[2] + jointForce[8]) < 1e-9);

  // ---- 9. destruction ----
  std::printf("9. destruction\n");
  Ok("DestroyConstraint(grip)        by pointer", scene->DestroyConstraint(grip, error), error);
  ConstraintHandle const holdHandle = hold->GetHandle();
  Ok("DestroyConstraint(holdHandle)  by handle", scene->DestroyConstraint(holdHandle, error),
     error);
  Check("GetConstraint(holdHandle) == nullptr (stale)",
        scene->GetConstraint(holdHandle) == nullptr);
  Fails("DestroyConstraint(holdHandle) again", scene->DestroyConstraint(holdHandle, error), error,
        ErrorCode::InvalidHandle);
  // a new constraint may reuse the freed slot; the old handle stays stale
  Constraint* hold2 = scene->CreateRigidPivotRotationConstraint(holdParams, error);
  Ok("CreateRigidPivotRotationConstraint (again)", hold2 != nullptr, error);
  if (hold2) {
    std::printf("          old handle {%u, gen %u}, new handle {%u, gen %u}\n", holdHandle.index,
                holdHandle.generation, hold2->GetHandle().index, hold2->GetHandle().generation);
    Check("the old handle still names nothing",
          scene->GetConstraint(holdHandle) == nullptr &&
              scene->GetConstraint(hold2->GetHandle()) == hold2);
  }
  int const before = scene->GetNumConstraints();
  Ok("DestroyActor(arm)", scene->DestroyActor(arm->GetHandle(), error), error);
  std::printf("          constraints: %d -> %d\n", before, scene->GetNumConstraints());
  Check(
      "the shoulder and the range went with the arm",
      scene->GetNumConstraints() == before - 2 && scene->GetConstraint(shoulderHandle) == nullptr);
  Check("the carriage's DoFs were renumbered: slide touches {6,7,8}",
        Str(slide->GetDofIndicesForActor(1)) == "{6,7,8}");
  Ok("scene->Step(0.01)", scene->Step(0.01, error), error);

  if (failures) {
    std::printf("superdex_constraint_tour: %d unexpected result(s)\n", failures);
    return 1;
  }
  std::printf("superdex_constraint_tour: every call returned what was expected\n");
  return 0;
}
