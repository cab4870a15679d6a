// SuperDex soft block: a soft 0.2 m cube (stable Neo-Hookean, E = 50 kPa,
// ν = 0.3, ρ = 500 kg/m³: 4 kg) hanging from a rigid handle, each node of its
// top face attached to the handle by a DeformableNodeToRigid constraint. The
// handle's centre is held by a RigidPivotPosition whose target is animated
// (lifted 0.2 m and carried 0.5 m sideways during the first 2 s, then held
// still); the handle turns freely about it, so the block swings under it
// like a pendulum (--upright K holds it upright instead). Gravity
// (0, −9.81, 0).
//
//   superdex_soft_block [--out DIR] [--dt S] [--time S] [--cells N]
//                       [--integrator be|bdf2] [--upright K] [--vtk-every N]
//
// Writes DIR/soft_block.csv (target, handle, centre of mass, the sum of the
// attachment forces against the weight and the momentum balance, per step
// plus t = 0), DIR/soft_block_NNNN.vtu every N steps and DIR/soft_block.pvd
// listing them (open it in ParaView), and prints a summary. Exits non-zero
// with the library's message when any call fails, or when the block ends
// with inverted tetrahedra or its momentum does not balance the forces on it.
#include <superdex/superdex.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <string_view>
#include <utility>

#include "../common/command_line.h"
#include "../common/output.h"

using namespace superdex;

namespace {

// ---- the model ----
constexpr real kSide = 0.2;   // cube side [m]
constexpr real kYoung = 5e4;  // [Pa]
constexpr real kPoisson = 0.3;
constexpr real kDensity = 500;         // [kg/m³]
constexpr real kHandleMass = 0.5;      // [kg]
constexpr real kHandleInertia = 1e-3;  // principal moments [kg·m²]
constexpr real kHandleHeight = 0.02;   // handle centre above the top face [m]
// Attachments, one per top-face node: 49 × 10⁴ N/m carry the 39 N weight at
// ~0.1 mm of stretch.
constexpr real kAttachmentStiffness = 1e4;
// The handle: its centre pinned to the target at 10⁷ N/m (~5 µm under the
// 44 N load).
constexpr real kHoldStiffness = 1e7;

// The target path: lifted by kLift during [0, 1] s while carried kCarry
// along +x during [0.5, 2] s, each along a quintic smoothstep (zero velocity
// and acceleration at both ends), then held.
constexpr real kLift = 0.2, kCarry = 0.5;
constexpr real kLiftStart = 0, kLiftEnd = 1, kCarryStart = 0.5, kCarryEnd = 2;

struct Options {
  std::string out = "results/soft_block";
  real dt = 1.0 / 60;
  real time = 4;
  int cells = 6;
  IntegratorType integrator = IntegratorType::BackwardEuler;
  int vtkEvery = 3;  // one .vtu every 3 steps: 20 frames/s at dt = 1/60
  // RigidPivotRotation stiffness keeping the handle upright [N·m/rad];
  // 0 (default): none, the handle turns freely about its pivot and the block
  // swings under it like a pendulum
  real upright = 0;
};

using examples::Fail;

Options ParseOptions(int argc, char** argv) {
  Options o;
  examples::CommandLine("superdex_soft_block")
      .Text("--out", "DIR", o.out, "output folder (default results/soft_block)")
      .Number("--dt", "S", o.dt, "time step [s] (default 1/60)")
      .Number("--time", "S", o.time, "simulated time [s] (default 4)")
      .Count("--cells", "N", o.cells, "N x N x N cells, 6 tets each (default 6)")
      .Integrator("--integrator", o.integrator, "backward Euler or BDF2 (default be)")
      .Number("--upright", "K", o.upright,
              "keep the handle upright with a RigidPivotRotation of stiffness K [N m/rad] "
              "(default 0: none, it swings)",
              /*allowZero=*/true)
      .Count("--vtk-every", "N", o.vtkEvery, "write a .vtu frame every N steps (default 3)")
      .Parse(argc, argv);
  return o;
}

// 10τ³ − 15τ⁴ + 6τ⁵ on τ = (t − start)/(end − start) clamped to [0, 1]
real Smoothstep(real t, real start, real end) {
  real const tau = std::clamp((t - start) / (end - start), real(0), real(1));
  return tau * tau * tau * (10 + tau * (-15 + 6 * tau));
}

Real3 TargetAt(Real3 const& start, real t) {
  return start + Real3(kCarry * Smoothstep(t, kCarryStart, kCarryEnd),
                       kLift * Smoothstep(t, kLiftStart, kLiftEnd), 0);
}

}  // namespace

