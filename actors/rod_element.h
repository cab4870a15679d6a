// Per-element kernels of the discrete elastic rod (docs/design.md §4.3), after
// Bergou, Wardetzky, Robinson, Audoly, Grinspun 2008, "Discrete Elastic Rods"
// (DER), with time-parallel reference frames (Bergou et al. 2010, "Discrete
// Viscous Threads").
//
// Geometry. Element e joins nodes e and e+1: edge vector eₑ = x_{e+1} − xₑ,
// length lₑ = ‖eₑ‖, tangent tₑ = eₑ/lₑ. Each element carries a reference
// frame (uₑ, vₑ = tₑ × uₑ, tₑ) and a twist angle θₑ (node e's 4th DoF); its
// material frame Rₑ = [d₁ d₂ t] is the reference frame turned by θₑ about t:
//
//   d₁ = cos θ u + sin θ v,   d₂ = −sin θ u + cos θ v.
//
// The reference frame is fixed data within a stage — the stage-start frame
// (u⁰, t⁰) — carried to the current tangent by parallel transport,
//
//   u(t) = P(t⁰→t) u⁰ = u⁰ − (t·u⁰)/(1 + t⁰·t) (t⁰ + t),
//
// the rotation about t⁰ × t taking t⁰ to t (exact for unit t⁰ ⊥ u⁰). Between
// stages the actor replaces (u⁰, t⁰) by (u(t), t): frames are carried from
// step to step by parallel transport in time.
//
// Energies (E Young's modulus, G shear modulus; EA, EI₁, EI₂, GJ section
// stiffnesses; bars are rest values):
//
//   stretching, per element:    ½ EA l̄ₑ (lₑ/l̄ₑ − 1)²
//   bending and twisting, per interior node i between elements a = i−1 and b = i,
//   Voronoi length l̄ᵢ = (l̄ₐ + l̄_b)/2:
//     κb = 2 tₐ × t_b / (1 + tₐ·t_b)                   (curvature binormal)
//     κ₁ = ½ κb·(d₁ᵃ + d₁ᵇ),  κ₂ = ½ κb·(d₂ᵃ + d₂ᵇ)    (bending about d₁, d₂)
//     m  = θ_b − θₐ + m_ref                            (twist)
//     ½ [EI₁ (κ₁ − κ̄₁)² + EI₂ (κ₂ − κ̄₂)² + GJ (m − m̄)²] / l̄ᵢ
//   with m_ref the reference twist: the angle about t_b from P(tₐ→t_b) uₐ to
//   u_b. m_ref is evaluated by atan2 and unwrapped to the branch nearest its
//   stage-start value (the derivatives do not depend on the branch).
//   κ̄, m̄ come from the rest shape and rest material frames (natural
//   curvature and twist).
//
// The stencil's 8 variables are its two edges and two twists. Each element's
// frame depends on its own 4 only; with [d₁ d₂ t] right-handed and
// c = 1 + tₐ·t_b, every strain is a function of dot products pairing a vector
// of element a with one of element b:
//
//   κ₁ = (tₐ·d₂ᵇ − t_b·d₂ᵃ)/c,   κ₂ = (t_b·d₁ᵃ − tₐ·d₁ᵇ)/c,
//   m_ref = atan2(s tₐ·v_b − uₐ·v_b, uₐ·u_b − s tₐ·u_b),   s = (t_b·uₐ)/c.
//
// The exact gradient and Hessian are written out by the chain rule: each
// frame's first and second derivatives over its element's 4 variables in
// closed form, each cross dot product's over the 8 from its block structure
// (∇(x·y) = [J_xᵀ y; J_yᵀ x], ∇²(x·y) = [Σ yₖ∇²xₖ, J_xᵀJ_y; ·, Σ xₖ∇²yₖ]), then
// the quotient and atan2 rules (rod_element.cc has the derivation). The 8×8
// result maps to the 11 DoFs [xᵢ₋₁, θᵢ₋₁, xᵢ, θᵢ, xᵢ₊₁]. The projected Hessian
// is the 8×8 one clamped to its non-negative eigenvalues, then mapped.
// RodBendTwistGradientHessianJet, the same function differentiated with
// second-order forward-mode jets (core/jet.h), is the tests' reference.
#pragma once

