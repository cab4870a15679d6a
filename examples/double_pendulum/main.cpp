// SuperDex double pendulum: two rigid rods joined by a compliant
// ball-and-socket joint (RigidSphericalJoint), the first rod's top end pinned
// to the world origin by a compliant RigidPivotPosition. Released from rest
// with the first rod horizontal (90° from the downward vertical) and the
// second at 120°, in the x–y plane; gravity (0, −9.81, 0).
//
//   superdex_double_pendulum [--out DIR] [--dt S] [--time S]
//                            [--integrator be|bdf2] [--stiffness K]
//
// Writes DIR/double_pendulum.csv (one row per step, plus t = 0) and prints a
// summary. Exits non-zero with the library's message when any call fails.
#include <superdex/superdex.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <string>
#include <string_view>

#include "../common/command_line.h"
#include "../common/output.h"

using namespace superdex;

namespace {

// ---- the model ----
constexpr real kLength = 1;       // rod length [m]
constexpr real kMass = 1;         // rod mass [kg]
constexpr real kRadius = 0.01;    // rod radius [m], only for the (tiny) axial inertia
constexpr real kTheta1 = 90;      // first rod, degrees from the downward vertical
constexpr real kTheta2 = 120;     // second rod

// A rod along its body-frame y axis, centre of mass at the body origin:
// its ends are (0, ±L/2, 0) in the body frame.
Real3 const kTopEnd{0, kLength / 2, 0};
Real3 const kBottomEnd{0, -kLength / 2, 0};

struct Options {
  std::string out = "results/double_pendulum";
  real dt = 1e-3;
  real time = 10;
  IntegratorType integrator = IntegratorType::Bdf2;
  // 1e7 N/m: the joints then stretch by m·a/k ≈ 10⁻⁶–10⁻⁵ m (forces up to
  // ~50 N), invisible at the 1 m scale, and their elastic energy (~10⁻⁴ J)
  // is negligible next to the ~20 J of motion. The joint spring mode
  // (√(k/m) ≈ 3·10³ rad/s, ω·dt ≈ 3 at dt = 1e-3) is far above the swing
  // frequencies (~1–10 rad/s); the implicit integrators damp it instead of
  // resolving it, and the Newton systems stay well conditioned (k·dt² / m = 10).
  real stiffness = 1e7;
};

using examples::Fail;

Options ParseOptions(int argc, char** argv) {
  Options o;
  examples::CommandLine("superdex_double_pendulum")
      .Text("--out", "DIR", o.out, "output folder (default results/double_pendulum)")
      .Number("--dt", "S", o.dt, "time step [s] (default 1e-3)")
      .Number("--time", "S", o.time, "simulated time [s] (default 10)")
      .Integrator("--integrator", o.integrator, "backward Euler or BDF2 (default bdf2)")
      .Number("--stiffness", "K", o.stiffness, "joint stiffness [N/m] (default 1e7)")
      .Parse(argc, argv);
  return o;
}

real DeviationNorm(Constraint const& c) {
  real sum = 0;
  for (real v : c.GetDeviation()) sum += v * v;
  return std::sqrt(sum);
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

  // ---- bodies: rod i points from its top end along d_i = (sin θ, −cos θ, 0) ----
  real const deg = std::numbers::pi_v<real> / 180;
  Quat const rotation1(Eigen::AngleAxis<real>(kTheta1 * deg, Real3::UnitZ()));
  Quat const rotation2(Eigen::AngleAxis<real>(kTheta2 * deg, Real3::UnitZ()));
  // principal inertia of a slender rod (thin solid cylinder) about its centre
  real const transverse = kMass * (3 * kRadius * kRadius + kLength * kLength) / 12;
  real const axial = kMass * kRadius * kRadius / 2;
  Real3 const inertia{transverse, axial, transverse};

  RigidActorParams rod;
  rod.mass = kMass;
  rod.inertia = inertia;
  rod.rotation = rotation1;
  rod.position = -(rotation1 * kTopEnd);  // top end at the origin
  RigidActor* body1 = scene->CreateRigidActor(rod, error);
  if (!body1) Fail("CreateRigidActor (rod 1)", error);

  Real3 const joint = body1->TransformPoint(kBottomEnd);
  rod.rotation = rotation2;
  rod.position = joint - rotation2 * kTopEnd;
  RigidActor* body2 = scene->CreateRigidActor(rod, error);
  if (!body2) Fail("CreateRigidActor (rod 2)", error);

  // ---- constraints ----
  RigidPivotPositionConstraintParams pivotParams;
  pivotParams.actor = body1->GetHandle();
  pivotParams.localPos = kTopEnd;
  pivotParams.position = Real3::Zero();
  pivotParams.stiffness = options.stiffness;
  Constraint* pivot = scene->CreateRigidPivotPositionConstraint(pivotParams, error);
  if (!pivot) Fail("CreateRigidPivotPositionConstraint", error);

  RigidSphericalJointConstraintParams jointParams;
  jointParams.actorA = body1->GetHandle();
  jointParams.actorB = body2->GetHandle();
  jointParams.localPosA = kBottomEnd;
  jointParams.localPosB = kTopEnd;
  jointParams.stiffness = options.stiffness;
  Constraint* sphericalJoint = scene->CreateRigidSphericalJointConstraint(jointParams, error);
  if (!sphericalJoint) Fail("CreateRigidSphericalJointConstraint", error);

  // ---- output ----
  std::filesystem::path const outDir(options.out);
  std::filesystem::path const csvPath = outDir / "double_pendulum.csv";
  std::FILE* csv = examples::OpenOutputFile(csvPath);
  std::fprintf(csv,
               "t,x1,y1,x2,y2,kinetic,potential,elastic,total,"
               "pivot_deviation,joint_deviation,newton_iterations\n");

  struct Energies {
    real kinetic, potential, elastic, total;
  };
  auto energies = [&]() {
    Energies e{};
    e.kinetic = body1->GetKineticEnergy() + body2->GetKineticEnergy();
    e.potential = gravity * (body1->GetMass() * body1->GetPosition().y() +
                             body2->GetMass() * body2->GetPosition().y());
    real const d1 = DeviationNorm(*pivot), d2 = DeviationNorm(*sphericalJoint);
    e.elastic = 0.5_r * (pivot->GetStiffness() * d1 * d1 + sphericalJoint->GetStiffness() * d2 * d2);
    e.total = e.kinetic + e.potential + e.elastic;
    return e;
  };
  auto writeRow = [&](int newtonIterations) {
    Real3 const tip1 = body1->TransformPoint(kBottomEnd);
    Real3 const tip2 = body2->TransformPoint(kBottomEnd);
    Energies const e = energies();
    std::fprintf(csv, "%.6f,%.9g,%.9g,%.9g,%.9g,%.12g,%.12g,%.6g,%.12g,%.6g,%.6g,%d\n",
                 scene->GetTime(), tip1.x(), tip1.y(), tip2.x(), tip2.y(), e.kinetic,
                 e.potential, e.elastic, e.total, DeviationNorm(*pivot),
                 DeviationNorm(*sphericalJoint), newtonIterations);
    return e;
  };

  Energies const initial = writeRow(0);
  // energy of the hanging rest state (both rods straight down, at rest):
  // the reference for the drift, so that it measures the fraction of the
  // motion's energy lost or gained.
  real const restEnergy = -gravity * (kMass * kLength / 2 + kMass * 3 * kLength / 2);
  real const motionEnergy = initial.total - restEnergy;

  int const numSteps = static_cast<int>(std::llround(options.time / options.dt));
  if (numSteps < 1) Fail("--time must be at least one --dt");

  std::printf("SuperDex double pendulum: %s, dt = %g s, %g s (%d steps), k = %g N/m\n",
              std::string(ToString(options.integrator)).c_str(), options.dt, options.time,
              numSteps, options.stiffness);

  double stepSeconds = 0;
  long long newtonTotal = 0;
  int newtonMax = 0;
  real maxPivotDeviation = 0, maxJointDeviation = 0;
  real minEnergy = initial.total, maxEnergy = initial.total;
  Energies last = initial;
  for (int step = 0; step < numSteps; ++step) {
    examples::TimedStep(*scene, options.dt, step + 1, stepSeconds, csv);
    int const iterations = scene->GetStats().newtonIterations;
    newtonTotal += iterations;
    newtonMax = std::max(newtonMax, iterations);
    maxPivotDeviation = std::max(maxPivotDeviation, DeviationNorm(*pivot));
    maxJointDeviation = std::max(maxJointDeviation, DeviationNorm(*sphericalJoint));
    last = writeRow(iterations);
    minEnergy = std::min(minEnergy, last.total);
    maxEnergy = std::max(maxEnergy, last.total);
    if (!std::isfinite(last.total)) {
      std::fclose(csv);
      Fail("non-finite energy at t = " + std::to_string(scene->GetTime()));
    }
  }
  if (std::fclose(csv) != 0) Fail("error writing '" + csvPath.string() + "'");

  SceneStats const& stats = scene->GetStats();
  real const drift = last.total - initial.total;
  real const maxDeviation = std::max(maxPivotDeviation, maxJointDeviation);
  std::printf("  steps                 %lld\n", static_cast<long long>(stats.steps));
  std::printf("  wall time per step    %.2f us\n", 1e6 * stepSeconds / numSteps);
  std::printf("  Newton iterations     mean %.2f, max %d\n",
              static_cast<double>(newtonTotal) / numSteps, newtonMax);
  std::printf("  energy                E0 = %.6f J, E(T) = %.6f J, range [%.6f, %.6f] J\n",
              initial.total, last.total, minEnergy, maxEnergy);
  std::printf("  energy drift          %+.4f %% of the motion's energy (E0 - E_rest = %.4f J); "
              "%+.4e J\n",
              100 * drift / motionEnergy, motionEnergy, drift);
  std::printf("  max joint deviation   %.3e m (pivot %.3e m, spherical joint %.3e m); "
              "k * max = %.1f N\n",
              maxDeviation, maxPivotDeviation, maxJointDeviation,
              options.stiffness * maxDeviation);
  std::printf("  linear solver         %s\n", stats.linearSolver.c_str());
  std::printf("  wrote                 %s\n", csvPath.string().c_str());
  return 0;
}
