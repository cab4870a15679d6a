// Mesh builders (counts, orientation, volume, conformity), hinges, readers
// (the same cube from every format; every malformed file rejected with the
// file name and line number, the mesh unchanged) and structural validation.
#include <superdex/actors/mesh.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "test_support.h"

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kNaN = std::numeric_limits<real>::quiet_NaN();
constexpr real kInf = std::numeric_limits<real>::infinity();

/// A test input: in tests/actors/data, or (the Gmsh and OBJ files the
/// fuzzers also start from, kept once) in tests/fuzz/corpus/gmsh or obj.
std::string Data(std::string const& name) {
  std::string const here = std::string(SUPERDEX_TEST_DATA_DIR) + "/" + name;
  if (std::filesystem::exists(here)) return here;
  std::string const corpus = name.ends_with(".msh") ? "gmsh" : name.ends_with(".obj") ? "obj" : "";
  return corpus.empty() ? here : std::string(SUPERDEX_FUZZ_CORPUS_DIR) + "/" + corpus + "/" + name;
}

bool Same(TetMesh const& a, TetMesh const& b) {
  return a.nodes == b.nodes && a.tetrahedra == b.tetrahedra;
}
bool Same(TriangleMesh const& a, TriangleMesh const& b) {
  return a.nodes == b.nodes && a.triangles == b.triangles;
}

/// A mesh that no reader produces, to check that a failed call leaves its
/// output alone.
TetMesh SentinelTets() {
  return {{Real3(7, 8, 9), Real3(1, 2, 3)}, {{0, 1, 1, 0}}};
}
TriangleMesh SentinelTriangles() {
  return {{Real3(7, 8, 9)}, {{0, 0, 0}}};
}

/// (x_b − x_a) × (x_c − x_a)
Real3 Normal(TriangleMesh const& mesh, std::array<int, 3> const& t) {
  return (mesh.nodes[t[1]] - mesh.nodes[t[0]]).cross(mesh.nodes[t[2]] - mesh.nodes[t[0]]);
}

/// True when (a, b, c) is a cyclic rotation of `t` (same orientation).
bool SameCycle(std::array<int, 3> const& t, int a, int b, int c) {
  for (int r = 0; r < 3; ++r)
    if (t[r] == a && t[(r + 1) % 3] == b && t[(r + 2) % 3] == c) return true;
  return false;
}

/// The enclosed volume of a closed, outward-oriented surface: Σ x0·(x1 × x2) / 6.
real EnclosedVolume(TriangleMesh const& mesh) {
  real volume = 0;
  for (auto const& t : mesh.triangles)
    volume += mesh.nodes[t[0]].dot(mesh.nodes[t[1]].cross(mesh.nodes[t[2]])) / 6;
  return volume;
}

TetMesh UnitCube() {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3::Ones(), {1, 1, 1}, mesh, error));
  return mesh;
}

}  // namespace

// ---------------------------------------------------------------- builders

TEST_CASE("MakeTetBox: counts, node positions, orientation, volume", "[actors][mesh]") {
  auto const cells = GENERATE(std::array<int, 3>{1, 1, 1}, std::array<int, 3>{2, 3, 4},
                              std::array<int, 3>{5, 1, 2});
  Real3 const origin = GENERATE(Real3(0, 0, 0), Real3(-1.5, 2.25, 10));
  Real3 const size(0.7, 1.3, 2.9);
  CAPTURE(cells[0], cells[1], cells[2], origin.transpose());
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(origin, size, cells, mesh, error));
  int const nx = cells[0], ny = cells[1], nz = cells[2];
  REQUIRE(mesh.nodes.size() == size_t((nx + 1) * (ny + 1) * (nz + 1)));
  REQUIRE(mesh.tetrahedra.size() == size_t(6 * nx * ny * nz));
  REQUIRE(ValidateTetMesh(mesh, error));

  // node (i, j, k) = i + (nx+1)(j + (ny+1) k) at origin + (i hx, j hy, k hz)
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Real3 const expected =
            origin + Real3(i * size.x() / nx, j * size.y() / ny, k * size.z() / nz);
        REQUIRE((mesh.nodes[i + (nx + 1) * (j + (ny + 1) * k)] - expected).norm() <= 1e-14 * 16);
      }
  REQUIRE(mesh.nodes.front() == origin);
  REQUIRE(mesh.nodes.back() == origin + size);

  real const cellVolume = size.prod() / (nx * ny * nz);
  real total = 0;
  for (int t = 0; t < int(mesh.tetrahedra.size()); ++t) {
    real const v = SignedVolume(mesh, t);
    CAPTURE(t);
    REQUIRE(v > 0);
    REQUIRE(Near(v, cellVolume / 6, 1e-12));  // Kuhn tetrahedra have equal volume
    total += v;
  }
  REQUIRE(std::abs(total - size.prod()) <= 1e-12 * size.prod());
}

