#include <superdex/contact/barrier.h>

#include <superdex/core/symmetric_eigen.h>

#include <cmath>
#include <limits>

namespace superdex::contact {

namespace {
constexpr real kInfinity = std::numeric_limits<real>::infinity();
}  // namespace

// ----------------------------------------------------------------- barrier

real Barrier(real s) {
  if (!(s > 0)) return kInfinity;
  if (s >= 1) return 0;
  return -(s - 1) * (s - 1) * std::log(s);
}

real BarrierDerivative(real s) {
  if (!(s > 0)) return -kInfinity;
  if (s >= 1) return 0;
  return -2 * (s - 1) * std::log(s) - (s - 1) * (s - 1) / s;
}

real BarrierSecondDerivative(real s) {
  if (!(s > 0)) return kInfinity;
  if (s >= 1) return 0;
  return -2 * std::log(s) + (1 - s) * (1 + 3 * s) / (s * s);
}

template <int n>
ValueGradientHessian<n> BarrierEnergy(ValueGradientHessian<n> const& distance2,
                                      BarrierParams const& params, BarrierHessian hessianForm) {
  ValueGradientHessian<n> e;
  real const q = distance2.value;
  real const r = std::sqrt(q);
  real const d = r - params.thickness;
  real const dHat = params.activationDistance;
  // inactive beyond d̂; a penetration (or a NaN distance) has infinite energy
  if (d >= dHat) return e;
  if (!(d > 0)) {
    e.value = kInfinity;
    return e;
  }
  // chain rule through q = d²: φ′ = dE/dq, φ″ = d²E/dq² (see BarrierHessian)
  real const s = d / dHat;
  real const k = params.stiffnessArea;
  real const b1 = BarrierDerivative(s);
  real const b2 = BarrierSecondDerivative(s);
  real const slope = k * b1 / (2 * r);
  real const curvature = k * (b2 / (4 * dHat * q) - b1 / (4 * q * r));
  e.value = k * dHat * Barrier(s);
  e.gradient = slope * distance2.gradient;
  e.hessian = curvature * distance2.gradient * distance2.gradient.transpose();
  if (hessianForm == BarrierHessian::GaussNewton) return e;
  e.hessian += slope * distance2.hessian;
  if (hessianForm == BarrierHessian::Projected) e.hessian = ProjectToPsd<n>(e.hessian);
  return e;
}

template <int n>
LocalMatrix<n> ProjectToPsd(LocalMatrix<n> const& a) {
  auto const eigen = ComputeSymmetricEigen(a);
  LocalVector<n> const lambda = eigen.values;
  if (lambda.minCoeff() >= 0) return a;
  LocalMatrix<n> const scaled = eigen.vectors * lambda.cwiseMax(real(0)).asDiagonal();
  return scaled * eigen.vectors.transpose();
}

// --------------------------------------------------------- friction ramp

real FrictionRamp(real x, real saturation) {
  real const g = saturation;
  if (x < g) return x * x / g - x * x * x / (3 * g * g);
  return x - g / 3;
}

real FrictionRampDerivative(real x, real saturation) {
  real const g = saturation;
  if (x < g) return x * (2 * g - x) / (g * g);
  return 1;
}

real FrictionRampSecondDerivative(real x, real saturation) {
  real const g = saturation;
  if (x < g) return 2 * (g - x) / (g * g);
  return 0;
}

real FrictionRampDerivativeOverX(real x, real saturation) {
  real const g = saturation;
  if (x < g) return (2 * g - x) / (g * g);
  return 1 / x;
}

TangentialFriction EvaluateTangentialFriction(Vector2 const& u, real muLambda, real saturation) {
  TangentialFriction f;
  real const x = u.norm();
  real const ratio = FrictionRampDerivativeOverX(x, saturation);
  f.energy = muLambda * FrictionRamp(x, saturation);
  f.gradient = muLambda * ratio * u;
  // μλ [ρ″ ûûᵀ + (ρ′/x)(I − ûûᵀ)] = μλ [(ρ′/x) I + (ρ″ − ρ′/x) ûûᵀ]; the
  // second term vanishes at x = 0 (ρ″ − ρ′/x = −x/ḡ² there), leaving (2μλ/ḡ) I
  f.hessian = muLambda * ratio * Matrix2::Identity();
  if (x > 0) {
    Vector2 const direction = u / x;
    real const radial = FrictionRampSecondDerivative(x, saturation) - ratio;
    f.hessian += muLambda * radial * direction * direction.transpose();
  }
  return f;
}

template <int n>
ValueGradientHessian<n> MapTangentialFriction(TangentialFriction const& friction,
                                              TangentFrame<n> const& frame) {
  Eigen::Matrix<real, 2, n> const map = frame.basis.transpose() * frame.weights;  // Tᵀ Γ
  ValueGradientHessian<n> r;
  r.value = friction.energy;
  r.gradient = map.transpose() * friction.gradient;
  r.hessian = map.transpose() * friction.hessian * map;
  return r;
}

template <int n>
ValueGradientHessian<n> FrictionEnergy(LocalVector<n> const& displacement,
                                       TangentFrame<n> const& frame, real muLambda,
                                       real saturation) {
  Vector2 const u = frame.basis.transpose() * (frame.weights * displacement);
  return MapTangentialFriction(EvaluateTangentialFriction(u, muLambda, saturation), frame);
}

// ------------------------------------------------- instantiations

#define SUPERDEX_CONTACT_INSTANTIATE(n)                                                    \
  template ValueGradientHessian<n> BarrierEnergy<n>(ValueGradientHessian<n> const&,        \
                                                    BarrierParams const&, BarrierHessian); \
  template LocalMatrix<n> ProjectToPsd<n>(LocalMatrix<n> const&);                          \
  template ValueGradientHessian<n> MapTangentialFriction<n>(TangentialFriction const&,     \
                                                            TangentFrame<n> const&);       \
  template ValueGradientHessian<n> FrictionEnergy<n>(LocalVector<n> const&,                \
                                                     TangentFrame<n> const&, real, real);
SUPERDEX_CONTACT_INSTANTIATE(6)
SUPERDEX_CONTACT_INSTANTIATE(9)
SUPERDEX_CONTACT_INSTANTIATE(12)
#undef SUPERDEX_CONTACT_INSTANTIATE
template Matrix2 ProjectToPsd<2>(Matrix2 const&);

}  // namespace superdex::contact
