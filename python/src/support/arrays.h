// Bulk conversions between the library's arrays and numpy, in one C++ loop
// (never a Python loop per element). Outputs are fresh copies the caller
// owns. Inputs accept anything numpy.asarray accepts; a wrong shape or type
// raises mochi.Error(InvalidArgument) naming `field`.
#pragma once

#include <array>
#include <string>

#include "support/errors.h"

namespace superdex::python {

py::array_t<real> ToArray(Span<real const> values);
py::array_t<int> ToArray(Span<int const> values);
/// (n, 3) float64.
py::array_t<real> ToArray(DynamicArray<Real3> const& points);

/// (n, N) int.
template <std::size_t N>
py::array_t<int> ToArray(DynamicArray<std::array<int, N>> const& tuples) {
  py::array_t<int> out({static_cast<py::ssize_t>(tuples.size()), static_cast<py::ssize_t>(N)});
  auto w = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < tuples.size(); ++i)
    for (std::size_t k = 0; k < N; ++k) w(i, k) = tuples[i][k];
  return out;
}

/// numpy.asarray(value), or mochi.Error naming `field`.
py::array AsArray(py::handle value, std::string const& field);

/// A 1-D sequence of numbers.
DynamicArray<real> LoadReals(py::handle value, std::string const& field);
/// A 1-D sequence of integers.
DynamicArray<int> LoadInts(py::handle value, std::string const& field);
/// An (n, 3) array of numbers (empty: any empty sequence).
DynamicArray<Real3> LoadPoints(py::handle value, std::string const& field);
/// An (n, columns) array of integers, row-major into `out` (empty: any empty sequence).
void LoadIntRows(py::handle value, std::string const& field, int columns, DynamicArray<int>& out);

template <std::size_t N>
DynamicArray<std::array<int, N>> LoadIndexTuples(py::handle value, std::string const& field) {
  DynamicArray<int> flat;
  LoadIntRows(value, field, static_cast<int>(N), flat);
  DynamicArray<std::array<int, N>> out(flat.size() / N);
  for (std::size_t i = 0; i < out.size(); ++i)
    for (std::size_t k = 0; k < N; ++k) out[i][k] = flat[N * i + k];
  return out;
}

}  // namespace superdex::python
