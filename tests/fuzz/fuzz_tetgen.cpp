// ReadTetGen on arbitrary bytes: the input is the .node file, a line "@@ele",
// then the .ele file (no such line: all of it is the .node file and the .ele
// file is empty). The contract of fuzz_obj.cpp; the message names one of
// the two files.
#include "fuzz_support.h"

using namespace superdex;
using namespace superdex::fuzz;

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  static ScratchFile nodeFile(".node"), eleFile(".ele");
  std::string_view const input(reinterpret_cast<char const*>(data), size);
  std::size_t const split = input.find("\n@@ele\n");
  std::string_view const node = input.substr(0, split);
  std::string_view const ele = split == std::string_view::npos ? std::string_view() : input.substr(split + 7);
  std::string const& nodePath = nodeFile.Write(node);
  std::string const& elePath = eleFile.Write(ele);
  CheckReader("ReadTetGen", {nodePath, elePath}, TetMesh{{Real3(7, 8, 9)}, {{0, 0, 0, 0}}}, &TetMesh::tetrahedra,
              [&](TetMesh& mesh, Error& error) { return ReadTetGen(nodePath, elePath, mesh, error); });
  return 0;
}
