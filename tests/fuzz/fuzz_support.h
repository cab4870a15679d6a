// Shared pieces of the fuzz targets (tests/fuzz/README.md): every target is a
// libFuzzer entry point, LLVMFuzzerTestOneInput, built either with clang's
// -fsanitize=fuzzer or, elsewhere, with replay_main.cpp, which runs the files
// given on its command line (the seed corpus in ctest).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>
#include <string_view>

#include <superdex/superdex.h>

namespace superdex::fuzz {

/// Stops the run (a libFuzzer crash) with `what` when `ok` is false.
inline void Expect(bool ok, std::string const& what, std::string const& detail = {}) {
  if (ok) return;
  std::fprintf(stderr, "fuzz check failed: %s %s\n", what.c_str(), detail.c_str());
  std::abort();
}

/// A file of this process that the readers read: rewritten for each input.
class ScratchFile {
 public:
  explicit ScratchFile(char const* suffix) {
    char const* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/superdex_fuzz_" + std::to_string(getpid()) + "_" +
            std::to_string(counter_++) + suffix;
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  ScratchFile(ScratchFile const&) = delete;
  ScratchFile& operator=(ScratchFile const&) = delete;

  /// Writes `bytes` as the whole file; returns its path.
  std::string const& Write(std::string_view bytes) {
    FILE* f = std::fopen(path_.c_str(), "wb");
    Expect(f != nullptr, "cannot write the scratch file", path_);
    if (!bytes.empty()) std::fwrite(bytes.data(), 1, bytes.size(), f);
    std::fclose(f);
    return path_;
  }

 private:
  static inline int counter_ = 0;
  std::string path_;
};

/// Every element's indices lie in [0, nodes) and every node is finite.
template <class Mesh, class Elements>
bool WellFormed(Mesh const& mesh, Elements const& elements) {
  for (auto const& x : mesh.nodes)
    if (!x.allFinite()) return false;
  for (auto const& element : elements)
    for (int n : element)
      if (n < 0 || n >= static_cast<int>(mesh.nodes.size())) return false;
  return !mesh.nodes.empty() && !elements.empty();
}

/// Runs `read(mesh, error)` on a copy of `sentinel` and checks the readers'
/// contract: a success gives a well-formed mesh; a failure sets an Error
/// whose message starts with one of `paths` and leaves the mesh unchanged.
template <class Mesh, class Elements, class Read>
void CheckReader(char const* name, std::initializer_list<std::string> paths, Mesh const& sentinel,
                 Elements Mesh::*elements, Read const& read) {
  Mesh mesh = sentinel;
  Error error;
  if (read(mesh, error)) {
    Expect(WellFormed(mesh, mesh.*elements), name, "returned a malformed mesh");
    return;
  }
  Expect(static_cast<bool>(error), name, "failed without an Error");
  bool named = false;
  for (std::string const& path : paths) named |= error.GetMessage().rfind(path, 0) == 0;
  Expect(named, name, "failed with a message that does not start with the path: " + error.GetMessage());
  Expect(mesh.nodes == sentinel.nodes && mesh.*elements == sentinel.*elements, name,
         "failed and changed the mesh");
}

}  // namespace superdex::fuzz
