// VTK output: a .vtu of tets + triangles with point and cell data, polylines,
// and a .pvd series, parsed back with a minimal XML reader; bad input is
// rejected and writes nothing.
#include <superdex/actors/mesh.h>
#include <superdex/actors/vtk_writer.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>

#include "test_support.h"

using namespace superdex;
using namespace superdex::test;
namespace fs = std::filesystem;

namespace {

/// A fresh folder for this test executable's files; removed at exit.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("superdex_vtk_test_" + std::to_string(getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(std::string const& name) const { return (path / name).string(); }
};

std::string ReadText(std::string const& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The value of attribute `name` in the first tag `<tag ...>` of `xml`.
std::string Attribute(std::string const& xml, std::string const& tag, std::string const& name) {
  std::smatch m;
  std::regex const tagRe("<" + tag + "\\b[^>]*>");
  REQUIRE(std::regex_search(xml, m, tagRe));
  std::string const element = m.str();
  std::regex const attrRe("\\b" + name + "=\"([^\"]*)\"");
  REQUIRE(std::regex_search(element, m, attrRe));
  return m[1].str();
}

/// The numbers inside `<DataArray ... Name="name" ...> ... </DataArray>`
/// within `section` (e.g. "Cells", "PointData"), and its attributes.
struct Array {
  std::string type;
  int components = 1;
  std::vector<double> values;
};

Array FindArray(std::string const& xml, std::string const& section, std::string const& name) {
  std::smatch m;
  std::regex const sectionRe("<" + section + "\\b[^>]*>([\\s\\S]*?)</" + section + ">");
  REQUIRE(std::regex_search(xml, m, sectionRe));
  std::string const body = m[1].str();
  std::regex const arrayRe("<DataArray\\b([^>]*)>([\\s\\S]*?)</DataArray>");
  for (auto it = std::sregex_iterator(body.begin(), body.end(), arrayRe);
       it != std::sregex_iterator(); ++it) {
    std::string const attributes = (*it)[1].str();
    std::smatch a;
    bool const named = std::regex_search(attributes, a, std::regex("\\bName=\"([^\"]*)\""));
    if (name.empty() ? named : !(named && a[1].str() == name)) continue;
    Array array;
    REQUIRE(std::regex_search(attributes, a, std::regex("\\btype=\"([^\"]*)\"")));
    array.type = a[1].str();
    if (std::regex_search(attributes, a, std::regex("\\bNumberOfComponents=\"([0-9]+)\"")))
      array.components = std::stoi(a[1].str());
    REQUIRE(attributes.find("format=\"ascii\"") != std::string::npos);
    std::istringstream numbers((*it)[2].str());
    std::string token;
    while (numbers >> token) array.values.push_back(std::strtod(token.c_str(), nullptr));
    return array;
  }
  FAIL("no DataArray '" << name << "' in <" << section << ">");
  return {};
}

std::vector<double> Flatten(DynamicArray<Real3> const& points) {
  std::vector<double> v;
  for (Real3 const& x : points) v.insert(v.end(), {x.x(), x.y(), x.z()});
  return v;
}

}  // namespace

