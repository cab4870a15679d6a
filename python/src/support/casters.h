// The pybind11 headers every binding file uses, and the one conversion
// pybind11 lacks: Quat (Eigen::Quaternion) <-> a numpy array (w, x, y, z).
//
// Conventions of the module (docs/python.md):
//   Real3, Real33, VectorX, MatrixX  numpy arrays (pybind11/eigen.h); a Real3
//                                    argument accepts any 3-sequence
//   Quat                             numpy array [w, x, y, z]; an argument
//                                    accepts any 4-sequence in that order
//                                    (the order of Eigen's Quat(w, x, y, z)
//                                    constructor, scalar first)
// Every binding file includes this header first, so that every translation
// unit sees the same casters (pybind11 requires it).
#pragma once

#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <superdex/superdex.h>

namespace pybind11::detail {

template <>
struct type_caster<superdex::Quat> {
 public:
  PYBIND11_TYPE_CASTER(superdex::Quat, const_name("numpy.ndarray[4] (w, x, y, z)"));

  /// Accepts a float64 array of 4 entries; with `convert`, any 4-sequence of numbers.
  bool load(handle src, bool convert) {
    if (!convert && !isinstance<array_t<double>>(src)) return false;
    auto values = array_t<double, array::forcecast>::ensure(src);
    if (!values || values.ndim() != 1 || values.shape(0) != 4) return false;
    value = superdex::Quat(values.at(0), values.at(1), values.at(2), values.at(3));
    return true;
  }

  static handle cast(superdex::Quat const& q, return_value_policy /*policy*/, handle /*parent*/) {
    array_t<double> out(4);
    auto w = out.mutable_unchecked<1>();
    w(0) = q.w();
    w(1) = q.x();
    w(2) = q.y();
    w(3) = q.z();
    return out.release();
  }
};

}  // namespace pybind11::detail

namespace superdex::python {
namespace py = pybind11;
}  // namespace superdex::python