TEST_CASE("MakeTetBox is conforming: interior faces shared by two tets, boundary faces by one",
          "[actors][mesh]") {
  auto const cells = GENERATE(std::array<int, 3>{1, 1, 1}, std::array<int, 3>{3, 2, 2},
                              std::array<int, 3>{1, 4, 3});
  CAPTURE(cells[0], cells[1], cells[2]);
  Real3 const origin(1, -2, 0.5), size(2, 1, 3);
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(origin, size, cells, mesh, error));

  // face (sorted nodes) -> sign of det[xb − xa, xc − xa, xd − xa] for each
  // tet having it, d being the tet's vertex opposite the face
  std::map<std::array<int, 3>, std::vector<int>> faces;
  for (auto const& tet : mesh.tetrahedra)
    for (int opposite = 0; opposite < 4; ++opposite) {
      std::array<int, 3> face;
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != opposite) face[n++] = tet[k];
      std::sort(face.begin(), face.end());
      Real3 const& xa = mesh.nodes[face[0]];
      real const det = (mesh.nodes[face[1]] - xa)
                           .cross(mesh.nodes[face[2]] - xa)
                           .dot(mesh.nodes[tet[opposite]] - xa);
      REQUIRE(det != 0);
      faces[face].push_back(det > 0 ? 1 : -1);
    }
  // a face lies on the box boundary when its three nodes share a boundary plane
  auto const onBoundary = [&](std::array<int, 3> const& face) {
    for (int axis = 0; axis < 3; ++axis)
      for (real plane : {origin[axis], origin[axis] + size[axis]}) {
        bool all = true;
        for (int n : face) all = all && mesh.nodes[n][axis] == plane;
        if (all) return true;
      }
    return false;
  };
  int numBoundary = 0;
  for (auto const& [face, signs] : faces) {
    CAPTURE(face[0], face[1], face[2]);
    if (onBoundary(face)) {
      REQUIRE(signs.size() == 1);
      ++numBoundary;
    } else {
      REQUIRE(signs.size() == 2);
      REQUIRE(signs[0] == -signs[1]);  // the two tets lie on opposite sides
    }
  }
  int const nx = cells[0], ny = cells[1], nz = cells[2];
  REQUIRE(numBoundary == 4 * (nx * ny + ny * nz + nz * nx));  // 2 triangles per boundary quad
}

TEST_CASE("MakeTetBox rejects bad cells, sizes and origins and changes nothing",
          "[actors][mesh][input]") {
  TetMesh mesh = SentinelTets();
  Error error;
  SECTION("cells") {
    auto const cells = GENERATE(std::array<int, 3>{0, 1, 1}, std::array<int, 3>{1, -2, 1},
                                std::array<int, 3>{1, 1, 0});
    REQUIRE_FALSE(MakeTetBox(Real3::Zero(), Real3::Ones(), cells, mesh, error));
    REQUIRE(Mentions(error, "cells"));
  }
  SECTION("size") {
    real const bad = GENERATE(0.0, -1.0, kNaN, kInf);
    CAPTURE(bad);
    REQUIRE_FALSE(MakeTetBox(Real3::Zero(), Real3(1, bad, 1), {1, 1, 1}, mesh, error));
    REQUIRE(Mentions(error, "size"));
  }
  SECTION("origin") {
    REQUIRE_FALSE(MakeTetBox(Real3(0, kNaN, 0), Real3::Ones(), {1, 1, 1}, mesh, error));
    REQUIRE(Mentions(error, "origin"));
  }
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Same(mesh, SentinelTets()));
}

