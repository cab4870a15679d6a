// Shared helpers of the Catch2 suites.
#pragma once

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include <superdex/core/symmetric_eigen.h>  // SymmetricEigenvalues: the eigensolver compiled once
#include <superdex/superdex.h>

namespace superdex::test {

/// `text` contains `part`.
inline bool Contains(std::string const& text, std::string const& part) {
  return text.find(part) != std::string::npos;
}

/// The error's message contains `part`.
inline bool Mentions(Error const& e, std::string const& part) { return Contains(e.GetMessage(), part); }

/// |a − b| <= tol · max(|a|, |b|, 1)
inline bool Near(real a, real b, real tol) {
  return std::abs(a - b) <= tol * std::max({std::abs(a), std::abs(b), real(1)});
}

/// A scene that must be created; fails the test with the Error otherwise.
inline std::unique_ptr<Scene> MakeScene(SceneParams const& params = {}) {
  Error error;
  auto scene = Scene::Create(params, error);
  INFO(error.ToString());
  REQUIRE(scene);
  return scene;
}

inline RigidActor* MakeRigid(Scene& scene, RigidActorParams const& params) {
  Error error;
  RigidActor* actor = scene.CreateRigidActor(params, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}

inline ArticulatedActor* MakeArticulated(Scene& scene, ArticulatedActorParams const& params) {
  Error error;
  ArticulatedActor* actor = scene.CreateArticulatedActor(params, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}

/// The scene's factory for each kind of actor params.
inline Actor* CreateActor(Scene& s, RigidActorParams const& p, Error& e) { return s.CreateRigidActor(p, e); }
inline Actor* CreateActor(Scene& s, DeformableActorParams const& p, Error& e) {
  return s.CreateDeformableActor(p, e);
}
inline Actor* CreateActor(Scene& s, RodActorParams const& p, Error& e) { return s.CreateRodActor(p, e); }
inline Actor* CreateActor(Scene& s, ArticulatedActorParams const& p, Error& e) {
  return s.CreateArticulatedActor(p, e);
}

/// Creating an actor from `params` fails with InvalidArgument, the message
/// mentions `mention`, and the scene has no new actor.
template <class Params>
void RequireActorRefused(Scene& scene, Params const& params, std::string const& mention) {
  int const before = scene.GetNumActors();
  Error e;
  REQUIRE_FALSE(CreateActor(scene, params, e));
  CAPTURE(e.ToString(), mention);
  REQUIRE(e.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(e, mention));
  REQUIRE(scene.GetNumActors() == before);
}

inline void StepOk(Scene& scene, real dt, int steps = 1) {
  for (int i = 0; i < steps; ++i) {
    Error error;
    bool ok = scene.Step(dt, error);
    INFO(error.ToString());
    REQUIRE(ok);
  }
}

inline Real3 ToReal3(DynamicArray<real> const& v) { return {v.at(0), v.at(1), v.at(2)}; }

/// Least-squares slope of log(y) against log(x): the convergence order of
/// errors y at step sizes x (or the power of any y ∝ xᵖ).
inline real FitOrder(DynamicArray<real> const& x, DynamicArray<real> const& y) {
  real sx = 0, sy = 0, sxx = 0, sxy = 0;
  int const n = static_cast<int>(x.size());
  for (int i = 0; i < n; ++i) {
    real const lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace superdex::test
