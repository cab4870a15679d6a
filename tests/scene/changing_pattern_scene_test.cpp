// A stage term whose contributors change between stages (the shape contact
// will have): zero-length springs between rigid bodies' centres, a
// different set of pairs each stage. The pattern grows in the kept order
// where a pair is new and is reused where the pairs fit; the states equal a
// run that analyses the pattern anew whenever the pairs change, and do not
// depend on the thread count.
#include "test_support.h"

#include <superdex/superdex.h>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr int kBodies = 12;
constexpr real kSpring = 50;  // [N/m]

/// ½ k |x_a − x_b|² for this stage's pairs (a, b) of rigid bodies: the
/// schedule repeats every four stages, and each of (0, 6), (2, 8), (4, 10)
/// comes and goes.
class SpringPairs final : public internal::StageTerm {
 public:
  explicit SpringPairs(DynamicArray<RigidActor*> bodies) : bodies_(std::move(bodies)) {}

  void AppendContributorDofs(DynamicArray<DynamicArray<int>>&) const override {}
  void BeginStage(internal::StageContext const&) override {
    static DynamicArray<DynamicArray<std::pair<int, int>>> const kSchedule{
        {{0, 6}}, {{0, 6}, {2, 8}}, {{2, 8}}, {{4, 10}, {0, 6}}};
    pairs_ = kSchedule[stage_++ % kSchedule.size()];
  }
  void AppendStageContributorDofs(internal::StageDofLists& dofLists) const override {
    for (auto [a, b] : pairs_) {
      int const oa = bodies_[a]->GetDofOffset(), ob = bodies_[b]->GetDofOffset();
      dofLists.Add() = {oa, oa + 1, oa + 2, ob, ob + 1, ob + 2};
    }
  }
  void AddEnergy(internal::HessianAssembler const&, int, internal::EnergySum& sum) const override {
    for (auto [a, b] : pairs_) sum.Add(0.5 * kSpring * Stretch(a, b).squaredNorm());
  }
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int,
                             internal::AssemblyOptions const& options) const override {
    Eigen::Matrix<real, 6, 6> hessian;
    hessian << kSpring * Real33::Identity(), -kSpring * Real33::Identity(), -kSpring * Real33::Identity(),
        kSpring * Real33::Identity();
    for (std::size_t k = 0; k < pairs_.size(); ++k) {
      Real3 const force = kSpring * Stretch(pairs_[k].first, pairs_[k].second);
      Eigen::Matrix<real, 6, 1> gradient;
      gradient << force, -force;
      assembler.AddDynamicGradient(options.firstStageContributor + static_cast<int>(k), gradient);
      assembler.AddDynamicBlock(options.firstStageContributor + static_cast<int>(k), hessian);
    }
  }
  void EndStage() override {}

 private:
  Real3 Stretch(int a, int b) const { return bodies_[a]->GetPosition() - bodies_[b]->GetPosition(); }

  DynamicArray<RigidActor*> bodies_;
  DynamicArray<std::pair<int, int>> pairs_;
  int stage_ = 0;
};

struct Run {
  std::unique_ptr<Scene> scene;
  DynamicArray<RigidActor*> bodies;
  std::unique_ptr<SpringPairs> springs;
};

Run MakeRun(PatternPolicy policy, int threads) {
  SceneParams params;
  params.patternPolicy = policy;
  params.numThreads = threads;
  params.newton.velocityTolerance = 1e-11;
  Error error;
  Run run;
  run.scene = Scene::Create(params, error);
  REQUIRE(run.scene);
  for (int i = 0; i < kBodies; ++i) {
    RigidActorParams body;
    body.mass = 1 + 0.1 * i;
    body.inertia = Real3(0.01, 0.02, 0.03);
    body.position = Real3(0.5 * i, 0.1 * (i % 2), 0);
    body.angularVelocity = Real3(0.1 * i, 0, 0.2);
    run.bodies.push_back(run.scene->CreateRigidActor(body, error));
    REQUIRE(run.bodies.back());
  }
  // a chain: body 0 held at its place by a spring to the world, each body
  // joined to the next half-way between them (the block graph the pattern
  // is ordered for; the springs' pairs are a few more of its pairs)
  RigidPivotPositionConstraintParams hold;
  hold.actor = run.bodies[0]->GetHandle();
  hold.stiffness = 1e3;
  REQUIRE(run.scene->CreateRigidPivotPositionConstraint(hold, error));
  for (int i = 0; i + 1 < kBodies; ++i) {
    RigidSphericalJointConstraintParams joint;
    joint.actorA = run.bodies[i]->GetHandle();
    joint.actorB = run.bodies[i + 1]->GetHandle();
    Real3 const half = 0.5 * (run.bodies[i + 1]->GetPosition() - run.bodies[i]->GetPosition());
    joint.localPosA = half;
    joint.localPosB = -half;
    joint.stiffness = 1e4;
    REQUIRE(run.scene->CreateRigidSphericalJointConstraint(joint, error));
  }
  run.springs = std::make_unique<SpringPairs>(run.bodies);
  internal::AttachStageTerm(*run.scene, *run.springs);
  return run;
}

