// SuperDex rods: a hub (a rigid body) with three elastic rods clamped to it,
// turned a quarter turn about the horizontal x axis. Each rod is 0.6 m long
// along +x, E = 2 GPa, G from ν = 0.4, ρ = 1100 kg/m³ (nylon-like), 40
// elements. Rod 0, on the turning axis, is round (radius 2 mm); rods 1 and 2,
// 4 cm off the axis (y = ±0.04), are ribbons 10 × 1 mm held edge-up: their
// width lies along d₁ = +y, so sagging (the tangent turning toward −y) bends
// them about d₂, the stiff way (EI₂ = E t w³/12), and sideways bending is
// 100× softer (EI₁ = E w t³/12); torsion J = w t³/3.
// The hub is held in place by a RigidPivotToRigidTarget and driven by a
// RigidPivotRotation whose target turns at π/2 rad/s for 1 s, then stops.
// Each rod end is clamped to the hub by DeformableNodeToRigid (the end node)
// + RodElementRotationToRigid (the end element), as docs/design.md §4.3 describes.
//
// Released straight, the round rod droops under gravity (q L³/EI ≈ 1.2: a
// large deflection) and the edge-up ribbons barely (q L³/EI₂ ≈ 0.14). The
// quarter turn lays the ribbons flat (q L³/EI₁ ≈ 14): they collapse, twist
// and swing; the round rod only twists along with the hub.
//
//   superdex_rods [--out DIR] [--dt S] [--time S] [--elements N]
//                 [--integrator be|bdf2] [--vtk-every N]
//
// Writes DIR/rods.csv (per step: hub angle, each rod's tip position, the twist
// of the axis rod at its middle and tip, the axial torque the clamps put on
// the hub, energies, Newton iterations), DIR/rods_NNNN.vtu every N steps
// (polylines with twist and material frame as point data, WriteRodsVtu) and
// DIR/rods.pvd listing them. `examples/rods/plot.py DIR` draws DIR/rods.png.
// Exits non-zero with the library's message when a call fails, or when an
// element stretches by more than 1 % (an exploded rod).
#include <superdex/superdex.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>

#include "../common/command_line.h"
#include "../common/output.h"

using namespace superdex;

namespace {

// ---- the model ----
constexpr real kLength = 0.6;    // [m]
constexpr real kRadius = 2e-3;   // round rod [m]
constexpr real kRibbonWidth = 1e-2, kRibbonThickness = 1e-3;  // [m]
constexpr real kYoung = 2e9;     // [Pa]
constexpr real kPoisson = 0.4;   // G = E / (2(1 + ν))
constexpr real kDensity = 1100;  // [kg/m³]
constexpr real kSpinRate = std::numbers::pi_v<real> / 2;  // [rad/s]
constexpr real kSpinTime = 1;                             // [s]
constexpr int kNumRods = 3;
constexpr std::array<real, kNumRods> kOffsets{0, 0.04, -0.04};  // y of each rod's root [m]
// Clamps: an element next to its clamp has an axial stiffness EA/l ≤ 1.7e6 N/m
// and a bending stiffness EI/l ≤ 11 N·m/rad (the ribbon's stiff way; 40
// elements of 15 mm); the clamps are ≥ 500× and ≥ 9000× stiffer.
constexpr real kClampLinear = 1e9;    // [N/m]
constexpr real kClampAngular = 1e5;   // [N·m/rad]
constexpr real kHubHold = 1e9;        // hub position and rotation drive [N/m], [N·m/rad]

struct Options {
  std::string out = "results/rods";
  real dt = 1.0 / 120;
  real time = 3;
  int elements = 40;
  IntegratorType integrator = IntegratorType::BackwardEuler;
  int vtkEvery = 4;  // 30 frames/s at dt = 1/120
};

using examples::Fail;

Options ParseOptions(int argc, char** argv) {
  Options o;
  examples::CommandLine("superdex_rods")
      .Text("--out", "DIR", o.out, "output folder (default results/rods)")
      .Number("--dt", "S", o.dt, "time step [s] (default 1/120)")
      .Number("--time", "S", o.time, "simulated time [s] (default 3)")
      .Count("--elements", "N", o.elements, "elements per rod (default 40)")
      .Integrator("--integrator", o.integrator, "backward Euler or BDF2 (default be)")
      .Count("--vtk-every", "N", o.vtkEvery, "write a .vtu frame every N steps (default 4)")
      .Parse(argc, argv);
  return o;
}

Quat HubRotation(real time) {
  real const angle = kSpinRate * std::min(time, kSpinTime);
  return Quat(Eigen::AngleAxis<real>(angle, Real3::UnitX()));
}

}  // namespace

