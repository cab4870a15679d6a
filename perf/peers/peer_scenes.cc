// The driver of perf/peers (peer_scenes.h): steps each scene, measures it
// from the boxes' poses alone (so every engine is judged by the same code)
// and prints the CSV rows.
#include "peer_scenes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

namespace peers {

Mat3 RotationZ(double angle) {
  double const c = std::cos(angle), s = std::sin(angle);
  return {{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}};
}

Mat3 FromQuaternion(double w, double x, double y, double z) {
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

Vec3 BoxInertia(double mass, Vec3 const& half) {
  double const x = 2 * half[0], y = 2 * half[1], z = 2 * half[2];
  return {mass / 12 * (y * y + z * z), mass / 12 * (x * x + z * z), mass / 12 * (x * x + y * y)};
}

namespace {

double Dot(Vec3 const& a, Vec3 const& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 Sub(Vec3 const& a, Vec3 const& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 Cross(Vec3 const& a, Vec3 const& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 Axis(Mat3 const& r, int j) {
  return {r[0][j], r[1][j], r[2][j]};
}

/// The smallest signed distance of a box's corners above the plane n·x = 0.
double LowestCorner(Pose const& box, Vec3 const& half, Vec3 const& normal) {
  double lowest = std::numeric_limits<double>::infinity();
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 p = box.position;
    for (int j = 0; j < 3; ++j) {
      double const sign = (corner >> j & 1) ? 1 : -1;
      for (int i = 0; i < 3; ++i) p[i] += sign * half[j] * box.rotation[i][j];
    }
    lowest = std::min(lowest, Dot(p, normal));
  }
  return lowest;
}

/// The signed gap of two boxes by the separating axis test: the largest
/// separation of their projections over the 15 axes of two boxes. Negative:
/// they overlap, and minus it is the penetration depth (the shortest
/// translation that parts two convex polyhedra lies along one of these
/// axes). Positive: a lower bound on their distance, equal to it when two
/// faces face each other (a resting stack).
double BoxBoxGap(Pose const& a, Vec3 const& ha, Pose const& b, Vec3 const& hb) {
  Vec3 const d = Sub(b.position, a.position);
  std::vector<Vec3> axes;
  for (int i = 0; i < 3; ++i) axes.push_back(Axis(a.rotation, i));
  for (int j = 0; j < 3; ++j) axes.push_back(Axis(b.rotation, j));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vec3 c = Cross(Axis(a.rotation, i), Axis(b.rotation, j));
      double const n = std::sqrt(Dot(c, c));
      // parallel edges: their cross product is no axis (a face axis covers it)
      if (n < 1e-9) continue;
      for (double& x : c) x /= n;
      axes.push_back(c);
    }
  double gap = -std::numeric_limits<double>::infinity();
  for (Vec3 const& axis : axes) {
    double reach = 0;
    for (int k = 0; k < 3; ++k) {
      reach += ha[k] * std::abs(Dot(Axis(a.rotation, k), axis));
      reach += hb[k] * std::abs(Dot(Axis(b.rotation, k), axis));
    }
    gap = std::max(gap, std::abs(Dot(d, axis)) - reach);
  }
  return gap;
}

/// The least-squares acceleration 2 c₂ of s(t) ≈ c₀ + c₁ τ + c₂ τ², τ = t − mid.
double FitAcceleration(std::vector<double> const& t, std::vector<double> const& s, double mid) {
  // normal equations of the quadratic fit; centring the time keeps them well conditioned
  double m[3][4] = {};
  for (size_t k = 0; k < t.size(); ++k) {
    double const tau = t[k] - mid;
    double const basis[3] = {1, tau, tau * tau};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m[i][j] += basis[i] * basis[j];
      m[i][3] += basis[i] * s[k];
    }
  }
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int r = col + 1; r < 3; ++r)
      if (std::abs(m[r][col]) > std::abs(m[pivot][col])) pivot = r;
    std::swap(m[col], m[pivot]);
    for (int r = 0; r < 3; ++r) {
      if (r == col) continue;
      double const f = m[r][col] / m[col][col];
      for (int c = col; c < 4; ++c) m[r][c] -= f * m[col][c];
    }
  }
  return 2 * m[2][3] / m[2][2];
}

struct Metric {
  std::string name;
  double value;
  std::string unit;
};

/// One run's outcome: its metrics, or why it stopped.
struct Outcome {
  double stepSeconds = 0;  ///< wall time of the Step calls only
  double simSeconds = 0;
  double iterations = 0;  ///< summed LastIterations (−1 when the engine has none)
  int steps = 0;
  std::vector<Metric> metrics;
  std::string failure;
};

/// Steps `world` over `seconds`, timing only Step, calling `observe(step,
/// time)` after each step (outside the timing).
template <class Observe>
bool Run(World& world, double dt, double seconds, Outcome& out, Observe&& observe) {
  int const steps = static_cast<int>(std::lround(seconds / dt));
  out.simSeconds = steps * dt;
  for (int s = 1; s <= steps; ++s) {
    std::string why;
    auto const start = std::chrono::steady_clock::now();
    bool const ok = world.Step(why);
    out.stepSeconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!ok) {
      out.failure = "step " + std::to_string(s) + " failed: " + why;
      return false;
    }
    double const iterations = world.LastIterations();
    out.iterations = iterations < 0 || out.iterations < 0 ? -1 : out.iterations + iterations;
    out.steps = s;
    observe(s, s * dt);
  }
  return true;
}

