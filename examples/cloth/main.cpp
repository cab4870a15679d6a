// SuperDex cloth: a 1 × 1 m sheet (MakeTriangleGrid, StVK membrane plus
// hinge bending, E = 1 MPa, ν = 0.3, h = 1 mm, ρ = 300 kg/m³: 0.3 kg/m²),
// lying flat in the x–z plane, pinned at its two corners on the edge z = 1 by
// DeformableNodePosition constraints and released under gravity
// (0, −9.81, 0). It falls, swings about the pinned edge and wrinkles.
//
//   superdex_cloth [--out DIR] [--dt S] [--time S] [--cells N]
//                  [--integrator be|bdf2] [--max-newton N] [--vtk-every N]
//
// Writes DIR/cloth.csv (energies, pin forces, lowest point, largest edge
// stretch and Newton iterations per step, plus t = 0), DIR/cloth_NNNN.vtu
// every N steps and DIR/cloth.pvd listing them (open it in ParaView), and
// prints a summary. Exits non-zero with the library's message when any call
// fails, or when an edge stretches past 1.5 times its rest length (a torn or
// exploded sheet).
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
constexpr real kSize = 1;     // side of the square sheet [m]
constexpr real kYoung = 1e6;  // [Pa]
constexpr real kPoisson = 0.3;
constexpr real kThickness = 1e-3;  // [m]
constexpr real kDensity = 300;     // [kg/m³]: 0.3 kg/m²
// Pins: 10⁵ N/m. Each pin carries about half the weight (1.5 N) plus the
// swing's inertial load, so the pinned corners move by ~10⁻⁵–10⁻⁴ m.
constexpr real kPinStiffness = 1e5;

struct Options {
  std::string out = "results/cloth";
  real dt = 1.0 / 60;
  real time = 4;
  int cells = 20;
  IntegratorType integrator = IntegratorType::BackwardEuler;
  MembraneModel membrane = MembraneModel::StVK;
  // Where the sheet is compressed (folds, wrinkles) the StVK membrane is
  // non-convex; the per-element PSD projection then makes Newton converge
  // only linearly, and a step can need far more than the default 50.
  int maxNewton = 300;
  int vtkEvery = 4;  // one .vtu every 4 steps: 15 frames/s at dt = 1/60
};

using examples::Fail;

