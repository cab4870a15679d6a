// Scenes stepped with the PETSc PCG backend:
//  - 30 steps with PCG at rtol 1e-10 agree with CHOLMOD within 1e-6 in every
//    position (a clamped deformable beam with a rigid block hung from it, for
//    every preconditioner);
//  - the PETSc Mat/KSP are created once per pattern build, across Newton
//    iterations and 100 steps, and once more after a topology change;
//  - a PCG that cannot converge makes Step fail with an Error naming the
//    solver and PETSc's reason, and the scene is unchanged;
//  - the solver switches at run time between steps, analysing lazily;
//  - inexact Newton (adaptive tolerance) reaches the same answer with fewer
//    CG iterations;
//  - bad PCG settings are refused by Scene::Create and SetLinearSolver;
//  - GAMG converges on a bundle of rods of 50 nodes (its default smoothers
//    were an indefinite preconditioner there), with and without reused
//    prolongators, and agrees with CHOLMOD.
#include "test_scenes.h"

#include <cstring>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {

/// A 0.6 × 0.1 × 0.1 m beam (E = 1e6) clamped at x = 0, with a rigid block
/// hung from its tip by DeformableNodeToRigid couplings: deformable, rigid and
/// constraint blocks in one Hessian.
struct BeamScene {
  std::unique_ptr<Scene> scene;
  DeformableActor* beam = nullptr;
  RigidActor* block = nullptr;

  /// Every position of the scene: beam nodes, then the block's centre.
  DynamicArray<Real3> Positions() const {
    DynamicArray<Real3> positions = beam->GetNodePositions();
    positions.push_back(block->GetPosition());
    return positions;
  }
};

BeamScene MakeBeamScene(SceneParams params) {
  params.newton.velocityTolerance = 1e-9;  // both solvers converge far below the 1e-6 comparison
  BeamScene s;
  s.scene = MakeScene(params);
  DeformableActorParams material;
  material.youngModulus = 1e6;
  material.density = 1000;
  s.beam = MakeBox(*s.scene, Real3(0, -0.05, -0.05), Real3(0.6, 0.1, 0.1), {6, 2, 2}, material);
  PinNodes(*s.scene, *s.beam, 1e7, [](Real3 const& x) { return x.x() < 1e-9; });
  RigidActorParams body;
  body.mass = 0.5;
  body.inertia = Real3(1e-3, 1e-3, 1e-3);
  body.position = Real3(0.6, -0.15, 0);
  s.block = MakeRigid(*s.scene, body);
  Error error;
  for (int i = 0; i < s.beam->GetNumNodes(); ++i) {
    Real3 const x = s.beam->GetNodeReferencePosition(i);
    if (x.x() < 0.6 - 1e-9 || x.y() > -0.05 + 1e-9) continue;  // tip's bottom edge
    DeformableNodeToRigidConstraintParams p;
    p.deformableActor = s.beam->GetHandle();
    p.deformableNodeIndex = i;
    p.rigidActor = s.block->GetHandle();
    p.stiffness = 1e6;
    REQUIRE(s.scene->CreateDeformableNodeToRigidConstraint(p, error));
  }
  return s;
}

real MaxRelativeDifference(DynamicArray<Real3> const& a, DynamicArray<Real3> const& b) {
  REQUIRE(a.size() == b.size());
  real worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    real const scale = std::max({a[i].norm(), b[i].norm(), real(1e-3)});
    worst = std::max(worst, (a[i] - b[i]).norm() / scale);
  }
  return worst;
}

/// The perf harness's rods family at size numRods x numNodes: straight rods
/// (1 m, r = 5 mm, E = 1e8 Pa, nu = 0.3, 1000 kg/m^3) along +x, in a square
/// grid of pitch 4 r, each clamped at x = 0 (ClampRodEnd) to an anchored
/// 1 kg plate, 1e3 times stiffer than the rod next to the clamp. Released
/// at rest, they droop far into the nonlinear range.
struct RodBundle {
  std::unique_ptr<Scene> scene;
  DynamicArray<RodActor*> rods;

