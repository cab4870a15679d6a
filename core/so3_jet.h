// SO(3) maps over second-order jets (core/jet.h), for exact Hessians of
// functions of rotations: a rotation matrix whose entries are jets in N
// variables, built from rotation increments, multiplied, and mapped back to a
// rotation vector by Log — value, gradient and Hessian carried through.
//
// Increments enter through Exp(u) at u = 0. Only derivatives at u = 0 are
// ever needed, so Exp is carried to second order, Exp(u) = I + Û + ½Û², which
// has the exact value, gradient and Hessian there.
//
// Log(M) = θ/(2 sin θ) vee(M − Mᵀ), θ = atan2(|vee|/2, (tr M − 1)/2). Near
// θ = 0, |vee| has no derivative, so θ/sin θ is taken from its series in
// s² = sin²θ = |vee|²/4 (θ/sin θ = arcsin(s)/s for θ < π/2).
#pragma once

#include <array>

#include <superdex/core/jet.h>
#include <superdex/core/types.h>

namespace superdex::internal {

template <int N>
using JetVector3 = std::array<Jet<N>, 3>;
template <int N>
using JetMatrix3 = std::array<std::array<Jet<N>, 3>, 3>;

/// Three consecutive independent variables at 0: (u₀, u₁, u₂) = variables
/// first, first + 1, first + 2.
template <int N>
JetVector3<N> JetIncrement(int first) {
  return {Jet<N>::Variable(0, first), Jet<N>::Variable(0, first + 1), Jet<N>::Variable(0, first + 2)};
}

/// A constant matrix as jets.
template <int N>
JetMatrix3<N> ToJetMatrix(Real33 const& m) {
  JetMatrix3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = Jet<N>(m(i, j));
  return r;
}

/// Exp(u) to second order at u = 0: I + Û + ½Û² (exact value, gradient and
/// Hessian there).
template <int N>
JetMatrix3<N> ExpSecondOrder(JetVector3<N> const& u) {
  JetMatrix3<N> hat;
  hat[0][1] = -u[2];
  hat[0][2] = u[1];
  hat[1][0] = u[2];
  hat[1][2] = -u[0];
  hat[2][0] = -u[1];
  hat[2][1] = u[0];
  JetMatrix3<N> e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      Jet<N> sum = (r == c) ? Jet<N>(1) : Jet<N>(0);
      sum = sum + hat[r][c];
      for (int k = 0; k < 3; ++k) sum = sum + 0.5 * (hat[r][k] * hat[k][c]);
      e[r][c] = sum;
    }
  return e;
}

template <int N>
JetMatrix3<N> Multiply(JetMatrix3<N> const& a, JetMatrix3<N> const& b) {
  JetMatrix3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
  return r;
}
template <int N>
JetMatrix3<N> Multiply(Real33 const& a, JetMatrix3<N> const& b) {
  JetMatrix3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a(i, 0) * b[0][j] + a(i, 1) * b[1][j] + a(i, 2) * b[2][j];
  return r;
}
template <int N>
JetMatrix3<N> Multiply(JetMatrix3<N> const& a, Real33 const& b) {
  JetMatrix3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[i][0] * b(0, j) + a[i][1] * b(1, j) + a[i][2] * b(2, j);
  return r;
}
template <int N>
JetMatrix3<N> Transpose(JetMatrix3<N> const& a) {
  JetMatrix3<N> r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = a[j][i];
  return r;
}

/// The rotation vector of a rotation matrix of jets, |Log| ∈ [0, π).
template <int N>
JetVector3<N> LogJet(JetMatrix3<N> const& m) {
  JetVector3<N> const vee{m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]};
  Jet<N> const cosine = 0.5 * (m[0][0] + m[1][1] + m[2][2] - 1);
  Jet<N> const vee2 = vee[0] * vee[0] + vee[1] * vee[1] + vee[2] * vee[2];
  Jet<N> factor;  // θ/(2 sin θ)
  if (vee2.value < 1e-4 && cosine.value > 0) {
    // θ/sin θ = 1 + x/6 + 3x²/40 + 5x³/112 + 35x⁴/1152, x = sin²θ < 2.5e-5
    Jet<N> const x = 0.25 * vee2;
    factor = 0.5 * (1 + x * (1.0 / 6 + x * (3.0 / 40 + x * (5.0 / 112 + x * (35.0 / 1152)))));
  } else {
    Jet<N> const sine = 0.5 * sqrt(vee2);
    factor = atan2(sine, cosine) / (2 * sine);
  }
  return {factor * vee[0], factor * vee[1], factor * vee[2]};
}

}  // namespace superdex::internal
