// The contact scenes of docs/contact.md for the tests: scenes/contact_scenes.h
// (shared with the perf harness and the fuzz target), each build REQUIREd
// to succeed, with the tests' default sizes (contact_scene_test checks their
// physics at one time step, contact_sweep_test every scene at dt = 1/30,
// 1/60 and 1/120).
#pragma once

#include <catch2/catch.hpp>

#include <string>

#include <superdex/superdex.h>

#include "scenes/contact_scenes.h"
#include "scenes/interpenetration.h"
#include "test_support.h"

namespace superdex::test {

using scenes::ArmPush;
using scenes::ContactScene;
using scenes::InterpenetrationCheck;
using scenes::kArmLink;
using scenes::kArmRadius;
using scenes::kGravity;

/// What `builder` added, REQUIREd to have succeeded.
template <class T>
T* Added(scenes::Builder const& builder, T* added) {
  INFO(builder.GetError().ToString());
  REQUIRE(builder.Ok());
  return added;
}

/// The scene a builder made, REQUIREd to exist.
inline ContactScene Built(ContactScene scene, Error const& error) {
  INFO(error.ToString());
  REQUIRE(scene.scene);
  return scene;
}

inline Collider* MakeCollider(Scene& scene, ColliderParams const& params) {
  scenes::Builder b(scene);
  return Added(b, b.AddCollider(params));
}

inline Collider* MakeGround(Scene& scene, real friction = 0.5) {
  scenes::Builder b(scene);
  return Added(b, b.AddGround(friction));
}

inline RigidActor* MakeRigidBox(Scene& scene, Real3 const& position, Quat const& rotation, Real3 const& half,
                                real mass, real friction = 0.5) {
  scenes::Builder b(scene);
  return Added(b, b.AddRigidBox(position, rotation, half, mass, friction));
}

inline Collider* MakeSurface(Scene& scene, Actor const& actor, bool selfContact = true) {
  scenes::Builder b(scene);
  return Added(b, b.AddSurface(&actor, selfContact));
}

inline DeformableActorParams TetBall(Real3 const& center, real radius, int cells) {
  DeformableActorParams ball;
  Error error;
  bool const made = scenes::TetBall(center, radius, cells, ball, error);
  INFO(error.ToString());
  REQUIRE(made);
  return ball;
}

inline DeformableActor* MakeDeformable(Scene& scene, DeformableActorParams const& params) {
  scenes::Builder b(scene);
  return Added(b, b.AddDeformable(params));
}

inline DeformableActor* MakeCloth(Scene& scene, int n, real size, real y, Quat const& rotation,
                                  MembraneModel membrane = MembraneModel::TensionField) {
  scenes::Builder b(scene);
  return Added(b, b.AddCloth(n, size, y, rotation, membrane));
}

inline ContactScene InclineScene(SceneParams params, real tanTheta = 0.49) {
  Error error;
  return Built(scenes::InclineScene(params, tanTheta, error), error);
}
inline ContactScene RollingScene(SceneParams params) {
  Error error;
  return Built(scenes::RollingScene(params, error), error);
}
inline ContactScene BallDropScene(SceneParams params, real drop = 1, int cells = 6) {
  Error error;
  return Built(scenes::BallDropScene(params, drop, cells, error), error);
}
inline ContactScene BoxStackScene(SceneParams params, int count = 5) {
  Error error;
  return Built(scenes::BoxStackScene(params, count, error), error);
}
inline ContactScene CubeStackScene(SceneParams params, int count = 5) {
  Error error;
  return Built(scenes::CubeStackScene(params, count, 2, error), error);
}
inline ContactScene ClothOnSphereScene(SceneParams params, int n = 32) {
  Error error;
  return Built(scenes::ClothOnSphereScene(params, n, error), error);
}
inline ContactScene ClothFoldScene(SceneParams params, int n = 24) {
  Error error;
  return Built(scenes::ClothFoldScene(params, n, error), error);
}
inline ContactScene RodCoilScene(SceneParams params, int n = 100) {
  Error error;
  return Built(scenes::RodCoilScene(params, n, error), error);
}
inline ContactScene FastBoxScene(SceneParams params) {
  Error error;
  return Built(scenes::FastBoxScene(params, error), error);
}
inline ContactScene ArmPushScene(SceneParams params) {
  Error error;
  return Built(scenes::ArmPushScene(params, error), error);
}
inline ContactScene FoldingArmScene(SceneParams params) {
  Error error;
  return Built(scenes::FoldingArmScene(params, error), error);
}

using scenes::ArmCapsule;
using scenes::ArmParams;

inline ArmPush MakeArmPush(Scene& scene, real speed = 0.3) {
  scenes::Builder b(scene);
  ArmPush const push = scenes::AddArmPush(b, speed);
  INFO(b.GetError().ToString());
  REQUIRE(b.Ok());
  return push;
}

/// Step `s` of `dt`, REQUIREd to succeed and to leave no two colliders
/// passing through each other (the exact check); adds its Newton iterations.
inline void StepChecked(Scene& scene, real dt, int s, scenes::InterpenetrationCheck& check, long& newton) {
  Error error;
  bool const stepped = scene.Step(dt, error);
  INFO("step " << s << ": " << error.ToString());
  REQUIRE(stepped);
  newton += scene.GetStats().newtonIterations;
  std::string const found = check.Find(scene);
  INFO(found);
  REQUIRE(found.empty());
}

/// Drives `scene` for the step from `from` to `to`, REQUIREd to succeed.
inline void Drive(ContactScene const& scene, real from, real to) {
  if (!scene.drive) return;
  Error error;
  bool const driven = scene.drive(from, to, error);
  INFO(error.ToString());
  REQUIRE(driven);
}

}  // namespace superdex::test