int main(int argc, char** argv) {
  Options const options = ParseOptions(argc, argv);
  Error error;

  SceneParams sceneParams;
  sceneParams.integrator = options.integrator;
  std::unique_ptr<Scene> scene = Scene::Create(sceneParams, error);
  if (!scene) Fail("Scene::Create", error);
  Real3 const gravity = sceneParams.gravity;

  // ---- the block: [−s/2, s/2] × [−s, 0] × [−s/2, s/2], top face at y = 0 ----
  TetMesh mesh;
  if (!MakeTetBox(Real3(-kSide / 2, -kSide, -kSide / 2), Real3::Constant(kSide),
                  {options.cells, options.cells, options.cells}, mesh, error))
    Fail("MakeTetBox", error);
  DeformableActorParams blockParams;
  blockParams.nodes = mesh.nodes;
  blockParams.tetrahedra = mesh.tetrahedra;
  blockParams.material = TetMaterialModel::StableNeoHookean;
  blockParams.youngModulus = kYoung;
  blockParams.poissonRatio = kPoisson;
  blockParams.density = kDensity;
  DeformableActor* block = scene->CreateDeformableActor(blockParams, error);
  if (!block) Fail("CreateDeformableActor", error);

  // ---- the handle, its animated hold and its upright constraint ----
  RigidActorParams handleParams;
  handleParams.mass = kHandleMass;
  handleParams.inertia = Real3::Constant(kHandleInertia);
  handleParams.position = Real3(0, kHandleHeight, 0);
  RigidActor* handle = scene->CreateRigidActor(handleParams, error);
  if (!handle) Fail("CreateRigidActor (handle)", error);
  Real3 const start = handle->GetPosition();

  RigidPivotPositionConstraintParams holdParams;
  holdParams.actor = handle->GetHandle();
  holdParams.localPos = Real3::Zero();
  holdParams.position = start;
  holdParams.stiffness = kHoldStiffness;
  Constraint* hold = scene->CreateRigidPivotPositionConstraint(holdParams, error);
  if (!hold) Fail("CreateRigidPivotPositionConstraint (hold)", error);

  if (options.upright > 0) {
    RigidPivotRotationConstraintParams uprightParams;
    uprightParams.actor = handle->GetHandle();
    uprightParams.rotation = handle->GetRotation();
    uprightParams.stiffness = options.upright;
    if (!scene->CreateRigidPivotRotationConstraint(uprightParams, error))
      Fail("CreateRigidPivotRotationConstraint (upright)", error);
  }

  // ---- attachments: every node of the top face to the handle ----
  DynamicArray<Constraint*> attachments;
  for (int i = 0; i < block->GetNumNodes(); ++i) {
    if (block->GetNodeReferencePosition(i).y() < -1e-9 * kSide) continue;  // top face only
    DeformableNodeToRigidConstraintParams a;
    a.deformableActor = block->GetHandle();
    a.rigidActor = handle->GetHandle();
    a.deformableNodeIndex = i;
    a.fixToDeformablePos = true;
    a.stiffness = kAttachmentStiffness;
    Constraint* c = scene->CreateDeformableNodeToRigidConstraint(a, error);
    if (!c) Fail("CreateDeformableNodeToRigidConstraint (node " + std::to_string(i) + ")", error);
    if (!c->RegisterQuery(QueryType::ConstraintForce, error)) Fail("RegisterQuery", error);
    attachments.push_back(c);
  }
  int const expectedAttachments = (options.cells + 1) * (options.cells + 1);
  if (static_cast<int>(attachments.size()) != expectedAttachments)
    Fail("expected " + std::to_string(expectedAttachments) + " top-face nodes, found " +
         std::to_string(attachments.size()));

  // ---- output ----
  std::filesystem::path const outDir(options.out);
  std::filesystem::path const csvPath = outDir / "soft_block.csv";
  std::FILE* csv = examples::OpenOutputFile(csvPath);
  std::fprintf(
      csv,
      "t,target_x,target_y,target_z,handle_x,handle_y,handle_z,handle_angle,com_x,com_y,com_z,"
      "force_x,force_y,force_z,weight,momentum_rate_x,momentum_rate_y,"
      "momentum_rate_z,balance_residual,kinetic,elastic,max_deformation,"
      "hold_deviation,newton_iterations\n");
  VtkSeries series((outDir / "soft_block.pvd").string());

  real const mass = block->GetTotalMass();
  real const weight = -mass * gravity.y();
  int const n = block->GetNumNodes();
  // the block as the handle would carry it if it were rigid:
  // t_h + R_h (X − start); the rest of the motion is deformation
  auto deformation = [&](int i) {
    Real3 const carried = handle->TransformPoint(block->GetNodeReferencePosition(i) - start);
    return Real3(block->GetNodePosition(i) - carried);
  };
  auto handleAngle = [&]() {  // about z [rad]: the swing in the x–y plane
    Real33 const r = handle->GetRotation().toRotationMatrix();
    return std::atan2(r(1, 0), r(0, 0));
  };
  auto centreOfMass = [&]() {
    Real3 x = Real3::Zero(), v = Real3::Zero();
    for (int i = 0; i < n; ++i) {
      x += block->GetNodeMass(i) * block->GetNodePosition(i);
      v += block->GetNodeMass(i) * block->GetNodeVelocity(i);
    }
    return std::pair<Real3, Real3>(x / mass, v / mass);
  };
  // the sum of the forces the attachments exert on the block's nodes
  // (entries 0–2 of each force; 3–8 act on the handle)
  auto attachmentForce = [&](bool afterStep) {
    Real3 sum = Real3::Zero();
    if (!afterStep) return sum;
    for (Constraint* c : attachments) {
      Span<real const> f = c->GetForce(error);
      if (f.size() != 9) Fail("Constraint::GetForce (attachment)", error);
      sum += Real3(f[0], f[1], f[2]);
    }
    return sum;
  };
  auto maxDeformation = [&]() {
    real worst = 0;
    for (int i = 0; i < n; ++i) worst = std::max(worst, deformation(i).norm());
    return worst;
  };

  // Momentum balance: every stage solves M (vⁿ⁺¹ − a vⁿ − b vⁿ⁻¹)/(β h) = F
  // node by node (scene/integrator.h); summed over the block the elastic
  // forces cancel, leaving M_total times the same combination of the centre
  // of mass's velocities = attachment forces + weight.
  Real3 velocity = centreOfMass().second, previousVelocity = velocity;
  real worstResidual = 0;
  auto writeRow = [&](int step, int newtonIterations) {
    bool const afterStep = step > 0;
    auto const [com, comVelocity] = centreOfMass();
    Real3 const force = attachmentForce(afterStep);
    Real3 momentumRate = Real3::Zero();
    real residual = 0;
    if (afterStep) {
      bool const bdf2 = options.integrator == IntegratorType::Bdf2 && step > 1;
      real const beta = bdf2 ? 2.0 / 3 : 1, a = bdf2 ? 4.0 / 3 : 1, b = bdf2 ? -1.0 / 3 : 0;
      momentumRate =
          mass * (comVelocity - a * velocity - b * previousVelocity) / (beta * options.dt);
      residual = (momentumRate - (force + mass * gravity)).norm() / weight;
      worstResidual = std::max(worstResidual, residual);
      previousVelocity = velocity;
      velocity = comVelocity;
    }
    Real3 const target = TargetAt(start, scene->GetTime());
    Real3 const h = handle->GetPosition();
    real deviationSquared = 0;
    for (real g : hold->GetDeviation()) deviationSquared += g * g;
    real const kinetic = block->GetKineticEnergy(), elastic = block->GetElasticEnergy();
    std::fprintf(csv,
                 "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,"
                 "%.9g,%.9g,%.9g,%.4e,%.9g,%.9g,%.6e,%.4e,%d\n",
                 scene->GetTime(), target.x(), target.y(), target.z(), h.x(), h.y(), h.z(),
                 handleAngle(), com.x(), com.y(), com.z(), force.x(), force.y(), force.z(), weight,
                 momentumRate.x(), momentumRate.y(), momentumRate.z(), residual, kinetic, elastic,
                 maxDeformation(), std::sqrt(deviationSquared), newtonIterations);
    if (!std::isfinite(com.norm()) || !std::isfinite(kinetic + elastic)) {
      std::fclose(csv);
      Fail("non-finite state at t = " + std::to_string(scene->GetTime()));
    }
  };

  // one .vtu: the standard node arrays, plus the deformation (displacement
  // less the handle's rigid carry)
  DynamicArray<VtkPointData> deformationData(2);
  deformationData[0].name = "deformation_magnitude";
  deformationData[1].name = "deformation";
  deformationData[1].components = 3;
  auto writeFrame = [&]() {
    for (auto& array : deformationData) array.values.assign(static_cast<std::size_t>(array.components * n), 0);
    for (int i = 0; i < n; ++i) {
      Real3 const d = deformation(i);
      deformationData[0].values[i] = d.norm();
      for (int k = 0; k < 3; ++k) deformationData[1].values[3 * i + k] = d[k];
    }
    char name[64];
    std::snprintf(name, sizeof name, "soft_block_%04d.vtu", series.GetNumFrames());
    examples::WriteDeformableVtu(*block, (outDir / name).string(), deformationData);
    if (!series.AddFrame(scene->GetTime(), name, error)) Fail("VtkSeries::AddFrame", error);
  };

  int const numSteps = static_cast<int>(std::llround(options.time / options.dt));
  if (numSteps < 1) Fail("--time must be at least one --dt");

  std::printf("SuperDex soft block: %s, dt = %g s, %g s (%d steps)\n",
              std::string(ToString(options.integrator)).c_str(), options.dt, options.time,
              numSteps);
  std::printf(
      "  block                 %g m cube, %d^3 cells, %d nodes (%d DoFs), %d tets, "
      "%.3f kg (weight %.3f N)\n",
      kSide, options.cells, n, block->GetNumDofs(), block->GetNumTetrahedra(), mass, weight);
  std::printf("  material              stable Neo-Hookean, E = %g Pa, nu = %g, rho = %g kg/m^3\n",
              kYoung, kPoisson, kDensity);
  std::printf("  handle                %g kg, %zu DeformableNodeToRigid attachments, k = %g N/m\n",
              kHandleMass, attachments.size(), kAttachmentStiffness);
  if (options.upright > 0)
    std::printf("  upright               RigidPivotRotation, k = %g N m/rad\n", options.upright);
  else
    std::printf("  upright               none: the handle turns freely about its pivot\n");
  std::printf(
      "  target                lifted %g m over [%g, %g] s, carried %g m along x over "
      "[%g, %g] s, then held\n",
      kLift, kLiftStart, kLiftEnd, kCarry, kCarryStart, kCarryEnd);

  writeRow(0, 0);
  writeFrame();

  double stepSeconds = 0;
  long long newtonTotal = 0;
  int newtonMax = 0;
  real deformationMax = 0, forceMin = INFINITY, forceMax = 0, angleMax = 0;
  for (int step = 1; step <= numSteps; ++step) {
    // the target of the stage is the one at its end time
    if (!hold->SetTargetPosition(TargetAt(start, scene->GetTime() + options.dt), error))
      Fail("SetTargetPosition", error);
    examples::TimedStep(*scene, options.dt, step, stepSeconds, csv);
    int const iterations = scene->GetStats().newtonIterations;
    newtonTotal += iterations;
    newtonMax = std::max(newtonMax, iterations);
    writeRow(step, iterations);
    deformationMax = std::max(deformationMax, maxDeformation());
    angleMax = std::max(angleMax, std::abs(handleAngle()));
    real const fy = attachmentForce(true).y();
    forceMin = std::min(forceMin, fy);
    forceMax = std::max(forceMax, fy);
    if (step % options.vtkEvery == 0 || step == numSteps) writeFrame();
  }
  if (std::fclose(csv) != 0) Fail("error writing '" + csvPath.string() + "'");

  SceneStats const& stats = scene->GetStats();
  Real3 const force = attachmentForce(true);
  Real3 const h = handle->GetPosition();
  Real3 const com = centreOfMass().first;
  std::printf("  steps                 %lld\n", static_cast<long long>(stats.steps));
  std::printf("  wall time per step    %.2f ms\n", 1e3 * stepSeconds / numSteps);
  std::printf("  Newton iterations     mean %.2f, max %d\n",
              static_cast<double>(newtonTotal) / numSteps, newtonMax);
  std::printf("  handle                (%.4f, %.4f, %.4f) m, target (%.4f, %.4f, %.4f) m\n", h.x(),
              h.y(), h.z(), TargetAt(start, scene->GetTime()).x(),
              TargetAt(start, scene->GetTime()).y(), TargetAt(start, scene->GetTime()).z());
  std::printf("  swing                 handle angle max %.2f deg, %.3f deg at the end\n",
              angleMax * 180 / std::numbers::pi, handleAngle() * 180 / std::numbers::pi);
  std::printf("  centre of mass        (%.4f, %.4f, %.4f) m\n", com.x(), com.y(), com.z());
  std::printf(
      "  attachment forces     (%.4f, %.4f, %.4f) N at the end vs weight %.4f N;\n"
      "                        vertical sum in [%.3f, %.3f] N during the run\n",
      force.x(), force.y(), force.z(), weight, forceMin, forceMax);
  std::printf("  momentum balance      |M a - (F + M g)| <= %.2e of the weight\n", worstResidual);
  std::printf(
      "  deformation           max %.3f mm (motion less the handle's rigid carry); %.3f mm\n"
      "                        at the end\n",
      1e3 * deformationMax, 1e3 * maxDeformation());
  std::printf("  kinetic energy        %.3e J at the end\n", block->GetKineticEnergy());
  std::printf("  inverted tets         %d\n", block->CountInvertedTetrahedra());
  std::printf("  linear solver         %s, %d DoFs\n", stats.linearSolver.c_str(), stats.numDofs);
  std::printf("  wrote                 %s, %s (%d frames)\n", csvPath.string().c_str(),
              series.GetPath().c_str(), series.GetNumFrames());
  if (block->CountInvertedTetrahedra() > 0) Fail("inverted tetrahedra at the end");
  // the Newton tolerance (10⁻⁶ m/s) leaves residual forces far below this
  if (worstResidual > 1e-3) Fail("the block's momentum does not balance the forces on it");
  return 0;
}
