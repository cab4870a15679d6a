// ReadGmshTets and ReadGmshTriangles on arbitrary bytes: the contract of
// fuzz_obj.cpp for both.
#include "fuzz_support.h"

using namespace superdex;
using namespace superdex::fuzz;

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  static ScratchFile file(".msh");
  std::string const& path = file.Write({reinterpret_cast<char const*>(data), size});
  CheckReader("ReadGmshTets", {path}, TetMesh{{Real3(7, 8, 9)}, {{0, 0, 0, 0}}}, &TetMesh::tetrahedra,
              [&](TetMesh& mesh, Error& error) { return ReadGmshTets(path, mesh, error); });
  CheckReader("ReadGmshTriangles", {path}, TriangleMesh{{Real3(7, 8, 9)}, {{0, 0, 0}}}, &TriangleMesh::triangles,
              [&](TriangleMesh& mesh, Error& error) { return ReadGmshTriangles(path, mesh, error); });
  return 0;
}
