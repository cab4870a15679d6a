// The line search's safe-step hook (StageTerm::LargestSafeStep): a term that
// bounds Newton's steps is never evaluated beyond its safe step. The term
// here is a floor at y = 0 under a falling rigid body, priced by the clamped
// log barrier of IPC, b(d) = −κ (d − d̂)² ln(d / d̂) for 0 < d < d̂ (0 beyond
// d̂, +∞ at or below the floor), whose safe step keeps the body at least 20 %
// of its distance above the floor, as a conservative continuous collision
// test does.
#include "test_support.h"

#include <cmath>
#include <limits>

#include <superdex/superdex.h>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kActivation = 0.1;  // d̂ [m]
constexpr real kStiffness = 100;   // κ [J/m²]

class Floor final : public internal::StageTerm {
 public:
  Floor(RigidActor const& body, bool boundsSteps) : body_(body), boundsSteps_(boundsSteps) {}

  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override {
    dofLists.push_back({body_.GetDofOffset() + 1});  // the height y
  }
  void BeginStage(internal::StageContext const&) override {}
  void AddEnergy(internal::HessianAssembler const&, int, internal::EnergySum& sum) const override {
    real const d = body_.GetPosition().y();
    lowest_ = std::min(lowest_, d);
    sum.Add(Barrier(d));
  }
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int first,
                             internal::AssemblyOptions const&) const override {
    real const d = body_.GetPosition().y();
    real gradient = 0, hessian = 0;
    if (d < kActivation) {
      real const r = d - kActivation, l = std::log(d / kActivation);
      gradient = -kStiffness * (2 * r * l + r * r / d);
      hessian = -kStiffness * (2 * l + 4 * r / d - r * r / (d * d));
    }
    assembler.AddGradient(first, VectorX::Constant(1, gradient));
    assembler.AddBlock(first, MatrixX::Constant(1, 1, hessian));
  }
  void EndStage() override {}
  bool BoundsSteps() const override { return boundsSteps_; }
  real LargestSafeStep(Span<real const> delta, real alpha) const override {
    real const d = body_.GetPosition().y(), dy = delta[body_.GetDofOffset() + 1];
    // at most 80 % of the way down to the floor
    if (dy < 0 && d + alpha * dy < 0.2 * d) {
      ++limited_;
      return 0.8 * d / -dy;
    }
    return alpha;
  }

  real Lowest() const { return lowest_; }
  int Limited() const { return limited_; }

 private:
  static real Barrier(real d) {
    if (!(d > 0)) return std::numeric_limits<real>::infinity();
    if (d >= kActivation) return 0;
    real const r = d - kActivation;
    return -kStiffness * r * r * std::log(d / kActivation);
  }

  RigidActor const& body_;
  bool boundsSteps_;
  mutable real lowest_ = std::numeric_limits<real>::infinity();
  mutable int limited_ = 0;
};

struct Drop {
  std::unique_ptr<Scene> scene;
  RigidActor* body = nullptr;
  std::unique_ptr<Floor> floor;
};

Drop MakeDrop(bool boundsSteps) {
  Error error;
  Drop drop;
  drop.scene = Scene::Create(SceneParams{}, error);
  REQUIRE(drop.scene);
  RigidActorParams body;
  body.position = Real3(0, 0.05, 0);
  body.linearVelocity = Real3(0, -4, 0);  // a free step of 1/60 s goes 0.07 m down: through the floor
  drop.body = drop.scene->CreateRigidActor(body, error);
  REQUIRE(drop.body);
  drop.floor = std::make_unique<Floor>(*drop.body, boundsSteps);
  internal::AttachStageTerm(*drop.scene, *drop.floor);
  return drop;
}
}  // namespace

TEST_CASE("a term that bounds the steps is never evaluated past its safe step", "[solver][line_search]") {
  Drop drop = MakeDrop(true);
  Error error;
  for (int s = 0; s < 30; ++s) REQUIRE(drop.scene->Step(1.0 / 60, error));
  // the hook cut steps, and no trial configuration reached the floor
  CHECK(drop.floor->Limited() > 0);
  CHECK(drop.floor->Lowest() > 0);
  // the body came to rest on the barrier, above the floor and below d̂
  real const y = drop.body->GetPosition().y();
  CHECK(y > 0);
  CHECK(y < kActivation);
  CHECK(std::abs(drop.body->GetLinearVelocity().y()) < 0.05);
}

TEST_CASE("without the hook the same floor is crossed by trial steps", "[solver][line_search]") {
  // (what the hook is for: Newton's full step goes through the floor, and
  // only the infinite energy there sends the line search back)
  Drop drop = MakeDrop(false);
  Error error;
  REQUIRE(drop.scene->Step(1.0 / 60, error));
  CHECK(drop.floor->Limited() == 0);
  CHECK(drop.floor->Lowest() < 0);
}
