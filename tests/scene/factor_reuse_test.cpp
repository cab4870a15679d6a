// Reused factorizations (NewtonParams::reuseFactorization): Newton iterations
// solve their own Hessian by CG preconditioned with the last factorization
// and refactorize only when that stops paying. The converged states equal
// those of full Newton (a factorization per iteration) within the Newton
// tolerance, with fewer factorizations.
#include "test_scenes.h"

using namespace superdex;
using namespace superdex::test;

namespace {

struct Beam {
  std::unique_ptr<Scene> scene;
  DeformableActor* actor = nullptr;
};

/// A tet cantilever (0.6 × 0.15 × 0.15 m, E = 1e6 Pa) clamped at x = 0,
/// sagging under gravity: 24×6×6 cells (3,675 DoFs) for CHOLMOD, where a
/// factorization is worth more than 3 CG iterations (by the flop model), and
/// 12×3×3 (624 DoFs) for the dense solver (n³/3 flops: reuse pays sooner).
Beam MakeBeam(bool reuse, LinearSolverType solver, bool forcingTerms = true, bool single = true) {
  SceneParams params;
  params.newton.reuseFactorization = reuse;
  params.newton.reuseForcingTerms = forcingTerms;
  params.newton.singlePrecisionReusedFactor = single;
  params.linearSolver = solver;
  Beam b;
  b.scene = MakeScene(params);
  DeformableActorParams p;
  p.youngModulus = 1e6;
  p.density = 1000;
  std::array<int, 3> const cells =
      solver == LinearSolverType::Dense ? std::array<int, 3>{12, 3, 3} : std::array<int, 3>{24, 6, 6};
  b.actor = MakeBox(*b.scene, Real3::Zero(), Real3(0.6, 0.15, 0.15), cells, p);
  PinNodes(*b.scene, *b.actor, 1e8, [](Real3 const& x) { return x.x() < 1e-9; });
  return b;
}

real MaxDistance(DeformableActor const& a, DeformableActor const& b) {
  real distance = 0;
  for (int i = 0; i < a.GetNumNodes(); ++i)
    distance = std::max(distance, (a.GetNodePosition(i) - b.GetNodePosition(i)).norm());
  return distance;
}

}  // namespace

TEST_CASE("reused factorizations reach full Newton's states with fewer factorizations",
          "[long][scene][newton][reuse]") {
  LinearSolverType const solver = GENERATE(LinearSolverType::Cholmod, LinearSolverType::Dense);
  CAPTURE(ToString(solver));
  // reused: each reused-factor CG to its forcing term (the default);
  // fixed: each to factorReuseTolerance
  Beam full = MakeBeam(false, solver), reused = MakeBeam(true, solver),
       fixed = MakeBeam(true, solver, /*forcingTerms=*/false);
  real const dt = 1.0 / 60;
  int const steps = 10;
  std::int64_t newton = 0, factorizations = 0, reusedSolves = 0, fullFactorizations = 0, fullNewton = 0;
  std::int64_t cgIterations = 0, fixedCgIterations = 0, fixedFactorizations = 0;
  real largest = 0, largestFixed = 0;
  for (int s = 0; s < steps; ++s) {
    StepOk(*full.scene, dt, 1);
    StepOk(*reused.scene, dt, 1);
    StepOk(*fixed.scene, dt, 1);
    SceneStats const& f = full.scene->GetStats();
    SceneStats const& r = reused.scene->GetStats();
    fullNewton += f.newtonIterations;
    fullFactorizations += f.factorizations;
    newton += r.newtonIterations;
    factorizations += r.factorizations;
    reusedSolves += r.reusedFactorSolves;
    cgIterations += r.linearIterations;
    fixedCgIterations += fixed.scene->GetStats().linearIterations;
    fixedFactorizations += fixed.scene->GetStats().factorizations;
    CHECK(f.reusedFactorSolves == 0);
    largest = std::max(largest, MaxDistance(*full.actor, *reused.actor));
    largestFixed = std::max(largestFixed, MaxDistance(*full.actor, *fixed.actor));
  }
  CAPTURE(fullNewton, fullFactorizations, newton, factorizations, reusedSolves, largest,
          cgIterations, fixedCgIterations, fixedFactorizations, largestFixed);
  // without reuse: one factorization per Newton iteration
  CHECK(fullFactorizations == fullNewton);
  // with it: every Newton iteration either reused a factorization or made one
  CHECK(reusedSolves > 0);
  CHECK(factorizations + reusedSolves >= newton);
  CHECK(factorizations < fullFactorizations / 2);
  // the same states: each stage stops once its step, as a velocity, is below
  // velocityTolerance (1e-6 m/s), so a converged state is within ~1e-6·dt of
  // the minimizer on either path; 10 steps of such differences, carried by
  // stable dynamics, stay below 10 · 1e-6 · dt
  CHECK(largest <= steps * 1e-6 * dt);
  CHECK(largestFixed <= steps * 1e-6 * dt);
  CHECK(fixedFactorizations < fullFactorizations / 2);
  // loose solves far from the minimum: fewer CG iterations in all
  CHECK(cgIterations < fixedCgIterations);
  // the sag is real (the comparison is not of two resting beams)
  CHECK((reused.actor->GetNodePosition(reused.actor->GetNumNodes() - 1) -
         reused.actor->GetNodeReferencePosition(reused.actor->GetNumNodes() - 1))
            .norm() > 1e-3);
}