Options ParseOptions(int argc, char** argv) {
  Options o;
  examples::CommandLine("superdex_cloth")
      .Text("--out", "DIR", o.out, "output folder (default results/cloth)")
      .Number("--dt", "S", o.dt, "time step [s] (default 1/60)")
      .Number("--time", "S", o.time, "simulated time [s] (default 4)")
      .Count("--cells", "N", o.cells, "N x N quads, 2 triangles each (default 20)")
      .Integrator("--integrator", o.integrator, "backward Euler or BDF2 (default be)")
      .Membrane("--membrane", o.membrane, "the sheet's membrane model (default stvk)")
      .Count("--max-newton", "N", o.maxNewton, "Newton iteration cap per stage (default 300)")
      .Count("--vtk-every", "N", o.vtkEvery, "write a .vtu frame every N steps (default 4)")
      .Parse(argc, argv);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  Options const options = ParseOptions(argc, argv);
  Error error;

  SceneParams sceneParams;
  sceneParams.integrator = options.integrator;
  sceneParams.newton.maxIterations = options.maxNewton;
  std::unique_ptr<Scene> scene = Scene::Create(sceneParams, error);
  if (!scene) Fail("Scene::Create", error);
  real const gravity = -sceneParams.gravity.y();

  // ---- the sheet: [0, 1] × {0} × [0, 1], normal +y ----
  TriangleMesh mesh;
  if (!MakeTriangleGrid(Real3::Zero(), kSize, kSize, options.cells, options.cells, mesh, error))
    Fail("MakeTriangleGrid", error);
  DeformableActorParams clothParams;
  clothParams.nodes = mesh.nodes;
  clothParams.triangles = mesh.triangles;
  clothParams.youngModulus = kYoung;
  clothParams.poissonRatio = kPoisson;
  clothParams.thickness = kThickness;
  clothParams.density = kDensity;
  clothParams.membrane = options.membrane;
  DeformableActor* cloth = scene->CreateDeformableActor(clothParams, error);
  if (!cloth) Fail("CreateDeformableActor", error);

  // ---- the pins: the corners (0, 0, 1) and (1, 0, 1), where they are ----
  int const n = options.cells;
  std::array<int, 2> const pinNodes{(n + 1) * n, (n + 1) * n + n};  // grid points (0, n), (n, n)
  std::array<Constraint*, 2> pins{};
  for (int k = 0; k < 2; ++k) {
    DeformableNodePositionConstraintParams pin;
    pin.actor = cloth->GetHandle();
    pin.nodeIndex = pinNodes[k];
    pin.position = cloth->GetNodePosition(pinNodes[k]);
    pin.stiffness = kPinStiffness;
    pins[k] = scene->CreateDeformableNodePositionConstraint(pin, error);
    if (!pins[k]) Fail("CreateDeformableNodePositionConstraint", error);
    if (!pins[k]->RegisterQuery(QueryType::ConstraintForce, error)) Fail("RegisterQuery", error);
  }
  if (cloth->GetNodeReferencePosition(pinNodes[0]) != Real3(0, 0, kSize) ||
      cloth->GetNodeReferencePosition(pinNodes[1]) != Real3(kSize, 0, kSize))
    Fail("the pinned nodes are not the corners (0, 0, 1) and (1, 0, 1)");

  // ---- output ----
  std::filesystem::path const outDir(options.out);
  std::filesystem::path const csvPath = outDir / "cloth.csv";
  std::FILE* csv = examples::OpenOutputFile(csvPath);
  std::fprintf(csv,
               "t,kinetic,elastic,potential,total,pin0_fx,pin0_fy,pin0_fz,pin1_fx,pin1_fy,"
               "pin1_fz,weight,lowest_y,max_stretch,newton_iterations\n");
  VtkSeries series((outDir / "cloth.pvd").string());

  real const weight = cloth->GetTotalMass() * gravity;
  real const restEdge = kSize / n;  // the grid's axis-aligned edges; diagonals √2 longer
  auto potential = [&]() {
    real e = 0;
    for (int i = 0; i < cloth->GetNumNodes(); ++i)
      e += gravity * cloth->GetNodeMass(i) * cloth->GetNodePosition(i).y();
    return e;
  };
  auto lowest = [&]() {
    real y = INFINITY;
    for (int i = 0; i < cloth->GetNumNodes(); ++i) y = std::min(y, cloth->GetNodePosition(i).y());
    return y;
  };
  // largest edge length / rest length over all triangle edges
  auto maxStretch = [&]() {
    real worst = 0;
    for (auto const& t : cloth->GetTriangles())
      for (int k = 0; k < 3; ++k) {
        int const a = t[k], b = t[(k + 1) % 3];
        real const rest =
            (cloth->GetNodeReferencePosition(a) - cloth->GetNodeReferencePosition(b)).norm();
        worst =
            std::max(worst, (cloth->GetNodePosition(a) - cloth->GetNodePosition(b)).norm() / rest);
      }
    return worst;
  };
  // the force each pin exerts on the sheet (zero before the first step)
  auto pinForce = [&](int k, bool afterStep) {
    if (!afterStep) return Real3(Real3::Zero());
    Span<real const> f = pins[k]->GetForce(error);
    if (f.size() != 3) Fail("Constraint::GetForce (pin)", error);
    return Real3(f[0], f[1], f[2]);
  };
  auto writeRow = [&](int newtonIterations, bool afterStep) {
    real const kinetic = cloth->GetKineticEnergy(), elastic = cloth->GetElasticEnergy();
    real const pot = potential();
    Real3 const f0 = pinForce(0, afterStep), f1 = pinForce(1, afterStep);
    std::fprintf(csv, "%.6f,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.9g,%.6g,%d\n",
                 scene->GetTime(), kinetic, elastic, pot, kinetic + elastic + pot, f0.x(), f0.y(),
                 f0.z(), f1.x(), f1.y(), f1.z(), weight, lowest(), maxStretch(), newtonIterations);
    if (!std::isfinite(kinetic + elastic + pot)) {
      std::fclose(csv);
      Fail("non-finite state at t = " + std::to_string(scene->GetTime()));
    }
  };
  auto writeFrame = [&]() {
    char name[64];
    std::snprintf(name, sizeof name, "cloth_%04d.vtu", series.GetNumFrames());
    examples::WriteDeformableVtu(*cloth, (outDir / name).string());
    if (!series.AddFrame(scene->GetTime(), name, error)) Fail("VtkSeries::AddFrame", error);
  };

  int const numSteps = static_cast<int>(std::llround(options.time / options.dt));
  if (numSteps < 1) Fail("--time must be at least one --dt");

  std::printf("SuperDex cloth: %s, dt = %g s, %g s (%d steps), Newton cap %d\n",
              std::string(ToString(options.integrator)).c_str(), options.dt, options.time, numSteps,
              options.maxNewton);
  std::printf(
      "  sheet                 %g x %g m, %dx%d quads, %d nodes (%d DoFs), %d triangles, "
      "%d hinges, %.3f kg\n",
      kSize, kSize, n, n, cloth->GetNumNodes(), cloth->GetNumDofs(), cloth->GetNumTriangles(),
      cloth->GetNumHinges(), cloth->GetTotalMass());
  std::printf(
      "  material              StVK membrane + bending, E = %g Pa, nu = %g, h = %g m, "
      "rho = %g kg/m^3\n",
      kYoung, kPoisson, kThickness, kDensity);
  std::printf("  pins                  2 DeformableNodePosition, k = %g N/m\n", kPinStiffness);

  writeRow(0, false);
  writeFrame();

  double stepSeconds = 0, assemblySeconds = 0, factorSeconds = 0, solveSeconds = 0;
  long long newtonTotal = 0;
  int newtonMax = 0, newtonMaxStep = 0;
  real worstStretch = 0, lowestEver = 0;
  for (int step = 0; step < numSteps; ++step) {
    examples::TimedStep(*scene, options.dt, step + 1, stepSeconds, csv);
    SceneStats const& stats = scene->GetStats();
    newtonTotal += stats.newtonIterations;
    if (stats.newtonIterations > newtonMax) {
      newtonMax = stats.newtonIterations;
      newtonMaxStep = step + 1;
    }
    assemblySeconds += stats.assemblySeconds;
    factorSeconds += stats.factorizationSeconds;
    solveSeconds += stats.solveSeconds;
    writeRow(stats.newtonIterations, true);
    worstStretch = std::max(worstStretch, maxStretch());
    lowestEver = std::min(lowestEver, lowest());
    if ((step + 1) % options.vtkEvery == 0 || step + 1 == numSteps) writeFrame();
  }
  if (std::fclose(csv) != 0) Fail("error writing '" + csvPath.string() + "'");

  SceneStats const& stats = scene->GetStats();
  Real3 const f0 = pinForce(0, true), f1 = pinForce(1, true);
  Real3 const carried = f0 + f1;
  std::printf("  steps                 %lld\n", static_cast<long long>(stats.steps));
  std::printf("  wall time per step    %.2f ms (assembly %.2f, factorization %.2f, solve %.2f)\n",
              1e3 * stepSeconds / numSteps, 1e3 * assemblySeconds / numSteps,
              1e3 * factorSeconds / numSteps, 1e3 * solveSeconds / numSteps);
  std::printf("  Newton iterations     mean %.2f, max %d (step %d)\n",
              static_cast<double>(newtonTotal) / numSteps, newtonMax, newtonMaxStep);
  std::printf("  kinetic energy        %.3e J at the end\n", cloth->GetKineticEnergy());
  std::printf("  pin forces            (%.3f, %.3f, %.3f) + (%.3f, %.3f, %.3f) N\n", f0.x(), f0.y(),
              f0.z(), f1.x(), f1.y(), f1.z());
  std::printf("                        sum y %.4f N vs weight %.4f N\n", carried.y(), weight);
  std::printf("  lowest point          y = %.4f m at the end (lowest %.4f m)\n", lowest(),
              lowestEver);
  std::printf("  largest edge stretch  %.4f x rest length (at the end %.4f; rest edge %g m)\n",
              worstStretch, maxStretch(), restEdge);
  std::printf("  linear solver         %s, %d DoFs\n", stats.linearSolver.c_str(), stats.numDofs);
  std::printf("  wrote                 %s, %s (%d frames)\n", csvPath.string().c_str(),
              series.GetPath().c_str(), series.GetNumFrames());
  // an exploded or torn sheet shows as edges far longer than their rest length
  if (worstStretch > 1.5) Fail("an edge stretched to more than 1.5 x its rest length");
  return 0;
}