  DynamicArray<Real3> Positions() const {
    DynamicArray<Real3> positions;
    for (RodActor const* rod : rods)
      for (int i = 0; i < rod->GetNumNodes(); ++i) positions.push_back(rod->GetNodePosition(i));
    return positions;
  }
};

RodBundle MakeRodBundle(SceneParams params, int numRods, int numNodes) {
  params.newton.velocityTolerance = 1e-9;  // both solvers converge far below the comparison
  real const length = 1, radius = 5e-3, pitch = 4 * radius;
  RodActorParams material;
  material.radius = radius;
  material.youngModulus = 1e8;
  material.poissonRatio = 0.3;
  material.density = 1000;
  RodBundle b;
  b.scene = MakeScene(params);
  int const cols = static_cast<int>(std::ceil(std::sqrt(static_cast<real>(numRods))));
  int const rows = (numRods + cols - 1) / cols;
  RigidActorParams plateParams;
  plateParams.mass = 1;
  plateParams.inertia = Real3(1e-3, 1e-3, 1e-3);
  plateParams.position = Real3(-0.005, 0, 0);
  RigidActor* plate = MakeRigid(*b.scene, plateParams);
  Anchor(*b.scene, *plate);
  real const area = std::numbers::pi_v<real> * radius * radius, inertia = area * radius * radius / 4;
  real const element = length / (numNodes - 1);
  real const ea = material.youngModulus * area, ei = material.youngModulus * inertia;
  real const linear = 1e3 * std::max(ea / element, 12 * ei / (element * element * element));
  real const angular = 1e3 * 4 * ei / element;
  for (int k = 0; k < numRods; ++k) {
    Real3 const start(0, (k / cols - (rows - 1) / 2.0) * pitch, (k % cols - (cols - 1) / 2.0) * pitch);
    RodActor* rod = MakeStraightRod(*b.scene, start, Real3::UnitX(), length, numNodes - 1, material);
    ClampRodEnd(*b.scene, *rod, *plate, false, linear, angular);
    b.rods.push_back(rod);
  }
  return b;
}

constexpr real kDt = 1.0 / 60;

DynamicArray<Real3> CholmodReference(int steps) {
  SceneParams params;
  params.linearSolver = LinearSolverType::Cholmod;
  BeamScene s = MakeBeamScene(params);
  StepOk(*s.scene, kDt, steps);
  return s.Positions();
}

}  // namespace

TEST_CASE("PCG at rtol 1e-10 agrees with CHOLMOD over 30 steps", "[long][scene][pcg]") {
  DynamicArray<Real3> const reference = CholmodReference(30);
  PcgPreconditioner const preconditioner = GENERATE(from_range(AvailablePcgPreconditioners()));
  CAPTURE(ToString(preconditioner));
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = preconditioner;
  params.pcg.relativeTolerance = 1e-10;
  BeamScene s = MakeBeamScene(params);
  StepOk(*s.scene, kDt, 30);
  REQUIRE(Contains(s.scene->GetStats().linearSolver, "PETSc"));
  REQUIRE(s.scene->GetStats().linearIterations > 0);

  real const difference = MaxRelativeDifference(s.Positions(), reference);
  CAPTURE(difference);
  REQUIRE(difference <= 1e-6);
  // the beam really moved: the comparison is not of two resting scenes
  REQUIRE((s.block->GetPosition() - Real3(0.6, -0.15, 0)).norm() > 1e-3);
}

