#include <superdex/actors/vtk_writer.h>

#include <superdex/actors/rod_actor.h>
#include <superdex/core/validate.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>

namespace superdex {

namespace {

bool Fail(ErrorCode code, std::string message, Error& error) {
  error.Set(code, std::move(message));
  return false;
}

/// Text for an XML attribute value or element content.
std::string EscapeXml(std::string_view text) {
  std::string s;
  s.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        s += "&amp;";
        break;
      case '<':
        s += "&lt;";
        break;
      case '>':
        s += "&gt;";
        break;
      case '"':
        s += "&quot;";
        break;
      case '\'':
        s += "&apos;";
        break;
      default:
        s += c;
    }
  }
  return s;
}

/// Shortest text that reads back as the same double.
void AppendReal(std::string& out, real value) {
  char buffer[32];
  auto const result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

void AppendInt(std::string& out, long long value) {
  char buffer[24];
  auto const result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.append(buffer, result.ptr);
}

/// Writes `text` to `path` through "<path>.tmp" and a rename.
bool WriteFileAtomically(std::string const& path, std::string const& text, Error& error) {
  std::string const temp = path + ".tmp";
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    if (!out)
      return Fail(ErrorCode::InvalidState,
                  "cannot open '" + temp + "' for writing (" + std::strerror(errno) + ")", error);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::remove(temp.c_str());
      return Fail(ErrorCode::InvalidState, "write error on '" + temp + "'", error);
    }
  }
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    int const code = errno;
    std::remove(temp.c_str());
    return Fail(ErrorCode::InvalidState,
                "cannot rename '" + temp + "' to '" + path + "' (" + std::strerror(code) + ")",
                error);
  }
  return true;
}

bool CheckPoints(DynamicArray<Real3> const& points, Error& error) {
  for (size_t i = 0; i < points.size(); ++i)
    if (!internal::CheckFinite(points[i], "points[" + std::to_string(i) + "]", error)) return false;
  return true;
}

/// Arrays of `count` tuples each, named `kind`Data[i] in messages.
bool CheckData(DynamicArray<VtkPointData> const& arrays, size_t count, char const* kind,
               char const* countName, Error& error) {
  std::set<std::string> names;
  for (size_t a = 0; a < arrays.size(); ++a) {
    VtkPointData const& array = arrays[a];
    std::string const field = std::string(kind) + "[" + std::to_string(a) + "]";
    if (array.name.empty())
      return Fail(ErrorCode::InvalidArgument, field + ".name must not be empty", error);
    if (!names.insert(array.name).second)
      return Fail(ErrorCode::InvalidArgument,
                  field + ".name '" + array.name + "' is used by an earlier array", error);
    if (array.components < 1)
      return Fail(ErrorCode::InvalidArgument,
                  field + " ('" + array.name + "').components must be >= 1, got " +
                      std::to_string(array.components),
                  error);
    size_t const expected = static_cast<size_t>(array.components) * count;
    if (array.values.size() != expected)
      return Fail(ErrorCode::InvalidArgument,
                  field + " ('" + array.name + "').values has " +
                      std::to_string(array.values.size()) + " entries, expected components · " +
                      countName + " = " + std::to_string(array.components) + " · " +
                      std::to_string(count) + " = " + std::to_string(expected),
                  error);
    for (size_t i = 0; i < array.values.size(); ++i)
      if (!std::isfinite(array.values[i]))
        return Fail(ErrorCode::InvalidArgument,
                    field + " ('" + array.name + "').values[" + std::to_string(i) +
                        "] must be finite, got " + internal::Format(array.values[i]),
                    error);
  }
  return true;
}

template <class Cell>
bool CheckCells(DynamicArray<Cell> const& cells, size_t numPoints, char const* name, Error& error) {
  for (size_t c = 0; c < cells.size(); ++c)
    for (size_t k = 0; k < cells[c].size(); ++k)
      if (cells[c][k] < 0 || static_cast<size_t>(cells[c][k]) >= numPoints)
        return Fail(ErrorCode::InvalidArgument,
                    std::string(name) + "[" + std::to_string(c) + "][" + std::to_string(k) +
                        "] = " + std::to_string(cells[c][k]) + " is out of range [0, " +
                        std::to_string(numPoints) + ")",
                    error);
  return true;
}

