#include <superdex/actors/rod_element.h>

#include <cmath>
#include <numbers>

#include <superdex/core/jet.h>
#include <superdex/core/so3.h>
#include <superdex/core/symmetric_eigen.h>

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

/// The frame with derivatives w.r.t. the element's own variables (e at jet
/// indices 0..2, θ at 3).
ElementFrame<Jet<4>> MakeFrameJet(Real3 const& edge, RodReferenceFrame const& ref, real theta) {
  using J4 = Jet<4>;
  return MakeFrame(
      Vec3<J4>{J4::Variable(edge[0], 0), J4::Variable(edge[1], 1), J4::Variable(edge[2], 2)}, ref,
      J4::Variable(theta, 3));
}

/// 2πk taking `angle` to the branch nearest `start`.
real BranchOffset(real angle, real start) {
  constexpr real kTwoPi = 2 * std::numbers::pi_v<real>;
  return kTwoPi * std::round((start - angle) / kTwoPi);
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
  return angle + BranchOffset(ValueOf(angle), start);
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
  ElementFrame<J4> const f = MakeFrameJet(edge, ref, theta);
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

// ---- the bending–twisting stencil, differentiated by hand ----
//
// The stencil's 8 variables are ordered by element, z = (eₐ, θₐ, e_b, θ_b):
// element a's own variables are z₀…z₃ and b's are z₄…z₇. Each element's frame
// depends on its own 4 only (FrameDerivatives, in closed form). With
// [d₁ d₂ t] right-handed (t × d₁ = d₂, d₂ × t = d₁), c = 1 + tₐ·t_b:
//
//   κ₁ = N₁/c,  N₁ = tₐ·d₂ᵇ − t_b·d₂ᵃ,     κ₂ = N₂/c,  N₂ = t_b·d₁ᵃ − tₐ·d₁ᵇ,
//
// and, since t_b·u_b ≡ 0 and v_b = t_b × u_b, the transported director
// p = uₐ − s (tₐ + t_b), s = (t_b·uₐ)/c, has
//
//   X = p·u_b = uₐ·u_b − s tₐ·u_b,   Y = (p × u_b)·t_b = s tₐ·v_b − uₐ·v_b,
//   φ = atan2(Y, X),   m = θ_b − θₐ + φ (+ 2πk, the branch).
//
// So the energy is a function of θ_b − θₐ and of ten dot products q = x·y
// (tₐ·t_b, the four in N₁ and N₂, t_b·uₐ, tₐ·u_b, tₐ·v_b, uₐ·u_b, uₐ·v_b), each
// pairing a vector x of element a with a vector y of element b. Such a
// product's derivatives have block structure,
//
//   ∇q = [J_xᵀ y; J_yᵀ x],   ∇²q = [Σₖ yₖ ∇²xₖ, J_xᵀ J_y; J_yᵀ J_x, Σₖ xₖ ∇²yₖ],
//
// and by the chain rule, with rᵢ = sᵢ − s̄ᵢ, wᵢ the stiffness over l̄ and
// fᵢ = wᵢ rᵢ,
//
//   ∇E = Σᵢ fᵢ ∇sᵢ = Σⱼ (∂E/∂qⱼ) ∇qⱼ + f₃ ∇(θ_b − θₐ),
//   ∇²E = Σⱼ (∂E/∂qⱼ) ∇²qⱼ + Σᵢ wᵢ ∇sᵢ ∇sᵢᵀ + (the rank-2 terms of the sᵢ(q)).
//
// The rank-2 terms follow from the quotient and atan2 rules: for κ = N/c,
// ∇²κ = (∇²N − κ ∇²c − sym(∇κ, ∇c))/c with sym(a, b) = a bᵀ + b aᵀ; for
// φ = atan2(Y, X), ∇φ = (X ∇Y − Y ∇X)/r² and
// ∇²φ = (X ∇²Y − Y ∇²X − sym(∇φ, X ∇X + Y ∇Y))/r², r² = X² + Y².
// The first sum is formed once, grouped by the vectors of each element.

using Vector8 = Eigen::Matrix<real, 8, 1>;
using Matrix8 = Eigen::Matrix<real, 8, 8>;
using VectorJacobian = RodVectorJacobian;
using VectorDerivatives = RodVectorDerivatives;
using FrameDerivatives = RodFrameDerivatives;

/// The element's frame with derivatives w.r.t. its own variables (e, θ) in
/// closed form; the same function as MakeFrame.
///
/// t = e/l: for a fixed vector c, ∇(t·c) = P c/l and
/// ∇²(t·c) = −[(Pc) tᵀ + t (Pc)ᵀ + (t·c) P]/l², P = I − t tᵀ. With
/// s = (t·u⁰)/β, β = 1 + t·t⁰ (quotient rule), uₖ = u⁰ₖ − s (t⁰ₖ + tₖ) and
/// vₖ = (t × u)ₖ = t·(u⁰ × eₖ) − s t·(t⁰ × eₖ) (t × t = 0), products of s with
/// such t·c. θ enters through d₁ = cos θ u + sin θ v, d₂ = −sin θ u + cos θ v:
/// ∂d₁/∂θ = d₂, ∂d₂/∂θ = −d₁.
}  // namespace

