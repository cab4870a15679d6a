// Automatic sub-stepping (SubstepParams): a step that fails at dt is retried
// from the exact pre-step state as 2, 4, ... sub-steps; it equals the steps
// Step(dt/k) would take (targets interpolated from the old to the new one,
// BDF2 history restarted where the step size changes), it is reported in
// SceneStats, and a step whose every attempt fails changes nothing.
//
// The scene that needs it: a chain of 6 rigid bodies on stiff joints
// (1e6 N/m) released horizontally at dt = 0.05, with the reference page's
// Gauss–Newton constraint Hessian (the default geometric stiffness converges
// here) and Newton capped at 30 iterations. Newton fails its first step whole
// (it would need 38); as 2 sub-steps of 0.025 it needs 6 and 13 iterations.
#include "test_scenes.h"
#include "white_box.h"

#include <superdex/core/validate.h>
#include <superdex/solver/newton_solver.h>

#include <cstring>

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kLargeDt = 0.05;
constexpr int kLinks = 6;

SceneParams Params(IntegratorType integrator, int maxSubsteps) {
  SceneParams params;
  params.integrator = integrator;
  params.substeps.maxSubsteps = maxSubsteps;
  params.newton.constraintHessian = ConstraintHessian::GaussNewton;
  params.newton.maxIterations = 30;
  return params;
}

/// Every rigid body's pose and velocities, and every constraint's target,
/// old target and force (when its query is registered), as raw bytes.
std::string Capture(Scene const& scene) {
  std::string bytes;
  auto append = [&](void const* data, std::size_t size) {
    bytes.append(static_cast<char const*>(data), size);
  };
  scene.ForEachActor([&](Actor& actor) {
    auto const& body = dynamic_cast<RigidActor const&>(actor);
    for (Real3 const& v : {body.GetPosition(), body.GetLinearVelocity(), body.GetAngularVelocity()})
      append(v.data(), sizeof(Real3));
    append(body.GetRotation().coeffs().data(), 4 * sizeof(real));
  });
  scene.ForEachConstraint([&](Constraint& c) {
    Span<real const> const target = internal::ConstraintTestAccess::Target(c);
    Span<real const> const old = internal::ConstraintTestAccess::OldTarget(c);
    append(target.data(), target.size() * sizeof(real));
    append(old.data(), old.size() * sizeof(real));
    Error error;
    Span<real const> const force = c.GetForce(error);
    append(force.data(), force.size() * sizeof(real));
  });
  return bytes;
}

Constraint* Pin(Scene& scene) {
  Constraint* pin = nullptr;
  scene.ForEachConstraint([&](Constraint& c) {
    if (c.GetType() == ConstraintType::RigidPivotPosition) pin = &c;
  });
  REQUIRE(pin);
  return pin;
}

void RegisterForces(Scene& scene) {
  scene.ForEachConstraint([&](Constraint& c) {
    Error error;
    REQUIRE(c.RegisterQuery(QueryType::ConstraintForce, error));
  });
}

/// A body beside the chain on soft, damped kinematic drives (so that the
/// path of their targets shows in its motion): a RigidPivotToRigidTarget
/// (transform target) and a RigidPivotRotation (rotation target).
struct DrivenBody {
  Constraint* transform = nullptr;
  Constraint* rotation = nullptr;
};

DrivenBody AddDrivenBody(Scene& scene) {
  RigidActorParams params;
  params.position = Real3(0, 1, 0);
  RigidActor* body = MakeRigid(scene, params);
  Error error;
  DrivenBody driven;
  RigidPivotToRigidTargetConstraintParams transform;
  transform.actor = body->GetHandle();
  transform.localPos = Real3(0.1, 0, 0);
  transform.position = Real3(0.1, 1, 0);
  transform.stiffness = 1e4;
  transform.damping = 50;
  driven.transform = scene.CreateRigidPivotToRigidTargetConstraint(transform, error);
  RigidPivotRotationConstraintParams rotation;
  rotation.actor = body->GetHandle();
  rotation.stiffness = 1e3;
  rotation.damping = 5;
  driven.rotation = scene.CreateRigidPivotRotationConstraint(rotation, error);
  REQUIRE(driven.transform);
  REQUIRE(driven.rotation);
  return driven;
}