TEST_CASE("MUMPS agrees with CHOLMOD over 30 steps",
          "[scene][mumps]") {
  DynamicArray<Real3> const reference = CholmodReference(30);
  bool const reuse = GENERATE(true, false);
  CAPTURE(reuse);
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscMumps;
  params.newton.reuseFactorization = reuse;
  BeamScene s = MakeBeamScene(params);
  SceneStats totals;
  for (int step = 0; step < 30; ++step) {
    StepOk(*s.scene, kDt);
    totals.factorizations += s.scene->GetStats().factorizations;
    totals.reusedFactorSolves += s.scene->GetStats().reusedFactorSolves;
    totals.newtonIterations += s.scene->GetStats().newtonIterations;
    totals.projectionFallbacks += s.scene->GetStats().projectionFallbacks;
  }
  REQUIRE(Contains(s.scene->GetStats().linearSolver, "MUMPS"));
  // one symbolic analysis for the 30 steps: the pattern never changed
  REQUIRE(s.scene->GetStats().symbolicAnalyses == 1);
  REQUIRE(s.scene->GetStats().factorNonzeros > 0);
  CAPTURE(totals.factorizations, totals.reusedFactorSolves, totals.newtonIterations,
          totals.projectionFallbacks);
  // (on this small beam a factorization is not worth 3 CG iterations, the
  // reuse rule's least: reuse=true keeps to factorizations too; the
  // reused-factor CG on a MUMPS factor is petsc_mumps_solver_test's)
  if (!reuse) {
    // one factorization per Newton iteration, and one more for each
    // iteration whose exact Hessian MUMPS found indefinite (re-assembled
    // with projected element Hessians)
    REQUIRE(totals.reusedFactorSolves == 0);
    REQUIRE(totals.factorizations == totals.newtonIterations + totals.projectionFallbacks);
  }
  // both solve each Newton system to round-off (or reused-factor CG to the
  // same tolerance as with CHOLMOD): the states agree to the Newton tolerance
  real const difference = MaxRelativeDifference(s.Positions(), reference);
  CAPTURE(difference);
  REQUIRE(difference <= 1e-6);
  REQUIRE((s.block->GetPosition() - Real3(0.6, -0.15, 0)).norm() > 1e-3);
}

TEST_CASE("PETSc objects are created once per pattern build", "[long][scene][pcg][reuse]") {
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = GENERATE(PcgPreconditioner::Jacobi, PcgPreconditioner::Gamg);
  CAPTURE(ToString(params.pcg.preconditioner));
  BeamScene s = MakeBeamScene(params);
  std::int64_t newtonIterations = 0;
  for (int step = 0; step < 100; ++step) {
    StepOk(*s.scene, kDt);
    newtonIterations += s.scene->GetStats().newtonIterations;
  }
  SceneStats const& stats = s.scene->GetStats();
  REQUIRE(newtonIterations > 100);  // several Newton iterations per step on average
  REQUIRE(stats.patternBuilds == 1);
  REQUIRE(stats.symbolicAnalyses == 1);
  REQUIRE(stats.linearSolverObjectBuilds == 1);

  // a topology change rebuilds the pattern, and the PETSc objects once more
  PinNodes(*s.scene, *s.beam, 1e5, [](Real3 const& x) { return x.x() > 0.6 - 1e-9 && x.y() > 0; });
  StepOk(*s.scene, kDt, 10);
  REQUIRE(stats.patternBuilds == 2);
  REQUIRE(stats.linearSolverObjectBuilds == 2);
}

