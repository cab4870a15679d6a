#include <superdex/actors/mesh.h>
#include <superdex/core/validate.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string_view>
#include <tuple>
#include <unordered_map>

namespace superdex {

namespace {

// ------------------------------------------------------------ text parsing

/// A reader reads a file that is not a regular file (a pipe, a device such as
/// /dev/zero) up to this many bytes, then fails.
constexpr std::size_t kMaxStreamBytes = std::size_t(256) << 20;

/// The lines of a text file, read whole, with a cursor over its non-blank
/// lines. Each line has its comment (from `comment` to the end) removed and
/// is split into whitespace-separated tokens. Errors are reported as
/// "<path>:<line>: what".
class LineReader {
 public:
  /// Reads the file; InvalidState naming the file when it cannot be read.
  /// Never throws: plain POSIX reads, a regular file up to its size, any
  /// other file (pipe, device) up to kMaxStreamBytes.
  bool Open(std::string const& path, char comment, Error& error) {
    path_ = path;
    comment_ = comment;
    auto const fail = [&](std::string const& what) {
      error.Set(ErrorCode::InvalidState, path + ": " + what);
      return false;
    };
    // non-blocking open: a FIFO without a writer must not hang the caller
    int const fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return fail(std::string("cannot open file for reading (") + std::strerror(errno) + ")");
    struct Closer {
      int fd;
      ~Closer() { ::close(fd); }
    } const closer{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0)
      return fail(std::string("cannot open file for reading (") + std::strerror(errno) + ")");
    if (S_ISDIR(st.st_mode)) return fail("cannot open file: it is a directory");
    int const flags = ::fcntl(fd, F_GETFL);
    if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    bool const regular = S_ISREG(st.st_mode);
    std::size_t const limit = regular ? static_cast<std::size_t>(st.st_size) : kMaxStreamBytes;
    try {
      text_.clear();
      if (regular) text_.reserve(limit);
      std::array<char, 1 << 16> buffer;
      for (;;) {
        ssize_t const n = ::read(fd, buffer.data(), buffer.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return fail(std::string("read error (") + std::strerror(errno) + ")");
        if (n == 0) break;
        if (!regular && text_.size() + static_cast<std::size_t>(n) > limit)
          return fail("read stopped after " + std::to_string(limit >> 20) +
                      " MiB: a file that is not a regular file (a pipe or device) is read up to that size");
        text_.append(buffer.data(), static_cast<std::size_t>(n));
      }
    } catch (std::bad_alloc const&) {
      text_.clear();
      text_.shrink_to_fit();
      return fail("out of memory reading " + std::to_string(limit >> 20) + " MiB");
    }
    return true;
  }

  /// Moves to the next non-blank line; false at the end of the file.
  bool Next() {
    while (pos_ < text_.size()) {
      size_t end = text_.find('\n', pos_);
      if (end == std::string::npos) end = text_.size();
      std::string_view line(text_.data() + pos_, end - pos_);
      pos_ = end + 1;
      ++lineNumber_;
      if (comment_ != '\0') {
        size_t const c = line.find(comment_);
        if (c != std::string_view::npos) line = line.substr(0, c);
      }
      Split(line);
      if (!tokens_.empty()) return true;
    }
    // past the last line: where missing data should have been
    atEnd_ = true;
    tokens_.clear();
    return false;
  }

  size_t Size() const { return tokens_.size(); }
  std::string_view operator[](size_t i) const { return tokens_[i]; }
  /// Line number of the current line; after Next() returned false, the
  /// number of the line after the last one.
  int Line() const { return atEnd_ ? NumLines() + 1 : lineNumber_; }

  /// Sets an InvalidArgument "<path>:<line>: what" at the current line.
  bool Fail(std::string const& what, Error& error) const { return FailAt(Line(), what, error); }
  bool FailAt(int line, std::string const& what, Error& error) const {
    error.Set(ErrorCode::InvalidArgument, path_ + ":" + std::to_string(line) + ": " + what);
    return false;
  }

  /// The current line's tokens joined by one space (for messages).
  std::string Text() const {
    std::string s;
    for (std::string_view t : tokens_) {
      if (!s.empty()) s += ' ';
      s += t;
    }
    if (s.size() > 80) s = s.substr(0, 77) + "...";
    return s;
  }

 private:
  void Split(std::string_view line) {
    tokens_.clear();
    size_t i = 0;
    auto const space = [](char c) {
      return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
    };
    while (i < line.size()) {
      while (i < line.size() && space(line[i])) ++i;
      size_t const start = i;
      while (i < line.size() && !space(line[i])) ++i;
      if (i > start) tokens_.push_back(line.substr(start, i - start));
    }
  }

  int NumLines() const {
    if (text_.empty()) return 0;
    int n = static_cast<int>(std::count(text_.begin(), text_.end(), '\n'));
    return text_.back() == '\n' ? n : n + 1;
  }

  std::string path_;
  char comment_ = '\0';
  std::string text_;
  size_t pos_ = 0;
  int lineNumber_ = 0;
  bool atEnd_ = false;
  std::vector<std::string_view> tokens_;
};

std::string Quoted(std::string_view token) {
  std::string s(token.substr(0, 40));
  if (token.size() > 40) s += "...";
  return "'" + s + "'";
}

/// An integer token (optional sign, digits only) that fits an int.
bool ParseInt(std::string_view token, int& value) {
  if (token.size() > 1 && token.front() == '+' && token[1] != '-') token.remove_prefix(1);
  long long v = 0;
  auto const [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
  if (ec != std::errc() || end != token.data() + token.size() || token.empty()) return false;
  if (v < INT_MIN || v > INT_MAX) return false;
  value = static_cast<int>(v);
  return true;
}

enum class RealParse { Ok, NotNumber, NotFinite };

/// A decimal floating-point token; "nan", "inf" and overflow are NotFinite.
RealParse ParseReal(std::string_view token, real& value) {
  if (token.size() > 1 && token.front() == '+' && token[1] != '-' && token[1] != '+')
    token.remove_prefix(1);
  auto const [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (token.empty() || end != token.data() + token.size()) return RealParse::NotNumber;
  if (ec == std::errc::result_out_of_range) return RealParse::NotFinite;
  if (ec != std::errc()) return RealParse::NotNumber;
  return std::isfinite(value) ? RealParse::Ok : RealParse::NotFinite;
}

/// Reads an integer token of the reader's current line, or fails naming `what`.
bool ReadInt(LineReader const& r, size_t i, std::string const& what, int& value, Error& error) {
  if (ParseInt(r[i], value)) return true;
  return r.Fail(what + " " + Quoted(r[i]) + " is not an integer", error);
}

/// Reads a real token; `finite` demands a finite value.
bool ReadReal(LineReader const& r, size_t i, std::string const& what, bool finite, real& value,
              Error& error) {
  switch (ParseReal(r[i], value)) {
    case RealParse::Ok:
      return true;
    case RealParse::NotFinite:
      if (!finite) return true;
      return r.Fail(what + " " + Quoted(r[i]) + " is not finite", error);
    case RealParse::NotNumber:
      break;
  }
  return r.Fail(what + " " + Quoted(r[i]) + " is not a number", error);
}

bool ReadPoint(LineReader const& r, size_t first, std::string const& what, Real3& x, Error& error) {
  static char const* const kAxis[3] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c)
    if (!ReadReal(r, first + c, what + " " + kAxis[c] + " coordinate", true, x[c], error))
      return false;
  return true;
}

/// Index of the first repeated entry of `nodes` (its second occurrence), or -1.
template <size_t N>
int FindRepeat(std::array<int, N> const& nodes, size_t count = N) {
  for (size_t a = 1; a < count; ++a)
    for (size_t b = 0; b < a; ++b)
      if (nodes[a] == nodes[b]) return static_cast<int>(a);
  return -1;
}

template <class T>
std::string CountMismatch(size_t got, T const& expected) {
  return "has " + std::to_string(got) + " values, expected " + expected;
}

// ------------------------------------------------------------------ TetGen

/// Counts in a header are not trusted for allocation beyond this.
constexpr int kMaxReserve = 1 << 20;

constexpr char kNodeHeader[] = "'<#points> <dimension = 3> <#attributes> <#boundary markers 0|1>'";
constexpr char kEleHeader[] = "'<#tetrahedra> <nodes per tetrahedron 4|10> <#attributes>'";

/// "header '<spec>': what (is the header line missing?)" at the current line.
bool FailHeader(LineReader const& r, char const* spec, std::string const& what, Error& error) {
  return r.Fail("header " + std::string(spec) + ": " + what + " (is the header line missing?)",
                error);
}

/// A header line of 1 to N integers; the values not given keep their defaults.
template <size_t N>
bool ReadHeader(LineReader const& r, char const* spec, std::array<char const*, N> const& names,
                std::array<int, N>& values, Error& error) {
  if (r.Size() > N)
    return FailHeader(
        r, spec,
        "line " + Quoted(r.Text()) + " " + CountMismatch(r.Size(), "1 to " + std::to_string(N)),
        error);
  for (size_t i = 0; i < r.Size(); ++i)
    if (!ParseInt(r[i], values[i]))
      return FailHeader(r, spec, std::string(names[i]) + " " + Quoted(r[i]) + " is not an integer",
                        error);
  return true;
}

bool ReadTetGenNodes(std::string const& path, DynamicArray<Real3>& nodes, int& firstIndex,
                     Error& error) {
  LineReader r;
  if (!r.Open(path, '#', error)) return false;
  if (!r.Next()) return r.Fail("missing header " + std::string(kNodeHeader) + ": no data", error);
  int const headerLine = r.Line();
  std::array<int, 4> header = {0, 3, 0, 0};  // points, dimension, attributes, markers
  if (!ReadHeader(
          r, kNodeHeader,
          {"number of points", "dimension", "number of attributes", "number of boundary markers"},
          header, error))
    return false;
  auto const [count, dimension, numAttributes, numMarkers] = header;
  if (count < 1)
    return FailHeader(r, kNodeHeader, "number of points must be >= 1, got " + std::to_string(count),
                      error);
  if (dimension != 3)
    return FailHeader(r, kNodeHeader, "dimension must be 3, got " + std::to_string(dimension),
                      error);
  if (numAttributes < 0)
    return FailHeader(r, kNodeHeader,
                      "number of attributes must be >= 0, got " + std::to_string(numAttributes),
                      error);
  if (numMarkers != 0 && numMarkers != 1)
    return FailHeader(
        r, kNodeHeader,
        "number of boundary markers must be 0 or 1, got " + std::to_string(numMarkers), error);

  size_t const numValues = size_t(4) + numAttributes + numMarkers;
  std::string const layout =
      std::to_string(numValues) + " (<index> <x> <y> <z>" +
      (numAttributes ? " + " + std::to_string(numAttributes) + " attributes" : "") +
      (numMarkers ? " + 1 boundary marker" : "") + ")";
  DynamicArray<Real3> result;
  result.reserve(std::min(count, kMaxReserve));
  for (int i = 0; i < count; ++i) {
    if (!r.Next())
      return r.Fail("unexpected end of file: " + std::to_string(i) + " of the " +
                        std::to_string(count) + " points declared on line " +
                        std::to_string(headerLine) + " were read",
                    error);
    if (r.Size() != numValues)
      return r.Fail("point line " + CountMismatch(r.Size(), layout), error);
    int index = 0;
    if (!ReadInt(r, 0, "point index", index, error)) return false;
    if (i == 0) {
      if (index != 0 && index != 1)
        return r.Fail("first point index must be 0 or 1, got " + std::to_string(index), error);
      firstIndex = index;
    } else if (index != firstIndex + i) {
      return r.Fail("point index " + std::to_string(index) + " out of sequence, expected " +
                        std::to_string(firstIndex + i),
                    error);
    }
    std::string const what = "point " + std::to_string(index);  // the file's numbering
    Real3 x;
    if (!ReadPoint(r, 1, what, x, error)) return false;
    result.push_back(x);
    real attribute;
    for (int a = 0; a < numAttributes; ++a)
      if (!ReadReal(r, 4 + a, what + " attribute " + std::to_string(a), false, attribute, error))
        return false;
    int marker;
    if (numMarkers && !ReadInt(r, 4 + numAttributes, what + " boundary marker", marker, error))
      return false;
  }
  if (r.Next())
    return r.Fail("unexpected data " + Quoted(r.Text()) + " after the " + std::to_string(count) +
                      " points declared on line " + std::to_string(headerLine),
                  error);
  nodes = std::move(result);
  return true;
}

bool ReadTetGenElements(std::string const& path, int numNodes, int firstIndex,
                        DynamicArray<std::array<int, 4>>& tetrahedra, Error& error) {
  LineReader r;
  if (!r.Open(path, '#', error)) return false;
  if (!r.Next()) return r.Fail("missing header " + std::string(kEleHeader) + ": no data", error);
  int const headerLine = r.Line();
  std::array<int, 3> header = {0, 4, 0};  // tetrahedra, nodes per tetrahedron, attributes
  if (!ReadHeader(r, kEleHeader,
                  {"number of tetrahedra", "nodes per tetrahedron", "number of attributes"}, header,
                  error))
    return false;
  auto const [count, nodesPerTet, numAttributes] = header;
  if (count < 1)
    return FailHeader(r, kEleHeader,
                      "number of tetrahedra must be >= 1, got " + std::to_string(count), error);
  if (nodesPerTet != 4 && nodesPerTet != 10)
    return FailHeader(r, kEleHeader,
                      "nodes per tetrahedron must be 4 or 10, got " + std::to_string(nodesPerTet),
                      error);
  if (numAttributes < 0)
    return FailHeader(r, kEleHeader,
                      "number of attributes must be >= 0, got " + std::to_string(numAttributes),
                      error);

  size_t const numValues = size_t(1) + nodesPerTet + numAttributes;
  std::string const layout =
      std::to_string(numValues) + " (<index> + " + std::to_string(nodesPerTet) + " nodes" +
      (numAttributes ? " + " + std::to_string(numAttributes) + " attributes" : "") + ")";
  int const lastIndex = firstIndex + numNodes - 1;
  DynamicArray<std::array<int, 4>> result;
  result.reserve(std::min(count, kMaxReserve));
  int firstTet = 0;
  for (int t = 0; t < count; ++t) {
    if (!r.Next())
      return r.Fail("unexpected end of file: " + std::to_string(t) + " of the " +
                        std::to_string(count) + " tetrahedra declared on line " +
                        std::to_string(headerLine) + " were read",
                    error);
    if (r.Size() != numValues)
      return r.Fail("tetrahedron line " + CountMismatch(r.Size(), layout), error);
    int index = 0;
    if (!ReadInt(r, 0, "tetrahedron index", index, error)) return false;
    if (t == 0) {
      if (index != 0 && index != 1)
        return r.Fail("first tetrahedron index must be 0 or 1, got " + std::to_string(index),
                      error);
      firstTet = index;
    } else if (index != firstTet + t) {
      return r.Fail("tetrahedron index " + std::to_string(index) + " out of sequence, expected " +
                        std::to_string(firstTet + t),
                    error);
    }
    std::string const what = "tetrahedron " + std::to_string(index);  // the file's numbering
    std::array<int, 10> all{};
    for (int k = 0; k < nodesPerTet; ++k) {
      if (!ReadInt(r, 1 + k, what + " node", all[k], error)) return false;
      if (all[k] < firstIndex || all[k] > lastIndex)
        return r.Fail(what + " node " + std::to_string(all[k]) + " is out of range [" +
                          std::to_string(firstIndex) + ", " + std::to_string(lastIndex) +
                          "] (the .node file's points)",
                      error);
    }
    if (int const k = FindRepeat(all, nodesPerTet); k >= 0)
      return r.Fail(what + " has node " + std::to_string(all[k]) + " more than once", error);
    real attribute;
    for (int a = 0; a < numAttributes; ++a)
      if (!ReadReal(r, 1 + nodesPerTet + a, what + " attribute " + std::to_string(a), false,
                    attribute, error))
        return false;
    result.push_back(
        {all[0] - firstIndex, all[1] - firstIndex, all[2] - firstIndex, all[3] - firstIndex});
  }
  if (r.Next())
    return r.Fail("unexpected data " + Quoted(r.Text()) + " after the " + std::to_string(count) +
                      " tetrahedra declared on line " + std::to_string(headerLine),
                  error);
  tetrahedra = std::move(result);
  return true;
}

/// Drops nodes no element uses (indices must be valid); kept nodes keep their order.
template <size_t N>
int RemoveUnused(DynamicArray<Real3>& nodes, DynamicArray<std::array<int, N>>& elements) {
  DynamicArray<int> newIndex(nodes.size(), -1);
  for (auto const& element : elements)
    for (int n : element) newIndex[n] = 0;
  int numUsed = 0;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (newIndex[i] == 0) {
      newIndex[i] = numUsed;
      nodes[numUsed++] = nodes[i];
    }
  int const removed = static_cast<int>(nodes.size()) - numUsed;
  nodes.resize(numUsed);
  for (auto& element : elements)
    for (int& n : element) n = newIndex[n];
  return removed;
}

// -------------------------------------------------------------------- Gmsh

/// Nodes per element of the standard MSH 2 element types; 0 when unknown.
int GmshNodesPerElement(int type) {
  static constexpr int kTable[] = {0, 2,  3,  4,  4, 8,  6,  5,  3,  6,  9, 10, 27, 18, 14, 1,
                                   8, 20, 15, 13, 9, 10, 12, 15, 15, 21, 4, 5,  6,  20, 35, 56};
  if (type >= 0 && type < static_cast<int>(std::size(kTable))) return kTable[type];
  if (type == 92) return 64;
  if (type == 93) return 125;
  return 0;
}

/// Reads a Gmsh MSH 2 ASCII file, keeping elements of `wantedType` (with N
/// nodes); unused nodes are dropped.
/// The $MeshFormat section: MSH 2.x, ASCII.
bool ReadGmshFormat(LineReader& r, Error& error) {
  // $MeshFormat / version file-type data-size / $EndMeshFormat
  if (!r.Next() || r[0] != "$MeshFormat")
    return r.Fail("missing header: the file must start with $MeshFormat (Gmsh MSH 2.2 ASCII)",
                  error);
  if (!r.Next()) return r.Fail("unexpected end of file in $MeshFormat", error);
  if (r.Size() != 3)
    return r.Fail("$MeshFormat line " + Quoted(r.Text()) + " " +
                      CountMismatch(r.Size(), "3 ('<version> <file-type> <data-size>')"),
                  error);
  real version = 0;
  int fileType = 0;
  if (!ReadReal(r, 0, "MSH version", true, version, error)) return false;
  if (version < 2 || version >= 3)
    return r.Fail("MSH version " + std::string(r[0]) +
                      " is not supported: save the mesh as MSH 2.2 ASCII (gmsh -format msh22)",
                  error);
  if (!ReadInt(r, 1, "file-type", fileType, error)) return false;
  if (fileType != 0)
    return r.Fail("binary MSH (file-type " + std::to_string(fileType) +
                      ") is not supported: save the mesh as ASCII",
                  error);
  if (!r.Next()) return r.Fail("unexpected end of file: $MeshFormat has no $EndMeshFormat", error);
  if (r[0] != "$EndMeshFormat")
    return r.Fail("expected $EndMeshFormat, got " + Quoted(r.Text()), error);

  return true;
}

/// One line of $Elements: its type, tags and nodes checked (every node
/// defined in $Nodes, on line `nodesLine`); an element of `wantedType` is
/// appended to `elements` (indices into the nodes).
template <size_t N>
bool ReadGmshElement(LineReader& r, int wantedType, std::unordered_map<int, int> const& nodeOfId, int nodesLine,
                     DynamicArray<std::array<int, N>>& elements, Error& error) {
  if (r.Size() < 3)
    return r.Fail(
        "element line " + Quoted(r.Text()) + " " +
            CountMismatch(r.Size(),
                          "at least 3 ('<id> <type> <#tags> <tags...> <nodes...>')"),
        error);
  int id = 0, type = 0, numTags = 0;
  if (!ReadInt(r, 0, "element id", id, error) ||
      !ReadInt(r, 1, "element type", type, error) ||
      !ReadInt(r, 2, "number of tags", numTags, error))
    return false;
  std::string const what =
      "element " + std::to_string(id) + " (type " + std::to_string(type) + ")";
  if (numTags < 0)
    return r.Fail(what + ": number of tags must be >= 0, got " + std::to_string(numTags),
                  error);
  for (size_t i = 3; i < r.Size(); ++i) {
    int value;
    if (!ReadInt(r, i, what + (i < 3 + size_t(numTags) ? " tag" : " node"), value, error))
      return false;
  }
  int const numNodes = static_cast<int>(r.Size()) - 3 - numTags;
  int const expected = GmshNodesPerElement(type);
  if (numNodes < 1 || (expected > 0 && numNodes != expected))
    return r.Fail(what + " has " + std::to_string(std::max(numNodes, 0)) +
                      " nodes after its " + std::to_string(numTags) + " tags, expected " +
                      (expected > 0 ? std::to_string(expected) : std::string("at least 1")),
                  error);
  // every element's nodes must exist; only the wanted type is kept
  std::array<int, N> element{};
  for (int k = 0; k < numNodes; ++k) {
    int nodeId = 0;
    ParseInt(r[3 + numTags + k], nodeId);
    auto const it = nodeOfId.find(nodeId);
    if (it == nodeOfId.end())
      return r.Fail(what + " node " + std::to_string(nodeId) +
                        " is not defined in $Nodes (line " + std::to_string(nodesLine) +
                        ")",
                    error);
    if (type == wantedType) element[k] = it->second;
  }
  if (type != wantedType) return true;
  if (int const k = FindRepeat(element); k >= 0)
    return r.Fail(what + " has node " + std::string(r[3 + numTags + k]) + " more than once",
                  error);
  elements.push_back(element);
  return true;
}

template <size_t N>
bool ReadGmsh(std::string const& path, int wantedType, char const* typeName,
              DynamicArray<Real3>& nodesOut, DynamicArray<std::array<int, N>>& elementsOut,
              Error& error) {
  LineReader r;
  if (!r.Open(path, '\0', error)) return false;

  if (!ReadGmshFormat(r, error)) return false;

  DynamicArray<Real3> nodes;
  std::unordered_map<int, int> nodeOfId;      // Gmsh id -> index in `nodes`
  DynamicArray<std::array<int, N>> elements;  // indices into `nodes`
  int nodesLine = 0, elementsLine = 0;

  while (r.Next()) {
    std::string_view const keyword = r[0];
    int const sectionLine = r.Line();
    if (keyword.empty() || keyword.front() != '$')
      return r.Fail("unexpected line " + Quoted(r.Text()) + " outside any $Section", error);
    if (r.Size() != 1)
      return r.Fail("section keyword line " + Quoted(r.Text()) + " has extra values", error);

    if (keyword == "$Nodes" || keyword == "$Elements") {
      bool const isNodes = keyword == "$Nodes";
      std::string const name(keyword.substr(1));
      if ((isNodes ? nodesLine : elementsLine) != 0)
        return r.Fail("second " + std::string(keyword) + " section (the first is on line " +
                          std::to_string(isNodes ? nodesLine : elementsLine) + ")",
                      error);
      if (!isNodes && nodesLine == 0) return r.Fail("$Elements before $Nodes", error);
      (isNodes ? nodesLine : elementsLine) = sectionLine;
      if (!r.Next())
        return r.Fail("unexpected end of file: " + std::string(keyword) + " has no count", error);
      int count = 0;
      if (r.Size() != 1)
        return r.Fail(std::string(keyword) + " count line " + Quoted(r.Text()) + " " +
                          CountMismatch(r.Size(), "1"),
                      error);
      if (!ReadInt(r, 0, std::string(keyword) + " count", count, error)) return false;
      int const countLine = r.Line();
      if (count < 0)
        return r.Fail(std::string(keyword) + " count must be >= 0, got " + std::to_string(count),
                      error);
      std::string const eof = "unexpected end of file: " + std::string(keyword) + " declares " +
                              std::to_string(count) + " on line " + std::to_string(countLine) +
                              ", ";
      auto const early = [&](int read) {
        return Quoted(r.Text()) + " ends " + std::string(keyword) +
               " early: " + std::to_string(count) + " declared on line " +
               std::to_string(countLine) + ", " + std::to_string(read) + " read";
      };
      if (isNodes) {
        nodes.reserve(std::min(count, kMaxReserve));
        for (int i = 0; i < count; ++i) {
          if (!r.Next()) return r.Fail(eof + std::to_string(i) + " were read", error);
          if (r[0].front() == '$') return r.Fail(early(i), error);
          if (r.Size() != 4)
            return r.Fail("node line " + Quoted(r.Text()) + " " +
                              CountMismatch(r.Size(), "4 ('<id> <x> <y> <z>')"),
                          error);
          int id = 0;
          if (!ReadInt(r, 0, "node id", id, error)) return false;
          if (id < 1) return r.Fail("node id must be >= 1, got " + std::to_string(id), error);
          Real3 x;
          if (!ReadPoint(r, 1, "node " + std::to_string(id), x, error)) return false;
          if (!nodeOfId.emplace(id, static_cast<int>(nodes.size())).second)
            return r.Fail("node id " + std::to_string(id) + " appears twice", error);
          nodes.push_back(x);
        }
      } else {
        for (int e = 0; e < count; ++e) {
          if (!r.Next()) return r.Fail(eof + std::to_string(e) + " were read", error);
          if (r[0].front() == '$') return r.Fail(early(e), error);
          if (!ReadGmshElement(r, wantedType, nodeOfId, nodesLine, elements, error)) return false;
        }
      }
      std::string const end = "$End" + name;
      if (!r.Next())
        return r.Fail("unexpected end of file: " + std::string(keyword) + " (line " +
                          std::to_string(sectionLine) + ") has no " + end,
                      error);
      if (r[0] != end)
        return r.Fail("expected " + end + " after the " + std::to_string(count) + " " +
                          (isNodes ? "nodes" : "elements") + " declared on line " +
                          std::to_string(countLine) + ", got " + Quoted(r.Text()),
                      error);
    } else {
      // any other section: skip to its end
      std::string const end = "$End" + std::string(keyword.substr(1));
      bool closed = false;
      while (!closed && r.Next()) closed = r[0] == end;
      if (!closed)
        return r.Fail("unexpected end of file: " + std::string(keyword) + " (line " +
                          std::to_string(sectionLine) + ") has no " + end,
                      error);
    }
  }
  if (nodesLine == 0) return r.Fail("missing $Nodes section", error);
  if (elementsLine == 0) return r.Fail("missing $Elements section", error);
  if (elements.empty())
    return r.FailAt(elementsLine,
                    "no " + std::string(typeName) + " (element type " + std::to_string(wantedType) +
                        ") in $Elements",
                    error);

  // keep only the nodes the elements use, in file order
  RemoveUnused(nodes, elements);
  nodesOut = std::move(nodes);
  elementsOut = std::move(elements);
  return true;
}

// --------------------------------------------------------------- validation

template <size_t N>
bool ValidateMesh(char const* meshName, char const* elementsName, DynamicArray<Real3> const& nodes,
                  DynamicArray<std::array<int, N>> const& elements, Error& error) {
  std::string const mesh(meshName);
  if (nodes.empty()) {
    error.Set(ErrorCode::InvalidArgument, mesh + ".nodes must not be empty");
    return false;
  }
  if (elements.empty()) {
    error.Set(ErrorCode::InvalidArgument, mesh + "." + elementsName + " must not be empty");
    return false;
  }
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!internal::CheckFinite(nodes[i], mesh + ".nodes[" + std::to_string(i) + "]", error))
      return false;
  int const numNodes = static_cast<int>(nodes.size());
  for (size_t e = 0; e < elements.size(); ++e) {
    auto const& element = elements[e];
    std::string const field = mesh + "." + elementsName + "[" + std::to_string(e) + "]";
    for (size_t k = 0; k < N; ++k)
      if (element[k] < 0 || element[k] >= numNodes) {
        error.Set(ErrorCode::InvalidArgument,
                  field + "[" + std::to_string(k) + "] = " + std::to_string(element[k]) +
                      " is out of range [0, " + std::to_string(numNodes) + ")");
        return false;
      }
    if (int const k = FindRepeat(element); k >= 0) {
      error.Set(ErrorCode::InvalidArgument, field + "[" + std::to_string(k) +
                                                "] = " + std::to_string(element[k]) +
                                                " repeats a node of the same element");
      return false;
    }
  }
  // an element listed twice (in any node order) would count its mass and
  // stiffness twice: sort each element's nodes, then the elements
  DynamicArray<std::pair<std::array<int, N>, int>> sorted(elements.size());
  for (size_t e = 0; e < elements.size(); ++e) {
    sorted[e] = {elements[e], static_cast<int>(e)};
    std::sort(sorted[e].first.begin(), sorted[e].first.end());
  }
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i].first == sorted[i - 1].first) {
      int const first = sorted[i - 1].second, second = sorted[i].second;
      std::string nodesText;
      for (int n : elements[second]) nodesText += (nodesText.empty() ? "" : ", ") + std::to_string(n);
      error.Set(ErrorCode::InvalidArgument,
                mesh + "." + elementsName + "[" + std::to_string(second) + "] = {" + nodesText + "} repeats " +
                    elementsName + "[" + std::to_string(first) +
                    "] (the same nodes): its mass and stiffness would count twice");
      return false;
    }
  return true;
}

}  // namespace