void Step(Run& run, int steps) {
  Error error;
  for (int s = 0; s < steps; ++s) REQUIRE(run.scene->Step(1.0 / 60, error));
}
}  // namespace

TEST_CASE("pairs that come and go: the pattern grows in the kept order, then fits; the states equal a fresh "
          "analysis whenever they change",
          "[scene][pattern]") {
  constexpr int kSteps = 24;
  Run reserve = MakeRun(PatternPolicy::ReserveAndGrow, 1);
  Step(reserve, kSteps);
  SceneStats const& stats = reserve.scene->GetStats();
  // one ordering (the first analysis); a growth where (0, 6), (2, 8) and
  // (4, 10) first appear (stages 1, 2 and 4): three new pairs, fewer than
  // kReorderFraction of the chain's 23 block pairs; every other stage fits
  CHECK(stats.patternBuilds == 1);
  CHECK(stats.patternGrowths == 3);
  CHECK(stats.patternFits == kSteps - 3);
  CHECK(stats.reservedBlockPairs == 9);  // each pair (a, b): (a, a), (a, b), (b, b)
  CHECK(stats.stageContributors == 2);   // the last stage (24 = 4·6: {(4, 10), (0, 6)})
  // the linear solver analyses each pattern it factorizes: the first
  // stage's (the analysis and its growth both before the first solve) and
  // the two later growths'
  CHECK(stats.symbolicAnalyses == 1 + 2);

  Run fresh = MakeRun(PatternPolicy::RebuildWhenChanged, 1);
  Step(fresh, kSteps);
  // an ordering at the first analysis and at every stage whose pairs differ
  // from the last stage's: all of them
  CHECK(fresh.scene->GetStats().patternBuilds == 1 + kSteps);
  CHECK(fresh.scene->GetStats().patternGrowths == 0);
  // the same minimizers: the two runs differ only by the orderings the
  // factorizations ran in (round-off), and each stage converges to a step
  // velocity of 1e-11 m/s (1e-11 / 60 m per step)
  real moved = 0;
  for (int i = 0; i < kBodies; ++i) {
    CAPTURE(i);
    CHECK((reserve.bodies[i]->GetPosition() - fresh.bodies[i]->GetPosition()).norm() <= 1e-10);
    CHECK((reserve.bodies[i]->GetLinearVelocity() - fresh.bodies[i]->GetLinearVelocity()).norm() <= 1e-8);
    moved = std::max(moved, (reserve.bodies[i]->GetPosition() - Real3(0.5 * i, 0.1 * (i % 2), 0)).norm());
  }
  REQUIRE(moved > 0.1);  // the springs and gravity moved the bodies
}

TEST_CASE("changing contributors assemble the same on any thread count", "[scene][pattern][parallel]") {
  Run one = MakeRun(PatternPolicy::ReserveAndGrow, 1);
  Run two = MakeRun(PatternPolicy::ReserveAndGrow, 2);
  Step(one, 13);
  Step(two, 13);
  for (int i = 0; i < kBodies; ++i) {
    CAPTURE(i);
    CHECK(one.bodies[i]->GetPosition() == two.bodies[i]->GetPosition());
    CHECK(one.bodies[i]->GetLinearVelocity() == two.bodies[i]->GetLinearVelocity());
  }
  CHECK(one.scene->GetStats().patternGrowths == two.scene->GetStats().patternGrowths);
}
