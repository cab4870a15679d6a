// SuperDex cantilever: a tetrahedral beam (1 × 0.1 × 0.1 m, stable
// Neo-Hookean, E = 1 MPa, ν = 0.3, ρ = 1000 kg/m³) clamped at x = 0 by one
// DeformableNodePosition pin per node of that face, released straight and
// falling under gravity (0, −9.81, 0). Backward Euler damps the swing, slowly
// at Δt = 1/60 s (the beam still swings after 3 s), so the program also
// settles the same beam to its static equilibrium, for comparison with the
// moving one and with Euler–Bernoulli beam theory.
//
//   superdex_cantilever [--out DIR] [--dt S] [--time S] [--cells NX,NY,NZ]
//                       [--young E] [--integrator be|bdf2] [--vtk-every N]
//
// Writes DIR/cantilever.csv (tip displacement, energies, clamp force and
// Newton iterations per step, plus t = 0), DIR/cantilever_NNNN.vtu every N
// steps and DIR/cantilever.pvd listing them (open it in ParaView),
// DIR/cantilever_static.vtu (the static equilibrium) and
// DIR/cantilever_reference.csv (its tip and the Euler–Bernoulli estimate), and
// prints a summary. Exits non-zero with the library's message when any call
// fails, or when the beam ends with inverted tetrahedra or did not sag.
#include <superdex/superdex.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>

#include "../common/command_line.h"
#include "../common/output.h"

using namespace superdex;

namespace {

// ---- the model ----
constexpr real kLength = 1;      // beam length along x [m]
constexpr real kSide = 0.1;      // square cross-section, side [m]
constexpr real kDensity = 1000;  // [kg/m³]
constexpr real kPoisson = 0.3;
// Clamp pins: 10⁸ N/m per node. The root carries the weight (98 N) and the
// bending moment (up to q L²/2 ≈ 49 N·m over a 0.1 m section, node forces of
// a few hundred N), so the pinned nodes move by ~10⁻⁶–10⁻⁵ m.
constexpr real kClampStiffness = 1e8;
// Static reference: backward-Euler steps of 1 s, whose inertia weight m/Δt²
// (~0.01 N/m per node) is negligible next to the element stiffness (~10⁴ N/m),
// so each step is a near-static solve; stop when the kinetic energy is below
// 10⁻¹⁰ J (node speeds ~10⁻⁵ m/s, i.e. displacement changes ~10⁻⁵ m per step).
constexpr real kStaticDt = 1;
constexpr real kStaticKinetic = 1e-10;
constexpr int kMaxStaticSteps = 60;

struct Options {
  std::string out = "results/cantilever";
  real dt = 1.0 / 60;
  real time = 3;
  std::array<int, 3> cells{40, 4, 4};
  // 1 MPa: soft enough that the beam sags far (the linear estimate is
  // larger than the beam itself); 1e9 gives a small, linear deflection
  real youngModulus = 1e6;
  IntegratorType integrator = IntegratorType::BackwardEuler;
  int vtkEvery = 4;  // one .vtu every 4 steps: 15 frames/s at dt = 1/60
};

using examples::Fail;

Options ParseOptions(int argc, char** argv) {
  Options o;
  examples::CommandLine("superdex_cantilever")
      .Text("--out", "DIR", o.out, "output folder (default results/cantilever)")
      .Number("--dt", "S", o.dt, "time step [s] (default 1/60)")
      .Number("--time", "S", o.time, "simulated time [s] (default 3)")
      .Counts("--cells", "NX,NY,NZ", o.cells, "cells along x (length), y and z (default 40,4,4)")
      .Number("--young", "E", o.youngModulus, "Young's modulus [Pa] (default 1e6)")
      .Integrator("--integrator", o.integrator, "backward Euler or BDF2 (default be)")
      .Count("--vtk-every", "N", o.vtkEvery, "write a .vtu frame every N steps (default 4)")
      .Parse(argc, argv);
  return o;
}

// The beam [0, L] × [−h/2, h/2]² (Kuhn-cut cells) with every node of the
// face x = 0 pinned where it is; the tip is the face x = L.
struct Beam {
  DeformableActor* actor = nullptr;
  DynamicArray<Constraint*> clamp;
  DynamicArray<int> tip;
};

Beam MakeBeam(Scene& scene, Options const& options) {
  Error error;
  TetMesh mesh;
  if (!MakeTetBox(Real3(0, -kSide / 2, -kSide / 2), Real3(kLength, kSide, kSide), options.cells,
                  mesh, error))
    Fail("MakeTetBox", error);
  DeformableActorParams params;
  params.nodes = mesh.nodes;
  params.tetrahedra = mesh.tetrahedra;
  params.material = TetMaterialModel::StableNeoHookean;
  params.youngModulus = options.youngModulus;
  params.poissonRatio = kPoisson;
  params.density = kDensity;
  Beam beam;
  beam.actor = scene.CreateDeformableActor(params, error);
  if (!beam.actor) Fail("CreateDeformableActor", error);
  real const tolerance = 1e-9 * kLength;
  for (int i = 0; i < beam.actor->GetNumNodes(); ++i) {
    real const x = beam.actor->GetNodeReferencePosition(i).x();
    if (x > kLength - tolerance) beam.tip.push_back(i);
    if (x > tolerance) continue;
    DeformableNodePositionConstraintParams pin;
    pin.actor = beam.actor->GetHandle();
    pin.nodeIndex = i;
    pin.position = beam.actor->GetNodePosition(i);
    pin.stiffness = kClampStiffness;
    Constraint* c = scene.CreateDeformableNodePositionConstraint(pin, error);
    if (!c) Fail("CreateDeformableNodePositionConstraint (node " + std::to_string(i) + ")", error);
    if (!c->RegisterQuery(QueryType::ConstraintForce, error)) Fail("RegisterQuery", error);
    beam.clamp.push_back(c);
  }
  if (beam.clamp.empty() || beam.tip.empty()) Fail("no clamp or tip nodes found");
  return beam;
}

// mean displacement of the tip face's nodes (world frame = actor frame here)
Real3 TipDisplacement(Beam const& beam) {
  Real3 sum = Real3::Zero();
  for (int i : beam.tip) sum += beam.actor->GetNodeDisplacement(i);
  return sum / static_cast<real>(beam.tip.size());
}

}  // namespace