TEST_CASE("a PCG that cannot converge fails the step and changes nothing", "[scene][pcg][failure]") {
  // Jacobi with 5 iterations against stiff constraints, truncated steps off
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Jacobi;
  params.pcg.maxIterations = 5;
  params.pcg.truncatedSteps = false;
  BeamScene s = MakeBeamScene(params);
  DynamicArray<Real3> const before = s.Positions();
  DynamicArray<Real3> const velocitiesBefore = [&] {
    DynamicArray<Real3> v;
    for (int i = 0; i < s.beam->GetNumNodes(); ++i) v.push_back(s.beam->GetNodeVelocity(i));
    return v;
  }();

  Error error;
  REQUIRE_FALSE(s.scene->Step(kDt, error));
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::LinearSolverFailed);
  REQUIRE(Contains(error.GetMessage(), "PETSc"));
  REQUIRE(Contains(error.GetMessage(), "Jacobi"));
  REQUIRE(Contains(error.GetMessage(), "KSP_DIVERGED_ITS"));
  REQUIRE(Contains(error.GetMessage(), "Newton iteration 1"));

  DynamicArray<Real3> const after = s.Positions();
  REQUIRE(std::memcmp(before.data(), after.data(), sizeof(Real3) * before.size()) == 0);
  for (int i = 0; i < s.beam->GetNumNodes(); ++i)
    REQUIRE(s.beam->GetNodeVelocity(i) == velocitiesBefore[i]);
  REQUIRE(s.scene->GetTime() == 0);
  REQUIRE(s.scene->GetStats().steps == 0);

  // the same scene steps once the solver can converge
  PcgParams enough = params.pcg;
  enough.maxIterations = 10000;
  REQUIRE(s.scene->SetLinearSolver(LinearSolverType::PetscPcg, enough, error));
  StepOk(*s.scene, kDt);
}

namespace {
/// PCG with Jacobi capped at `pcgCap` iterations per solve, Newton at `newtonCap`.
SceneParams JacobiCapped(int pcgCap, int newtonCap) {
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Jacobi;
  params.pcg.maxIterations = pcgCap;
  params.newton.maxIterations = newtonCap;
  return params;
}
}  // namespace

TEST_CASE("Newton steps with PCG solves truncated at the cap and reaches the full solves' state",
          "[scene][pcg][truncated]") {
  // Jacobi capped at 100 iterations: most solves stop at the cap (a full one
  // needs 140-158 here), yet Newton converges to the same tolerance
  // (1e-9 m/s) as with CHOLMOD, to the same positions. (Capped at 40, each
  // solve gains only ~0.6 in residual, and at the round-off floor of the
  // gradient the resumptions stagnate near 1e-4: Newton then fails at its cap,
  // which the next test shows for a harder cap.)
  DynamicArray<Real3> const reference = CholmodReference(12);
  BeamScene s = MakeBeamScene(JacobiCapped(100, 200));
  int truncated = 0, solves = 0;
  for (int step = 0; step < 12; ++step) {
    StepOk(*s.scene, kDt);
    truncated += s.scene->GetStats().truncatedSolves;
    solves += s.scene->GetStats().linearSolves;
  }
  CAPTURE(truncated, solves);
  REQUIRE(truncated > solves / 4);
  real const difference = MaxRelativeDifference(s.Positions(), reference);
  CAPTURE(difference);
  REQUIRE(difference <= 1e-6);
}

TEST_CASE("a truncated solve never ends Newton: a hard stage still fails", "[scene][pcg][truncated]") {
  // 2 CG iterations per solve and 3 Newton iterations cannot reach 1e-9 m/s:
  // the step fails with NewtonFailed (not a false convergence) and changes
  // nothing
  BeamScene s = MakeBeamScene(JacobiCapped(2, 3));
  DynamicArray<Real3> const before = s.Positions();
  Error error;
  REQUIRE_FALSE(s.scene->Step(kDt, error));
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::NewtonFailed);
  REQUIRE(s.scene->GetStats().truncatedSolves >= 3);
  REQUIRE(Contains(error.GetMessage(), "stopped at the PCG cap of 2 iterations"));
  DynamicArray<Real3> const after = s.Positions();
  REQUIRE(std::memcmp(before.data(), after.data(), sizeof(Real3) * before.size()) == 0);
  REQUIRE(s.scene->GetTime() == 0);
}

