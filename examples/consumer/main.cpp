// Uses an installed SuperDex through find_package(SuperDex): builds a scene
// with the reference page's ball-and-socket example, steps it, and checks
// the results. Exits non-zero when a result is wrong.
#include <superdex/superdex.h>

#include <cmath>
#include <cstdio>

int main() {
  using namespace superdex;
  int failures = 0;
  auto check = [&](bool ok, char const* what) {
    std::printf("%-58s %s\n", what, ok ? "ok" : "WRONG");
    failures += ok ? 0 : 1;
  };

  std::printf("SuperDex %s\n", SUPERDEX_VERSION_STRING);
  BlasInfo const blas = GetBlasInfo();
  std::printf("BLAS: %s, core %s, %d threads\n", blas.library.c_str(),
              blas.coreName.empty() ? "-" : blas.coreName.c_str(), blas.numThreads);

  Error error;
  std::unique_ptr<Scene> scene = Scene::Create(SceneParams{}, error);
  if (!scene) {
    std::printf("Scene::Create failed: %s\n", error.ToString().c_str());
    return 1;
  }

  // two bodies, A pinned at its centre, B hanging from A by a ball joint
  RigidActorParams a;
  a.mass = 1;
  RigidActorParams b = a;
  b.position = Real3{1_r, 0_r, 0_r};
  RigidActor* bodyA = scene->CreateRigidActor(a, error);
  RigidActor* bodyB = scene->CreateRigidActor(b, error);
  check(bodyA && bodyB, "create two rigid actors");
  if (!bodyA || !bodyB) return 1;

  RigidPivotPositionConstraintParams pin;
  pin.actor = bodyA->GetHandle();
  pin.position = Real3{0_r, 0_r, 0_r};
  pin.stiffness = 1e6_r;
  check(scene->CreateRigidPivotPositionConstraint(pin, error) != nullptr, "create RigidPivotPosition");

  RigidSphericalJointConstraintParams p;
  p.actorA = bodyA->GetHandle();  p.actorB = bodyB->GetHandle();
  p.localPosA = Real3{0.5_r, 0_r, 0_r};  p.localPosB = Real3{-0.5_r, 0_r, 0_r};
  p.stiffness = 1e6_r;
  Constraint* j = scene->CreateRigidSphericalJointConstraint(p, error);
  check(j != nullptr, "create RigidSphericalJoint (the reference page's example)");
  if (!j) return 1;

  for (int i = 0; i < 100; ++i)
    if (!scene->Step(1e-3_r, error)) {
      std::printf("Step failed: %s\n", error.ToString().c_str());
      return 1;
    }
  std::printf("after 0.1 s: B at (%.4f, %.4f, %.4f), solver %s\n", bodyB->GetPosition().x(),
              bodyB->GetPosition().y(), bodyB->GetPosition().z(),
              scene->GetStats().linearSolver.c_str());
  check(bodyB->GetPosition().y() < -1e-3_r, "B swings down under gravity");
  DynamicArray<real> const g = j->GetDeviation();
  real const deviation = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  check(g.size() == 3 && deviation < 1e-4_r, "joint deviation stays at the compliance scale");
  check(scene->GetStats().patternBuilds == 1, "pattern built once");

  // bad input is an Error, not a crash
  check(!j->SetStiffness(-1_r, error) && error.GetCode() == ErrorCode::InvalidArgument,
        "negative stiffness is rejected");

  std::printf("%s\n", failures == 0 ? "consumer: ok" : "consumer: WRONG RESULTS");
  return failures == 0 ? 0 : 1;
}
