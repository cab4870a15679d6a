// Output of the example programs: the results folder, CSV files, and one
// VTK frame of a deformable actor with its standard node arrays.
#pragma once

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include <superdex/superdex.h>

#include "command_line.h"

namespace superdex::examples {

/// Creates the folder of `path` (and its parents) and opens `path` for
/// writing; fails the program when either is impossible.
inline std::FILE* OpenOutputFile(std::filesystem::path const& path) {
  std::error_code fsError;
  std::filesystem::create_directories(path.parent_path(), fsError);
  if (fsError) Fail("cannot create '" + path.parent_path().string() + "': " + fsError.message());
  std::FILE* file = std::fopen(path.string().c_str(), "w");
  if (!file) Fail("cannot write '" + path.string() + "'");
  return file;
}

/// One .vtu of `actor`: world positions, its tets and triangles, and per node
/// the displacement (magnitude and vector) and the velocity, followed by
/// `extra` arrays. Fails the program on error.
inline void WriteDeformableVtu(DeformableActor const& actor, std::string const& path,
                               DynamicArray<VtkPointData> extra = {}) {
  int const n = actor.GetNumNodes();
  DynamicArray<VtkPointData> pointData(3);
  pointData[0].name = "displacement_magnitude";
  pointData[1].name = "displacement";
  pointData[1].components = 3;
  pointData[2].name = "velocity";
  pointData[2].components = 3;
  for (auto& array : pointData) array.values.resize(static_cast<std::size_t>(array.components * n));
  for (int i = 0; i < n; ++i) {
    Real3 const u = actor.GetNodeDisplacement(i), v = actor.GetNodeVelocity(i);
    pointData[0].values[i] = u.norm();
    for (int k = 0; k < 3; ++k) {
      pointData[1].values[3 * i + k] = u[k];
      pointData[2].values[3 * i + k] = v[k];
    }
  }
  for (auto& array : extra) pointData.push_back(std::move(array));
  Error error;
  if (!WriteVtu(path, actor.GetNodePositions(), actor.GetTetrahedra(), actor.GetTriangles(), pointData, error))
    Fail("WriteVtu", error);
}

/// One step of `scene`, its wall time added to `seconds`; on failure closes
/// `file` (when given) and fails the program naming the step and the time.
inline void TimedStep(Scene& scene, real dt, int stepNumber, double& seconds, std::FILE* file = nullptr) {
  Error error;
  auto const start = std::chrono::steady_clock::now();
  bool const ok = scene.Step(dt, error);
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (ok) return;
  if (file) std::fclose(file);
  char where[96];
  std::snprintf(where, sizeof where, "Scene::Step failed at step %d (t = %.6f s)", stepNumber,
                static_cast<double>(scene.GetTime()));
  Fail(where, error);
}

}  // namespace superdex::examples