/// <PointData>/<CellData> with its arrays; the first scalar and the first
/// 3-vector are marked as the active ones.
void AppendData(std::string& out, char const* tag, DynamicArray<VtkPointData> const& arrays) {
  if (arrays.empty()) return;
  out += "      <";
  out += tag;
  for (auto const& [attribute, components] : {std::pair{"Scalars", 1}, std::pair{"Vectors", 3}})
    for (VtkPointData const& array : arrays)
      if (array.components == components) {
        out += std::string(" ") + attribute + "=\"" + EscapeXml(array.name) + "\"";
        break;
      }
  out += ">\n";
  for (VtkPointData const& array : arrays) {
    out += "        <DataArray type=\"Float64\" Name=\"" + EscapeXml(array.name) +
           "\" NumberOfComponents=\"" + std::to_string(array.components) + "\" format=\"ascii\">\n";
    for (size_t i = 0; i < array.values.size(); i += array.components) {
      out += "         ";
      for (int c = 0; c < array.components; ++c) {
        out += ' ';
        AppendReal(out, array.values[i + c]);
      }
      out += '\n';
    }
    out += "        </DataArray>\n";
  }
  out += "      </";
  out += tag;
  out += ">\n";
}

/// The whole .vtu. `cells` calls back with (emit) for each cell's node list
/// and type, in order.
template <class ForEachCell>
std::string VtuText(DynamicArray<Real3> const& points, size_t numCells, ForEachCell forEachCell,
                    DynamicArray<VtkPointData> const& pointData,
                    DynamicArray<VtkCellData> const& cellData) {
  std::string out;
  out.reserve(64 * points.size() + 48 * numCells + 1024);
  out +=
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <UnstructuredGrid>\n"
      "    <Piece NumberOfPoints=\"" +
      std::to_string(points.size()) + "\" NumberOfCells=\"" + std::to_string(numCells) + "\">\n";
  AppendData(out, "PointData", pointData);
  AppendData(out, "CellData", cellData);
  out +=
      "      <Points>\n"
      "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Real3 const& x : points) {
    out += "         ";
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      AppendReal(out, x[c]);
    }
    out += '\n';
  }
  out +=
      "        </DataArray>\n"
      "      </Points>\n"
      "      <Cells>\n"
      "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  std::string offsets, types;
  long long offset = 0;
  forEachCell([&](auto const& nodes, int type) {
    out += "         ";
    for (int n : nodes) {
      out += ' ';
      AppendInt(out, n);
    }
    out += '\n';
    offset += static_cast<long long>(nodes.size());
    offsets += ' ';
    AppendInt(offsets, offset);
    types += ' ';
    AppendInt(types, type);
  });
  out +=
      "        </DataArray>\n"
      "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n         " +
      offsets +
      "\n        </DataArray>\n"
      "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n         " +
      types +
      "\n        </DataArray>\n"
      "      </Cells>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n"
      "</VTKFile>\n";
  return out;
}

}  // namespace

bool WriteVtu(std::string const& path, DynamicArray<Real3> const& points,
              DynamicArray<std::array<int, 4>> const& tetrahedra,
              DynamicArray<std::array<int, 3>> const& triangles,
              DynamicArray<VtkPointData> const& pointData, Error& error) {
  return WriteVtu(path, points, tetrahedra, triangles, pointData, {}, error);
}

bool WriteVtu(std::string const& path, DynamicArray<Real3> const& points,
              DynamicArray<std::array<int, 4>> const& tetrahedra,
              DynamicArray<std::array<int, 3>> const& triangles,
              DynamicArray<VtkPointData> const& pointData,
              DynamicArray<VtkCellData> const& cellData, Error& error) {
  size_t const numCells = tetrahedra.size() + triangles.size();
  if (path.empty()) return Fail(ErrorCode::InvalidArgument, "path must not be empty", error);
  if (!CheckPoints(points, error) || !CheckCells(tetrahedra, points.size(), "tetrahedra", error) ||
      !CheckCells(triangles, points.size(), "triangles", error) ||
      !CheckData(pointData, points.size(), "pointData", "points", error) ||
      !CheckData(cellData, numCells, "cellData", "cells", error))
    return false;
  auto const forEachCell = [&](auto&& emit) {
    for (auto const& tet : tetrahedra) emit(tet, kVtkTetra);
    for (auto const& triangle : triangles) emit(triangle, kVtkTriangle);
  };
  return WriteFileAtomically(path, VtuText(points, numCells, forEachCell, pointData, cellData),
                             error);
}