TEST_CASE("MakeTriangleGrid: counts, positions, area, orientation", "[actors][mesh]") {
  int const cellsX = GENERATE(1, 3);
  int const cellsZ = GENERATE(1, 2, 5);
  CAPTURE(cellsX, cellsZ);
  Real3 const origin(0.5, -1.25, 2);
  real const sizeX = 1.5, sizeZ = 0.75;
  TriangleMesh mesh;
  Error error;
  REQUIRE(MakeTriangleGrid(origin, sizeX, sizeZ, cellsX, cellsZ, mesh, error));
  REQUIRE(mesh.nodes.size() == size_t((cellsX + 1) * (cellsZ + 1)));
  REQUIRE(mesh.triangles.size() == size_t(2 * cellsX * cellsZ));
  REQUIRE(ValidateTriangleMesh(mesh, error));
  for (int k = 0; k <= cellsZ; ++k)
    for (int i = 0; i <= cellsX; ++i) {
      Real3 const expected = origin + Real3(i * sizeX / cellsX, 0, k * sizeZ / cellsZ);
      REQUIRE((mesh.nodes[i + (cellsX + 1) * k] - expected).norm() <= 1e-14 * 8);
    }
  REQUIRE(mesh.nodes.back() == origin + Real3(sizeX, 0, sizeZ));
  real area = 0;
  for (auto const& t : mesh.triangles) {
    Real3 const n = Normal(mesh, t);
    REQUIRE(n.y() > 0);  // counter-clockwise seen from +y
    REQUIRE(n.x() == 0);
    REQUIRE(n.z() == 0);
    area += n.norm() / 2;
  }
  REQUIRE(Near(area, sizeX * sizeZ, 1e-12));
  // the documented diagonal: quad (0, 0) = {n00, n01, n11}, {n00, n11, n10}
  int const s = cellsX + 1;
  REQUIRE(mesh.triangles[0] == std::array<int, 3>{0, s, s + 1});
  REQUIRE(mesh.triangles[1] == std::array<int, 3>{0, s + 1, 1});
}

TEST_CASE("MakeTriangleGrid rejects bad input and changes nothing", "[actors][mesh][input]") {
  TriangleMesh mesh = SentinelTriangles();
  Error error;
  REQUIRE_FALSE(MakeTriangleGrid(Real3::Zero(), 1, 1, 0, 1, mesh, error));
  REQUIRE(Mentions(error, "cellsX"));
  REQUIRE_FALSE(MakeTriangleGrid(Real3::Zero(), 1, 1, 2, -1, mesh, error));
  REQUIRE(Mentions(error, "cellsZ"));
  real const bad = GENERATE(0.0, -2.0, kNaN, kInf);
  CAPTURE(bad);
  REQUIRE_FALSE(MakeTriangleGrid(Real3::Zero(), bad, 1, 1, 1, mesh, error));
  REQUIRE(Mentions(error, "sizeX"));
  REQUIRE_FALSE(MakeTriangleGrid(Real3::Zero(), 1, bad, 1, 1, mesh, error));
  REQUIRE(Mentions(error, "sizeZ"));
  REQUIRE_FALSE(MakeTriangleGrid(Real3(kInf, 0, 0), 1, 1, 1, 1, mesh, error));
  REQUIRE(Mentions(error, "origin"));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Same(mesh, SentinelTriangles()));
}

// ------------------------------------------------------------------ hinges

TEST_CASE("MakeHinges: one hinge per interior edge of a triangle grid", "[actors][mesh]") {
  int const cellsX = GENERATE(1, 2, 4);
  int const cellsZ = GENERATE(1, 3);
  CAPTURE(cellsX, cellsZ);
  TriangleMesh mesh;
  Error error;
  REQUIRE(MakeTriangleGrid(Real3::Zero(), 1, 1, cellsX, cellsZ, mesh, error));
  auto const hinges = MakeHinges(mesh);
  // edges: along x, along z, diagonals; boundary edges: the perimeter
  int const numEdges = cellsX * (cellsZ + 1) + (cellsX + 1) * cellsZ + cellsX * cellsZ;
  int const numBoundary = 2 * (cellsX + cellsZ);
  REQUIRE(hinges.size() == size_t(numEdges - numBoundary));

  std::set<std::pair<int, int>> edges;
  for (auto const& h : hinges) {
    CAPTURE(h[0], h[1], h[2], h[3]);
    REQUIRE(edges.insert({std::min(h[0], h[1]), std::max(h[0], h[1])}).second);  // distinct
    REQUIRE(h[2] != h[3]);
    // (x0, x1, x2) is a triangle with its orientation, (x1, x0, x3) another
    int first = 0, second = 0;
    for (auto const& t : mesh.triangles) {
      first += SameCycle(t, h[0], h[1], h[2]);
      second += SameCycle(t, h[1], h[0], h[3]);
    }
    REQUIRE(first == 1);
    REQUIRE(second == 1);
    // a flat grid: the opposite vertices lie on opposite sides of the edge
    Real3 const e = mesh.nodes[h[1]] - mesh.nodes[h[0]];
    real const s2 = e.cross(mesh.nodes[h[2]] - mesh.nodes[h[0]]).y();
    real const s3 = e.cross(mesh.nodes[h[3]] - mesh.nodes[h[0]]).y();
    REQUIRE(s2 * s3 < 0);
  }
}