// ---------------------------------------------------------------- builders

bool MakeTetBox(Real3 const& origin, Real3 const& size, std::array<int, 3> const& cells,
                TetMesh& mesh, Error& error) {
  using namespace internal;
  if (!CheckFinite(origin, "origin", error) || !CheckPositive(size, "size", error)) return false;
  for (int a = 0; a < 3; ++a)
    if (cells[a] < 1) {
      error.Set(ErrorCode::InvalidArgument,
                "cells must be >= 1 in every component, got (" + std::to_string(cells[0]) + ", " +
                    std::to_string(cells[1]) + ", " + std::to_string(cells[2]) + ")");
      return false;
    }
  int const nx = cells[0], ny = cells[1], nz = cells[2];
  long long const numNodes = (nx + 1LL) * (ny + 1LL) * (nz + 1LL);
  if (6LL * nx * ny * nz > INT_MAX || numNodes > INT_MAX) {
    error.Set(ErrorCode::InvalidArgument, "cells (" + std::to_string(nx) + ", " +
                                              std::to_string(ny) + ", " + std::to_string(nz) +
                                              ") give more than " + std::to_string(INT_MAX) +
                                              " tetrahedra");
    return false;
  }
  TetMesh result;
  result.nodes.reserve(numNodes);
  Real3 const h = size.cwiseQuotient(Real3(nx, ny, nz));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        // the last layer lands exactly on origin + size
        result.nodes.push_back(origin + Real3(i == nx ? size.x() : i * h.x(),
                                              j == ny ? size.y() : j * h.y(),
                                              k == nz ? size.z() : k * h.z()));

  // Cell corners by bits: c = bx + 2 by + 4 bz. Kuhn tetrahedron for the axis
  // order (a, b, c): 0 → e_a → e_a + e_b → 7. Odd permutations have det < 0;
  // their two middle vertices are swapped so that every det is +h_x h_y h_z.
  static constexpr int kKuhn[6][4] = {
      {0, 1, 3, 7},  // x y z (even)
      {0, 5, 1, 7},  // x z y (odd: 0 1 5 7 with the middle swapped)
      {0, 3, 2, 7},  // y x z (odd: 0 2 3 7)
      {0, 2, 6, 7},  // y z x (even)
      {0, 4, 5, 7},  // z x y (even)
      {0, 6, 4, 7},  // z y x (odd: 0 4 6 7)
  };
  int const sx = 1, sy = nx + 1, sz = (nx + 1) * (ny + 1);
  result.tetrahedra.reserve(6LL * nx * ny * nz);
  for (int ck = 0; ck < nz; ++ck)
    for (int cj = 0; cj < ny; ++cj)
      for (int ci = 0; ci < nx; ++ci) {
        int const base = ci * sx + cj * sy + ck * sz;
        std::array<int, 8> corner;
        for (int c = 0; c < 8; ++c)
          corner[c] = base + (c & 1) * sx + ((c >> 1) & 1) * sy + ((c >> 2) & 1) * sz;
        for (auto const& tet : kKuhn)
          result.tetrahedra.push_back(
              {corner[tet[0]], corner[tet[1]], corner[tet[2]], corner[tet[3]]});
      }
  mesh = std::move(result);
  return true;
}

