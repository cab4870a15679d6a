// Per-element kernels of the linear tetrahedron (docs/design.md §4.2): rest data,
// deformation gradient, hyperelastic energy, its gradient and (optionally
// PSD-projected) Hessian w.r.t. the 12 node coordinates.
//
// Nodes X₀..X₃ at rest, x₀..x₃ now (node-major: x = [x₀; x₁; x₂; x₃]).
//
//   D_m = [X₁−X₀, X₂−X₀, X₃−X₀],  D_s = [x₁−x₀, x₂−x₀, x₃−x₀]
//   F   = D_s D_m⁻¹,              V = det(D_m)/6 > 0
//   E(x) = V Ψ(F),  ∇E = V Bᵀ vec P,  ∇²E = V Bᵀ (∂²Ψ/∂F²) B
//
// with vec column-major, P = ∂Ψ/∂F the first Piola–Kirchhoff stress and
// B = ∂vec F/∂x (9×12). With G = D_m⁻¹ (rows g₁ᵀ, g₂ᵀ, g₃ᵀ) and
// g₀ = −(g₁ + g₂ + g₃), F = Σₐ xₐ gₐᵀ, so the gradient block of node a is
// V P gₐ and the Hessian block (a, b) is V Σⱼₗ G_aj G_bl A_jl, A_jl the 3×3
// block (column j of F, column l of F) of ∂²Ψ/∂F². Node 0's blocks are minus
// the sums of the others' (translation invariance holds by construction).
//
// Models (TetMaterialModel), J = det F, cof F = J F⁻ᵀ = [f₁×f₂, f₂×f₀, f₀×f₁]:
//
//   StableNeoHookean (Smith, de Goes, Kim 2018, "Stable Neo-Hookean Flesh
//   Simulation", without the log(I_C+1) term):
//     Ψ = μ/2 (I_C − 3) − μ (J − 1) + λ'/2 (J − 1)²,  λ' = λ + μ
//     P = μ F + (λ'(J − 1) − μ) cof F
//     ∂²Ψ/∂F² = μ I₉ + (λ'(J − 1) − μ) ∂²J/∂F² + λ' vec(cof F) vec(cof F)ᵀ
//     ∂²J/∂F² = [[0, −[f₂]×, [f₁]×], [[f₂]×, 0, −[f₀]×], [−[f₁]×, [f₀]×, 0]]
//   A polynomial in F: finite for every F, inverted (J < 0) and flat (J = 0)
//   elements included, and with Ψ(I) = 0, P(I) = 0 and a linearization at
//   F = I equal to LinearElastic's (this is what fixes λ' = λ + μ).
//
//   LinearElastic (small strain, ε = sym(F) − I):
//     Ψ = μ ε:ε + λ/2 tr(ε)²,  P = 2μ ε + λ tr(ε) I,
//     ∂²Ψ/∂F² = μ (I₉ + T₉) + λ vec(I) vec(I)ᵀ  (T₉: vec F ↦ vec Fᵀ), constant.
//   Not rotation invariant: a rigidly rotated element has ε ≠ 0 and stores
//   energy (ε = diag(cos θ − 1, cos θ − 1, 0) for a rotation θ about z).
//
// PSD projection (`project`): ∂²Ψ/∂F² is replaced by Σₖ max(αₖ, 0) qₖ qₖᵀ
// over its eigenpairs (αₖ, qₖ), so the element Hessian V Bᵀ PSD(·) B is PSD
// (B has full column rank 9 over the non-translational motions). By default
// the eigensystem is analytic (Smith, de Goes, Kim 2019, "Analytic
// Eigensystems for Isotropic Distortion Energies"): with the rotation-variant
// SVD F = U Σ Vᵀ (U, V rotations, σ₂ may be negative) and {i, j, m} a
// permutation of {0, 1, 2}, ∂²J/∂F² has the twist eigenpairs
// (+σₘ, vec(U(eᵢeⱼᵀ − eⱼeᵢᵀ)Vᵀ)/√2), the flip eigenpairs
// (−σₘ, vec(U(eᵢeⱼᵀ + eⱼeᵢᵀ)Vᵀ)/√2), and couples the three scaling modes
// vec(U eᵢeᵢᵀ Vᵀ) through the 3×3 block [[0, σ₂, σ₁], [σ₂, 0, σ₀], [σ₁, σ₀, 0]];
// vec(cof F) = vec(U diag(σ₁σ₂, σ₀σ₂, σ₀σ₁) Vᵀ) lies in the scaling space. So
// SNH's ∂²Ψ/∂F² has the eigenvalues μ + sσₘ (twist), μ − sσₘ (flip),
// s = λ'(J − 1) − μ, and those of the 3×3 scaling block
// μ I + s [[0, σ₂, σ₁], …] + λ' c cᵀ, c = (σ₁σ₂, σ₀σ₂, σ₀σ₁). The kernel takes
// the exact ∂²Ψ/∂F² and subtracts αₖ qₖ qₖᵀ for each negative eigenpair
// only (the SVD by Jacobi rotations on FᵀF, the scaling block by Jacobi
// rotations only when Sylvester's criterion says it is not definite), so
// the projected Hessian equals the exact one, bitwise, wherever the latter
// is PSD. It agrees with Eigen's 9×9 SelfAdjointEigenSolver (kept as
// TetPsdProjection::EigenSolver) to ~1e-15 relative and is ~6× faster
// (docs/deformables.md, "Element throughput").
// LinearElastic's eigenvalues are 0 (skew), 2μ (symmetric deviatoric) and
// 2μ + 3λ = 3K (volumetric): PSD for every valid E, ν.
//
// Everything is fixed-size: no heap allocation (tests/actors checks it).
#pragma once