#include <array>

#include <superdex/core/so3_jet.h>
#include <superdex/core/types.h>

namespace superdex::internal {

using Vector6 = Eigen::Matrix<real, 6, 1>;
using Matrix6 = Eigen::Matrix<real, 6, 6>;
using Vector11 = Eigen::Matrix<real, 11, 1>;
using Matrix11 = Eigen::Matrix<real, 11, 11>;
using Matrix38 = Eigen::Matrix<real, 3, 8>;
using Matrix4 = Eigen::Matrix<real, 4, 4>;
using Matrix34 = Eigen::Matrix<real, 3, 4>;

/// Section stiffnesses [N, N·m², N·m², N·m²].
struct RodStiffness {
  real stretch = 0;  ///< EA
  real bend1 = 0;    ///< EI₁, about d₁
  real bend2 = 0;    ///< EI₂, about d₂
  real twist = 0;    ///< GJ
};

/// The stage-fixed reference frame of an element: unit tangent t⁰ and unit
/// director u⁰ ⊥ t⁰.
struct RodReferenceFrame {
  Real3 tangent = Real3::UnitX();
  Real3 director = Real3::UnitY();
};

/// Rest data of a bending–twisting stencil (interior node).
struct RodStencilRest {
  real voronoiLength = 0;  ///< l̄ᵢ
  Real3 strain = Real3::Zero();  ///< (κ̄₁, κ̄₂, m̄)
};

/// P(a→b) u for unit a, b and u ⊥ a.
Real3 TransportDirector(Real3 const& a, Real3 const& b, Real3 const& u);

/// The material frame [d₁ d₂ t] of an element with edge vector `edge`,
/// stage reference frame `ref` and twist θ.
Real33 RodMaterialFrame(Real3 const& edge, RodReferenceFrame const& ref, real theta);

/// The material frame [d₁ d₂ t] with its first and second derivatives w.r.t.
/// the element's 4 variables (edge vector e at jet indices 0..2, twist θ at 3).
JetMatrix3<4> RodMaterialFrameJet(Real3 const& edge, RodReferenceFrame const& ref, real theta);

/// dω/d(δxₐ, δθₐ, δx_b, δθ_b): the world angular increment of the material
/// frame (R ← Exp(ω) R) per increment of the element's two nodes' 4 DoFs
/// (node a = e, node b = e+1; δθ_b does not act: column 7 is zero).
Matrix38 RodMaterialFrameJacobian(Real3 const& edge, RodReferenceFrame const& ref);

/// The twist increment of element e under the infinitesimal rigid rotation ω
/// of the whole rod (for the rigid-body modes): δθ = ω·t − ω_ref(ω × t)·t.
real RodTwistUnderRotation(Real3 const& edge, RodReferenceFrame const& ref, Real3 const& omega);

/// (κ₁, κ₂, m) of a stencil; `refTwistStart` picks the branch of m_ref.
Real3 RodStencilStrain(Real3 const& edgeA, Real3 const& edgeB, real thetaA, real thetaB,
                       RodReferenceFrame const& refA, RodReferenceFrame const& refB, real refTwistStart);

/// The reference twist m_ref alone (unwrapped near `refTwistStart`).
real RodReferenceTwist(Real3 const& edgeA, Real3 const& edgeB, RodReferenceFrame const& refA,
                       RodReferenceFrame const& refB, real refTwistStart);

real RodStretchEnergy(real stiffness, real restLength, Real3 const& edge);
/// Gradient and Hessian w.r.t. [xₐ, x_b]; `project` clamps the transverse
/// term (1 − l̄/l) at 0 (a compressed element's Hessian is indefinite).
void RodStretchGradientHessian(real stiffness, real restLength, Real3 const& edge, Vector6& gradient,
                               Matrix6& hessian, bool project);

real RodBendTwistEnergy(RodStiffness const& k, RodStencilRest const& rest, Real3 const& edgeA,
                        Real3 const& edgeB, real thetaA, real thetaB, RodReferenceFrame const& refA,
                        RodReferenceFrame const& refB, real refTwistStart);
/// Gradient and exact Hessian of RodBendTwistEnergy w.r.t. [xᵢ₋₁, θᵢ₋₁, xᵢ, θᵢ,
/// xᵢ₊₁]; `project` clamps the 8×8 Hessian over (eₐ, θₐ, e_b, θ_b) to its
/// non-negative eigenvalues before mapping it. The gradient does not depend on
/// `project`.
void RodBendTwistGradientHessian(RodStiffness const& k, RodStencilRest const& rest, Real3 const& edgeA,
                                 Real3 const& edgeB, real thetaA, real thetaB, RodReferenceFrame const& refA,
                                 RodReferenceFrame const& refB, real refTwistStart, Vector11& gradient,
                                 Matrix11& hessian, bool project);

/// A 3-vector function of one element's 4 variables (e, θ) with its first
/// derivatives.
struct RodVectorJacobian {
  Real3 value;
  Matrix34 jacobian;  ///< ∂xₖ/∂(e, θ), row k
};

/// ... and its second derivatives.
struct RodVectorDerivatives : RodVectorJacobian {
  std::array<Matrix4, 3> hessian;  ///< ∂²xₖ/∂(e, θ)²