bool MakeTriangleGrid(Real3 const& origin, real sizeX, real sizeZ, int cellsX, int cellsZ,
                      TriangleMesh& mesh, Error& error) {
  using namespace internal;
  if (!CheckFinite(origin, "origin", error) || !CheckPositive(sizeX, "sizeX", error) ||
      !CheckPositive(sizeZ, "sizeZ", error))
    return false;
  if (cellsX < 1 || cellsZ < 1) {
    error.Set(ErrorCode::InvalidArgument, std::string(cellsX < 1 ? "cellsX" : "cellsZ") +
                                              " must be >= 1, got " +
                                              std::to_string(cellsX < 1 ? cellsX : cellsZ));
    return false;
  }
  if (2LL * cellsX * cellsZ > INT_MAX || (cellsX + 1LL) * (cellsZ + 1LL) > INT_MAX) {
    error.Set(ErrorCode::InvalidArgument, "cellsX × cellsZ = " + std::to_string(cellsX) + " × " +
                                              std::to_string(cellsZ) + " is too large");
    return false;
  }
  TriangleMesh result;
  result.nodes.reserve((cellsX + 1LL) * (cellsZ + 1LL));
  real const hx = sizeX / cellsX, hz = sizeZ / cellsZ;
  for (int k = 0; k <= cellsZ; ++k)
    for (int i = 0; i <= cellsX; ++i)
      result.nodes.push_back(origin +
                             Real3(i == cellsX ? sizeX : i * hx, 0, k == cellsZ ? sizeZ : k * hz));
  int const stride = cellsX + 1;
  result.triangles.reserve(2LL * cellsX * cellsZ);
  for (int k = 0; k < cellsZ; ++k)
    for (int i = 0; i < cellsX; ++i) {
      int const n00 = i + stride * k, n10 = n00 + 1, n01 = n00 + stride, n11 = n01 + 1;
      // (x_b − x_a) × (x_c − x_a) = e_z × e_x = +e_y for both
      result.triangles.push_back({n00, n01, n11});
      result.triangles.push_back({n00, n11, n10});
    }
  mesh = std::move(result);
  return true;
}