TEST_CASE("the linear solver switches between steps at run time", "[scene][pcg][switch]") {
  DynamicArray<Real3> const reference = CholmodReference(12);
  SceneParams params;
  params.linearSolver = LinearSolverType::Cholmod;
  BeamScene s = MakeBeamScene(params);
  Scene& scene = *s.scene;
  Error error;
  PcgParams gamg;
  gamg.relativeTolerance = 1e-10;
  StepOk(scene, kDt, 3);
  REQUIRE(Contains(scene.GetStats().linearSolver, "CHOLMOD"));
  REQUIRE(scene.SetLinearSolver(LinearSolverType::PetscPcg, gamg, error));
  REQUIRE(scene.GetParams().linearSolver == LinearSolverType::PetscPcg);
  StepOk(scene, kDt, 3);
  REQUIRE(Contains(scene.GetStats().linearSolver, "CG + Gamg (rigid-body near-null space)"));
  REQUIRE(scene.SetLinearSolver(LinearSolverType::Dense, error));
  StepOk(scene, kDt, 3);
  REQUIRE(Contains(scene.GetStats().linearSolver, "dense"));
  PcgParams icc = gamg;
  icc.preconditioner = PcgPreconditioner::Icc;
  REQUIRE(scene.SetLinearSolver(LinearSolverType::PetscPcg, icc, error));
  StepOk(scene, kDt, 3);
  REQUIRE(Contains(scene.GetStats().linearSolver, "Icc"));

  // one pattern; each new backend analysed it once, lazily
  REQUIRE(scene.GetStats().patternBuilds == 1);
  REQUIRE(scene.GetStats().symbolicAnalyses == 4);
  REQUIRE(scene.GetStats().linearSolverObjectBuilds == 2);
  REQUIRE(MaxRelativeDifference(s.Positions(), reference) <= 1e-6);
}

TEST_CASE("inexact Newton reaches the same answer with fewer CG iterations", "[scene][pcg][adaptive]") {
  auto const run = [](bool adaptive, std::int64_t& linearIterations, std::int64_t& solves) {
    SceneParams params;
    params.linearSolver = LinearSolverType::PetscPcg;
    params.pcg.preconditioner = PcgPreconditioner::Icc;
    params.pcg.relativeTolerance = 1e-10;
    params.pcg.adaptiveTolerance = adaptive;
    BeamScene s = MakeBeamScene(params);
    linearIterations = solves = 0;
    for (int step = 0; step < 20; ++step) {
      StepOk(*s.scene, kDt);
      linearIterations += s.scene->GetStats().linearIterations;
      solves += s.scene->GetStats().linearSolves;
    }
    return s.Positions();
  };
  std::int64_t exactIterations = 0, exactSolves = 0, inexactIterations = 0, inexactSolves = 0;
  DynamicArray<Real3> const exact = run(false, exactIterations, exactSolves);
  DynamicArray<Real3> const inexact = run(true, inexactIterations, inexactSolves);
  CAPTURE(exactIterations, inexactIterations, exactSolves, inexactSolves);
  REQUIRE(MaxRelativeDifference(exact, inexact) <= 1e-6);
  // measured 4,458 against 5,534 CG iterations (0.81): at least 10 % fewer
  REQUIRE(10 * inexactIterations <= 9 * exactIterations);
}

TEST_CASE("bad PCG settings are refused and change nothing", "[scene][pcg][input]") {
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.relativeTolerance = -1;
  Error error;
  REQUIRE(Scene::Create(params, error) == nullptr);
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Contains(error.GetMessage(), "SceneParams.pcg.relativeTolerance"));
  REQUIRE(Contains(error.GetMessage(), "-1"));

  BeamScene s = MakeBeamScene(SceneParams{});
  PcgParams bad;
  bad.maxIterations = -3;
  error.Clear();
  REQUIRE_FALSE(s.scene->SetLinearSolver(LinearSolverType::PetscPcg, bad, error));
  REQUIRE(Contains(error.GetMessage(), "maxIterations"));
  REQUIRE(s.scene->GetParams().linearSolver == LinearSolverType::Auto);
  REQUIRE(s.scene->GetParams().pcg.maxIterations == PcgParams{}.maxIterations);
  StepOk(*s.scene, kDt);
  REQUIRE(Contains(s.scene->GetStats().linearSolver, "CHOLMOD"));
}