TEST_CASE("WriteVtu: tets and triangles with point and cell data read back exactly",
          "[actors][vtk][io]") {
  TempDir dir;
  TetMesh box;
  Error error;
  REQUIRE(MakeTetBox(Real3(0.1, -0.2, 0.3), Real3(1.0 / 3, 1, 0.7), {2, 1, 1}, box, error));
  DynamicArray<std::array<int, 3>> const triangles = {{0, 3, 4}, {0, 4, 1}};  // a bottom quad
  int const numPoints = int(box.nodes.size()), numTets = int(box.tetrahedra.size());
  int const numCells = numTets + 2;

  VtkPointData displacement{"displacement", 3, {}}, temperature{"temperature", 1, {}};
  for (int i = 0; i < numPoints; ++i) {
    displacement.values.insert(displacement.values.end(), {0.1 * i, -1e-17 * i, 1.0 / (i + 3)});
    temperature.values.push_back(273.15 + i / 7.0);
  }
  VtkCellData volume{"volume", 1, {}};
  for (int t = 0; t < numTets; ++t) volume.values.push_back(SignedVolume(box, t));
  volume.values.insert(volume.values.end(), {0, 0});

  std::string const path = dir / "frame.vtu";
  bool const ok = WriteVtu(path, box.nodes, box.tetrahedra, triangles, {displacement, temperature},
                           {volume}, error);
  INFO(error.ToString());
  REQUIRE(ok);
  REQUIRE_FALSE(fs::exists(path + ".tmp"));
  std::string const xml = ReadText(path);
  REQUIRE(xml.starts_with("<?xml version=\"1.0\"?>"));
  REQUIRE(Attribute(xml, "VTKFile", "type") == "UnstructuredGrid");
  REQUIRE(Attribute(xml, "Piece", "NumberOfPoints") == std::to_string(numPoints));
  REQUIRE(Attribute(xml, "Piece", "NumberOfCells") == std::to_string(numCells));
  REQUIRE(Attribute(xml, "PointData", "Scalars") == "temperature");
  REQUIRE(Attribute(xml, "PointData", "Vectors") == "displacement");

  Array const points = FindArray(xml, "Points", "");
  REQUIRE(points.components == 3);
  REQUIRE(points.values == Flatten(box.nodes));  // bit for bit

  Array const connectivity = FindArray(xml, "Cells", "connectivity");
  Array const offsets = FindArray(xml, "Cells", "offsets");
  Array const types = FindArray(xml, "Cells", "types");
  std::vector<double> expectedConnectivity, expectedOffsets, expectedTypes;
  for (auto const& tet : box.tetrahedra) {
    expectedConnectivity.insert(expectedConnectivity.end(), tet.begin(), tet.end());
    expectedOffsets.push_back(double(expectedConnectivity.size()));
    expectedTypes.push_back(kVtkTetra);
  }
  for (auto const& triangle : triangles) {
    expectedConnectivity.insert(expectedConnectivity.end(), triangle.begin(), triangle.end());
    expectedOffsets.push_back(double(expectedConnectivity.size()));
    expectedTypes.push_back(kVtkTriangle);
  }
  REQUIRE(connectivity.values == expectedConnectivity);
  REQUIRE(offsets.values == expectedOffsets);
  REQUIRE(offsets.values.back() == 4 * numTets + 3 * 2);
  REQUIRE(types.values == expectedTypes);
  REQUIRE(types.type == "UInt8");

  Array const d = FindArray(xml, "PointData", "displacement");
  REQUIRE(d.components == 3);
  REQUIRE(d.values == std::vector<double>(displacement.values.begin(), displacement.values.end()));
  Array const t = FindArray(xml, "PointData", "temperature");
  REQUIRE(t.components == 1);
  REQUIRE(t.values == std::vector<double>(temperature.values.begin(), temperature.values.end()));
  Array const v = FindArray(xml, "CellData", "volume");
  REQUIRE(v.values.size() == size_t(numCells));
  REQUIRE(v.values == std::vector<double>(volume.values.begin(), volume.values.end()));
}

TEST_CASE("WriteVtu: tets only, no data, and the 5-argument form", "[actors][vtk][io]") {
  TempDir dir;
  TetMesh box;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3::Ones(), {1, 1, 1}, box, error));
  std::string const path = dir / "tets.vtu";
  REQUIRE(WriteVtu(path, box.nodes, box.tetrahedra, {}, {}, error));
  std::string const xml = ReadText(path);
  REQUIRE(Attribute(xml, "Piece", "NumberOfCells") == "6");
  REQUIRE(xml.find("<PointData") == std::string::npos);
  REQUIRE(xml.find("<CellData") == std::string::npos);
  REQUIRE(FindArray(xml, "Cells", "types").values == std::vector<double>(6, kVtkTetra));
}

TEST_CASE("WriteVtuPolylines: one VTK_POLY_LINE per index list", "[actors][vtk][io]") {
  TempDir dir;
  DynamicArray<Real3> const points = {Real3(0, 0, 0), Real3(1, 0, 0), Real3(2, 0, 0),
                                      Real3(0, 1, 0), Real3(0, 2, 0)};
  DynamicArray<DynamicArray<int>> const polylines = {{0, 1, 2}, {0, 3, 4}};
  VtkPointData twist{"twist", 1, {0, 0.1, 0.2, 0.3, 0.4}};
  std::string const path = dir / "rods.vtu";
  Error error;
  REQUIRE(WriteVtuPolylines(path, points, polylines, {twist}, error));
  std::string const xml = ReadText(path);
  REQUIRE(Attribute(xml, "Piece", "NumberOfPoints") == "5");
  REQUIRE(Attribute(xml, "Piece", "NumberOfCells") == "2");
  REQUIRE(FindArray(xml, "Cells", "connectivity").values == std::vector<double>{0, 1, 2, 0, 3, 4});
  REQUIRE(FindArray(xml, "Cells", "offsets").values == std::vector<double>{3, 6});
  REQUIRE(FindArray(xml, "Cells", "types").values ==
          std::vector<double>{kVtkPolyLine, kVtkPolyLine});
  REQUIRE(FindArray(xml, "PointData", "twist").values ==
          std::vector<double>(twist.values.begin(), twist.values.end()));

  // a polyline needs two points; bad input writes nothing
  std::string const bad = dir / "bad_rods.vtu";
  REQUIRE_FALSE(WriteVtuPolylines(bad, points, {{0, 1}, {3}}, {}, error));
  REQUIRE(Mentions(error, "polylines[1] has 1 points, expected at least 2"));
  REQUIRE_FALSE(WriteVtuPolylines(bad, points, {{0, 5}}, {}, error));
  REQUIRE(Mentions(error, "polylines[0][1] = 5 is out of range [0, 5)"));
  REQUIRE_FALSE(fs::exists(bad));
}

