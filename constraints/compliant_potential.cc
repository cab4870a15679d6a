#include <superdex/constraints/compliant_potential.h>

namespace superdex::internal {

real CompliantElasticEnergy(CompliantParams const& p, real x) {
  real const k = p.stiffness;
  if (!p.IsSaturated()) return 0.5 * k * x * x;
  real const s = p.saturation;
  if (x < s) return k * (x * x - x * x * x / (3 * s));  // k ḡ (x²/ḡ − x³/(3ḡ²))
  return k * s * (x - s / 3);
}

real CompliantKappa(CompliantParams const& p, real x) {
  real const k = p.stiffness;
  if (!p.IsSaturated()) return k;
  real const s = p.saturation;
  if (x < s) return k * (2 - x / s);
  return k * s / x;
}

CompliantParams NearRigidParams(CompliantParams const& p, real h, real beta, real w, bool& capped) {
  capped = false;
  if (!(beta > 0) || !(w > 0)) return p;
  constexpr real kTwoPi = 6.283185307179586476925286766559;
  real const maxScale = kTwoPi * kTwoPi / (beta * beta * h * h * w);
  real const scale = p.stiffness + p.damping / h;
  if (!(scale > maxScale)) return p;
  capped = true;
  real const c = maxScale / scale;
  CompliantParams result = p;
  // d = 0: k_eff is s_max itself, not s_max/k·k rounded
  result.stiffness = p.damping == 0 ? maxScale : c * p.stiffness;
  result.damping = c * p.damping;
  if (p.IsSaturated()) result.saturation = p.saturation / c;
  return result;
}

bool IsRangeInactive(Eigen::Ref<VectorX const> const& g, Eigen::Ref<VectorX const> const& gStart) {
  return (g.array() == 0).all() && (gStart.array() == 0).all();
}

real CompliantEnergy(CompliantParams const& p, Eigen::Ref<VectorX const> const& g,
                     Eigen::Ref<VectorX const> const& gStart, real h) {
  real const damping = p.damping > 0 ? p.damping / (2 * h) * (g - gStart).squaredNorm() : 0;
  return CompliantElasticEnergy(p, g.norm()) + damping;
}

real CompliantForceCoefficients(CompliantParams const& p, Eigen::Ref<VectorX const> const& g,
                                Eigen::Ref<VectorX const> const& gStart, real h,
                                Eigen::Ref<VectorX> f) {
  real const kappa = CompliantKappa(p, g.norm());
  real const dOverH = p.damping / h;
  f = kappa * g + dOverH * (g - gStart);
  return kappa + dOverH;
}

}  // namespace superdex::internal
