// actors/mesh.h: tetrahedral and triangle meshes, their builders, readers
// and checks. Every function raises mochi.Error where the C++ one returns
// false; the ones whose C++ preconditions are "indices valid" validate first.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineMesh(py::module_& m) {
  ParamsClass<TetMesh>(m, "TetMesh",
                       "Linear tetrahedra: nodes (n, 3) [m] and tetrahedra (m, 4) int, 0-based. "
                       "A tetrahedron {a, b, c, d} is positively oriented when det[x_b - x_a, "
                       "x_c - x_a, x_d - x_a] > 0.")
      .Field("nodes", &TetMesh::nodes, "reference positions [m], an (n, 3) array")
      .Field("tetrahedra", &TetMesh::tetrahedra, "node indices, an (m, 4) int array");
  ParamsClass<TriangleMesh>(m, "TriangleMesh",
                            "Triangles: nodes (n, 3) [m] and triangles (m, 3) int, 0-based; {a, "
                            "b, c} has the normal (x_b - x_a) × (x_c - x_a).")
      .Field("nodes", &TriangleMesh::nodes, "reference positions [m], an (n, 3) array")
      .Field("triangles", &TriangleMesh::triangles, "node indices, an (m, 3) int array");

  m.def(
       "make_tet_box",
       [](Real3 const& origin, Real3 const& size, std::array<int, 3> const& cells) {
         TetMesh mesh;
         Checked([&](Error& e) { MakeTetBox(origin, size, cells, mesh, e); });
         return mesh;
       },
       py::arg("origin"), py::arg("size"), py::arg("cells"),
       "A box [origin, origin + size] split into cells[0] × cells[1] × cells[2] cuboids, each "
       "cut into 6 positively oriented tetrahedra (Kuhn subdivision, conforming). Node of grid "
       "point (i, j, k): i + (cells[0] + 1)·(j + (cells[1] + 1)·k).")
      .def(
          "make_triangle_grid",
          [](Real3 const& origin, real sizeX, real sizeZ, int cellsX, int cellsZ) {
            TriangleMesh mesh;
            Checked(
                [&](Error& e) { MakeTriangleGrid(origin, sizeX, sizeZ, cellsX, cellsZ, mesh, e); });
            return mesh;
          },
          py::arg("origin"), py::arg("size_x"), py::arg("size_z"), py::arg("cells_x"),
          py::arg("cells_z"),
          "A rectangle in the x-z plane at y = origin[1], cells_x × cells_z quads each cut into "
          "2 triangles along the same diagonal, normals +y. Node of grid point (i, k): i + "
          "(cells_x + 1)·k.")
      .def(
          "make_hinges",
          [](TriangleMesh const& mesh) {
            Checked([&](Error& e) { ValidateTriangleMesh(mesh, e); });
            return ToArray(MakeHinges(mesh));
          },
          py::arg("mesh"),
          "Interior edges as bending hinges {x0, x1, x2, x3} (shared edge x0-x1, opposite "
          "vertices x2, x3), an (h, 4) int array. The mesh is validated first.")
      .def(
          "read_tet_gen",
          [](std::string const& nodeFile, std::string const& eleFile) {
            TetMesh mesh;
            Checked([&](Error& e) { ReadTetGen(nodeFile, eleFile, mesh, e); });
            return mesh;
          },
          py::arg("node_file"), py::arg("ele_file"),
          "Reads TetGen .node + .ele files. Errors name '<file>:<line>: ...' (InvalidArgument) "
          "or the file that cannot be opened (InvalidState).")
      .def(
          "read_gmsh_tets",
          [](std::string const& path) {
            TetMesh mesh;
            Checked([&](Error& e) { ReadGmshTets(path, mesh, e); });
            return mesh;
          },
          py::arg("path"), "Reads the 4-node tetrahedra of a Gmsh MSH 2.x ASCII file.")
      .def(
          "read_gmsh_triangles",
          [](std::string const& path) {
            TriangleMesh mesh;
            Checked([&](Error& e) { ReadGmshTriangles(path, mesh, e); });
            return mesh;
          },
          py::arg("path"), "Reads the 3-node triangles of a Gmsh MSH 2.x ASCII file.")
      .def(
          "read_obj",
          [](std::string const& path) {
            TriangleMesh mesh;
            Checked([&](Error& e) { ReadObj(path, mesh, e); });
            return mesh;
          },
          py::arg("path"), "Reads a Wavefront OBJ file (faces fan-triangulated).")
      .def(
          "validate_tet_mesh",
          [](TetMesh const& mesh) { Checked([&](Error& e) { ValidateTetMesh(mesh, e); }); },
          py::arg("mesh"),
          "Structural checks of actor creation: nodes and tetrahedra present, finite "
          "coordinates, indices in range, no node repeated in a tetrahedron. Raises mochi.Error "
          "naming the element.")
      .def(
          "validate_triangle_mesh",
          [](TriangleMesh const& mesh) {
            Checked([&](Error& e) { ValidateTriangleMesh(mesh, e); });
          },
          py::arg("mesh"), "As validate_tet_mesh, for triangles.")
      .def(
          "remove_unused_nodes",
          [](TetMesh& mesh) {
            Checked([&](Error& e) { ValidateTetMesh(mesh, e); });
            return RemoveUnusedNodes(mesh);
          },
          py::arg("mesh"),
          "Drops nodes no element references and renumbers (in place); returns the number "
          "removed. The mesh is validated first.")
      .def(
          "remove_unused_nodes",
          [](TriangleMesh& mesh) {
            Checked([&](Error& e) { ValidateTriangleMesh(mesh, e); });
            return RemoveUnusedNodes(mesh);
          },
          py::arg("mesh"), "As above, for a TriangleMesh.")
      .def(
          "signed_volume",
          [](TetMesh const& mesh, int tet) {
            Checked([&](Error& e) { ValidateTetMesh(mesh, e); });
            CheckIndex(tet, static_cast<int>(mesh.tetrahedra.size()), "tet");
            return SignedVolume(mesh, tet);
          },
          py::arg("mesh"), py::arg("tet"),
          "det[x1 - x0, x2 - x0, x3 - x0] / 6 of tetrahedron `tet` [m³].");
}

}  // namespace superdex::python