bool WriteVtuPolylines(std::string const& path, DynamicArray<Real3> const& points,
                       DynamicArray<DynamicArray<int>> const& polylines,
                       DynamicArray<VtkPointData> const& pointData, Error& error) {
  if (path.empty()) return Fail(ErrorCode::InvalidArgument, "path must not be empty", error);
  for (size_t p = 0; p < polylines.size(); ++p)
    if (polylines[p].size() < 2)
      return Fail(ErrorCode::InvalidArgument,
                  "polylines[" + std::to_string(p) + "] has " +
                      std::to_string(polylines[p].size()) + " points, expected at least 2",
                  error);
  if (!CheckPoints(points, error) || !CheckCells(polylines, points.size(), "polylines", error) ||
      !CheckData(pointData, points.size(), "pointData", "points", error))
    return false;
  auto const forEachCell = [&](auto&& emit) {
    for (auto const& polyline : polylines) emit(polyline, kVtkPolyLine);
  };
  return WriteFileAtomically(path, VtuText(points, polylines.size(), forEachCell, pointData, {}),
                             error);
}

bool WriteRodsVtu(std::string const& path, DynamicArray<RodActor const*> const& rods,
                  DynamicArray<VtkPointData> const& extra, Error& error) {
  DynamicArray<Real3> points;
  DynamicArray<DynamicArray<int>> polylines;
  DynamicArray<VtkPointData> data{{"twist", 1, {}}, {"d1", 3, {}}, {"d2", 3, {}}, {"tangent", 3, {}},
                                  {"velocity", 3, {}}};
  for (std::size_t r = 0; r < rods.size(); ++r) {
    RodActor const* rod = rods[r];
    if (!rod) return Fail(ErrorCode::InvalidArgument, "rods[" + std::to_string(r) + "] is null", error);
    DynamicArray<int>& line = polylines.emplace_back();
    for (int i = 0; i < rod->GetNumNodes(); ++i) {
      int const element = std::min(i, rod->GetNumElements() - 1);
      Real33 const frame = rod->GetMaterialFrame(element);
      line.push_back(static_cast<int>(points.size()));
      points.push_back(rod->GetNodePosition(i));
      data[0].values.push_back(rod->GetTwist(element));
      for (int column = 0; column < 3; ++column)
        for (int k = 0; k < 3; ++k) data[1 + column].values.push_back(frame(k, column));
      Real3 const v = rod->GetNodeVelocity(i);
      data[4].values.insert(data[4].values.end(), v.data(), v.data() + 3);
    }
  }
  data.insert(data.end(), extra.begin(), extra.end());
  return WriteVtuPolylines(path, points, polylines, data, error);
}

VtkSeries::VtkSeries(std::string pvdPath) : pvdPath_(std::move(pvdPath)) {}

bool VtkSeries::AddFrame(real time, std::string const& vtuFileName, Error& error) {
  if (!internal::CheckFinite(time, "time", error)) return false;
  if (vtuFileName.empty())
    return Fail(ErrorCode::InvalidArgument, "vtuFileName must not be empty", error);
  if (pvdPath_.empty())
    return Fail(ErrorCode::InvalidArgument, "the series' .pvd path is empty", error);
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  auto const appendFrame = [&out](real t, std::string const& file) {
    out += "    <DataSet timestep=\"";
    AppendReal(out, t);
    out += "\" group=\"\" part=\"0\" file=\"" + EscapeXml(file) + "\"/>\n";
  };
  for (Frame const& frame : frames_) appendFrame(frame.time, frame.file);
  appendFrame(time, vtuFileName);
  out +=
      "  </Collection>\n"
      "</VTKFile>\n";
  if (!WriteFileAtomically(pvdPath_, out, error)) return false;
  frames_.push_back({time, vtuFileName});
  return true;
}

}  // namespace superdex