TEST_CASE("a reused factorization is not tried where one factorization costs less than 3 CG iterations",
          "[scene][newton][reuse]") {
  // a 4-body chain: the dense 24×24 factorization is worth less than 3 CG
  // iterations by the flop model, so every iteration factorizes
  SceneParams params;
  params.linearSolver = LinearSolverType::Dense;
  Chain chain = MakeChain(4, params);
  StepOk(*chain.scene, 1e-3, 5);
  SceneStats const& s = chain.scene->GetStats();
  CHECK(s.reusedFactorSolves == 0);
  CHECK(s.factorizations == s.newtonIterations);
}

TEST_CASE("a factorReuseTolerance outside (0, 1) is refused, naming the field", "[scene][newton][input]") {
  for (real bad : {0.0, 1.0, -1e-3, std::numeric_limits<real>::quiet_NaN()}) {
    SceneParams params;
    params.newton.factorReuseTolerance = bad;
    Error error;
    CAPTURE(bad);
    REQUIRE_FALSE(Scene::Create(params, error));
    CHECK(error.GetCode() == ErrorCode::InvalidArgument);
    CHECK(Contains(error.GetMessage(), "SceneParams.newton.factorReuseTolerance"));
  }
}

TEST_CASE("the single-precision copy of the factor reaches the double-precision states",
          "[long][scene][newton][reuse][single]") {
  // the CHOLMOD beam (3,675 DoFs: a supernodal factor); reused-factor CG
  // applies L from its float copy, or from CHOLMOD's double L
  Beam single = MakeBeam(true, LinearSolverType::Cholmod, true, true),
       doubled = MakeBeam(true, LinearSolverType::Cholmod, true, false);
  real const dt = 1.0 / 60;
  std::int64_t singleSolves = 0, reusedSolves = 0, newtonSingle = 0, newtonDouble = 0;
  real largest = 0;
  for (int s = 0; s < 10; ++s) {
    StepOk(*single.scene, dt, 1);
    StepOk(*doubled.scene, dt, 1);
    SceneStats const& a = single.scene->GetStats();
    SceneStats const& b = doubled.scene->GetStats();
    singleSolves += a.singlePrecisionSolves;
    reusedSolves += a.reusedFactorSolves;
    newtonSingle += a.newtonIterations;
    newtonDouble += b.newtonIterations;
    CHECK(b.singlePrecisionSolves == 0);
    largest = std::max(largest, MaxDistance(*single.actor, *doubled.actor));
  }
  CAPTURE(singleSolves, reusedSolves, newtonSingle, newtonDouble, largest);
  // every reused-factor solve used the copy
  REQUIRE(reusedSolves > 0);
  CHECK(singleSolves == reusedSolves);
  // both converge each step to the Newton tolerance (1e-6 m/s, times dt)
  CHECK(largest <= 10 * 1e-6 * dt);
  CHECK(std::abs(newtonSingle - newtonDouble) <= 2);
}