int main(int argc, char** argv) {
  Options const options = ParseOptions(argc, argv);
  Error error;

  SceneParams sceneParams;
  sceneParams.integrator = options.integrator;
  std::unique_ptr<Scene> scene = Scene::Create(sceneParams, error);
  if (!scene) Fail("Scene::Create", error);

  // ---- the hub: a 0.1 m disc-like body at the origin, held and spun ----
  RigidActorParams hubParams;
  hubParams.mass = 0.5;
  hubParams.inertia = Real3(2.5e-3, 1.5e-3, 1.5e-3);
  RigidActor* hub = scene->CreateRigidActor(hubParams, error);
  if (!hub) Fail("CreateRigidActor", error);
  RigidPivotToRigidTargetConstraintParams hold;
  hold.actor = hub->GetHandle();
  hold.stiffness = kHubHold;
  if (!scene->CreateRigidPivotToRigidTargetConstraint(hold, error)) Fail("CreateRigidPivotToRigidTargetConstraint", error);
  RigidPivotRotationConstraintParams drive;
  drive.actor = hub->GetHandle();
  drive.stiffness = kHubHold;
  Constraint* spin = scene->CreateRigidPivotRotationConstraint(drive, error);
  if (!spin) Fail("CreateRigidPivotRotationConstraint", error);

  // ---- the rods, clamped at their root to the hub ----
  std::array<RodActor*, kNumRods> rods{};
  std::array<Constraint*, kNumRods> clamps{};
  for (int r = 0; r < kNumRods; ++r) {
    RodActorParams p;
    for (int i = 0; i <= options.elements; ++i)
      p.nodes.push_back(Real3(kLength * i / options.elements, kOffsets[r], 0));
    if (r == 0) {
      p.radius = kRadius;
    } else {
      p.sectionArea = kRibbonWidth * kRibbonThickness;
      p.secondMomentOfArea1 = kRibbonWidth * std::pow(kRibbonThickness, 3) / 12;  // about d₁ (width)
      p.secondMomentOfArea2 = kRibbonThickness * std::pow(kRibbonWidth, 3) / 12;  // about d₂
      p.torsionConstant = kRibbonWidth * std::pow(kRibbonThickness, 3) / 3;
    }
    p.youngModulus = kYoung;
    p.poissonRatio = kPoisson;
    p.density = kDensity;
    p.materialDirector = Real3::UnitY();
    rods[r] = scene->CreateRodActor(p, error);
    if (!rods[r]) Fail("CreateRodActor", error);
    DeformableNodeToRigidConstraintParams root;
    root.deformableActor = rods[r]->GetHandle();
    root.rigidActor = hub->GetHandle();
    root.deformableNodeIndex = 0;
    root.stiffness = kClampLinear;
    if (!scene->CreateDeformableNodeToRigidConstraint(root, error)) Fail("CreateDeformableNodeToRigidConstraint", error);
    RodElementRotationToRigidConstraintParams frame;
    frame.rigidActor = hub->GetHandle();
    frame.rodActor = rods[r]->GetHandle();
    frame.elementIndex = 0;
    frame.stiffness = kClampAngular;
    clamps[r] = scene->CreateRodElementRotationToRigidConstraint(frame, error);
    if (!clamps[r]) Fail("CreateRodElementRotationToRigidConstraint", error);
    if (!clamps[r]->RegisterQuery(QueryType::ConstraintForce, error)) Fail("RegisterQuery", error);
  }
  RodActor const& axisRod = *rods[0];
  internal::RodStiffness const stiffness = axisRod.GetStiffness();

  // ---- output ----
  std::filesystem::path const outDir(options.out);
  std::filesystem::path const csvPath = outDir / "rods.csv";
  std::FILE* csv = examples::OpenOutputFile(csvPath);
  std::fprintf(csv, "t,hub_angle");
  for (int r = 0; r < kNumRods; ++r) std::fprintf(csv, ",tip%d_x,tip%d_y,tip%d_z", r, r, r);
  std::fprintf(csv, ",axis_twist_mid,axis_twist_tip,hub_torque_x,kinetic,elastic,newton_iterations\n");
  VtkSeries series((outDir / "rods.pvd").string());
  DynamicArray<RodActor const*> const rodList(rods.begin(), rods.end());

  // the torque about x the rods' rotation clamps exert on the hub (zero before a step)
  auto hubTorque = [&](bool afterStep) {
    real torque = 0;
    if (!afterStep) return torque;
    for (Constraint* c : clamps) {
      Span<real const> f = c->GetForce(error);
      if (f.size() != 11) Fail("Constraint::GetForce (clamp)", error);
      torque += f[0];
    }
    return torque;
  };
  real worstStretch = 0;
  auto stretch = [&]() {
    real worst = 0;
    for (RodActor const* rod : rods)
      for (int e = 0; e < rod->GetNumElements(); ++e)
        worst = std::max(worst, std::abs((rod->GetNodePosition(e + 1) - rod->GetNodePosition(e)).norm() /
                                             rod->GetRestLength(e) -
                                         1));
    return worst;
  };
  auto writeRow = [&](int newtonIterations, bool afterStep) {
    real kinetic = hub->GetKineticEnergy(), elastic = 0;
    for (RodActor const* rod : rods) {
      kinetic += rod->GetKineticEnergy();
      elastic += rod->GetElasticEnergy();
    }
    std::fprintf(csv, "%.6f,%.9g", scene->GetTime(), kSpinRate * std::min(scene->GetTime(), kSpinTime));
    for (RodActor const* rod : rods) {
      Real3 const tip = rod->GetNodePosition(rod->GetNumNodes() - 1);
      std::fprintf(csv, ",%.9g,%.9g,%.9g", tip.x(), tip.y(), tip.z());
    }
    std::fprintf(csv, ",%.9g,%.9g,%.9g,%.9g,%.9g,%d\n", axisRod.GetTwist(options.elements / 2),
                 axisRod.GetTwist(options.elements - 1), hubTorque(afterStep), kinetic, elastic,
                 newtonIterations);
    if (!std::isfinite(kinetic + elastic)) {
      std::fclose(csv);
      Fail("non-finite state at t = " + std::to_string(scene->GetTime()));
    }
  };
  auto writeFrame = [&]() {
    char name[64];
    std::snprintf(name, sizeof name, "rods_%04d.vtu", series.GetNumFrames());
    if (!WriteRodsVtu((outDir / name).string(), rodList, {}, error)) Fail("WriteRodsVtu", error);
    if (!series.AddFrame(scene->GetTime(), name, error)) Fail("VtkSeries::AddFrame", error);
  };

  int const numSteps = static_cast<int>(std::llround(options.time / options.dt));
  if (numSteps < 1) Fail("--time must be at least one --dt");
  std::printf("SuperDex rods: %s, dt = %g s, %g s (%d steps)\n",
              std::string(ToString(options.integrator)).c_str(), options.dt, options.time, numSteps);
  std::printf("  rods                  %d x %g m, %d elements each (%d DoFs in all)\n", kNumRods, kLength,
              options.elements, scene->GetNumDofs());
  std::printf("  round rod             r = %g m: EA = %.4g N, EI = %.4g N m^2, GJ = %.4g N m^2\n", kRadius,
              stiffness.stretch, stiffness.bend1, stiffness.twist);
  internal::RodStiffness const ribbon = rods[1]->GetStiffness();
  std::printf("  ribbons               %g x %g m: EA = %.4g N, EI1 = %.4g, EI2 = %.4g, GJ = %.4g N m^2\n",
              kRibbonWidth, kRibbonThickness, ribbon.stretch, ribbon.bend1, ribbon.bend2, ribbon.twist);
  std::printf("  hub                   turned about x at %.4g rad/s for %g s\n", kSpinRate, kSpinTime);

  writeRow(0, false);
  writeFrame();
  double stepSeconds = 0;
  long long newtonTotal = 0;
  int newtonMax = 0;
  for (int step = 0; step < numSteps; ++step) {
    if (!spin->SetTargetRotation(HubRotation(scene->GetTime() + options.dt), error)) Fail("SetTargetRotation", error);
    examples::TimedStep(*scene, options.dt, step + 1, stepSeconds, csv);
    SceneStats const& stats = scene->GetStats();
    newtonTotal += stats.newtonIterations;
    newtonMax = std::max(newtonMax, stats.newtonIterations);
    writeRow(stats.newtonIterations, true);
    worstStretch = std::max(worstStretch, stretch());
    if ((step + 1) % options.vtkEvery == 0 || step + 1 == numSteps) writeFrame();
  }
  if (std::fclose(csv) != 0) Fail("error writing '" + csvPath.string() + "'");

  SceneStats const& stats = scene->GetStats();
  real const twistRootToTip = axisRod.GetTwist(options.elements - 1) - axisRod.GetTwist(0);
  std::printf("  wall time per step    %.2f ms\n", 1e3 * stepSeconds / numSteps);
  std::printf("  Newton iterations     mean %.2f, max %d\n", static_cast<double>(newtonTotal) / numSteps,
              newtonMax);
  std::printf("  hub angle             %.4f rad at the end\n", kSpinRate * std::min(scene->GetTime(), kSpinTime));
  for (int r = 0; r < kNumRods; ++r) {
    Real3 const tip = rods[r]->GetNodePosition(rods[r]->GetNumNodes() - 1);
    std::printf("  tip of rod %d          (%.4f, %.4f, %.4f) m\n", r, tip.x(), tip.y(), tip.z());
  }
  std::printf("  axis rod twist        %.4f rad root to tip; clamp torque on the hub %.4g N m\n",
              twistRootToTip, hubTorque(true));
  std::printf("  largest element strain %.3g\n", worstStretch);
  std::printf("  linear solver         %s, %d DoFs\n", stats.linearSolver.c_str(), stats.numDofs);
  std::printf("  wrote                 %s, %s (%d frames)\n", csvPath.string().c_str(), series.GetPath().c_str(),
              series.GetNumFrames());
  if (worstStretch > 0.01) Fail("an element stretched by more than 1 %");
  return 0;
}
