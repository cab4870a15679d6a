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
#include <limits>
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

/// The input, read front to back; zeros once it is used up.
class Input {
 public:
  Input(std::uint8_t const* data, std::size_t size) : data_(data), size_(size) {}
  bool Done() const { return pos_ >= size_; }
  std::uint8_t Byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  int Int(int n) { return n > 0 ? Byte() % n : 0; }
  /// A value from the hostile table, or 8 raw bytes.
  real Real() {
    static constexpr real kInf = std::numeric_limits<real>::infinity();
    static real const kTable[] = {0,     1,      -1,    0.5,    1e-3,   10,     1e6,   1e9,    1e300,
                                  -1e300, 1e-300, 5e-324, kInf,  -kInf,  std::numeric_limits<real>::quiet_NaN(),
                                  0.1,   -0.25,  2,     1e200, 3.14159265358979};
    int const pick = Byte();
    if (pick < 240) return kTable[pick % std::size(kTable)];
    std::uint64_t bits = 0;
    for (int k = 0; k < 8; ++k) bits = bits << 8 | Byte();
    real value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }
  /// Three values of next() in this order (the arguments of one call are
  /// evaluated in an order each compiler picks, so a corpus read that way
  /// would mean another scene under clang than under gcc).
  template <class Next>
  static Real3 Triple(Next&& next) {
    real const x = next();
    real const y = next();
    real const z = next();
    return Real3(x, y, z);
  }
  Real3 Vector() { return Triple([&] { return Real(); }); }
  /// Mostly unit quaternions, sometimes hostile ones.
  Quat Rotation() {
    if (Int(4) != 0) {
      Real3 const axis = Triple([&] { return real(Int(7) - 3); });
      if (axis.isZero()) return Quat::Identity();
      return Quat(Eigen::AngleAxis<real>(0.1 * Int(60), axis.normalized()));
    }
    real const w = Real();
    Real3 const xyz = Vector();
    return Quat(w, xyz.x(), xyz.y(), xyz.z());
  }

 private:
  std::uint8_t const* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
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