TEST_CASE("WriteRodsVtu: each rod a polyline with its twist and material frame as point data",
          "[actors][vtk][io][rod]") {
  TempDir dir;
  auto scene = MakeScene();
  Error error;
  RodActorParams p;
  p.nodes = {Real3(0, 0, 0), Real3(0.1, 0, 0), Real3(0.2, 0.05, 0)};
  p.materialDirector = Real3(0, 0, 1);
  RodActor* a = scene->CreateRodActor(p, error);
  p.nodes = {Real3(0, 1, 0), Real3(0, 1, 0.2)};
  p.materialDirector = Real3(1, 0, 0);
  RodActor* b = scene->CreateRodActor(p, error);
  REQUIRE(a);
  REQUIRE(b);
  std::string const path = dir / "rods.vtu";
  VtkPointData const extra{"id", 1, {0, 0, 0, 1, 1}};
  REQUIRE(WriteRodsVtu(path, {a, b}, {extra}, error));
  std::string const xml = ReadText(path);
  REQUIRE(Attribute(xml, "Piece", "NumberOfPoints") == "5");
  REQUIRE(FindArray(xml, "Cells", "connectivity").values == std::vector<double>{0, 1, 2, 3, 4});
  REQUIRE(FindArray(xml, "Cells", "types").values == std::vector<double>{kVtkPolyLine, kVtkPolyLine});
  REQUIRE(FindArray(xml, "Points", "").values ==
          Flatten({a->GetNodePosition(0), a->GetNodePosition(1), a->GetNodePosition(2), b->GetNodePosition(0),
                   b->GetNodePosition(1)}));
  REQUIRE(FindArray(xml, "PointData", "twist").values == std::vector<double>(5, 0.0));
  // node i carries element min(i, last)'s frame; rod a's first element is
  // along x with d1 = z, rod b's along z with d1 = x
  std::vector<double> const d1 = FindArray(xml, "PointData", "d1").values;
  std::vector<double> const tangent = FindArray(xml, "PointData", "tangent").values;
  REQUIRE(d1.size() == 15);
  for (int i = 0; i < 5; ++i) {
    RodActor const* rod = i < 3 ? a : b;
    int const element = std::min(i < 3 ? i : i - 3, rod->GetNumElements() - 1);
    Real33 const frame = rod->GetMaterialFrame(element);
    for (int k = 0; k < 3; ++k) {
      REQUIRE(d1[3 * i + k] == frame(k, 0));
      REQUIRE(tangent[3 * i + k] == frame(k, 2));
    }
  }
  REQUIRE(d1[2] == 1.0);
  REQUIRE(d1[9] == 1.0);
  REQUIRE(FindArray(xml, "PointData", "id").values == std::vector<double>{0, 0, 0, 1, 1});
  // a null rod, or extra data of the wrong size: nothing written
  std::string const bad = dir / "bad.vtu";
  REQUIRE_FALSE(WriteRodsVtu(bad, {a, nullptr}, {}, error));
  REQUIRE(Mentions(error, "rods[1] is null"));
  REQUIRE_FALSE(WriteRodsVtu(bad, {a}, {extra}, error));
  REQUIRE_FALSE(fs::exists(bad));
}