using TargetArray = std::array<real, 7>;

TargetArray StoredTarget(Constraint const& c, bool old) {
  Span<real const> const t = old ? internal::ConstraintTestAccess::OldTarget(c)
                                 : internal::ConstraintTestAccess::Target(c);
  TargetArray out{};
  std::copy(t.begin(), t.begin() + 7, out.begin());
  return out;
}

Quat StoredRotation(TargetArray const& t, int first) {
  return Quat(t[first], t[first + 1], t[first + 2], t[first + 3]);
}

}  // namespace

TEST_CASE("a step that fails whole succeeds as sub-steps and reports them", "[scene][substep]") {
  IntegratorType const integrator = GENERATE(IntegratorType::BackwardEuler, IntegratorType::Bdf2);
  CAPTURE(ToString(integrator));
  Error error;

  // sub-stepping off (the default): the step fails and says so
  Chain off = MakeChain(kLinks, Params(integrator, 1));
  REQUIRE_FALSE(off.scene->Step(kLargeDt, error));
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::NewtonFailed);
  REQUIRE_FALSE(Contains(error.GetMessage(), "sub-step"));
  REQUIRE(off.scene->GetStats().substeps == 1);
  int const failedWholeIterations = off.scene->GetStats().newtonIterations;
  REQUIRE(failedWholeIterations > 0);

  // on: the same step succeeds as 2 sub-steps
  Chain on = MakeChain(kLinks, Params(integrator, 8));
  REQUIRE(on.scene->Step(kLargeDt, error));
  SceneStats const stats = on.scene->GetStats();
  REQUIRE(stats.substeps == 2);
  REQUIRE(stats.substeppedSteps == 1);
  REQUIRE(stats.steps == 1);
  REQUIRE(on.scene->GetTime() == kLargeDt);

  // the last step's figures add up both attempts: the failed whole one and
  // the two sub-steps (measured on a scene stepped by hand)
  Chain manual = MakeChain(kLinks, Params(integrator, 1));
  int manualIterations = 0;
  for (int i = 0; i < 2; ++i) {
    StepOk(*manual.scene, kLargeDt / 2);
    manualIterations += manual.scene->GetStats().newtonIterations;
  }
  REQUIRE(stats.newtonIterations == failedWholeIterations + manualIterations);

  // a step that needs no sub-stepping reports 1 and leaves the counter
  Chain small = MakeChain(kLinks, Params(integrator, 8));
  StepOk(*small.scene, 1e-3, 3);
  REQUIRE(small.scene->GetStats().substeps == 1);
  REQUIRE(small.scene->GetStats().substeppedSteps == 0);
}

