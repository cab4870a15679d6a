// Basic numeric and container types of SuperDex.
//
// real      the floating-point type of every simulated quantity (double).
// Real3     a 3-vector (Eigen fixed size).
// Quat      a unit quaternion (Eigen), used for rigid-body rotations.
// _r        literal suffix: 1.5_r is a real.
// Span<T>   a non-owning view of contiguous elements (std::span).
// DynamicArray<T>  an owning, growable array (std::vector).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

namespace superdex {

using real = double;

using Real3 = Eigen::Matrix<real, 3, 1>;
using Real33 = Eigen::Matrix<real, 3, 3>;
using Quat = Eigen::Quaternion<real>;

template <class T>
using Span = std::span<T>;

template <class T>
using DynamicArray = std::vector<T>;

/// Dynamic vectors and matrices for global and variable-size data.
using VectorX = Eigen::Matrix<real, Eigen::Dynamic, 1>;
using MatrixX = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic>;

inline namespace literals {
constexpr real operator""_r(long double v) { return static_cast<real>(v); }
constexpr real operator""_r(unsigned long long v) { return static_cast<real>(v); }
}  // namespace literals

}  // namespace superdex