TEST_CASE("MakeHinges: boundary and non-manifold edges give no hinge", "[actors][mesh]") {
  TriangleMesh mesh;
  mesh.nodes = {Real3(0, 0, 0), Real3(1, 0, 0), Real3(0, 1, 0), Real3(0, -1, 0), Real3(0, 0, 1)};
  SECTION("two triangles: one hinge, ordered as documented") {
    mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
    auto const hinges = MakeHinges(mesh);
    REQUIRE(hinges.size() == 1);
    REQUIRE(hinges[0] == std::array<int, 4>{0, 1, 2, 3});
  }
  SECTION("inconsistent orientation still gives the hinge; x0 x1 follow the first triangle") {
    mesh.triangles = {{1, 2, 0}, {0, 1, 3}};
    auto const hinges = MakeHinges(mesh);
    REQUIRE(hinges.size() == 1);
    REQUIRE(hinges[0] == std::array<int, 4>{0, 1, 2, 3});
  }
  SECTION("three triangles on one edge: none") {
    mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    REQUIRE(MakeHinges(mesh).empty());
  }
  SECTION("a single triangle: none") {
    mesh.triangles = {{0, 1, 2}};
    REQUIRE(MakeHinges(mesh).empty());
  }
}

// ----------------------------------------------------------------- readers

TEST_CASE("readers: the unit cube in TetGen (0- and 1-based) and Gmsh gives the same mesh",
          "[actors][mesh][io]") {
  TetMesh const expected = UnitCube();
  Error error;
  TetMesh oneBased, zeroBased, gmsh;
  bool ok = ReadTetGen(Data("cube1.node"), Data("cube1.ele"), oneBased, error);
  INFO(error.ToString());
  REQUIRE(ok);
  ok = ReadTetGen(Data("cube0.node"), Data("cube0.ele"), zeroBased, error);
  INFO(error.ToString());
  REQUIRE(ok);
  ok = ReadGmshTets(Data("cube.msh"), gmsh, error);
  INFO(error.ToString());
  REQUIRE(ok);
  REQUIRE(Same(oneBased, expected));
  REQUIRE(Same(zeroBased, expected));
  REQUIRE(Same(gmsh, expected));  // node 99 (point element only) dropped, ids mapped
  REQUIRE(ValidateTetMesh(gmsh, error));
}

TEST_CASE("readers: Gmsh triangles of a mixed file keep only the nodes they use",
          "[actors][mesh][io]") {
  TriangleMesh mesh;
  Error error;
  bool const ok = ReadGmshTriangles(Data("cube.msh"), mesh, error);
  INFO(error.ToString());
  REQUIRE(ok);
  // the bottom face z = 0: nodes 10 20 30 40 -> 0 1 2 3, outward (−z) normals
  REQUIRE(mesh.nodes ==
          DynamicArray<Real3>{Real3(0, 0, 0), Real3(1, 0, 0), Real3(0, 1, 0), Real3(1, 1, 0)});
  REQUIRE(mesh.triangles == DynamicArray<std::array<int, 3>>{{0, 2, 3}, {0, 3, 1}});
  for (auto const& t : mesh.triangles) REQUIRE(Normal(mesh, t).z() < 0);
}

TEST_CASE("readers: OBJ quads with slashes and negative indices equal the explicit triangles",
          "[actors][mesh][io]") {
  TriangleMesh quads, triangles;
  Error error;
  bool ok = ReadObj(Data("cube_quads.obj"), quads, error);
  INFO(error.ToString());
  REQUIRE(ok);
  ok = ReadObj(Data("cube_triangles.obj"), triangles, error);
  INFO(error.ToString());
  REQUIRE(ok);
  REQUIRE(quads.nodes.size() == 8);
  REQUIRE(quads.triangles.size() == 12);
  REQUIRE(Same(quads, triangles));
  REQUIRE(quads.nodes == UnitCube().nodes);
  // a closed, outward-oriented surface: every edge in two triangles
  // (opposite directions), enclosed volume 1
  REQUIRE(MakeHinges(quads).size() == 18);
  REQUIRE(Near(EnclosedVolume(quads), 1, 1e-14));
}