void MakeRodFrameDerivatives(Real3 const& edge, RodReferenceFrame const& ref, real theta,
                             RodFrameDerivatives& f) {
  real const inverseLength = 1 / edge.norm();
  real const inverseLengthSquared = inverseLength * inverseLength;
  Real3 const t = edge * inverseLength;
  Real33 const p = Real33::Identity() - t * t.transpose();
  auto gradientOf = [&](Real3 const& c) -> Real3 { return (p * c) * inverseLength; };
  auto hessianOf = [&](Real3 const& c) -> Real33 {
    Real33 const m = (p * c) * t.transpose();
    return -inverseLengthSquared * (m + m.transpose() + t.dot(c) * p);
  };
  // s = (t·u⁰)/β: ∇s = (∇(t·u⁰) − s ∇β)/β, ∇²s = (∇²(t·u⁰) − s ∇²β − sym(∇s, ∇β))/β
  real const beta = 1 + t.dot(ref.tangent);
  real const s = t.dot(ref.director) / beta;
  Real3 const q = ref.director - s * ref.tangent;
  Real3 const betaGradient = gradientOf(ref.tangent);
  Real3 const sGradient = (gradientOf(ref.director) - s * betaGradient) / beta;
  Real33 const sb = sGradient * betaGradient.transpose();
  Real33 const sHessian = (hessianOf(q) - sb - sb.transpose()) / beta;

  f.t.value = t;
  f.u.value = ref.director - s * (ref.tangent + t);
  f.v.value = t.cross(f.u.value);
  for (VectorDerivatives* x : {&f.t, &f.u, &f.v}) {
    x->jacobian.col(3).setZero();
    for (Matrix4& h : x->hessian) {
      h.col(3).setZero();
      h.row(3).setZero();
    }
  }
  for (int k = 0; k < 3; ++k) {
    Real3 const unit = Real3::Unit(k);
    // tₖ = t·eₖ
    Real3 const tGradient = p.col(k) * inverseLength;
    Real33 const tHessian = hessianOf(unit);
    f.t.jacobian.row(k).head<3>() = tGradient;
    f.t.hessian[k].topLeftCorner<3, 3>() = tHessian;
    // uₖ = u⁰ₖ − s (t⁰ₖ + tₖ)
    Real33 const st = sGradient * tGradient.transpose();
    f.u.jacobian.row(k).head<3>() = -(ref.tangent[k] + t[k]) * sGradient - s * tGradient;
    f.u.hessian[k].topLeftCorner<3, 3>() =
        -(ref.tangent[k] + t[k]) * sHessian - st - st.transpose() - s * tHessian;
    // vₖ = t·(u⁰ × eₖ) − s hₖ, hₖ = t·(t⁰ × eₖ); q = u⁰ − s t⁰ takes in s ∇hₖ, s ∇²hₖ
    Real3 const h = ref.tangent.cross(unit);
    Real33 const sh = sGradient * gradientOf(h).transpose();
    f.v.jacobian.row(k).head<3>() = gradientOf(q.cross(unit)) - t.dot(h) * sGradient;
    f.v.hessian[k].topLeftCorner<3, 3>() =
        hessianOf(q.cross(unit)) - t.dot(h) * sHessian - sh - sh.transpose();
  }
  // d₁ = cos θ u + sin θ v, d₂ = −sin θ u + cos θ v
  real const cosine = std::cos(theta), sine = std::sin(theta);
  f.cosine = cosine, f.sine = sine;
  f.d1.value = cosine * f.u.value + sine * f.v.value;
  f.d2.value = -sine * f.u.value + cosine * f.v.value;
  f.d1.jacobian << cosine * f.u.jacobian.leftCols<3>() + sine * f.v.jacobian.leftCols<3>(),
      f.d2.value;
  f.d2.jacobian << -sine * f.u.jacobian.leftCols<3>() + cosine * f.v.jacobian.leftCols<3>(),
      -f.d1.value;
}