Outcome RunIncline(PeerEngine const& engine, double tanTheta, double dt) {
  Outcome out;
  std::unique_ptr<World> world = engine.incline(tanTheta, dt, out.failure);
  if (!world) return out;
  double const theta = std::atan(tanTheta);
  Mat3 const tilt = RotationZ(theta);
  Vec3 const uphill = Axis(tilt, 0), normal = Axis(tilt, 1);
  Vec3 const start = world->BoxPose(0).position;
  int const oneSecond = static_cast<int>(std::lround(1 / dt));
  std::vector<double> times, downhill;
  double atOne = 0, minGap = std::numeric_limits<double>::infinity();
  Vec3 const half{kInclineHalf, kInclineHalf, kInclineHalf};
  bool const ran = Run(*world, dt, kInclineSeconds, out, [&](int step, double t) {
    Pose const pose = world->BoxPose(0);
    double const s = -Dot(Sub(pose.position, start), uphill);
    if (step == oneSecond) atOne = s;
    if (t >= 1 - 1e-9 && t <= 3 + 1e-9) {
      times.push_back(t);
      downhill.push_back(s);
    }
    minGap = std::min(minGap, LowestCorner(pose, half, normal));
  });
  if (!ran) return out;
  double const end = -Dot(Sub(world->BoxPose(0).position, start), uphill);
  if (tanTheta < kFriction) {
    // signed: positive down the slope; over [1 s, 5 s], after the start's settling
    out.metrics.push_back({"creep_um_per_s", (end - atOne) / (kInclineSeconds - 1) * 1e6, "um/s"});
  } else {
    double const expected = kGravity * (std::sin(theta) - kFriction * std::cos(theta));
    double const measured = FitAcceleration(times, downhill, 2);
    out.metrics.push_back({"acceleration_m_per_s2", measured, "m/s^2"});
    out.metrics.push_back({"acceleration_rel_error", (measured - expected) / expected, "1"});
  }
  out.metrics.push_back({"min_gap_m", minGap, "m"});
  return out;
}

Outcome RunStack(PeerEngine const& engine, double dt) {
  Outcome out;
  std::unique_ptr<World> world = engine.stack(dt, out.failure);
  if (!world) return out;
  std::vector<Pose> start;
  for (int i = 0; i < kStackCount; ++i) start.push_back(world->BoxPose(i));
  Vec3 const half{kStackHalf, kStackHalf, kStackHalf};
  double drift = 0, minGap = std::numeric_limits<double>::infinity(),
         lowestTop = start.back().position[1];
  bool const ran = Run(*world, dt, kStackSeconds, out, [&](int, double) {
    std::vector<Pose> poses;
    for (int i = 0; i < kStackCount; ++i) poses.push_back(world->BoxPose(i));
    for (int i = 0; i < kStackCount; ++i) {
      Vec3 const moved = Sub(poses[i].position, start[i].position);
      drift = std::max(drift, std::hypot(moved[0], moved[2]));
    }
    minGap = std::min(minGap, LowestCorner(poses[0], half, {0, 1, 0}));
    for (int i = 1; i < kStackCount; ++i)
      minGap = std::min(minGap, BoxBoxGap(poses[i - 1], half, poses[i], half));
    lowestTop = std::min(lowestTop, poses.back().position[1]);
  });
  if (!ran) return out;
  bool const toppled = drift > 0.1 || lowestTop < 4 * 2 * kStackHalf;
  out.metrics.push_back({"max_drift_m", drift, "m"});
  out.metrics.push_back({"toppled", toppled ? 1.0 : 0.0, "bool"});
  out.metrics.push_back({"min_gap_m", minGap, "m"});
  return out;
}