TEST_CASE("CHOLMOD with its own ordering gives the same steps as with METIS", "[scene][ordering]") {
  DynamicArray<Real3> const reference = CholmodReference(10);
  SceneParams params;
  params.linearSolver = LinearSolverType::Cholmod;
  params.ordering = OrderingMethod::SolverDefault;
  BeamScene s = MakeBeamScene(params);
  StepOk(*s.scene, kDt, 10);
  CAPTURE(s.scene->GetStats().linearSolver);
  REQUIRE(!Contains(s.scene->GetStats().linearSolver, "ordering natural"));
  REQUIRE(MaxRelativeDifference(s.Positions(), reference) <= 1e-9);
}

TEST_CASE("GAMG converges on rods of 50 nodes and agrees with CHOLMOD", "[scene][pcg][gamg][rod]") {
  // 4 rods of 50 nodes (the harness's rods 4x50, 806 DoFs). GAMG's default
  // Chebyshev smoothers (upper eigenvalue bound 1.1 x the estimate) made an
  // indefinite preconditioner here: CG stopped with KSP_DIVERGED_INDEFINITE_PC
  // at the first solve. The backend's defaults: a 30-iteration estimate and
  // a bound of 1.3 x it.
  int const numRods = 4, numNodes = 50, steps = 3;
  SceneParams reference;
  reference.linearSolver = LinearSolverType::Cholmod;
  RodBundle direct = MakeRodBundle(reference, numRods, numNodes);
  StepOk(*direct.scene, kDt, steps);

  bool const reuse = GENERATE(false, true);
  CAPTURE(reuse);
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Gamg;
  params.pcg.reuseAmgInterpolation = reuse;
  params.pcg.relativeTolerance = 1e-10;
  RodBundle b = MakeRodBundle(params, numRods, numNodes);
  for (int step = 0; step < steps; ++step) {
    Error error;
    bool const ok = b.scene->Step(kDt, error);
    CAPTURE(step, error.ToString());
    REQUIRE(ok);
    SceneStats const& stats = b.scene->GetStats();
    CAPTURE(stats.linearIterations, stats.linearSolves);
    REQUIRE(stats.numDofs == 4 * numRods * numNodes + 6);
    REQUIRE(Contains(stats.linearSolver, "CG + Gamg (rigid-body near-null space)"));
    // CG never met negative curvature (no retry with projected Hessians),
    // and every solve did real work
    REQUIRE(stats.projectionFallbacks == 0);
    REQUIRE(stats.linearSolves >= 1);
    REQUIRE(stats.linearIterations >= stats.linearSolves);
  }
  real const difference = MaxRelativeDifference(b.Positions(), direct.Positions());
  CAPTURE(difference);
  REQUIRE(difference <= 1e-6);
  // the rods really moved: the tips dropped by more than a centimetre
  REQUIRE(b.rods[0]->GetNodePosition(numNodes - 1).y() <
          b.rods[0]->GetNodeReferencePosition(numNodes - 1).y() - 1e-2);
}

