#include <superdex/core/so3.h>

#include <cmath>

namespace superdex {

Real33 Hat(Real3 const& a) {
  Real33 m;
  m << 0, -a.z(), a.y(),  //
      a.z(), 0, -a.x(),   //
      -a.y(), a.x(), 0;
  return m;
}

Quat Exp(Real3 const& phi) {
  real const theta2 = phi.squaredNorm();
  real const theta = std::sqrt(theta2);
  // sin(θ/2)/θ and cos(θ/2), by series below θ = 1e-4 (error < 1e-18)
  real s, c;
  if (theta < 1e-4) {
    s = 0.5 - theta2 / 48;
    c = 1 - theta2 / 8;
  } else {
    s = std::sin(theta / 2) / theta;
    c = std::cos(theta / 2);
  }
  return Quat(c, s * phi.x(), s * phi.y(), s * phi.z());
}

Real33 ExpMatrix(Real3 const& phi) { return Exp(phi).toRotationMatrix(); }

Real3 Log(Quat const& qIn) {
  // take the hemisphere w >= 0 so that the angle is in [0, π]
  Quat q = qIn.w() < 0 ? Quat(-qIn.coeffs()) : qIn;
  Real3 const v = q.vec();
  real const n = v.norm();
  real const w = q.w();
  // θ = 2 atan2(|v|, w); φ = θ/|v| · v, the ratio by series when |v| is tiny
  real scale;
  if (n < 1e-8) {
    scale = 2 / w * (1 - n * n / (3 * w * w));
  } else {
    scale = 2 * std::atan2(n, w) / n;
  }
  return scale * v;
}

Real3 Log(Real33 const& rotation) { return Log(Quat(rotation)); }

namespace {
// Coefficients of J_l(φ) = I + a Hat(φ) + b Hat(φ)²:
//   a = (1 − cos θ)/θ², b = (θ − sin θ)/θ³
void LeftJacobianCoefficients(real theta, real& a, real& b) {
  real const t2 = theta * theta;
  if (theta < 1e-3) {
    a = 0.5 - t2 / 24 + t2 * t2 / 720;
    b = 1.0 / 6 - t2 / 120 + t2 * t2 / 5040;
  } else {
    a = (1 - std::cos(theta)) / t2;
    b = (theta - std::sin(theta)) / (t2 * theta);
  }
}
}  // namespace

real LeftJacobianInverseCoefficient(real theta) {
  real const t2 = theta * theta;
  if (theta < 1e-3) return 1.0 / 12 + t2 / 720 + t2 * t2 / 30240;
  return 1 / t2 - std::cos(theta / 2) / (2 * theta * std::sin(theta / 2));
}

real LeftJacobianInverseCoefficientRate(real theta) {
  // γ′(θ) = −2/θ³ + cot(θ/2)/(2θ²) + 1/(4θ sin²(θ/2)); below 0.1 rad its
  // terms cancel to ~1e-9, where the series (γ = 1/12 + θ²/720 + θ⁴/30240 +
  // θ⁶/1209600 + …, differentiated) is exact to round-off
  real const t2 = theta * theta;
  if (theta < 0.1) return 1.0 / 360 + t2 / 7560 + t2 * t2 / 201600;
  real const sine = std::sin(theta / 2), cotangent = std::cos(theta / 2) / sine;
  return (-2 / (t2 * theta) + cotangent / (2 * t2) + 1 / (4 * theta * sine * sine)) / theta;
}

Real33 LeftJacobian(Real3 const& phi) {
  real a, b;
  LeftJacobianCoefficients(phi.norm(), a, b);
  Real33 const h = Hat(phi);
  return Real33::Identity() + a * h + b * h * h;
}

Real33 LeftJacobianInverse(Real3 const& phi) {
  real const c = LeftJacobianInverseCoefficient(phi.norm());
  Real33 const h = Hat(phi);
  return Real33::Identity() - 0.5 * h + c * h * h;
}

Real33 RightJacobian(Real3 const& phi) { return LeftJacobian(-phi); }
Real33 RightJacobianInverse(Real3 const& phi) { return LeftJacobianInverse(-phi); }

}  // namespace superdex