TEST_CASE("WriteVtu rejects bad input, writes nothing and keeps an earlier file",
          "[actors][vtk][input]") {
  TempDir dir;
  DynamicArray<Real3> points = {Real3(0, 0, 0), Real3(1, 0, 0), Real3(0, 1, 0), Real3(0, 0, 1)};
  DynamicArray<std::array<int, 4>> tets = {{0, 1, 2, 3}};
  DynamicArray<std::array<int, 3>> triangles = {{0, 2, 1}};
  DynamicArray<VtkPointData> data = {{"speed", 1, {1, 2, 3, 4}}};
  DynamicArray<VtkCellData> cellData;
  std::string const path = dir / "frame.vtu";
  Error error;
  REQUIRE(WriteVtu(path, points, tets, triangles, data, error));
  std::string const before = ReadText(path);

  // each case's input is refused with its message, and the file stays
  // as it was (checked inside each SECTION: a section checks what it sets up)
  auto const refused = [&](std::string const& expected) {
    REQUIRE_FALSE(WriteVtu(path, points, tets, triangles, data, cellData, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    CAPTURE(error.GetMessage());
    REQUIRE(Mentions(error, expected));
    REQUIRE(ReadText(path) == before);
    REQUIRE_FALSE(fs::exists(path + ".tmp"));
  };
  SECTION("tet index out of range") {
    tets[0][3] = 4;
    refused("tetrahedra[0][3] = 4 is out of range [0, 4)");
  }
  SECTION("triangle index negative") {
    triangles[0][1] = -1;
    refused("triangles[0][1] = -1 is out of range");
  }
  SECTION("non-finite point") {
    points[2].z() = std::numeric_limits<real>::infinity();
    refused("points[2] must be finite");
  }
  SECTION("wrong data size") {
    data[0].components = 3;
    refused("pointData[0] ('speed').values has 4 entries, expected components · points = 3 · 4 = 12");
  }
  SECTION("non-finite data") {
    data[0].values[1] = std::numeric_limits<real>::quiet_NaN();
    refused("pointData[0] ('speed').values[1] must be finite");
  }
  SECTION("repeated name") {
    data.push_back({"speed", 1, {0, 0, 0, 0}});
    refused("pointData[1].name 'speed' is used by an earlier array");
  }
  SECTION("empty name") {
    data[0].name.clear();
    refused("pointData[0].name must not be empty");
  }
  SECTION("cell data size") {
    cellData.push_back({"volume", 1, {1}});
    refused("cellData[0] ('volume').values has 1 entries, expected components · cells = 1 · 2 = 2");
  }
}

TEST_CASE("WriteVtu into a missing folder is an I/O error naming the file",
          "[actors][vtk][input]") {
  TempDir dir;
  std::string const path = dir / "no_such_folder/frame.vtu";
  Error error;
  REQUIRE_FALSE(WriteVtu(path, {Real3::Zero()}, {}, {}, {}, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidState);
  REQUIRE(Mentions(error, path));
}

TEST_CASE("VtkSeries: the .pvd lists every frame so far", "[actors][vtk][io]") {
  TempDir dir;
  std::string const pvd = dir / "run.pvd";
  VtkSeries series(pvd);
  REQUIRE(series.GetPath() == pvd);
  REQUIRE_FALSE(fs::exists(pvd));  // nothing until the first frame
  TetMesh box;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3::Ones(), {1, 1, 1}, box, error));
  real const times[] = {0, 0.1, 0.30000000000000004};
  for (int f = 0; f < 3; ++f) {
    std::string const name = "run_000" + std::to_string(f) + ".vtu";
    REQUIRE(WriteVtu(dir / name, box.nodes, box.tetrahedra, {}, {}, error));
    REQUIRE(series.AddFrame(times[f], name, error));
    REQUIRE(series.GetNumFrames() == f + 1);
    // rewritten after every frame: parse what is on disk now
    std::string const xml = ReadText(pvd);
    REQUIRE(Attribute(xml, "VTKFile", "type") == "Collection");
    std::regex const dataSet(
        "<DataSet\\b[^>]*\\btimestep=\"([^\"]*)\"[^>]*\\bfile=\"([^\"]*)\"[^>]*/>");
    std::vector<std::pair<double, std::string>> listed;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), dataSet);
         it != std::sregex_iterator(); ++it)
      listed.push_back({std::strtod((*it)[1].str().c_str(), nullptr), (*it)[2].str()});
    REQUIRE(listed.size() == size_t(f + 1));
    for (int g = 0; g <= f; ++g) {
      REQUIRE(listed[g].first == times[g]);  // exact round trip
      REQUIRE(listed[g].second == "run_000" + std::to_string(g) + ".vtu");
      REQUIRE(fs::exists(dir / listed[g].second));  // relative to the .pvd's folder
    }
  }
  // bad frames are not added
  std::string const before = ReadText(pvd);
  REQUIRE_FALSE(series.AddFrame(std::numeric_limits<real>::quiet_NaN(), "x.vtu", error));
  REQUIRE(Mentions(error, "time"));
  REQUIRE_FALSE(series.AddFrame(1, "", error));
  REQUIRE(Mentions(error, "vtuFileName"));
  REQUIRE(series.GetNumFrames() == 3);
  REQUIRE(ReadText(pvd) == before);
  // names are XML-escaped
  REQUIRE(series.AddFrame(1, "a&b\"<c>.vtu", error));
  REQUIRE(ReadText(pvd).find("file=\"a&amp;b&quot;&lt;c&gt;.vtu\"") != std::string::npos);
  // an unwritable .pvd: InvalidState, frame not added
  VtkSeries lost(dir / "no_such_folder/run.pvd");
  REQUIRE_FALSE(lost.AddFrame(0, "run_0000.vtu", error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidState);
  REQUIRE(lost.GetNumFrames() == 0);
}