TEST_CASE("GAMG's coarsening for rods needs fewer CG iterations than PETSc's own",
          "[scene][pcg][gamg][rod]") {
  // 4 rods of 50 nodes. On rod-dominated matrices the backend aggregates on
  // the graph itself (PETSc squares it on the first level), thresholds the
  // first coarse graph at 0.02 and solves below 2000 equations directly
  // (here: two levels). PETSc's coarsening, passed back through the
  // options, needs about 5x more iterations (harness rods 4x50: 15.3 vs 88
  // per solve). Counts, never time.
  auto iterationsPerSolve = [](std::string const& options) {
    SceneParams params;
    params.linearSolver = LinearSolverType::PetscPcg;
    params.pcg.preconditioner = PcgPreconditioner::Gamg;
    params.pcg.relativeTolerance = 1e-8;
    params.pcg.options = options;
    RodBundle b = MakeRodBundle(params, 4, 50);
    StepOk(*b.scene, kDt, 2);
    SceneStats const& stats = b.scene->GetStats();
    CAPTURE(options, stats.linearIterations, stats.linearSolves);
    REQUIRE(stats.projectionFallbacks == 0);
    REQUIRE(stats.linearSolves >= 2);
    return static_cast<real>(stats.linearIterations) / static_cast<real>(stats.linearSolves);
  };
  real const rods = iterationsPerSolve("");
  real const petsc =
      iterationsPerSolve("-pc_gamg_square_graph 1 -pc_gamg_threshold -1 -pc_gamg_coarse_eq_limit 50");
  CAPTURE(rods, petsc);
  REQUIRE(rods <= 30);
  REQUIRE(petsc >= 3 * rods);
}

TEST_CASE("PcgParams.options override GAMG's default smoother bounds", "[scene][pcg][gamg][rod]") {
  // PETSc's own smoother defaults (a 10-iteration estimate, bound 1.1 x it),
  // passed through, bring back the indefinite preconditioner on the same
  // rods: the user's options win over the backend's defaults
  SceneParams params;
  params.linearSolver = LinearSolverType::PetscPcg;
  params.pcg.preconditioner = PcgPreconditioner::Gamg;
  params.pcg.options = "-pc_gamg_esteig_ksp_max_it 10 -mg_levels_ksp_chebyshev_esteig 0,0.1,0,1.1";
  RodBundle b = MakeRodBundle(params, 4, 50);
  Error error;
  REQUIRE_FALSE(b.scene->Step(kDt, error));
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::LinearSolverFailed);
  REQUIRE(Contains(error.GetMessage(), "KSP_DIVERGED_INDEFINITE_PC"));
  REQUIRE(b.scene->GetStats().steps == 0);
}

TEST_CASE("GAMG on a system smaller than the six rigid-body modes steps (found by fuzz_scene_api)",
          "[scene][pcg][gamg]") {
  // one revolute joint: a 1-DoF system against 6 near-null-space modes;
  // before, the orthonormalization read the QR factor's diagonal past its
  // end (an Eigen assertion in a debug or sanitizer build)
  auto swing = [](LinearSolverType solver) {
    SceneParams params;
    params.linearSolver = solver;
    params.pcg.preconditioner = PcgPreconditioner::Gamg;
    params.pcg.relativeTolerance = 1e-12;
    params.newton.velocityTolerance = 1e-10;
    std::unique_ptr<Scene> scene = MakeScene(params);
    ArticulatedActorParams arm;
    arm.links.resize(1);
    arm.links[0].jointToChildPosition = Real3(0.5, 0, 0);
    arm.links[0].centerOfMass = Real3(0.25, 0, 0);
    Error error;
    ArticulatedActor* actor = scene->CreateArticulatedActor(arm, error);
    REQUIRE(actor);
    REQUIRE(scene->GetNumDofs() == 1);
    StepOk(*scene, 1e-2, 3);
    return actor->GetJointPositions()[0];
  };
  // the same swing as the direct solver's, to the Newton tolerance (a step
  // as a velocity of 1e-10 rad/s moves the joint by 1e-12 rad)
  real const gamg = swing(LinearSolverType::PetscPcg);
  real const direct = swing(LinearSolverType::Dense);
  CAPTURE(gamg, direct);
  REQUIRE(direct < -1e-4);  // it swings down under gravity
  REQUIRE(std::abs(gamg - direct) <= 1e-10);
}
