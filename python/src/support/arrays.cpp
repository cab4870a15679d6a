#include "support/arrays.h"

#include <cstdint>
#include <limits>
#include <type_traits>

namespace superdex::python {

namespace {

std::string ShapeText(py::array const& a) {
  std::string text = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) text += (d ? ", " : "") + std::to_string(a.shape(d));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

[[noreturn]] void BadShape(std::string const& field, std::string const& expected,
                           py::array const& a) {
  Raise(ErrorCode::InvalidArgument, field + " must be " + expected + ", got shape " + ShapeText(a));
}

bool IsIntegerKind(py::array const& a) {
  char const kind = a.dtype().kind();
  return kind == 'i' || kind == 'u';
}

/// The integers of `a` (row-major) into `out`, each checked to fit an int
/// (64-bit indices are never truncated); an entry is named field[i] or, with
/// `columns` > 0, field[i][j].
template <class Wide>
void CopyInts(py::array const& a, std::string const& field, int columns, DynamicArray<int>& out) {
  auto const values = py::array_t<Wide, py::array::c_style | py::array::forcecast>::ensure(a);
  out.resize(static_cast<std::size_t>(values.size()));
  Wide const* data = values.data();
  for (std::size_t k = 0; k < out.size(); ++k) {
    bool const fits = std::is_signed_v<Wide>
                          ? (data[k] >= Wide(std::numeric_limits<int>::min()) &&
                             data[k] <= Wide(std::numeric_limits<int>::max()))
                          : data[k] <= Wide(std::numeric_limits<int>::max());
    if (!fits) {
      std::string const where = columns > 0 ? "[" + std::to_string(k / columns) + "][" +
                                                  std::to_string(k % columns) + "]"
                                            : "[" + std::to_string(k) + "]";
      Raise(ErrorCode::InvalidArgument, field + where + " = " + std::to_string(data[k]) +
                                            " does not fit a 32-bit index (at most " +
                                            std::to_string(std::numeric_limits<int>::max()) + ")");
    }
    out[k] = static_cast<int>(data[k]);
  }
}

void LoadIntegers(py::array const& a, std::string const& field, int columns, DynamicArray<int>& out) {
  if (!IsIntegerKind(a)) Raise(ErrorCode::InvalidArgument, field + " must contain integers");
  if (a.dtype().kind() == 'u')
    CopyInts<std::uint64_t>(a, field, columns, out);
  else
    CopyInts<std::int64_t>(a, field, columns, out);
}

}  // namespace

py::array_t<real> ToArray(Span<real const> values) {
  py::array_t<real> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

py::array_t<int> ToArray(Span<int const> values) {
  py::array_t<int> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

py::array_t<real> ToArray(DynamicArray<Real3> const& points) {
  py::array_t<real> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
  auto w = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) w(i, k) = points[i][k];
  return out;
}

py::array AsArray(py::handle value, std::string const& field) {
  py::array a = py::array::ensure(value);
  if (!a)
    Raise(ErrorCode::InvalidArgument,
          field + " must be array-like, got " + std::string(py::repr(value)));
  return a;
}

DynamicArray<real> LoadReals(py::handle value, std::string const& field) {
  py::array const a = AsArray(value, field);
  if (a.size() == 0) return {};
  if (a.ndim() != 1) BadShape(field, "a 1-D sequence of numbers", a);
  auto values = py::array_t<real, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!values) Raise(ErrorCode::InvalidArgument, field + " must contain numbers");
  return DynamicArray<real>(values.data(), values.data() + values.size());
}

DynamicArray<int> LoadInts(py::handle value, std::string const& field) {
  py::array const a = AsArray(value, field);
  if (a.size() == 0) return {};
  if (a.ndim() != 1) BadShape(field, "a 1-D sequence of integers", a);
  DynamicArray<int> out;
  LoadIntegers(a, field, 0, out);
  return out;
}

DynamicArray<Real3> LoadPoints(py::handle value, std::string const& field) {
  py::array const a = AsArray(value, field);
  if (a.size() == 0) return {};
  if (a.ndim() != 2 || a.shape(1) != 3) BadShape(field, "an (n, 3) array", a);
  auto values = py::array_t<real, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!values) Raise(ErrorCode::InvalidArgument, field + " must contain numbers");
  auto r = values.unchecked<2>();
  DynamicArray<Real3> out(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i) out[i] = Real3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

void LoadIntRows(py::handle value, std::string const& field, int columns, DynamicArray<int>& out) {
  out.clear();
  py::array const a = AsArray(value, field);
  if (a.size() == 0) return;
  if (a.ndim() != 2 || a.shape(1) != columns)
    BadShape(field, "an (n, " + std::to_string(columns) + ") array of integers", a);
  LoadIntegers(a, field, columns, out);
}

}  // namespace superdex::python
