// Scene families of the perf harness. Each family builds a Scene from a size
// label, a stiffness ratio (multiplying its base stiffness) and the scene
// parameters (solver, integrator, Newton settings), and exposes the points
// the error metric tracks and the scene length L that normalizes it.
//
//   cantilever  tetrahedral beam 1 × 0.2 × 0.2 m, size "NXxNYxNZ" (cells)
//   cloth       pinned shell sheet 1 × 1 m, size "NxN" (quads)
//   chain       rigid boxes joined by spherical joints, size "N=50" (bodies)
//   chain-articulated  the chain's boxes as one articulated actor (exact
//               spherical joints), size "N=50" (links)
//   rods        R discrete elastic rods of N nodes, 1 m, clamped to an
//               anchored rigid plate, size "RxN" (DoFs 4·R·N + 6)
//   contact-cloth   an N × N cloth (0.6 m) dropped on a sphere: it drapes
//               and folds onto itself, size "NxN" (nodes)
//   contact-solids  a stack of K tet cubes of C³ cells, size "KxC"
//   contact-rigid   a stack of N rigid boxes, size "N=5"
//   contact-rods    R rods of N nodes dropped into a bin, size "RxN"
// The contact families are scenes/contact_scenes.h's; their stiffness ratio
// multiplies the barrier stiffness κ (ContactParams::stiffness), not a
// material's.
//
// The parameters of each family are documented in families.cc and in
// perf/harness/README.md.
#pragma once

#include <superdex/superdex.h>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace superdex::perf {

/// A built scene and what the error metric needs of it.
struct FamilyScene {
  std::unique_ptr<Scene> scene;
  real length = 1;  ///< scene length L [m]
  /// World positions of the tracked points (nodes or body centres), in a
  /// fixed order.
  std::function<DynamicArray<Real3>()> trackedPositions;
  /// Mechanisms only (the chain families; empty elsewhere), measured the
  /// same way for every way of modelling the joints, from the link poses:
  /// the largest distance between the two points a joint should hold
  /// together (on the parent and on the child, or on the world) [m] ...
  std::function<real()> jointDrift;
  /// ... and the mechanical energy: kinetic + gravity potential of the links
  /// [J] (without the energy stored in compliant joints).
  std::function<real()> mechanicalEnergy;
  /// The scale of energy_gain: total mass · g · L, more than the links can
  /// ever release falling from rest [J].
  real energyScale = 0;
  /// Contact families only: the bodies that come to rest and should then
  /// stay put — their points, whose drift over the run's second half is the
  /// creep column (empty: nothing should stick).
  std::function<DynamicArray<Real3>()> restingPoints;
  /// Scenes moved by targets (contact-grasp): called before each step with
  /// the times at its start and end [s]; false and `error` when a target is
  /// refused. Empty elsewhere.
  std::function<bool(real from, real to, Error& error)> drive;
};

/// Whether `family` is a contact family (its runs fill the contact columns).
bool IsContactFamily(std::string_view family);

/// The family names, in display order.
std::vector<std::string_view> const& FamilyNames();

/// DoFs of `family` at `size`, or -1 (and `message`) for an unknown family
/// or a malformed size label. Computed from the label, without a scene.
int CountDofs(std::string const& family, std::string const& size, std::string& message);

/// The material label of the CSV ("E=1e5", "k=1e6").
std::string MaterialLabel(std::string const& family, double stiffnessRatio);

/// The family's Newton iteration cap (cloth needs more: its compressed
/// membrane is non-convex, see examples/cloth).
int DefaultNewtonMaxIterations(std::string const& family);

/// Builds the scene; false and `error` on failure (`params` as given).
bool BuildFamilyScene(std::string const& family, std::string const& size, double stiffnessRatio,
                      SceneParams const& params, FamilyScene& out, Error& error);

}  // namespace superdex::perf