TEST_CASE("readers: CRLF line ends read the same", "[actors][mesh][io]") {
  std::filesystem::path const dir =
      std::filesystem::temp_directory_path() / ("superdex_mesh_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  auto const crlfCopy = [&](std::string const& name) {
    std::ifstream in(Data(name), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    std::string out;
    for (char c : text.str()) {
      if (c == '\n') out += '\r';
      out += c;
    }
    std::string const path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << out;
    return path;
  };
  Error error;
  TetMesh tets;
  REQUIRE(ReadTetGen(crlfCopy("cube1.node"), crlfCopy("cube1.ele"), tets, error));
  REQUIRE(Same(tets, UnitCube()));
  REQUIRE(ReadGmshTets(crlfCopy("cube.msh"), tets, error));
  REQUIRE(Same(tets, UnitCube()));
  TriangleMesh a, b;
  REQUIRE(ReadObj(crlfCopy("cube_quads.obj"), a, error));
  REQUIRE(ReadObj(Data("cube_quads.obj"), b, error));
  REQUIRE(Same(a, b));
  std::filesystem::remove_all(dir);
}

namespace {

enum class Reader { TetGen, GmshTets, GmshTriangles, Obj };

struct BadFile {
  Reader reader;
  std::string file;     // the malformed file
  std::string partner;  // TetGen: the valid other half
  int line;             // the line the error must name
  std::string what;     // a part of the message
};

/// Runs the reader on a sentinel mesh; REQUIREs failure, an unchanged mesh,
/// and returns the error.
Error ReadBad(BadFile const& bad, std::string const& badPath) {
  Error error;
  TetMesh tets = SentinelTets();
  TriangleMesh triangles = SentinelTriangles();
  bool ok = true;
  switch (bad.reader) {
    case Reader::TetGen:
      ok = bad.file.ends_with(".node") ? ReadTetGen(badPath, Data(bad.partner), tets, error)
                                       : ReadTetGen(Data(bad.partner), badPath, tets, error);
      break;
    case Reader::GmshTets:
      ok = ReadGmshTets(badPath, tets, error);
      break;
    case Reader::GmshTriangles:
      ok = ReadGmshTriangles(badPath, triangles, error);
      break;
    case Reader::Obj:
      ok = ReadObj(badPath, triangles, error);
      break;
  }
  INFO(error.ToString());
  REQUIRE_FALSE(ok);
  REQUIRE(error);
  REQUIRE(Same(tets, SentinelTets()));
  REQUIRE(Same(triangles, SentinelTriangles()));
  return error;
}

}  // namespace

TEST_CASE("readers: every malformed file gives its file, line and reason, and the mesh is unchanged",
          "[actors][mesh][io][input]") {
  using R = Reader;
  auto const bad = GENERATE(values<BadFile>({
      // TetGen .node
      {R::TetGen, "bad_node_no_header.node", "cube1.ele", 2, "is the header line missing?"},
      {R::TetGen, "bad_node_truncated.node", "cube1.ele", 11, "end of file: 8 of the 9 points"},
      {R::TetGen, "bad_node_extra.node", "cube1.ele", 10, "after the 7 points declared on line 2"},
      {R::TetGen, "bad_node_non_numeric.node", "cube1.ele", 7,
       "y coordinate '1.0x' is not a number"},
      {R::TetGen, "bad_node_nan.node", "cube1.ele", 8, "z coordinate 'nan' is not finite"},
      {R::TetGen, "bad_node_wrong_size.node", "cube1.ele", 6,
       "has 3 values, expected 4 (<index> <x> <y> <z>)"},
      {R::TetGen, "bad_node_sequence.node", "cube1.ele", 7,
       "point index 6 out of sequence, expected 5"},
      {R::TetGen, "bad_node_dimension.node", "cube1.ele", 2, "dimension must be 3, got 2"},
      // TetGen .ele
      {R::TetGen, "bad_ele_out_of_range.ele", "cube1.node", 5, "node 9 is out of range [1, 8]"},
      {R::TetGen, "bad_ele_zero_in_one_based.ele", "cube1.node", 3,
       "node 0 is out of range [1, 8]"},
      {R::TetGen, "bad_ele_repeated.ele", "cube1.node", 7, "has node 5 more than once"},
      {R::TetGen, "bad_ele_wrong_size.ele", "cube1.node", 4, "has 4 values, expected 5"},
      {R::TetGen, "bad_ele_truncated.ele", "cube1.node", 7, "end of file: 4 of the 6 tetrahedra"},
      {R::TetGen, "bad_ele_extra.ele", "cube1.node", 8,
       "after the 5 tetrahedra declared on line 2"},
      {R::TetGen, "bad_ele_non_numeric.ele", "cube1.node", 5, "node '4.0' is not an integer"},
      {R::TetGen, "bad_ele_nodes_per_tet.ele", "cube1.node", 3,
       "nodes per tetrahedron must be 4 or 10, got 3"},
      // Gmsh
      {R::GmshTets, "bad_msh_no_format.msh", "", 1, "missing header"},
      {R::GmshTets, "bad_msh_version4.msh", "", 2, "MSH version 4.1 is not supported"},
      {R::GmshTets, "bad_msh_binary.msh", "", 2, "binary MSH"},
      {R::GmshTets, "bad_msh_nodes_truncated.msh", "", 23,
       "end of file: $Nodes declares 9 on line 14, 8 were read"},
      {R::GmshTets, "bad_msh_nodes_count.msh", "", 23,
       "expected $EndNodes after the 8 nodes declared on line 14"},
      {R::GmshTets, "bad_msh_node_non_numeric.msh", "", 17, "y coordinate 'one' is not a number"},
      {R::GmshTets, "bad_msh_node_inf.msh", "", 21, "z coordinate 'inf' is not finite"},
      {R::GmshTets, "bad_msh_duplicate_node.msh", "", 20, "node id 40 appears twice"},
      {R::GmshTets, "bad_msh_undefined_node.msh", "", 34, "node 77 is not defined in $Nodes"},
      {R::GmshTets, "bad_msh_wrong_size.msh", "", 31, "has 3 nodes after its 2 tags, expected 4"},
      {R::GmshTets, "bad_msh_ignored_wrong_size.msh", "", 28,
       "(type 1) has 1 nodes after its 2 tags, expected 2"},
      {R::GmshTets, "bad_msh_repeated.msh", "", 35, "has node 50 more than once"},
      {R::GmshTets, "bad_msh_no_end_elements.msh", "", 38, "has no $EndElements"},
      {R::GmshTets, "bad_msh_elements_count.msh", "", 38,
       "'$EndElements' ends $Elements early: 12 declared on line 26, 11 read"},
      {R::GmshTets, "bad_msh_non_numeric_tag.msh", "", 30, "tag 'x' is not an integer"},
      {R::GmshTets, "bad_msh_no_tets.msh", "", 25, "no tetrahedra (element type 4)"},
      {R::GmshTriangles, "bad_msh_no_triangles.msh", "", 25, "no triangles (element type 2)"},
      {R::GmshTriangles, "bad_msh_undefined_node.msh", "", 34, "node 77 is not defined"},
      {R::GmshTets, "bad_msh_missing_nodes.msh", "", 13, "$Elements before $Nodes"},
      {R::GmshTets, "bad_msh_unclosed_section.msh", "", 38,
       "$Comments (line 9) has no $EndComments"},
      // OBJ
      {R::Obj, "bad_obj_out_of_range.obj", "", 14, "face vertex index 9 is out of range [1, 8]"},
      {R::Obj, "bad_obj_zero_index.obj", "", 12, "index 0 is invalid"},
      {R::Obj, "bad_obj_negative.obj", "", 11,
       "relative face vertex index -9 reaches before the first vertex"},
      {R::Obj, "bad_obj_non_numeric.obj", "", 5, "z coordinate 'zero' is not a number"},
      {R::Obj, "bad_obj_inf.obj", "", 7, "z coordinate 'inf' is not finite"},
      {R::Obj, "bad_obj_repeated.obj", "", 16, "face uses vertex 6 more than once"},
      {R::Obj, "bad_obj_short_face.obj", "", 18, "has 2 vertices, expected at least 3"},
      {R::Obj, "bad_obj_short_vertex.obj", "", 3, "has 3 values, expected at least 4"},
      {R::Obj, "bad_obj_bad_ref.obj", "", 13, "texture index 'x' is not an integer"},
      {R::Obj, "bad_obj_too_many_slashes.obj", "", 15, "more than 3 '/'-separated parts"},
      {R::Obj, "bad_obj_no_faces.obj", "", 10, "no faces"},
  }));
  CAPTURE(bad.file);
  std::string const path = Data(bad.file);
  Error const error = ReadBad(bad, path);
  CAPTURE(error.GetMessage());
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  // "<path>:<line>: ..." names the file and the line
  REQUIRE(error.GetMessage().starts_with(path + ":" + std::to_string(bad.line) + ": "));
  REQUIRE(Mentions(error, bad.what));
}

TEST_CASE("readers: an unreadable file is an I/O error naming the file",
          "[actors][mesh][io][input]") {
  std::string const missing = Data("no_such_file.msh");
  BadFile const cases[] = {
      {Reader::TetGen, "no_such_file.node", "cube1.ele", 0, ""},
      {Reader::TetGen, "no_such_file.ele", "cube1.node", 0, ""},
      {Reader::GmshTets, "no_such_file.msh", "", 0, ""},
      {Reader::GmshTriangles, "no_such_file.msh", "", 0, ""},
      {Reader::Obj, "no_such_file.obj", "", 0, ""},
  };
  for (BadFile const& bad : cases) {
    CAPTURE(bad.file);
    Error const error = ReadBad(bad, Data(bad.file));
    REQUIRE(error.GetCode() == ErrorCode::InvalidState);
    REQUIRE(Mentions(error, Data(bad.file) + ": cannot open"));
  }
  // a directory is not a file
  Error error;
  TriangleMesh mesh = SentinelTriangles();
  REQUIRE_FALSE(ReadObj(SUPERDEX_TEST_DATA_DIR, mesh, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidState);
  REQUIRE(Same(mesh, SentinelTriangles()));
}

TEST_CASE("readers: special files give an Error, never an exception or an unbounded read",
          "[actors][mesh][io][input]") {
  // every reader on the file: an Error naming it, the mesh unchanged
  auto const readAll = [](std::string const& path) {
    for (Reader reader : {Reader::GmshTets, Reader::GmshTriangles, Reader::Obj})
      REQUIRE(Mentions(ReadBad({reader, "", "", 0, ""}, path), path + ":"));
    Error error;
    TetMesh tets = SentinelTets();
    REQUIRE_FALSE(ReadTetGen(path, Data("cube1.ele"), tets, error));
    REQUIRE(Mentions(error, path + ":"));
    REQUIRE(Same(tets, SentinelTets()));
  };
  // /dev/zero never ends: read up to the cap for non-regular files (before:
  // read until std::bad_alloc)
  SECTION("/dev/zero") {
    if (!std::filesystem::exists("/dev/zero")) {
      WARN("no /dev/zero: not checked");
      return;
    }
    Error error;
    TriangleMesh mesh = SentinelTriangles();
    REQUIRE_FALSE(ReadObj("/dev/zero", mesh, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidState);
    REQUIRE(Mentions(error, "/dev/zero: read stopped after 256 MiB"));
    REQUIRE(Same(mesh, SentinelTriangles()));
  }
  // a file whose read fails (EIO): before, std::ios_base::failure escaped
  SECTION("/proc/self/mem") {
    if (access("/proc/self/mem", R_OK) != 0) {
      WARN("no readable /proc/self/mem: not checked");
      return;
    }
    readAll("/proc/self/mem");
    Error error;
    TriangleMesh mesh;
    REQUIRE_FALSE(ReadObj("/proc/self/mem", mesh, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidState);
    REQUIRE(Mentions(error, "read error"));
  }
  // /dev/null: an empty file
  SECTION("/dev/null") { readAll("/dev/null"); }
  // a FIFO nobody writes to: before, opening it blocked forever
  SECTION("a FIFO without a writer") {
    std::string const fifo =
        (std::filesystem::temp_directory_path() / ("superdex_mesh_fifo_" + std::to_string(getpid()))).string();
    REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
    Error error;
    TriangleMesh mesh = SentinelTriangles();
    REQUIRE_FALSE(ReadObj(fifo, mesh, error));
    REQUIRE(Mentions(error, fifo + ":1: no faces"));  // read as an empty file
    REQUIRE(Same(mesh, SentinelTriangles()));
    std::filesystem::remove(fifo);
  }
}

TEST_CASE("ReadObj: one face of 400,000 vertices, and a vertex repeated in it", "[actors][mesh][io]") {
  // before: the repeated-vertex check compared every pair (26 s for this face)
  std::filesystem::path const dir =
      std::filesystem::temp_directory_path() / ("superdex_mesh_big_face_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  int const n = 400000;
  std::ostringstream vertexLines, faceLine;
  faceLine << "f";
  for (int i = 0; i < n; ++i) {
    real const angle = 2 * std::numbers::pi_v<real> * i / n;
    vertexLines << "v " << std::cos(angle) << " " << std::sin(angle) << " 0\n";
    faceLine << " " << i + 1;
  }
  std::string const vertices = vertexLines.str(), face = faceLine.str();
  std::string const good = (dir / "good.obj").string(), bad = (dir / "bad.obj").string();
  std::ofstream(good) << vertices << face << "\n";
  // vertex 7 again near the end
  std::ofstream(bad) << vertices << face << " 7\n";
  Error error;
  TriangleMesh mesh;
  REQUIRE(ReadObj(good, mesh, error));
  REQUIRE(mesh.nodes.size() == std::size_t(n));
  REQUIRE(mesh.triangles.size() == std::size_t(n - 2));
  REQUIRE(mesh.triangles.back() == std::array<int, 3>{0, n - 2, n - 1});
  TriangleMesh unchanged = SentinelTriangles();
  REQUIRE_FALSE(ReadObj(bad, unchanged, error));
  REQUIRE(Mentions(error, "face uses vertex 7 more than once (as '7' and '7')"));
  REQUIRE(Same(unchanged, SentinelTriangles()));
  std::filesystem::remove_all(dir);
}

// -------------------------------------------------------------- validation

TEST_CASE("ValidateTetMesh names the element and the offending node", "[actors][mesh][input]") {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3::Ones(), {2, 1, 1}, mesh, error));  // 12 nodes
  REQUIRE(ValidateTetMesh(mesh, error));
  SECTION("index out of range") {
    mesh.tetrahedra[3][2] = 12;
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.tetrahedra[3][2] = 12 is out of range [0, 12)"));
  }
  SECTION("negative index") {
    mesh.tetrahedra[0][0] = -1;
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.tetrahedra[0][0] = -1 is out of range"));
  }
  SECTION("repeated node") {
    mesh.tetrahedra[5][3] = mesh.tetrahedra[5][1];
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.tetrahedra[5][3] = " + std::to_string(mesh.tetrahedra[5][1]) +
                                " repeats a node"));
  }
  SECTION("an element listed twice, in another node order") {
    // before: accepted, and the deformable counted its mass twice
    auto const& t = mesh.tetrahedra[2];
    mesh.tetrahedra.push_back({t[3], t[1], t[2], t[0]});
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.tetrahedra[12] = {"));
    REQUIRE(Mentions(error, "repeats tetrahedra[2] (the same nodes)"));
  }
  SECTION("non-finite node") {
    mesh.nodes[7].y() = kNaN;
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.nodes[7] must be finite"));
  }
  SECTION("empty") {
    mesh.tetrahedra.clear();
    REQUIRE_FALSE(ValidateTetMesh(mesh, error));
    REQUIRE(Mentions(error, "TetMesh.tetrahedra must not be empty"));
    REQUIRE_FALSE(ValidateTetMesh(TetMesh{}, error));
    REQUIRE(Mentions(error, "TetMesh.nodes must not be empty"));
  }
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
}

TEST_CASE("ValidateTriangleMesh names the element and the offending node",
          "[actors][mesh][input]") {
  TriangleMesh mesh;
  Error error;
  REQUIRE(MakeTriangleGrid(Real3::Zero(), 1, 1, 2, 2, mesh, error));  // 9 nodes
  REQUIRE(ValidateTriangleMesh(mesh, error));
  SECTION("index out of range") {
    mesh.triangles[6][1] = 9;
    REQUIRE_FALSE(ValidateTriangleMesh(mesh, error));
    REQUIRE(Mentions(error, "TriangleMesh.triangles[6][1] = 9 is out of range [0, 9)"));
  }
  SECTION("repeated node") {
    mesh.triangles[2][2] = mesh.triangles[2][0];
    REQUIRE_FALSE(ValidateTriangleMesh(mesh, error));
    REQUIRE(Mentions(error, "TriangleMesh.triangles[2][2]"));
    REQUIRE(Mentions(error, "repeats a node"));
  }
  SECTION("a triangle listed twice") {
    mesh.triangles.push_back(mesh.triangles[1]);
    REQUIRE_FALSE(ValidateTriangleMesh(mesh, error));
    REQUIRE(Mentions(error, "TriangleMesh.triangles[8] = {"));
    REQUIRE(Mentions(error, "repeats triangles[1]"));
  }
  SECTION("non-finite node") {
    mesh.nodes[4].x() = -kInf;
    REQUIRE_FALSE(ValidateTriangleMesh(mesh, error));
    REQUIRE(Mentions(error, "TriangleMesh.nodes[4] must be finite"));
  }
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
}

TEST_CASE("RemoveUnusedNodes drops unreferenced nodes and renumbers", "[actors][mesh]") {
  TriangleMesh mesh;
  mesh.nodes = {Real3(0, 0, 0), Real3(9, 9, 9), Real3(1, 0, 0), Real3(0, 1, 0), Real3(8, 8, 8)};
  mesh.triangles = {{0, 2, 3}, {3, 2, 0}};
  REQUIRE(RemoveUnusedNodes(mesh) == 2);
  REQUIRE(mesh.nodes == DynamicArray<Real3>{Real3(0, 0, 0), Real3(1, 0, 0), Real3(0, 1, 0)});
  REQUIRE(mesh.triangles == DynamicArray<std::array<int, 3>>{{0, 1, 2}, {2, 1, 0}});
  TetMesh cube = UnitCube();
  REQUIRE(RemoveUnusedNodes(cube) == 0);
  REQUIRE(Same(cube, UnitCube()));
}
