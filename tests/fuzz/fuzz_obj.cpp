// ReadObj on arbitrary bytes: never throws or crashes; a failure is an Error
// naming the file and leaves the mesh alone; a success is a mesh whose
// indices are in range and whose nodes are finite (CheckReader).
#include "fuzz_support.h"

using namespace superdex;
using namespace superdex::fuzz;

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  static ScratchFile file(".obj");
  std::string const& path = file.Write({reinterpret_cast<char const*>(data), size});
  CheckReader("ReadObj", {path}, TriangleMesh{{Real3(7, 8, 9)}, {{0, 0, 0}}}, &TriangleMesh::triangles,
              [&](TriangleMesh& mesh, Error& error) { return ReadObj(path, mesh, error); });
  return 0;
}