TEST_CASE("a sub-stepped step equals the steps of dt/k taken by hand, bit for bit",
          "[scene][substep]") {
  // Tolerance 0: the sub-steps run the same stages on the same state as
  // k calls of Step(dt/k) (dt/k is exact: k is a power of two), with the
  // targets moved before the step and interpolated as a caller would for
  // sub-step j: p̂⁰ + j/k (p̂ − p̂⁰) for positions, the slerp at j/k for
  // rotations, both for a transform (from the stored old and new targets,
  // the same arithmetic). Under BDF2 the scene has history at 1e-3 first,
  // which neither the sub-steps nor the manual steps may use.
  IntegratorType const integrator = GENERATE(IntegratorType::BackwardEuler, IntegratorType::Bdf2);
  CAPTURE(ToString(integrator));
  Chain sub = MakeChain(kLinks, Params(integrator, 8));
  Chain manual = MakeChain(kLinks, Params(integrator, 1));
  DrivenBody const subDriven = AddDrivenBody(*sub.scene);
  DrivenBody const manualDriven = AddDrivenBody(*manual.scene);
  RegisterForces(*sub.scene);
  RegisterForces(*manual.scene);
  StepOk(*sub.scene, 1e-3, 3);
  StepOk(*manual.scene, 1e-3, 3);
  REQUIRE(Capture(*sub.scene) == Capture(*manual.scene));

  // step 0 runs whole; before step 1 (which needs sub-steps) the targets move
  Real3 const from = Real3::Zero(), to(0.01, 0.02, -0.005);
  Real3 const transformTo(0.15, 1.02, 0);
  Quat const transformRotationTo(Eigen::AngleAxis<real>(0.5, Real3::UnitZ()));
  Quat const rotationTo(Eigen::AngleAxis<real>(0.3, Real3::UnitX()));
  Error error;
  int substepped = 0;
  for (int step = 0; step < 3; ++step) {
    CAPTURE(step);
    TargetArray transformFrom{}, transformTarget{}, rotationFrom{}, rotationTarget{};
    if (step == 1) {
      REQUIRE(Pin(*sub.scene)->SetTargetPosition(to, error));
      REQUIRE(subDriven.transform->SetTargetTransform(transformTo, transformRotationTo, error));
      REQUIRE(subDriven.rotation->SetTargetRotation(rotationTo, error));
      transformFrom = StoredTarget(*subDriven.transform, true);
      transformTarget = StoredTarget(*subDriven.transform, false);
      rotationFrom = StoredTarget(*subDriven.rotation, true);
      rotationTarget = StoredTarget(*subDriven.rotation, false);
      REQUIRE(transformFrom != transformTarget);
      REQUIRE(rotationFrom != rotationTarget);
    }
    INFO(error.ToString());
    REQUIRE(sub.scene->Step(kLargeDt, error));
    int const k = sub.scene->GetStats().substeps;
    CAPTURE(k);
    if (step == 1) REQUIRE(k >= 4);
    substepped += k > 1;
    for (int j = 1; j <= k; ++j) {
      if (step == 1) {
        if (j < k) {
          // (the scene's formula, component by component: p̂⁰ᵢ + s (p̂ᵢ − p̂⁰ᵢ))
          real const s = real(j) / k;
          Real3 target, transformPosition;
          for (int i = 0; i < 3; ++i) {
            target[i] = from[i] + s * (to[i] - from[i]);
            transformPosition[i] = transformFrom[i] + s * (transformTarget[i] - transformFrom[i]);
          }
          Quat const transformRotation =
              StoredRotation(transformFrom, 3).slerp(s, StoredRotation(transformTarget, 3));
          Quat const rotation =
              StoredRotation(rotationFrom, 0).slerp(s, StoredRotation(rotationTarget, 0));
          REQUIRE(Pin(*manual.scene)->SetTargetPosition(target, error));
          REQUIRE(
              manualDriven.transform->SetTargetTransform(transformPosition, transformRotation, error));
          REQUIRE(manualDriven.rotation->SetTargetRotation(rotation, error));
        } else {
          REQUIRE(Pin(*manual.scene)->SetTargetPosition(to, error));
          REQUIRE(
              manualDriven.transform->SetTargetTransform(transformTo, transformRotationTo, error));
          REQUIRE(manualDriven.rotation->SetTargetRotation(rotationTo, error));
        }
      }
      StepOk(*manual.scene, kLargeDt / k);
    }
    REQUIRE(Capture(*sub.scene) == Capture(*manual.scene));
  }
  REQUIRE(sub.scene->GetStats().substeppedSteps == substepped);
  // time advanced by dt per step, not by a sum of sub-steps
  REQUIRE(sub.scene->GetTime() == 1e-3 + 1e-3 + 1e-3 + kLargeDt + kLargeDt + kLargeDt);
  // the caller's target is the target at the end of the step, and the old one
  Span<real const> const target = internal::ConstraintTestAccess::Target(*Pin(*sub.scene));
  Span<real const> const old = internal::ConstraintTestAccess::OldTarget(*Pin(*sub.scene));
  REQUIRE(Real3(target[0], target[1], target[2]) == to);
  REQUIRE(Real3(old[0], old[1], old[2]) == to);
}