  /// Σₖ wₖ ∇²xₖ
  Matrix4 Contract(Real3 const& w) const {
    return w[0] * hessian[0] + w[1] * hessian[1] + w[2] * hessian[2];
  }
};

/// An element's frame vectors t, u, v = t × u, d₁, d₂ with their derivatives
/// w.r.t. the element's own (e, θ): all that a bending–twisting stencil needs
/// of each of its two elements. The second derivatives of d₁ = cos θ u +
/// sin θ v and d₂ = −sin θ u + cos θ v are not stored: they follow from u's,
/// v's and the first derivatives (RodBendTwistGradientHessian contracts them
/// that way).
struct RodFrameDerivatives {
  RodVectorDerivatives t, u, v;
  RodVectorJacobian d1, d2;
  real cosine = 1, sine = 0;  ///< of θ
};

/// The frame derivatives of the element with edge `edge`, reference frame
/// `ref` and twist θ, in closed form. An interior element belongs to two
/// stencils; a caller walking a rod's stencils in order computes it once.
void MakeRodFrameDerivatives(Real3 const& edge, RodReferenceFrame const& ref, real theta,
                             RodFrameDerivatives& frame);

/// RodBendTwistGradientHessian from the two elements' frame derivatives
/// (MakeRodFrameDerivatives); the same numbers, bit for bit.
void RodBendTwistGradientHessian(RodStiffness const& k, RodStencilRest const& rest,
                                 RodFrameDerivatives const& a, RodFrameDerivatives const& b,
                                 real thetaA, real thetaB, real refTwistStart, Vector11& gradient,
                                 Matrix11& hessian, bool project);

/// The reference implementation of RodBendTwistGradientHessian, the same
/// function differentiated the plain way: the frames lifted to 8-variable jets
/// and every operation of the strain (cross product, sums, the transported
/// director, atan2) a full Jet<8> operation. About 10 times slower; kept for
/// the tests and perf/rod_stencil, which compare the two.
void RodBendTwistGradientHessianJet(RodStiffness const& k, RodStencilRest const& rest,
                                    Real3 const& edgeA, Real3 const& edgeB, real thetaA,
                                    real thetaB, RodReferenceFrame const& refA,
                                    RodReferenceFrame const& refB, real refTwistStart,
                                    Vector11& gradient, Matrix11& hessian, bool project);

}  // namespace superdex::internal