Outcome RunFastBox(PeerEngine const& engine, double dt) {
  Outcome out;
  std::unique_ptr<World> world = engine.fastBox(dt, out.failure);
  if (!world) return out;
  Pose const plate;  // static, at the origin, unturned
  Vec3 const half{kFastHalf, kFastHalf, kFastHalf};
  double minGap = std::numeric_limits<double>::infinity();
  bool const ran = Run(*world, dt, kFastSeconds, out, [&](int, double) {
    minGap = std::min(minGap, BoxBoxGap(plate, kPlateHalf, world->BoxPose(0), half));
  });
  if (!ran) return out;
  double const finalY = world->BoxPose(0).position[1];
  out.metrics.push_back({"tunnelled", finalY < 0 ? 1.0 : 0.0, "bool"});
  out.metrics.push_back({"max_penetration_m", std::max(0.0, -minGap), "m"});
  out.metrics.push_back({"final_y_m", finalY, "m"});
  return out;
}

/// The note without the CSV's separators.
std::string Clean(std::string text) {
  for (char& c : text)
    if (c == ',' || c == '\n' || c == '"') c = ';';
  return text;
}

bool Print(std::string const& engine, std::string const& scene, double dt, std::string const& note,
           Outcome const& out) {
  double const perSim = out.simSeconds > 0 ? out.stepSeconds / out.simSeconds : 0;
  if (!out.failure.empty() || out.metrics.empty()) {
    std::printf("%s,%s,%.9g,%.6g,failed,1,bool,%s\n", engine.c_str(), scene.c_str(), dt, perSim,
                Clean(note + "; " + out.failure).c_str());
    return false;
  }
  std::vector<Metric> metrics = out.metrics;
  if (out.iterations >= 0 && out.steps > 0)
    metrics.push_back({"iterations_per_step", out.iterations / out.steps, "1"});
  for (Metric const& m : metrics)
    std::printf("%s,%s,%.9g,%.6g,%s,%.6g,%s,%s\n", engine.c_str(), scene.c_str(), dt, perSim,
                m.name.c_str(), m.value, m.unit.c_str(), Clean(note).c_str());
  std::fflush(stdout);
  return true;
}

std::vector<std::string> Split(std::string const& list) {
  std::vector<std::string> parts;
  std::stringstream in(list);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

}  // namespace

int RunPeers(std::vector<PeerEngine> const& engines, int argc, char** argv) {
  std::vector<std::string> rates{"60", "120", "240"}, scenes{"incline", "stack", "fast"};
  bool header = true;
  for (int i = 1; i < argc; ++i) {
    std::string const arg = argv[i];
    if (arg == "--rates" && i + 1 < argc) {
      rates = Split(argv[++i]);
    } else if (arg == "--scenes" && i + 1 < argc) {
      scenes = Split(argv[++i]);
    } else if (arg == "--no-header") {
      header = false;
    } else {
      std::fprintf(stderr,
                   "usage: %s [--rates 60,120,240] [--scenes incline,stack,fast] [--no-header]\n"
                   "prints CSV rows engine,scene,dt,wall_per_sim_s,metric,value,unit,note\n",
                   argv[0]);
      return 2;
    }
  }
  if (header) std::printf("engine,scene,dt,wall_per_sim_s,metric,value,unit,note\n");
  auto const wanted = [&](char const* scene) {
    return std::find(scenes.begin(), scenes.end(), scene) != scenes.end();
  };
  bool ok = true;
  for (PeerEngine const& engine : engines)
    for (std::string const& rate : rates) {
      double const dt = 1.0 / std::stod(rate);
      // a variant without a scene's builder does not run it (bullet-ccd: the fast box only)
      if (wanted("incline") && engine.incline) {
        ok &= Print(engine.name, "incline_stick", dt, engine.note,
                    RunIncline(engine, kStickSlope, dt));
        ok &= Print(engine.name, "incline_slide", dt, engine.note,
                    RunIncline(engine, kSlideSlope, dt));
      }
      if (wanted("stack") && engine.stack)
        ok &= Print(engine.name, "box_stack", dt, engine.note, RunStack(engine, dt));
      if (wanted("fast") && engine.fastBox)
        ok &= Print(engine.name, "fast_box", dt, engine.note, RunFastBox(engine, dt));
    }
  return ok ? 0 : 1;
}

}  // namespace peers
