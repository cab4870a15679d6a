// The rigid contact scenes of scenes/contact_scenes.h, described once for
// every engine that perf/peers runs them in (README.md), and the driver that
// steps them and measures them the same way whatever the engine.
//
// An engine program supplies a PeerEngine: for each scene a World that holds
// the scene at a time step and answers the poses of its boxes. The driver
// (peer_scenes.cc) times the stepping loop only, reads the poses after every
// step and prints the metrics as CSV rows. Every number of the scenes lives
// here so that no engine can drift from SuperDex's builders: the gaps at the
// start are SuperDex's (0.5 d̂ and 0.9 d̂ with d̂ = 1 mm), so all engines
// start from the same positions.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace peers {

using Vec3 = std::array<double, 3>;
/// Row-major rotation matrix: R[i][j], column j is the body's axis j in the world.
using Mat3 = std::array<Vec3, 3>;

inline constexpr Mat3 kIdentity{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

struct Pose {
  Vec3 position{};
  Mat3 rotation = kIdentity;
};

/// R_z(angle) as a matrix.
Mat3 RotationZ(double angle);
/// The rotation of a unit quaternion (w, x, y, z).
Mat3 FromQuaternion(double w, double x, double y, double z);

// ---- the scenes (scenes/contact_scenes.cc) ----
inline constexpr double kGravity = 9.81;  ///< along −y
inline constexpr double kFriction = 0.5;  ///< μ of every collider
inline constexpr double kActivation =
    1e-3;  ///< SuperDex's default d̂: the starting gaps below are its fractions

// 1. A 0.2 m, 1 kg box on a plane through the origin tilted by θ about z,
// its centre at n·(0.1 + 0.5 d̂), turned by the same tilt.
inline constexpr double kInclineHalf = 0.1;
inline constexpr double kInclineGap = 0.5 * kActivation;
inline constexpr double kStickSlope = 0.49;  ///< tan θ below μ: must stick
inline constexpr double kSlideSlope = 0.51;  ///< tan θ above μ: slides at g (sin θ − μ cos θ)
inline constexpr double kInclineSeconds = 5;

// 2. Five 0.2 m, 1 kg boxes on the ground y = 0, box i's centre at
// gap + half + i (2 half + gap), gap = 0.9 d̂.
inline constexpr int kStackCount = 5;
inline constexpr double kStackHalf = 0.1;
inline constexpr double kStackGap = 0.9 * kActivation;
inline constexpr double kStackSeconds = 10;
/// Centre height of stack box i at the start.
inline double StackHeight(int i) {
  return kStackGap + kStackHalf + i * (2 * kStackHalf + kStackGap);
}

// 3. A static plate of half extents (1, 0.0025, 1) at the origin; a 0.1 m,
// 1 kg box at (0, 0.3, 0) moving at (0, −20, 0).
inline constexpr Vec3 kPlateHalf{1, 0.0025, 1};
inline constexpr double kFastHalf = 0.05;
inline constexpr double kFastHeight = 0.3;
inline constexpr double kFastSpeed = 20;
inline constexpr double kFastSeconds = 0.5;

/// A solid box's principal inertia (mass m, half extents h).
Vec3 BoxInertia(double mass, Vec3 const& half);

/// One engine's scene at one time step.
class World {
 public:
  virtual ~World() = default;
  /// Advances by the step the world was built with; false (and `why`) when
  /// the engine refuses the step.
  virtual bool Step(std::string& why) = 0;
  /// The pose of dynamic box `i` (creation order: the stack from the bottom).
  virtual Pose BoxPose(int i) const = 0;
  /// The solver iterations of the last step, for an engine whose solver
  /// runs to a tolerance (SuperDex's Newton, MuJoCo's); −1: a fixed count
  /// or a direct solve, not reported.
  virtual double LastIterations() const { return -1; }
};

/// What an engine program runs: one or more variants (a row each), each
/// building the three scenes. A builder returns null and `why` when it
/// fails; a variant without a builder for a scene does not run that scene.
struct PeerEngine {
  std::string name;  ///< the CSV's engine column
  std::string note;  ///< its settings, in the CSV's note column
  std::function<std::unique_ptr<World>(double tanTheta, double dt, std::string& why)> incline;
  std::function<std::unique_ptr<World>(double dt, std::string& why)> stack;
  std::function<std::unique_ptr<World>(double dt, std::string& why)> fastBox;
};

/// Parses the command line (--rates 60,240 [--scenes incline,stack,fast]
/// [--no-header]), runs every scene of every engine at each dt = 1/rate and
/// prints the CSV rows on stdout; returns the exit status (1 when a scene
/// failed to build or step: its rows are printed with the failure in the
/// note).
int RunPeers(std::vector<PeerEngine> const& engines, int argc, char** argv);

}  // namespace peers