TEST_CASE("a step whose every attempt fails changes nothing", "[scene][substep][transaction]") {
  // Capped at 2 sub-steps, the chain at dt = 0.05 goes on as 2 sub-steps per
  // step until a step fails whole and as 2 sub-steps, the first of which
  // succeeds (its stage committed velocities, history, old targets and
  // forces) before the second fails: all of it must be undone. The pin's
  // target, moved before the failing step, is interpolated in the attempt
  // and must come back as set.
  IntegratorType const integrator = GENERATE(IntegratorType::BackwardEuler, IntegratorType::Bdf2);
  CAPTURE(ToString(integrator));
  Chain failing = MakeChain(kLinks, Params(integrator, 2));
  RegisterForces(*failing.scene);
  Error error;
  int succeeded = 0, substepped = 0;
  std::string before;
  for (;; ++succeeded) {
    REQUIRE(succeeded < 10);  // the chain speeds up: a step fails within a few
    REQUIRE(Pin(*failing.scene)->SetTargetPosition(Real3(0, 1e-3 * (succeeded + 1), 0), error));
    before = Capture(*failing.scene);
    if (!failing.scene->Step(kLargeDt, error)) break;
    int const k = failing.scene->GetStats().substeps;
    REQUIRE((k == 1 || k == 2));  // (under BDF2 a step after a sub-stepped one may run whole)
    substepped += k == 2;
  }
  REQUIRE(substepped >= 1);
  CAPTURE(succeeded, error.ToString());
  REQUIRE(succeeded >= 1);
  REQUIRE(error.GetCode() == ErrorCode::NewtonFailed);
  // the message names the last attempt and its failed sub-step: under
  // backward Euler the first sub-step succeeded before the second failed
  // (under BDF2 here the first one fails)
  std::string const t = internal::Format(succeeded * kLargeDt);
  std::string const failedSubstep = integrator == IntegratorType::BackwardEuler ? "2" : "1";
  REQUIRE(error.GetMessage().starts_with("Step(dt = " + internal::Format(kLargeDt) + ") at t = " + t +
                                         " failed in sub-step " + failedSubstep + " of 2 (dt/2 = " +
                                         internal::Format(kLargeDt / 2) + " from t = "));
  REQUIRE(Contains(error.GetMessage(), "the last of the attempts as 1 and 2 sub-steps "
                                       "(SceneParams.substeps.maxSubsteps = 2): stage 0, Newton "
                                       "iteration 30: Newton did not converge"));
  REQUIRE(error.GetMessage().ends_with("; the scene is unchanged"));
  REQUIRE(failing.scene->GetStats().substeps == 2);

  // bit-identical, and the scene goes on exactly as one that never tried
  REQUIRE(Capture(*failing.scene) == before);
  REQUIRE(failing.scene->GetTime() == succeeded * kLargeDt);
  REQUIRE(failing.scene->GetStats().steps == succeeded);
  REQUIRE(failing.scene->GetStats().substeppedSteps == substepped);
  Chain reference = MakeChain(kLinks, Params(integrator, 2));
  RegisterForces(*reference.scene);
  for (int i = 0; i <= succeeded; ++i) {
    REQUIRE(Pin(*reference.scene)->SetTargetPosition(Real3(0, 1e-3 * (i + 1), 0), error));
    if (i < succeeded) StepOk(*reference.scene, kLargeDt);
  }
  REQUIRE(Capture(*reference.scene) == before);
  for (Chain* chain : {&failing, &reference}) {
    REQUIRE(chain->scene->SetSubstepParams({.maxSubsteps = 16}, error));
    StepOk(*chain->scene, kLargeDt);
    REQUIRE(chain->scene->GetStats().substeps > 2);
  }
  REQUIRE(Capture(*failing.scene) == Capture(*reference.scene));
}