DynamicArray<std::array<int, 4>> MakeHinges(TriangleMesh const& mesh) {
  // one record per (triangle, local edge), sorted by undirected edge then by
  // appearance: an edge's records are adjacent, its first appearance first
  struct HalfEdge {
    int lo, hi, order;  // order = 3·triangle + local edge
  };
  DynamicArray<HalfEdge> halfEdges;
  halfEdges.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int e = 0; e < 3; ++e) {
      int const a = mesh.triangles[t][e], b = mesh.triangles[t][(e + 1) % 3];
      halfEdges.push_back({std::min(a, b), std::max(a, b), static_cast<int>(3 * t + e)});
    }
  std::sort(halfEdges.begin(), halfEdges.end(), [](HalfEdge const& p, HalfEdge const& q) {
    return std::tie(p.lo, p.hi, p.order) < std::tie(q.lo, q.hi, q.order);
  });
  DynamicArray<std::pair<int, std::array<int, 4>>> hinges;  // (order, hinge)
  for (size_t i = 0; i < halfEdges.size();) {
    size_t j = i + 1;
    while (j < halfEdges.size() && halfEdges[j].lo == halfEdges[i].lo &&
           halfEdges[j].hi == halfEdges[i].hi)
      ++j;
    if (j - i == 2) {
      auto const& first = mesh.triangles[halfEdges[i].order / 3];
      auto const& second = mesh.triangles[halfEdges[i + 1].order / 3];
      int const e1 = halfEdges[i].order % 3, e2 = halfEdges[i + 1].order % 3;
      hinges.push_back(
          {halfEdges[i].order,
           {first[e1], first[(e1 + 1) % 3], first[(e1 + 2) % 3], second[(e2 + 2) % 3]}});
    }
    i = j;
  }
  std::sort(hinges.begin(), hinges.end(),
            [](auto const& p, auto const& q) { return p.first < q.first; });
  DynamicArray<std::array<int, 4>> result;
  result.reserve(hinges.size());
  for (auto const& h : hinges) result.push_back(h.second);
  return result;
}

