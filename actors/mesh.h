// Meshes of deformable actors: linear tetrahedra (volumes) and triangles
// (shells), builders for the scenes the harness needs, readers for common
// mesh files, and the structural checks actor creation runs (docs/design.md §4.2).
//
// Indices are 0-based throughout. A tetrahedron {a, b, c, d} is positively
// oriented when det[x_b − x_a, x_c − x_a, x_d − x_a] > 0 (its signed volume
// is that determinant / 6); a triangle {a, b, c} has the normal
// (x_b − x_a) × (x_c − x_a), i.e. it is counter-clockwise seen from the side
// that normal points to.
//
// Errors (core/error.h). Builders and validators: InvalidArgument, message
// naming the field and value. Readers: the message always starts
// "<file>:<line>: " (compiler style) followed by what is wrong and the
// offending value; the code is
//   InvalidState     the file cannot be opened or read (I/O), message
//                    "<file>: cannot open ...", "<file>: read error (...)"
//                    (there is no line), or it is not a regular file (a
//                    pipe, a device) and longer than 256 MiB ("<file>: read
//                    stopped after 256 MiB ..."). Readers never throw, and a
//                    pipe without a writer reads as empty;
//   InvalidArgument  anything wrong with the content: missing header or
//                    section, wrong counts, non-numeric or non-finite values,
//                    indices out of range, elements of the wrong size, a node
//                    repeated within an element, truncated file (reported on
//                    the line after the last one: where the missing data
//                    should have been).
// On failure the output mesh is left unchanged.
#pragma once

#include <superdex/core/error.h>
#include <superdex/core/types.h>

#include <array>
#include <string>