int main(int argc, char** argv) {
  Options const options = ParseOptions(argc, argv);
  Error error;

  SceneParams sceneParams;
  sceneParams.integrator = options.integrator;
  std::unique_ptr<Scene> scene = Scene::Create(sceneParams, error);
  if (!scene) Fail("Scene::Create", error);
  real const gravity = -sceneParams.gravity.y();
  Beam const model = MakeBeam(*scene, options);
  DeformableActor* beam = model.actor;
  DynamicArray<Constraint*> const& clamp = model.clamp;

  // ---- output ----
  std::filesystem::path const outDir(options.out);
  std::filesystem::path const csvPath = outDir / "cantilever.csv";
  std::FILE* csv = examples::OpenOutputFile(csvPath);
  std::fprintf(csv,
               "t,tip_dx,tip_dy,tip_dz,tip_deflection,kinetic,elastic,potential,total,"
               "clamp_fx,clamp_fy,clamp_fz,inverted,newton_iterations\n");
  VtkSeries series((outDir / "cantilever.pvd").string());

  auto potential = [&]() {
    real e = 0;
    for (int i = 0; i < beam->GetNumNodes(); ++i)
      e += gravity * beam->GetNodeMass(i) * beam->GetNodePosition(i).y();
    return e;
  };
  // the force the clamp pins exert on the beam (zero before the first step)
  auto clampForce = [&](bool afterStep) {
    Real3 sum = Real3::Zero();
    if (!afterStep) return sum;
    for (Constraint* c : clamp) {
      Span<real const> f = c->GetForce(error);
      if (f.size() != 3) Fail("Constraint::GetForce (clamp)", error);
      sum += Real3(f[0], f[1], f[2]);
    }
    return sum;
  };
  auto writeRow = [&](int newtonIterations, bool afterStep) {
    Real3 const tip = TipDisplacement(model);
    Real3 const force = clampForce(afterStep);
    real const kinetic = beam->GetKineticEnergy(), elastic = beam->GetElasticEnergy();
    real const pot = potential();
    std::fprintf(csv, "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%d,%d\n",
                 scene->GetTime(), tip.x(), tip.y(), tip.z(), -tip.y(), kinetic, elastic, pot,
                 kinetic + elastic + pot, force.x(), force.y(), force.z(),
                 beam->CountInvertedTetrahedra(), newtonIterations);
    if (!std::isfinite(tip.norm()) || !std::isfinite(kinetic + elastic + pot)) {
      std::fclose(csv);
      Fail("non-finite state at t = " + std::to_string(scene->GetTime()));
    }
  };

  auto writeFrame = [&]() {
    char name[64];
    std::snprintf(name, sizeof name, "cantilever_%04d.vtu", series.GetNumFrames());
    examples::WriteDeformableVtu(*beam, (outDir / name).string());
    if (!series.AddFrame(scene->GetTime(), name, error)) Fail("VtkSeries::AddFrame", error);
  };

  int const numSteps = static_cast<int>(std::llround(options.time / options.dt));
  if (numSteps < 1) Fail("--time must be at least one --dt");

  // Euler–Bernoulli: uniform load q = ρ g A on a clamped beam, static tip
  // deflection q L⁴ / (8 E I) with I = h⁴ / 12 (small deflections only)
  real const area = kSide * kSide;
  real const q = kDensity * gravity * area;
  real const inertia = std::pow(kSide, 4) / 12;
  real const eulerBernoulli = q * std::pow(kLength, 4) / (8 * options.youngModulus * inertia);

  std::printf("SuperDex cantilever: %s, dt = %g s, %g s (%d steps)\n",
              std::string(ToString(options.integrator)).c_str(), options.dt, options.time,
              numSteps);
  std::printf(
      "  beam                  %g x %g x %g m, %dx%dx%d cells, %d nodes (%d DoFs), "
      "%d tets, %.3f kg\n",
      kLength, kSide, kSide, options.cells[0], options.cells[1], options.cells[2],
      beam->GetNumNodes(), beam->GetNumDofs(), beam->GetNumTetrahedra(), beam->GetTotalMass());
  std::printf("  material              stable Neo-Hookean, E = %g Pa, nu = %g, rho = %g kg/m^3\n",
              options.youngModulus, kPoisson, kDensity);
  std::printf("  clamp                 %zu DeformableNodePosition pins, k = %g N/m\n", clamp.size(),
              kClampStiffness);

  writeRow(0, false);
  writeFrame();

  double stepSeconds = 0, assemblySeconds = 0, factorSeconds = 0, solveSeconds = 0;
  long long newtonTotal = 0;
  int newtonMax = 0;
  real maxDeflection = 0;
  for (int step = 0; step < numSteps; ++step) {
    examples::TimedStep(*scene, options.dt, step + 1, stepSeconds, csv);
    SceneStats const& stats = scene->GetStats();
    newtonTotal += stats.newtonIterations;
    newtonMax = std::max(newtonMax, stats.newtonIterations);
    assemblySeconds += stats.assemblySeconds;
    factorSeconds += stats.factorizationSeconds;
    solveSeconds += stats.solveSeconds;
    writeRow(stats.newtonIterations, true);
    maxDeflection = std::max(maxDeflection, -TipDisplacement(model).y());
    if ((step + 1) % options.vtkEvery == 0 || step + 1 == numSteps) writeFrame();
  }
  if (std::fclose(csv) != 0) Fail("error writing '" + csvPath.string() + "'");

  // ---- static reference: the same beam, settled from straight by long
  // backward-Euler steps (inertia m/Δt² then negligible: each step is a
  // near-static solve), until the kinetic energy is negligible ----
  SceneParams staticParams;
  staticParams.integrator = IntegratorType::BackwardEuler;
  std::unique_ptr<Scene> staticScene = Scene::Create(staticParams, error);
  if (!staticScene) Fail("Scene::Create (static reference)", error);
  Beam const rest = MakeBeam(*staticScene, options);
  auto const staticStart = std::chrono::steady_clock::now();
  int staticSteps = 0, staticNewton = 0;
  while (true) {
    if (!staticScene->Step(kStaticDt, error)) Fail("Scene::Step (static reference)", error);
    ++staticSteps;
    staticNewton += staticScene->GetStats().newtonIterations;
    if (staticSteps >= 3 && rest.actor->GetKineticEnergy() <= kStaticKinetic) break;
    if (staticSteps == kMaxStaticSteps)
      Fail("the static reference did not settle in " + std::to_string(kMaxStaticSteps) +
           " steps of " + std::to_string(kStaticDt) + " s");
  }
  double const staticSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - staticStart).count();
  Real3 const staticTip = TipDisplacement(rest);
  examples::WriteDeformableVtu(*rest.actor, (outDir / "cantilever_static.vtu").string());
  std::filesystem::path const referencePath = outDir / "cantilever_reference.csv";
  std::FILE* reference = examples::OpenOutputFile(referencePath);
  std::fprintf(reference,
               "length,side,young,static_tip_dx,static_tip_dy,static_tip_deflection,"
               "euler_bernoulli\n%g,%g,%g,%.9g,%.9g,%.9g,%.9g\n",
               kLength, kSide, options.youngModulus, staticTip.x(), staticTip.y(), -staticTip.y(),
               eulerBernoulli);
  if (std::fclose(reference) != 0) Fail("error writing '" + referencePath.string() + "'");

  SceneStats const& stats = scene->GetStats();
  Real3 const tip = TipDisplacement(model);
  Real3 const carried = clampForce(true);
  real const weight = beam->GetTotalMass() * gravity;
  int const inverted = beam->CountInvertedTetrahedra();
  real const deflection = -tip.y();
  std::printf("  steps                 %lld\n", static_cast<long long>(stats.steps));
  std::printf("  wall time per step    %.2f ms (assembly %.2f, factorization %.2f, solve %.2f)\n",
              1e3 * stepSeconds / numSteps, 1e3 * assemblySeconds / numSteps,
              1e3 * factorSeconds / numSteps, 1e3 * solveSeconds / numSteps);
  std::printf("  Newton iterations     mean %.2f, max %d\n",
              static_cast<double>(newtonTotal) / numSteps, newtonMax);
  std::printf(
      "  tip deflection        %.4f m at t = %g s (max %.4f m); tip moved %+.4f m along x\n",
      deflection, scene->GetTime(), maxDeflection, tip.x());
  std::printf("  kinetic energy        %.3e J at the end\n", beam->GetKineticEnergy());
  std::printf("  clamp force           (%.2f, %.2f, %.2f) N vs weight %.2f N\n", carried.x(),
              carried.y(), carried.z(), weight);
  std::printf(
      "  static equilibrium    tip deflection %.4f m, tip moved %+.4f m along x\n"
      "                        (same mesh, %d backward-Euler steps of %g s, %d Newton\n"
      "                        iterations, %.2f s)\n",
      -staticTip.y(), staticTip.x(), staticSteps, kStaticDt, staticNewton, staticSeconds);
  std::printf("  Euler-Bernoulli       q L^4 / (8 E I) = %.4f m (q = %.2f N/m, I = %.3e m^4)\n",
              eulerBernoulli, q, inertia);
  if (eulerBernoulli > 0.1 * kLength)
    std::printf(
        "                        = %.2f L: far past the linear (small-deflection) regime,\n"
        "                        where the estimate no longer applies (the tip cannot\n"
        "                        drop by more than L; the static beam's tip drops\n"
        "                        %.2f L and moves %.2f L towards the clamp)\n",
        eulerBernoulli / kLength, -staticTip.y() / kLength, -staticTip.x() / kLength);
  else
    std::printf(
        "                        static / estimate = %.3f (linear tets are stiff in\n"
        "                        bending: coarse meshes deflect less)\n",
        -staticTip.y() / eulerBernoulli);
  std::printf("  inverted tets         %d\n", inverted);
  std::printf("  linear solver         %s, %d DoFs\n", stats.linearSolver.c_str(), stats.numDofs);
  std::printf("  wrote                 %s, %s (%d frames)\n", csvPath.string().c_str(),
              series.GetPath().c_str(), series.GetNumFrames());
  if (inverted > 0) Fail(std::to_string(inverted) + " inverted tetrahedra at the end");
  if (!(deflection > 0)) Fail("the beam did not sag");
  return 0;
}
