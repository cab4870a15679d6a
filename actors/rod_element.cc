#include <superdex/actors/rod_element.h>

#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include <superdex/core/jet.h>
#include <superdex/core/so3.h>

namespace superdex::internal {

namespace {

// ---- small vector algebra over a scalar type S (real or Jet<N>) ----
template <class S>
using Vec3 = std::array<S, 3>;

real ValueOf(real s) { return s; }
template <int N>
real ValueOf(Jet<N> const& s) {
  return s.value;
}

template <class S>
S Dot(Vec3<S> const& a, Vec3<S> const& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S>
S Dot(Vec3<S> const& a, Real3 const& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class S>
Vec3<S> Cross(Vec3<S> const& a, Vec3<S> const& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class S>
Vec3<S> Sum(Vec3<S> const& x, Vec3<S> const& y) {
  return {x[0] + y[0], x[1] + y[1], x[2] + y[2]};
}
template <class S>
Vec3<S> Combine(S const& a, Vec3<S> const& x, S const& b, Vec3<S> const& y) {
  return {a * x[0] + b * y[0], a * x[1] + b * y[1], a * x[2] + b * y[2]};
}

/// P(t⁰→t) u⁰ = u⁰ − (t·u⁰)/(1 + t⁰·t) (t⁰ + t), for the stage reference frame.
template <class S>
Vec3<S> Transport(RodReferenceFrame const& ref, Vec3<S> const& t) {
  S const s = Dot(t, ref.director) / (1 + Dot(t, ref.tangent));
  return {ref.director[0] - s * (ref.tangent[0] + t[0]), ref.director[1] - s * (ref.tangent[1] + t[1]),
          ref.director[2] - s * (ref.tangent[2] + t[2])};
}

template <class S>
struct ElementFrame {
  Vec3<S> t, u, d1, d2;
};

template <class S>
ElementFrame<S> MakeFrame(Vec3<S> const& edge, RodReferenceFrame const& ref, S const& theta) {
  using std::cos;
  using std::sin;
  using std::sqrt;
  ElementFrame<S> f;
  S const inverseLength = 1 / sqrt(Dot(edge, edge));
  f.t = {edge[0] * inverseLength, edge[1] * inverseLength, edge[2] * inverseLength};
  f.u = Transport(ref, f.t);
  Vec3<S> const v = Cross(f.t, f.u);
  S const c = cos(theta), s = sin(theta);
  f.d1 = Combine(c, f.u, s, v);
  f.d2 = Combine(-s, f.u, c, v);
  return f;
}

/// m_ref: the angle about t_b from P(tₐ→t_b) uₐ to u_b, on the branch
/// nearest `start`; `onePlusCos` = 1 + tₐ·t_b.
template <class S>
S ReferenceTwist(ElementFrame<S> const& a, ElementFrame<S> const& b, S const& onePlusCos, real start) {
  using std::atan2;
  S const s = Dot(b.t, a.u) / onePlusCos;
  Vec3<S> const p = {a.u[0] - s * (a.t[0] + b.t[0]), a.u[1] - s * (a.t[1] + b.t[1]),
                     a.u[2] - s * (a.t[2] + b.t[2])};
  S const angle = atan2(Dot(Cross(p, b.u), b.t), Dot(p, b.u));
  constexpr real kTwoPi = 2 * std::numbers::pi_v<real>;
  return angle + kTwoPi * std::round((start - ValueOf(angle)) / kTwoPi);
}

/// (κ₁, κ₂, m) from the two elements' frames and twists.
template <class S>
Vec3<S> StrainFromFrames(ElementFrame<S> const& a, ElementFrame<S> const& b, S const& thetaA, S const& thetaB,
                         real refTwistStart) {
  S const onePlusCos = 1 + Dot(a.t, b.t);
  S const half = 1 / onePlusCos;             // ½ κb = binormal / (1 + tₐ·t_b)
  Vec3<S> const binormal = Cross(a.t, b.t);
  return {half * Dot(binormal, Sum(a.d1, b.d1)), half * Dot(binormal, Sum(a.d2, b.d2)),
          thetaB - thetaA + ReferenceTwist(a, b, onePlusCos, refTwistStart)};
}

template <class S>
Vec3<S> StencilStrain(Vec3<S> const& edgeA, Vec3<S> const& edgeB, S const& thetaA, S const& thetaB,
                      RodReferenceFrame const& refA, RodReferenceFrame const& refB, real refTwistStart) {
  return StrainFromFrames(MakeFrame(edgeA, refA, thetaA), MakeFrame(edgeB, refB, thetaB), thetaA, thetaB,
                          refTwistStart);
}

/// A jet over an element's 4 variables (e, θ) as a jet over the stencil's 8,
/// the element's variables at `index` (e at index[0..2], θ at index[3]).
Jet<8> Lift(Jet<4> const& x, std::array<int, 4> const& index) {
  Jet<8> y(x.value);
  for (int i = 0; i < 4; ++i) {
    y.gradient[index[i]] = x.gradient[i];
    for (int j = 0; j < 4; ++j) y.hessian(index[i], index[j]) = x.hessian(i, j);
  }
  return y;
}

/// An element's frame with derivatives w.r.t. its own (e, θ), lifted to the stencil's variables.
ElementFrame<Jet<8>> ElementFrameJet(Real3 const& edge, RodReferenceFrame const& ref, real theta,
                                     std::array<int, 4> const& index) {
  using J4 = Jet<4>;
  ElementFrame<J4> const f =
      MakeFrame(Vec3<J4>{J4::Variable(edge[0], 0), J4::Variable(edge[1], 1), J4::Variable(edge[2], 2)}, ref,
                J4::Variable(theta, 3));
  auto lift = [&index](Vec3<J4> const& v) { return Vec3<Jet<8>>{Lift(v[0], index), Lift(v[1], index), Lift(v[2], index)}; };
  return {lift(f.t), lift(f.u), lift(f.d1), lift(f.d2)};
}

template <class S>
Vec3<S> ToVec3(Real3 const& x) {
  return {S(x[0]), S(x[1]), S(x[2])};
}

template <class S>
S BendTwistEnergyFromStrain(RodStiffness const& k, RodStencilRest const& rest, Vec3<S> const& strain) {
  S const d1 = strain[0] - rest.strain[0], d2 = strain[1] - rest.strain[1], d3 = strain[2] - rest.strain[2];
  return (0.5 / rest.voronoiLength) * (k.bend1 * (d1 * d1) + k.bend2 * (d2 * d2) + k.twist * (d3 * d3));
}

/// dω/dt of the transported reference frame at tangent t (3×3, acting on
/// δt ⊥ t): ω = t × δt + (v·δu) t with δu = (∂u/∂t) δt.
Real33 ReferenceFrameRate(Real3 const& t, RodReferenceFrame const& ref) {
  real const c = 1 + ref.tangent.dot(t);
  real const s = t.dot(ref.director) / c;
  Real3 const u = ref.director - s * (ref.tangent + t);
  Real3 const v = t.cross(u);
  // ∂s/∂t = u⁰/c − (t·u⁰) t⁰/c², ∂u/∂t = −(t⁰ + t)(∂s/∂t)ᵀ − s I
  Eigen::Matrix<real, 1, 3> const dsdt = (ref.director / c - (t.dot(ref.director) / (c * c)) * ref.tangent).transpose();
  Eigen::Matrix<real, 1, 3> const twistRate = -v.dot(ref.tangent + t) * dsdt - s * v.transpose();
  return Hat(t) + t * twistRate;
}

}  // namespace

Real3 TransportDirector(Real3 const& a, Real3 const& b, Real3 const& u) {
  return u - (b.dot(u) / (1 + a.dot(b))) * (a + b);
}

Real33 RodMaterialFrame(Real3 const& edge, RodReferenceFrame const& ref, real theta) {
  ElementFrame<real> const f = MakeFrame(ToVec3<real>(edge), ref, theta);
  Real33 frame;
  for (int k = 0; k < 3; ++k) {
    frame(k, 0) = f.d1[k];
    frame(k, 1) = f.d2[k];
    frame(k, 2) = f.t[k];
  }
  return frame;
}

JetMatrix3<4> RodMaterialFrameJet(Real3 const& edge, RodReferenceFrame const& ref, real theta) {
  using J4 = Jet<4>;
  ElementFrame<J4> const f =
      MakeFrame(Vec3<J4>{J4::Variable(edge[0], 0), J4::Variable(edge[1], 1), J4::Variable(edge[2], 2)}, ref,
                J4::Variable(theta, 3));
  JetMatrix3<4> frame;
  for (int k = 0; k < 3; ++k) {
    frame[k][0] = f.d1[k];
    frame[k][1] = f.d2[k];
    frame[k][2] = f.t[k];
  }
  return frame;
}

Matrix38 RodMaterialFrameJacobian(Real3 const& edge, RodReferenceFrame const& ref) {
  real const length = edge.norm();
  Real3 const t = edge / length;
  // δt = (I − t tᵀ)(δx_b − δxₐ)/l
  Real33 const dOmega = ReferenceFrameRate(t, ref) * ((Real33::Identity() - t * t.transpose()) / length);
  Matrix38 jacobian = Matrix38::Zero();
  jacobian.block<3, 3>(0, 0) = -dOmega;
  jacobian.col(3) = t;
  jacobian.block<3, 3>(0, 4) = dOmega;
  return jacobian;
}

real RodTwistUnderRotation(Real3 const& edge, RodReferenceFrame const& ref, Real3 const& omega) {
  Real3 const t = edge.normalized();
  return omega.dot(t) - t.dot(ReferenceFrameRate(t, ref) * omega.cross(t));
}

Real3 RodStencilStrain(Real3 const& edgeA, Real3 const& edgeB, real thetaA, real thetaB,
                       RodReferenceFrame const& refA, RodReferenceFrame const& refB, real refTwistStart) {
  Vec3<real> const s =
      StencilStrain(ToVec3<real>(edgeA), ToVec3<real>(edgeB), thetaA, thetaB, refA, refB, refTwistStart);
  return {s[0], s[1], s[2]};
}

real RodReferenceTwist(Real3 const& edgeA, Real3 const& edgeB, RodReferenceFrame const& refA,
                       RodReferenceFrame const& refB, real refTwistStart) {
  ElementFrame<real> const a = MakeFrame(ToVec3<real>(edgeA), refA, 0.0);
  ElementFrame<real> const b = MakeFrame(ToVec3<real>(edgeB), refB, 0.0);
  return ReferenceTwist(a, b, 1 + Dot(a.t, b.t), refTwistStart);
}

real RodStretchEnergy(real stiffness, real restLength, Real3 const& edge) {
  real const strain = edge.norm() / restLength - 1;
  return 0.5 * stiffness * restLength * strain * strain;
}

void RodStretchGradientHessian(real stiffness, real restLength, Real3 const& edge, Vector6& gradient,
                               Matrix6& hessian, bool project) {
  // ∇_e = EA (l/l̄ − 1) t,  ∇²_e = EA/l̄ [t tᵀ + (1 − l̄/l)(I − t tᵀ)], e = x_b − xₐ
  real const length = edge.norm();
  Real3 const t = edge / length;
  Real3 const g = stiffness * (length / restLength - 1) * t;
  real transverse = 1 - restLength / length;
  if (project) transverse = std::max<real>(transverse, 0);
  Real33 const tt = t * t.transpose();
  Real33 const h = (stiffness / restLength) * (tt + transverse * (Real33::Identity() - tt));
  gradient << -g, g;
  hessian << h, -h, -h, h;
}

real RodBendTwistEnergy(RodStiffness const& k, RodStencilRest const& rest, Real3 const& edgeA,
                        Real3 const& edgeB, real thetaA, real thetaB, RodReferenceFrame const& refA,
                        RodReferenceFrame const& refB, real refTwistStart) {
  return BendTwistEnergyFromStrain<real>(
      k, rest, StencilStrain(ToVec3<real>(edgeA), ToVec3<real>(edgeB), thetaA, thetaB, refA, refB, refTwistStart));
}

void RodBendTwistGradientHessian(RodStiffness const& k, RodStencilRest const& rest, Real3 const& edgeA,
                                 Real3 const& edgeB, real thetaA, real thetaB, RodReferenceFrame const& refA,
                                 RodReferenceFrame const& refB, real refTwistStart, Vector11& gradient,
                                 Matrix11& hessian, bool project) {
  // each element's frame depends on its own 4 variables only: differentiate
  // it over those (cheap 4-variable jets), then lift to the stencil's 8
  using J = Jet<8>;
  J const energy = BendTwistEnergyFromStrain<J>(
      k, rest,
      StrainFromFrames(ElementFrameJet(edgeA, refA, thetaA, {0, 1, 2, 6}),
                       ElementFrameJet(edgeB, refB, thetaB, {3, 4, 5, 7}), J::Variable(thetaA, 6),
                       J::Variable(thetaB, 7), refTwistStart));
  Eigen::Matrix<real, 8, 8> h8 = energy.hessian;
  if (project) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix<real, 8, 8>> eigen(h8);
    h8 = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).asDiagonal() * eigen.eigenvectors().transpose();
  }
  // (eₐ, e_b, θₐ, θ_b) = M [xᵢ₋₁, θᵢ₋₁, xᵢ, θᵢ, xᵢ₊₁]
  Eigen::Matrix<real, 8, 11> map = Eigen::Matrix<real, 8, 11>::Zero();
  map.block<3, 3>(0, 0) = -Real33::Identity();
  map.block<3, 3>(0, 4) = Real33::Identity();
  map.block<3, 3>(3, 4) = -Real33::Identity();
  map.block<3, 3>(3, 8) = Real33::Identity();
  map(6, 3) = 1;
  map(7, 7) = 1;
  gradient = map.transpose() * energy.gradient;
  hessian = map.transpose() * h8 * map;
}

}  // namespace superdex::internal