namespace superdex {

struct TetMesh {
  DynamicArray<Real3> nodes;                    ///< reference positions [m]
  DynamicArray<std::array<int, 4>> tetrahedra;  ///< node indices, 0-based
};

struct TriangleMesh {
  DynamicArray<Real3> nodes;                   ///< reference positions [m]
  DynamicArray<std::array<int, 3>> triangles;  ///< node indices, 0-based
};

// ---------------------------------------------------------------- builders

/// A box [origin, origin + size] split into cells.x × cells.y × cells.z
/// cubes (cuboids), each cut into 6 tetrahedra by the Kuhn (Freudenthal)
/// subdivision: the 6 monotone paths from the cell's lowest corner to its
/// highest corner along the main diagonal, one per permutation of the axes.
/// The same cut in every cell makes the mesh conforming (every interior
/// triangular face is shared by exactly two tetrahedra). Every tetrahedron
/// is positively oriented.
///
/// Node of grid point (i, j, k), 0 <= i <= cells.x etc.:
///   i + (cells.x + 1)·(j + (cells.y + 1)·k),  at origin + (i·hx, j·hy, k·hz).
/// Tetrahedra of cell (ci, cj, ck) are 6·(ci + cells.x·(cj + cells.y·ck)) + 0..5.
/// Counts: (cells.x+1)(cells.y+1)(cells.z+1) nodes, 6·cells.x·cells.y·cells.z
/// tetrahedra. Returns false + InvalidArgument (mesh unchanged) on cells < 1,
/// a size that is not finite and > 0, or a non-finite origin.
bool MakeTetBox(Real3 const& origin, Real3 const& size, std::array<int, 3> const& cells,
                TetMesh& mesh, Error& error);

/// A rectangle in the x–z plane at height y = origin.y,
/// [origin.x, origin.x + sizeX] × [origin.z, origin.z + sizeZ], split into
/// cellsX × cellsZ quads, each cut into 2 triangles along the SAME diagonal
/// everywhere (no alternation): the one from grid point (i, k) to (i+1, k+1).
/// With n00 = (i,k), n10 = (i+1,k), n01 = (i,k+1), n11 = (i+1,k+1), quad
/// (i, k) gives triangles 2·(i + cellsX·k) + 0 = {n00, n01, n11} and
/// + 1 = {n00, n11, n10}: both counter-clockwise seen from +y (normal +y).
/// Node of grid point (i, k) = i + (cellsX + 1)·k, at
/// origin + (i·sizeX/cellsX, 0, k·sizeZ/cellsZ).
/// Returns false + InvalidArgument (mesh unchanged) on cells < 1, sizes not
/// finite and > 0, or a non-finite origin.
bool MakeTriangleGrid(Real3 const& origin, real sizeX, real sizeZ, int cellsX, int cellsZ,
                      TriangleMesh& mesh, Error& error);

/// Interior edges of a triangle mesh as bending hinges {x0, x1, x2, x3}: one
/// per edge shared by exactly two triangles (boundary edges and non-manifold
/// edges shared by three or more triangles give none). x0, x1 are the shared
/// edge, in the order it runs in the first triangle (lower index) sharing it,
/// so (x0, x1, x2) has that triangle's orientation; x2 is the first
/// triangle's vertex opposite the edge, x3 the second's. When the two
/// triangles are consistently oriented, (x1, x0, x3) has the second
/// triangle's orientation. Hinges are listed in order of the edge's first
/// appearance (triangle by triangle, edges (0,1), (1,2), (2,0)).
/// Indices are not checked: run ValidateTriangleMesh first.
DynamicArray<std::array<int, 4>> MakeHinges(TriangleMesh const& mesh);

// ----------------------------------------------------------------- readers

/// TetGen .node + .ele (https://wias-berlin.de/software/tetgen/fformats.html).
///   .node: "<#points> <dim = 3> <#attributes> <#boundary markers 0|1>", then
///          "<index> <x> <y> <z> [attributes] [marker]" per point;
///   .ele:  "<#tets> <nodes per tet 4|10> <#attributes>", then
///          "<index> <n0> <n1> <n2> <n3> [... 10-node extras] [attributes]".
/// '#' starts a comment; blank lines are skipped. Numbering starts at 0 or 1,
/// as the first point of the .node file says (TetGen's rule); point indices
/// must then run consecutively, and the .ele's node references use the same
/// base. Tetrahedron indices start at 0 or 1 and run consecutively. For
/// 10-node (quadratic) tets the 4 corner nodes are kept. Every line must
/// have exactly the number of values its header implies; more data lines
/// than declared is an error. Attributes and markers are read and dropped.
/// All nodes are kept, in file order.
bool ReadTetGen(std::string const& nodeFile, std::string const& eleFile, TetMesh& mesh,
                Error& error);

/// Gmsh MSH 2.2 (also 2.0, 2.1) ASCII: "$MeshFormat" first, then "$Nodes"
/// ("<n>", then "<id> <x> <y> <z>") and "$Elements" ("<m>", then
/// "<id> <type> <#tags> <tags...> <nodes...>"). Element type 4 (4-node
/// tetrahedron) is read; every other type is checked for syntax (and its
/// node count, for the standard types) and ignored, as are other sections
/// ($PhysicalNames, $NodeData, ...). Node ids may be any distinct positive
/// integers. Nodes that no tetrahedron uses are dropped; the others keep
/// their file order. MSH 4 and binary files are rejected with a message
/// saying so. A file with no tetrahedron is an error.
bool ReadGmshTets(std::string const& path, TetMesh& mesh, Error& error);

/// As ReadGmshTets, reading element type 2 (3-node triangle) instead.
bool ReadGmshTriangles(std::string const& path, TriangleMesh& mesh, Error& error);

/// Wavefront OBJ: "v x y z [w | r g b]" and "f" lines; face references of the
/// forms v, v/vt, v/vt/vn, v//vn (only v is used; vt and vn must be
/// integers when present). Indices are 1-based; a negative index is relative
/// (−1 = the last vertex defined before that line); 0 is an error. Polygons
/// are fan-triangulated: (p0, p1, p2), (p0, p2, p3), ... All other statements
/// (vt, vn, o, g, s, usemtl, mtllib, l, ...) are ignored; '#' starts a
/// comment. All vertices are kept, in file order. A file with no face is an
/// error.
bool ReadObj(std::string const& path, TriangleMesh& mesh, Error& error);

// -------------------------------------------------------------- validation

/// Structural validation used by actor creation: at least one node and one
/// tetrahedron, finite node coordinates, every index in [0, nodes.size()),
/// no node repeated within a tetrahedron. Orientation and degeneracy are the
/// element's business (actors/tet_element.h). The message names the element
/// index and the offending node, e.g. "TetMesh.tetrahedra[5][2] = 17 is out
/// of range [0, 8)".
bool ValidateTetMesh(TetMesh const& mesh, Error& error);

/// As ValidateTetMesh, for triangles ("TriangleMesh.triangles[i][k] ...").
bool ValidateTriangleMesh(TriangleMesh const& mesh, Error& error);

/// Drops nodes no element references and renumbers the elements; the kept
/// nodes keep their relative order. Indices must be valid. Returns the
/// number of nodes removed.
int RemoveUnusedNodes(TetMesh& mesh);
int RemoveUnusedNodes(TriangleMesh& mesh);

/// Signed volume of tetrahedron `tet`: det[x1 − x0, x2 − x0, x3 − x0] / 6.
real SignedVolume(TetMesh const& mesh, int tet);

}  // namespace superdex
