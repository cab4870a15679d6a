// A rigid body hung from a pivot, stepped for one second.
#include <cstdio>
#include <superdex/superdex.h>

int main() {
  using namespace superdex;
  Error error;
  auto scene = Scene::Create({}, error);
  RigidActor* body = scene->CreateRigidActor({.position = {0.5, 0, 0}}, error);
  RigidPivotPositionConstraintParams pin{.actor = body->GetHandle(), .localPos = {-0.5, 0, 0}, .stiffness = 1e6};
  scene->CreateRigidPivotPositionConstraint(pin, error);
  for (int step = 0; step < 60; ++step) scene->Step(1.0 / 60, error);
  std::printf("%s: the body swung to y = %.3f m\n", error ? error.ToString().c_str() : "ok", body->GetPosition().y());
  return error ? 1 : 0;
}