TEST_CASE("BDF2 history restarts at each change of step size, within and after a sub-stepped step",
          "[scene][substep][bdf2]") {
  // A free body beside the chain: under constant gravity both integrators
  // give its velocity exactly v⁰ + g t when the history they use spans the
  // step they take; a history over another step size would not (after a
  // step of h/2, BDF2's fixed coefficients give v + (5/6) g h). The first
  // step at dt = 0.04 fails whole (a linear-solver fault at the first Newton
  // iteration the whole step reaches and its halves do not), the next two run
  // whole after it.
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.substeps.maxSubsteps = 4;
  Chain chain = MakeChain(4, params);
  Scene& scene = *chain.scene;
  params.substeps.maxSubsteps = 1;
  Chain manual = MakeChain(4, params);
  Chain probe = MakeChain(4, params);
  RigidActorParams freeParams;
  freeParams.position = Real3(0, 5, 0);
  freeParams.linearVelocity = Real3(1, 2, 0);
  RigidActor* body = MakeRigid(scene, freeParams);
  MakeRigid(*manual.scene, freeParams);
  MakeRigid(*probe.scene, freeParams);
  Real3 const v0 = freeParams.linearVelocity, g = params.gravity;
  real const dt = 0.04;

  // the fault goes at the first Newton iteration the whole step reaches and
  // neither half step does (measured on a probe scene)
  StepOk(*probe.scene, dt / 2);
  int const firstHalf = probe.scene->GetStats().newtonIterations;
  StepOk(*probe.scene, dt / 2);
  int const faultIteration = std::max(firstHalf, probe.scene->GetStats().newtonIterations) + 1;
  probe = MakeChain(4, params);
  MakeRigid(*probe.scene, freeParams);
  StepOk(*probe.scene, dt);
  CAPTURE(faultIteration, probe.scene->GetStats().newtonIterations);
  REQUIRE(probe.scene->GetStats().newtonIterations >= faultIteration);
  internal::SetFaultInjectionForTesting(scene, {.failLinearSolveAtIteration = faultIteration});
  StepOk(scene, dt);
  internal::SetFaultInjectionForTesting(scene, {});
  REQUIRE(scene.GetStats().substeps == 2);
  // (the exact velocity to round-off: Newton ends with a step of ~1e-16)
  REQUIRE((body->GetLinearVelocity() - (v0 + dt * g)).norm() <= 1e-12);
  StepOk(scene, dt, 2);
  REQUIRE(scene.GetStats().substeps == 1);
  REQUIRE((body->GetLinearVelocity() - (v0 + 3 * dt * g)).norm() <= 1e-12);

  // and all of it is what the steps dt/2, dt/2, dt, dt would do
  StepOk(*manual.scene, dt / 2, 2);
  StepOk(*manual.scene, dt, 2);
  REQUIRE(Capture(scene) == Capture(*manual.scene));
}

TEST_CASE("sub-stepping params are validated", "[scene][substep][errors]") {
  Error error;
  for (int bad : {0, -1, -4, 3, 6, 12, 1000, 8192, 1 << 30}) {
    CAPTURE(bad);
    SceneParams params;
    params.substeps.maxSubsteps = bad;
    REQUIRE_FALSE(Scene::Create(params, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    std::string const expected =
        "SceneParams.substeps.maxSubsteps must be a power of two in [1, kMaxSubsteps = 4096] (1 turns "
        "sub-stepping off), got " + std::to_string(bad);
    REQUIRE(error.GetMessage() == expected);
  }
  for (int good : {1, 2, 4, 1024, kMaxSubsteps}) {
    CAPTURE(good);
    SceneParams params;
    params.substeps.maxSubsteps = good;
    REQUIRE(MakeScene(params)->GetParams().substeps.maxSubsteps == good);
  }
  REQUIRE(SceneParams{}.substeps.maxSubsteps == 1);  // off by default

  auto scene = MakeScene();
  REQUIRE_FALSE(scene->SetSubstepParams({.maxSubsteps = 5}, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Contains(error.GetMessage(), "SubstepParams.maxSubsteps must be a power of two in [1, kMaxSubsteps"));
  REQUIRE(Contains(error.GetMessage(), "got 5"));
  REQUIRE(scene->GetParams().substeps.maxSubsteps == 1);
  REQUIRE(scene->SetSubstepParams({.maxSubsteps = 4}, error));
  REQUIRE(scene->GetParams().substeps.maxSubsteps == 4);
}

TEST_CASE("a step failing every attempt up to kMaxSubsteps reports them all and changes nothing",
          "[scene][substep][errors]") {
  // a rigid body at 1e300 m/s overflows in every attempt; listing the
  // attempts up to 2^30 overflowed an int in the message's loop (bad_alloc
  // after ~25 s). At the limit, 13 attempts are made and listed
  SceneParams params;
  params.substeps.maxSubsteps = kMaxSubsteps;
  auto scene = MakeScene(params);
  Error error;
  RigidActorParams body;
  body.linearVelocity = Real3(1e300, 0, 0);
  REQUIRE(scene->CreateRigidActor(body, error));
  std::string const before = Capture(*scene);
  REQUIRE_FALSE(scene->Step(0.01, error));
  INFO(error.ToString());
  CHECK(Contains(error.GetMessage(), "the last of the attempts as 1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, "
                                     "2048 and 4096"));
  CHECK(Capture(*scene) == before);
}