namespace {

/// Σₖ (w₁ₖ ∇²d₁ₖ + w₂ₖ ∇²d₂ₖ) from u's and v's second derivatives: with
/// ∂²d₁/∂e² = cos θ ∂²u + sin θ ∂²v, ∂²d₁/∂e∂θ = ∂d₂/∂e, ∂²d₁/∂θ² = −d₁ and
/// ∂²d₂/∂e² = −sin θ ∂²u + cos θ ∂²v, ∂²d₂/∂e∂θ = −∂d₁/∂e, ∂²d₂/∂θ² = −d₂,
/// added to the element's u and v weights (`uWeight`, `vWeight`, contracted
/// by the caller) and to `block`'s θ row and column.
void AddDirectorContraction(FrameDerivatives const& f, Real3 const& w1, Real3 const& w2,
                            Real3& uWeight, Real3& vWeight, Matrix4& block) {
  uWeight += f.cosine * w1 - f.sine * w2;
  vWeight += f.sine * w1 + f.cosine * w2;
  Real3 const mixed = f.d2.jacobian.leftCols<3>().transpose() * w1 -
                      f.d1.jacobian.leftCols<3>().transpose() * w2;
  block.col(3).head<3>() += mixed;
  block.row(3).head<3>() += mixed.transpose();
  block(3, 3) -= w1.dot(f.d1.value) + w2.dot(f.d2.value);
}

/// ∇(x·y) = [J_xᵀ y; J_yᵀ x] for x of element a and y of element b.
Vector8 CrossGradient(VectorJacobian const& x, VectorJacobian const& y) {
  Vector8 g;
  g << x.jacobian.transpose() * y.value, y.jacobian.transpose() * x.value;
  return g;
}

/// y = Mᵀ x for the map M from the stencil's 11 DoFs [xᵢ₋₁, θᵢ₋₁, xᵢ, θᵢ, xᵢ₊₁]
/// to its variables (eₐ, θₐ, e_b, θ_b) = (xᵢ − xᵢ₋₁, θᵢ₋₁, xᵢ₊₁ − xᵢ, θᵢ); x has 8 rows, y 11.
template <class In, class Out>
void MapToDofs(In const& x, Out&& y) {
  y.template middleRows<3>(0) = -x.template middleRows<3>(0);
  y.row(3) = x.row(3);
  y.template middleRows<3>(4) = x.template middleRows<3>(0) - x.template middleRows<3>(4);
  y.row(7) = x.row(7);
  y.template middleRows<3>(8) = x.template middleRows<3>(4);
}

/// The 8×8 Hessian clamped to its non-negative eigenvalues.
Matrix8 ProjectToPsd(Matrix8 const& h) {
  auto const eigen = ComputeSymmetricEigen(h);
  return eigen.vectors * eigen.values.cwiseMax(0).asDiagonal() *
         eigen.vectors.transpose();
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
  ElementFrame<Jet<4>> const f = MakeFrameJet(edge, ref, theta);
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
  FrameDerivatives a, b;
  MakeRodFrameDerivatives(edgeA, refA, thetaA, a);
  MakeRodFrameDerivatives(edgeB, refB, thetaB, b);
  RodBendTwistGradientHessian(k, rest, a, b, thetaA, thetaB, refTwistStart, gradient, hessian, project);
}

void RodBendTwistGradientHessian(RodStiffness const& k, RodStencilRest const& rest,
                                 RodFrameDerivatives const& a, RodFrameDerivatives const& b,
                                 real thetaA, real thetaB, real refTwistStart, Vector11& gradient,
                                 Matrix11& hessian, bool project) {

  // bending: κ₁ = N₁/c, κ₂ = N₂/c, ∇κ = (∇N − κ ∇c)/c
  real const c = 1 + a.t.value.dot(b.t.value);
  Vector8 const cGradient = CrossGradient(a.t, b.t);
  real const bend1 = (a.t.value.dot(b.d2.value) - a.d2.value.dot(b.t.value)) / c;
  real const bend2 = (a.d1.value.dot(b.t.value) - a.t.value.dot(b.d1.value)) / c;
  Vector8 const bend1Gradient =
      (CrossGradient(a.t, b.d2) - CrossGradient(a.d2, b.t) - bend1 * cGradient) / c;
  Vector8 const bend2Gradient =
      (CrossGradient(a.d1, b.t) - CrossGradient(a.t, b.d1) - bend2 * cGradient) / c;

  // twist: φ = atan2(Y, X), X = uₐ·u_b − s tₐ·u_b, Y = s tₐ·v_b − uₐ·v_b, s = (t_b·uₐ)/c
  real const s = a.u.value.dot(b.t.value) / c;
  Vector8 const sGradient = (CrossGradient(a.u, b.t) - s * cGradient) / c;
  real const tu = a.t.value.dot(b.u.value), tv = a.t.value.dot(b.v.value);
  Vector8 const tuGradient = CrossGradient(a.t, b.u), tvGradient = CrossGradient(a.t, b.v);
  real const x = a.u.value.dot(b.u.value) - s * tu;
  real const y = s * tv - a.u.value.dot(b.v.value);
  Vector8 const xGradient = CrossGradient(a.u, b.u) - s * tuGradient - tu * sGradient;
  Vector8 const yGradient = s * tvGradient + tv * sGradient - CrossGradient(a.u, b.v);
  real const r2 = x * x + y * y;
  real const phiX = -y / r2, phiY = x / r2;  // ∂φ/∂X, ∂φ/∂Y
  real const phiS = phiY * tv - phiX * tu;   // ∂φ/∂s
  real const phi = std::atan2(y, x);
  Vector8 const phiGradient = phiX * xGradient + phiY * yGradient;
  real const twist = thetaB - thetaA + (phi + BranchOffset(phi, refTwistStart));
  Vector8 twistGradient = phiGradient;
  twistGradient[3] -= 1;
  twistGradient[7] += 1;

  // energy ½ Σ wᵢ rᵢ²: fᵢ = wᵢ rᵢ, ∇E = Σ fᵢ ∇sᵢ
  real const weight1 = k.bend1 / rest.voronoiLength, weight2 = k.bend2 / rest.voronoiLength,
             weight3 = k.twist / rest.voronoiLength;
  real const force1 = weight1 * (bend1 - rest.strain[0]),
             force2 = weight2 * (bend2 - rest.strain[1]),
             force3 = weight3 * (twist - rest.strain[2]);
  Vector8 const g8 = force1 * bend1Gradient + force2 * bend2Gradient + force3 * twistGradient;

  // Σⱼ (∂E/∂qⱼ) ∇²qⱼ over the products q = x·y, grouped by x (the a block),
  // by y (the b block) and by pair (the a–b block)
  real const wN1 = force1 / c, wN2 = force2 / c;
  real const wC = -(force1 * bend1 + force2 * bend2) / c - force3 * phiS * s / c;
  real const wP = force3 * phiS / c;                             // t_b·uₐ
  real const wTU = -force3 * phiX * s, wTV = force3 * phiY * s;  // tₐ·u_b, tₐ·v_b
  real const wUU = force3 * phiX, wUV = -force3 * phiY;          // uₐ·u_b, uₐ·v_b
  Matrix8 h8;
  // (the directors' second derivatives through u's and v's: AddDirectorContraction)
  Matrix4 blockA = Matrix4::Zero(), blockB = Matrix4::Zero();
  Real3 uWeightA = wP * b.t.value + wUU * b.u.value + wUV * b.v.value, vWeightA = Real3::Zero();
  AddDirectorContraction(a, wN2 * b.t.value, -wN1 * b.t.value, uWeightA, vWeightA, blockA);
  Real3 uWeightB = wTU * a.t.value + wUU * a.u.value, vWeightB = wTV * a.t.value + wUV * a.u.value;
  AddDirectorContraction(b, -wN2 * a.t.value, wN1 * a.t.value, uWeightB, vWeightB, blockB);
  h8.topLeftCorner<4, 4>() = a.t.Contract(wC * b.t.value + wN1 * b.d2.value - wN2 * b.d1.value +
                                          wTU * b.u.value + wTV * b.v.value) +
                             a.u.Contract(uWeightA) + a.v.Contract(vWeightA) + blockA;
  h8.bottomRightCorner<4, 4>() =
      b.t.Contract(wC * a.t.value - wN1 * a.d2.value + wN2 * a.d1.value + wP * a.u.value) +
      b.u.Contract(uWeightB) + b.v.Contract(vWeightB) + blockB;
  Matrix34 const partnerOfT = wC * b.t.jacobian + wN1 * b.d2.jacobian - wN2 * b.d1.jacobian +
                              wTU * b.u.jacobian + wTV * b.v.jacobian;
  Matrix34 const partnerOfU = wP * b.t.jacobian + wUU * b.u.jacobian + wUV * b.v.jacobian;
  Matrix34 const partnerOfTB = wN2 * a.d1.jacobian - wN1 * a.d2.jacobian;
  h8.topRightCorner<4, 4>().noalias() = a.t.jacobian.transpose() * partnerOfT;
  h8.topRightCorner<4, 4>().noalias() += a.u.jacobian.transpose() * partnerOfU;
  h8.topRightCorner<4, 4>().noalias() += partnerOfTB.transpose() * b.t.jacobian;
  h8.bottomLeftCorner<4, 4>() = h8.topRightCorner<4, 4>().transpose();

  // Σᵢ wᵢ ∇sᵢ ∇sᵢᵀ and the rank-2 terms of κ₁, κ₂ (through c) and of φ
  // (through s and the atan2): f₁∇²κ₁ + f₂∇²κ₂ ∋ −sym((f₁∇κ₁ + f₂∇κ₂)/c, ∇c),
  // f₃∇²φ ∋ f₃ sym(∇s, φ_Y ∇(tₐ·v_b) − φ_X ∇(tₐ·u_b) − (φ_s/c) ∇c) − (f₃/r²) sym(∇φ, X∇X + Y∇Y)
  auto addSymmetric = [&h8](Vector8 const& p, Vector8 const& q) {
    h8.noalias() += p * q.transpose();
    h8.noalias() += q * p.transpose();
  };
  h8.noalias() += (weight1 * bend1Gradient) * bend1Gradient.transpose();
  h8.noalias() += (weight2 * bend2Gradient) * bend2Gradient.transpose();
  h8.noalias() += (weight3 * twistGradient) * twistGradient.transpose();
  addSymmetric(-(force1 * bend1Gradient + force2 * bend2Gradient) / c, cGradient);
  addSymmetric(force3 * sGradient, phiY * tvGradient - phiX * tuGradient - (phiS / c) * cGradient);
  addSymmetric(-(force3 / r2) * phiGradient, x * xGradient + y * yGradient);
  if (project) h8 = ProjectToPsd(h8);

  // H₁₁ = Mᵀ H₈ M = Mᵀ (Mᵀ H₈)ᵀ (H₈ symmetric)
  MapToDofs(g8, gradient);
  Eigen::Matrix<real, 11, 8> halfMapped;
  MapToDofs(h8, halfMapped);
  MapToDofs(halfMapped.transpose(), hessian);
}

void RodBendTwistGradientHessianJet(RodStiffness const& k, RodStencilRest const& rest,
                                    Real3 const& edgeA, Real3 const& edgeB, real thetaA,
                                    real thetaB, RodReferenceFrame const& refA,
                                    RodReferenceFrame const& refB, real refTwistStart,
                                    Vector11& gradient, Matrix11& hessian, bool project) {
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
    auto const eigen = ComputeSymmetricEigen(h8);
    h8 = eigen.vectors * eigen.values.cwiseMax(0).asDiagonal() * eigen.vectors.transpose();
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
