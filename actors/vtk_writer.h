// Output of meshes for ParaView/VisIt: VTK XML UnstructuredGrid files (.vtu),
// ASCII, one per frame, and a .pvd collection listing the frames with their
// times (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html).
//
// Every writer validates its input first (sizes, index ranges, finite
// values, non-empty names) and writes nothing on bad input. The file is
// written next to its destination (".tmp" appended) and renamed over it, so
// a reader never sees a half-written file and a failed call leaves any
// previous file in place.
// Errors: InvalidArgument for bad input (message naming the field and
// value), InvalidState for I/O (message naming the file).
// Numbers are written in shortest round-trip form (std::to_chars): reading
// the file back gives the same doubles bit for bit.
#pragma once

#include <superdex/core/error.h>
#include <superdex/core/types.h>

#include <array>
#include <string>

namespace superdex {

class RodActor;

/// VTK cell type ids.
inline constexpr int kVtkPolyLine = 4;
inline constexpr int kVtkTriangle = 5;
inline constexpr int kVtkTetra = 10;

/// A named data array, `components` values per point (or per cell):
/// values.size() == components · count, point (cell) after point (cell).
/// components = 1 is a scalar, 3 a vector; other counts are allowed.
struct VtkPointData {
  std::string name;
  int components = 1;
  DynamicArray<real> values;
};
/// Same layout, one tuple per cell.
using VtkCellData = VtkPointData;

/// Writes one frame: points, then cells: all `tetrahedra` (VTK_TETRA = 10)
/// first, then all `triangles` (VTK_TRIANGLE = 5), so cell i < tets.size()
/// is tetrahedron i and cell tets.size() + j is triangle j. Either list may
/// be empty. Points must be finite, indices in [0, points.size()), each
/// array's values finite with values.size() == components · points.size(),
/// names non-empty and distinct.
bool WriteVtu(std::string const& path, DynamicArray<Real3> const& points,
              DynamicArray<std::array<int, 4>> const& tetrahedra,
              DynamicArray<std::array<int, 3>> const& triangles,
              DynamicArray<VtkPointData> const& pointData, Error& error);

/// As above, with cell data: each array has components · (tetrahedra.size()
/// + triangles.size()) values, in the cell order above.
bool WriteVtu(std::string const& path, DynamicArray<Real3> const& points,
              DynamicArray<std::array<int, 4>> const& tetrahedra,
              DynamicArray<std::array<int, 3>> const& triangles,
              DynamicArray<VtkPointData> const& pointData,
              DynamicArray<VtkCellData> const& cellData, Error& error);

/// Polylines (rods): one VTK_POLY_LINE = 4 cell per index list, each with at
/// least 2 points, indices in [0, points.size()). Point data as WriteVtu.
bool WriteVtuPolylines(std::string const& path, DynamicArray<Real3> const& points,
                       DynamicArray<DynamicArray<int>> const& polylines,
                       DynamicArray<VtkPointData> const& pointData, Error& error);

/// Rods (RodActor) as polylines: one VTK_POLY_LINE per rod through its nodes'
/// world positions, rods in the given order, and per point: "twist" θ [rad]
/// and the material frame "d1", "d2", "tangent" of the element starting at
/// the node (the last node repeats its rod's last element), "velocity",
/// then the `extra` arrays (values for every point of every rod). Rods must
/// be non-null; otherwise as WriteVtuPolylines.
bool WriteRodsVtu(std::string const& path, DynamicArray<RodActor const*> const& rods,
                  DynamicArray<VtkPointData> const& extra, Error& error);

/// A .pvd collection of frames for a time series:
///
///   VtkSeries series("out/run.pvd");
///   WriteVtu("out/run_0000.vtu", ...);
///   series.AddFrame(time, "run_0000.vtu", error);
///
/// Each AddFrame appends (time, file) and rewrites the whole .pvd, so the
/// listing on disk is complete after every frame (a crashed run still
/// opens). File names are written as given: ParaView resolves a relative
/// name against the .pvd's folder. The .pvd is not written until the first
/// frame.
class VtkSeries {
 public:
  explicit VtkSeries(std::string pvdPath);

  /// Appends a frame and rewrites the .pvd. `time` must be finite,
  /// `vtuFileName` non-empty. On error (bad input: InvalidArgument; the
  /// .pvd cannot be written: InvalidState) the frame is not added.
  bool AddFrame(real time, std::string const& vtuFileName, Error& error);

  std::string const& GetPath() const { return pvdPath_; }
  int GetNumFrames() const { return static_cast<int>(frames_.size()); }

 private:
  struct Frame {
    real time;
    std::string file;
  };
  std::string pvdPath_;
  DynamicArray<Frame> frames_;
};

}  // namespace superdex