// ----------------------------------------------------------------- readers

bool ReadTetGen(std::string const& nodeFile, std::string const& eleFile, TetMesh& mesh,
                Error& error) {
  TetMesh result;
  int firstIndex = 0;
  if (!ReadTetGenNodes(nodeFile, result.nodes, firstIndex, error)) return false;
  if (!ReadTetGenElements(eleFile, static_cast<int>(result.nodes.size()), firstIndex,
                          result.tetrahedra, error))
    return false;
  mesh = std::move(result);
  return true;
}

bool ReadGmshTets(std::string const& path, TetMesh& mesh, Error& error) {
  TetMesh result;
  if (!ReadGmsh<4>(path, 4, "tetrahedra", result.nodes, result.tetrahedra, error)) return false;
  mesh = std::move(result);
  return true;
}

bool ReadGmshTriangles(std::string const& path, TriangleMesh& mesh, Error& error) {
  TriangleMesh result;
  if (!ReadGmsh<3>(path, 2, "triangles", result.nodes, result.triangles, error)) return false;
  mesh = std::move(result);
  return true;
}

bool ReadObj(std::string const& path, TriangleMesh& mesh, Error& error) {
  LineReader r;
  if (!r.Open(path, '#', error)) return false;
  TriangleMesh result;
  // positive indices may refer forward: checked at the end against the
  // final vertex count, reported on the face's line
  struct PendingCheck {
    int line, vertex, index;
  };
  DynamicArray<PendingCheck> forward;
  DynamicArray<int> polygon;
  DynamicArray<std::pair<int, int>> corners;  // (vertex, position in the face)
  while (r.Next()) {
    std::string_view const keyword = r[0];
    if (keyword == "v") {
      if (r.Size() < 4)
        return r.Fail("vertex line " + Quoted(r.Text()) + " " +
                          CountMismatch(r.Size(), "at least 4 ('v x y z')"),
                      error);
      std::string const what = "vertex " + std::to_string(result.nodes.size() + 1);
      Real3 x;
      if (!ReadPoint(r, 1, what, x, error)) return false;
      for (size_t i = 4; i < r.Size(); ++i) {
        real extra;
        if (!ReadReal(r, i, what + " value", false, extra, error)) return false;
      }
      result.nodes.push_back(x);
    } else if (keyword == "f") {
      if (r.Size() < 4)
        return r.Fail("face " + Quoted(r.Text()) + " has " + std::to_string(r.Size() - 1) +
                          " vertices, expected at least 3",
                      error);
      polygon.clear();
      for (size_t i = 1; i < r.Size(); ++i) {
        std::string_view const ref = r[i];
        // v, v/vt, v/vt/vn, v//vn
        std::array<std::string_view, 3> parts;
        size_t numParts = 0, start = 0;
        for (;;) {
          size_t const slash = ref.find('/', start);
          if (numParts == 3)
            return r.Fail("face vertex " + Quoted(ref) + " has more than 3 '/'-separated parts",
                          error);
          parts[numParts++] =
              ref.substr(start, slash == std::string_view::npos ? slash : slash - start);
          if (slash == std::string_view::npos) break;
          start = slash + 1;
        }
        int index = 0;
        if (!ParseInt(parts[0], index))
          return r.Fail("face vertex " + Quoted(ref) + ": vertex index " + Quoted(parts[0]) +
                            " is not an integer",
                        error);
        for (size_t p = 1; p < numParts; ++p) {
          int other;
          if (!parts[p].empty() && !ParseInt(parts[p], other))
            return r.Fail("face vertex " + Quoted(ref) + ": " + (p == 1 ? "texture" : "normal") +
                              " index " + Quoted(parts[p]) + " is not an integer",
                          error);
        }
        int const numSoFar = static_cast<int>(result.nodes.size());
        int vertex = 0;
        if (index == 0) {
          return r.Fail(
              "face vertex index 0 is invalid (OBJ indices start at 1; negative ones are relative)",
              error);
        } else if (index < 0) {
          vertex = numSoFar + index;
          if (vertex < 0)
            return r.Fail("relative face vertex index " + std::to_string(index) +
                              " reaches before the first vertex (" + std::to_string(numSoFar) +
                              " defined so far)",
                          error);
        } else {
          vertex = index - 1;
          if (vertex >= numSoFar) forward.push_back({r.Line(), vertex, index});
        }
        polygon.push_back(vertex);
      }
      // a vertex used twice: sort (vertex, position) pairs, O(n log n) in
      // the polygon's size (a single face may have 10⁵ vertices)
      corners.resize(polygon.size());
      for (size_t k = 0; k < polygon.size(); ++k) corners[k] = {polygon[k], static_cast<int>(k)};
      std::sort(corners.begin(), corners.end());
      for (size_t k = 1; k < corners.size(); ++k)
        if (corners[k].first == corners[k - 1].first)
          return r.Fail("face uses vertex " + std::to_string(corners[k].first + 1) + " more than once (as " +
                            Quoted(r[corners[k - 1].second + 1]) + " and " + Quoted(r[corners[k].second + 1]) +
                            ")",
                        error);
      for (size_t k = 1; k + 1 < polygon.size(); ++k)
        result.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
    }
    // every other statement is ignored
  }
  int const numVertices = static_cast<int>(result.nodes.size());
  for (PendingCheck const& check : forward)
    if (check.vertex >= numVertices)
      return r.FailAt(check.line,
                      "face vertex index " + std::to_string(check.index) + " is out of range [1, " +
                          std::to_string(numVertices) + "] (the file's vertices)",
                      error);
  if (result.triangles.empty()) return r.Fail("no faces ('f' lines) in the file", error);
  mesh = std::move(result);
  return true;
}

// -------------------------------------------------------------- validation

bool ValidateTetMesh(TetMesh const& mesh, Error& error) {
  return ValidateMesh("TetMesh", "tetrahedra", mesh.nodes, mesh.tetrahedra, error);
}

bool ValidateTriangleMesh(TriangleMesh const& mesh, Error& error) {
  return ValidateMesh("TriangleMesh", "triangles", mesh.nodes, mesh.triangles, error);
}

int RemoveUnusedNodes(TetMesh& mesh) {
  return RemoveUnused(mesh.nodes, mesh.tetrahedra);
}
int RemoveUnusedNodes(TriangleMesh& mesh) {
  return RemoveUnused(mesh.nodes, mesh.triangles);
}

real SignedVolume(TetMesh const& mesh, int tet) {
  auto const& t = mesh.tetrahedra[tet];
  Real3 const& x0 = mesh.nodes[t[0]];
  return (mesh.nodes[t[1]] - x0).cross(mesh.nodes[t[2]] - x0).dot(mesh.nodes[t[3]] - x0) / 6;
}

}  // namespace superdex
