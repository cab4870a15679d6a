// Jet<N>: a second-order forward-mode automatic-differentiation scalar over N
// independent variables — value f, gradient ∇f (N) and Hessian ∇²f (N×N,
// symmetric) carried together through arithmetic.
//
// Used where an element's exact Hessian is needed but its closed form is
// long and error-prone (the rod's bending–twist stencil, actors/rod_element.h).
// Every operation is the chain rule for a scalar function φ of one or two
// jets: for φ(a),  ∇φ = φ' ∇a,  ∇²φ = φ' ∇²a + φ'' ∇a ∇aᵀ.
// Sizes are fixed, so nothing is allocated.
#pragma once

#include <array>
#include <cmath>

#include <superdex/core/types.h>

namespace superdex::internal {

template <int N>
struct Jet {
  using Vector = Eigen::Matrix<real, N, 1>;
  using Matrix = Eigen::Matrix<real, N, N>;

  real value = 0;
  Vector gradient = Vector::Zero();
  Matrix hessian = Matrix::Zero();

  Jet() = default;
  /// A constant.
  Jet(real v) : value(v) {}  // NOLINT: constants mix freely with jets
  /// The independent variable `index` with value v.
  static Jet Variable(real v, int index) {
    Jet x(v);
    x.gradient[index] = 1;
    return x;
  }

  /// φ(a) given φ(a.value), φ'(a.value), φ''(a.value).
  static Jet Apply(Jet const& a, real f, real df, real ddf) {
    Jet r;
    r.value = f;
    r.gradient = df * a.gradient;
    r.hessian = df * a.hessian + ddf * a.gradient * a.gradient.transpose();
    return r;
  }
};

template <int N>
Jet<N> operator+(Jet<N> a, Jet<N> const& b) {
  a.value += b.value;
  a.gradient += b.gradient;
  a.hessian += b.hessian;
  return a;
}
template <int N>
Jet<N> operator-(Jet<N> a, Jet<N> const& b) {
  a.value -= b.value;
  a.gradient -= b.gradient;
  a.hessian -= b.hessian;
  return a;
}
template <int N>
Jet<N> operator-(Jet<N> a) {
  a.value = -a.value;
  a.gradient = -a.gradient;
  a.hessian = -a.hessian;
  return a;
}
template <int N>
Jet<N> operator*(Jet<N> const& a, Jet<N> const& b) {
  Jet<N> r;
  r.value = a.value * b.value;
  r.gradient = a.value * b.gradient + b.value * a.gradient;
  typename Jet<N>::Matrix const cross = a.gradient * b.gradient.transpose();
  r.hessian = a.value * b.hessian + b.value * a.hessian + cross + cross.transpose();
  return r;
}
template <int N>
Jet<N> operator*(real s, Jet<N> a) {
  a.value *= s;
  a.gradient *= s;
  a.hessian *= s;
  return a;
}
template <int N>
Jet<N> operator*(Jet<N> a, real s) {
  return s * a;
}
template <int N>
Jet<N> operator+(Jet<N> a, real s) {
  a.value += s;
  return a;
}
template <int N>
Jet<N> operator+(real s, Jet<N> a) {
  a.value += s;
  return a;
}
template <int N>
Jet<N> operator-(Jet<N> a, real s) {
  a.value -= s;
  return a;
}
template <int N>
Jet<N> operator-(real s, Jet<N> const& a) {
  return s + (-a);
}
/// 1/a
template <int N>
Jet<N> Reciprocal(Jet<N> const& a) {
  real const inv = 1 / a.value;
  return Jet<N>::Apply(a, inv, -inv * inv, 2 * inv * inv * inv);
}
template <int N>
Jet<N> operator/(Jet<N> const& a, Jet<N> const& b) {
  return a * Reciprocal(b);
}
template <int N>
Jet<N> operator/(real s, Jet<N> const& a) {
  return s * Reciprocal(a);
}
template <int N>
Jet<N> operator/(Jet<N> const& a, real s) {
  return (1 / s) * a;
}
template <int N>
Jet<N> sqrt(Jet<N> const& a) {
  real const s = std::sqrt(a.value);
  return Jet<N>::Apply(a, s, 0.5 / s, -0.25 / (s * a.value));
}
template <int N>
Jet<N> sin(Jet<N> const& a) {
  real const s = std::sin(a.value), c = std::cos(a.value);
  return Jet<N>::Apply(a, s, c, -s);
}
template <int N>
Jet<N> cos(Jet<N> const& a) {
  real const s = std::sin(a.value), c = std::cos(a.value);
  return Jet<N>::Apply(a, c, -s, -c);
}
/// atan2(y, x) with the derivatives of the angle; the value's branch is
/// std::atan2's (callers that need a continuous angle add a constant 2πk).
template <int N>
Jet<N> atan2(Jet<N> const& y, Jet<N> const& x) {
  // θ = atan2(y, x): dθ = (x dy − y dx)/r², second derivatives by the
  // product rule on that expression
  real const r2 = x.value * x.value + y.value * y.value;
  Jet<N> r;
  r.value = std::atan2(y.value, x.value);
  typename Jet<N>::Vector const dy = y.gradient / r2, dx = x.gradient / r2;
  r.gradient = x.value * dy - y.value * dx;
  // d(x/r²) = dx/r² − 2x (x dx + y dy)/r⁴, d(y/r²) likewise
  typename Jet<N>::Vector const dr2 = 2 * (x.value * x.gradient + y.value * y.gradient) / r2;
  typename Jet<N>::Vector const dxOverR2 = dx - (x.value / r2) * dr2;
  typename Jet<N>::Vector const dyOverR2 = dy - (y.value / r2) * dr2;
  r.hessian = x.value * (y.hessian / r2) - y.value * (x.hessian / r2) + dxOverR2 * y.gradient.transpose() -
              dyOverR2 * x.gradient.transpose();
  r.hessian = (0.5 * (r.hessian + r.hessian.transpose())).eval();
  return r;
}

}  // namespace superdex::internal