#include <array>
#include <string_view>

#include <superdex/core/types.h>

namespace superdex {

/// Hyperelastic models of the volumetric elements.
enum class TetMaterialModel {
  StableNeoHookean,  ///< Smith, de Goes, Kim 2018: Ψ = μ/2 (I_C − 3) − μ (J − 1) + λ'/2 (J − 1)², λ' = λ + μ (matches linear elasticity at rest), defined through inversion
  LinearElastic,     ///< small strain: Ψ = μ ε:ε + λ/2 tr(ε)², ε = sym(F) − I; cheapest, constant Hessian, not rotation invariant
};

std::string_view ToString(TetMaterialModel model);

namespace internal {

struct LameParameters {
  real mu = 0;      ///< μ [Pa]
  real lambda = 0;  ///< λ [Pa]
};

/// μ = E / (2(1+ν)), λ = E ν / ((1+ν)(1−2ν)); requires E > 0, −1 < ν < 0.5 (caller validates)
LameParameters LameFromYoungPoisson(real youngModulus, real poissonRatio);

using Vector12 = Eigen::Matrix<real, 12, 1>;
using Matrix12 = Eigen::Matrix<real, 12, 12>;
/// A 9×9 derivative w.r.t. vec F (column-major): ∂²Ψ/∂F² = ∂vec P/∂vec F.
using Matrix9 = Eigen::Matrix<real, 9, 9>;

/// Rest data of a tetrahedron (nodes X0..X3): D_m⁻¹ with D_m = [X1−X0, X2−X0, X3−X0], and the rest volume det(D_m)/6.
struct TetRestData {
  Real33 restShapeInverse;
  real restVolume = 0;
};

/// Returns false when the rest element is degenerate or inverted: det(D_m)/6 <= 1e-12 · (max edge length)³ (i.e. volume non-positive or tiny relative to its size).
/// Also false for non-finite coordinates. `rest` is written only on success.
bool MakeTetRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, Real3 const& x3, TetRestData& rest);

/// Deformation gradient F = D_s D_m⁻¹ from the 12 current coordinates (node-major: x0, x1, x2, x3).
Real33 TetDeformationGradient(TetRestData const& rest, Vector12 const& x);

/// Energy V·Ψ(F).
real TetEnergy(TetMaterialModel model, LameParameters const& lame, TetRestData const& rest, Vector12 const& x);

/// Energy, gradient (12) and Hessian (12×12) w.r.t. the node coordinates. With `project` the Hessian is V·Bᵀ·PSD(∂²Ψ/∂F²)·B (B = ∂vec F/∂x, the 9×9 projected by clamping negative eigenvalues to 0), which is PSD; without it, the exact Hessian.
/// The Hessian is exactly symmetric. Projection by the analytic eigensystem (TetPsdProjection::Analytic).
real TetEnergyGradientHessian(TetMaterialModel model, LameParameters const& lame, TetRestData const& rest, Vector12 const& x, Vector12& gradient, Matrix12& hessian, bool project);

/// First Piola–Kirchhoff stress P(F) (for patch tests and stress output).
Real33 TetFirstPiolaStress(TetMaterialModel model, LameParameters const& lame, Real33 const& F);

// --- additions: the pieces of TetEnergyGradientHessian, for tests and perf ---

/// How the 9×9 ∂²Ψ/∂F² is made PSD.
enum class TetPsdProjection {
  None,         ///< the exact ∂²Ψ/∂F² (may be indefinite)
  Analytic,     ///< closed-form eigensystem (see the file comment); the default
  EigenSolver,  ///< Eigen::SelfAdjointEigenSolver on the fixed-size 9×9 (reference)
};

/// Energy density Ψ(F) [J/m³].
real TetEnergyDensity(TetMaterialModel model, LameParameters const& lame, Real33 const& F);

/// The exact ∂²Ψ/∂F² (9×9, vec column-major).
Matrix9 TetStressDerivative(TetMaterialModel model, LameParameters const& lame, Real33 const& F);

/// ∂²Ψ/∂F² made PSD by `projection` (None: the exact one).
Matrix9 TetProjectedStressDerivative(TetMaterialModel model, LameParameters const& lame, Real33 const& F,
                                     TetPsdProjection projection);

/// Clamps the negative eigenvalues of the symmetric `a` to 0 with Eigen's
/// SelfAdjointEigenSolver (fixed size); returns `a` unchanged if none is negative.
Matrix9 ProjectToPsdEigenSolver(Matrix9 const& a);

/// The element Hessian V Bᵀ `stressDerivative` B (12×12, node-major), exactly
/// symmetric; `stressDerivative` must be symmetric.
void TetHessianFromStressDerivative(TetRestData const& rest, Matrix9 const& stressDerivative, Matrix12& hessian);

/// TetEnergyGradientHessian with an explicit projection method.
real TetEnergyGradientHessian(TetMaterialModel model, LameParameters const& lame, TetRestData const& rest,
                              Vector12 const& x, Vector12& gradient, Matrix12& hessian,
                              TetPsdProjection projection);

}  // namespace internal
}  // namespace superdex
