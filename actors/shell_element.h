// Per-element kernels of shells (docs/design.md §4.2): the membrane of a triangle
// and the bending of a hinge (two triangles sharing an edge). Positions are
// node-major: x = [x₀; x₁; x₂] (9) for a triangle, [x₀; x₁; x₂; x₃] (12) for
// a hinge. Everything is fixed-size: no heap allocation.
//
// Membrane (StVK, plane stress). At rest, an orthonormal frame (e₁, e₂) of the
// triangle's plane (e₁ along X₁ − X₀, e₂ = n̂ × e₁) gives the 2×2 rest edge
// matrix D_m = [e₁ e₂]ᵀ [X₁−X₀, X₂−X₀] and the rest area A. Then
//
//   F   = D_s D_m⁻¹ (3×2),  D_s = [x₁−x₀, x₂−x₀],  E_G = ½(FᵀF − I₂)
//   Ψ   = μ tr(E_G²) + λ_s/2 tr(E_G)²,  λ_s = 2μλ/(λ + 2μ) = Eν/(1 − ν²)
//   E   = h A Ψ,  ∇E = h A Gᵀ vec(F S),  S = 2μ E_G + λ_s tr(E_G) I₂
//   ∇²E = h A Gᵀ (∂²Ψ/∂F²) G,  G = ∂vec F/∂x (6×9, vec column-major)
//
// with ∂vec P/∂vec F applied to dF: dF S + F (2μ dE + λ_s tr(dE) I₂),
// dE = sym(Fᵀ dF). StVK is not convex: under compression (E_G with negative
// eigenvalues) ∂²Ψ/∂F² is indefinite (S < 0 makes out-of-plane and in-plane
// buckling directions negative). PSD projection clamps the negative
// eigenvalues of the 6×6 ∂²Ψ/∂F² to zero (Eigen::SelfAdjointEigenSolver on a
// fixed-size 6×6; cheaper than the 9×9 and with the same null space of rigid
// translations), so h A Gᵀ PSD(∂²Ψ/∂F²) G is PSD; where ∂²Ψ/∂F² has no
// negative eigenvalue the projected Hessian equals the exact one. A flipped
// triangle (F with the orientation of the rest triangle reversed) is not
// special for StVK: its energy is that of the mirror image, finite.
//
// MembraneModel::TensionField relaxes this Ψ where it would carry a
// compressive principal stress (the enum below; docs/deformables.md): S and
// dS come from E_G's principal strains and directions, the rest (F, G, the
// assembly) is shared.
//
// Bending (Bergou, Wardetzky, Harmon, Zorin, Grinspun 2006, "A Quadratic
// Bending Model for Inextensible Surfaces", SGP). Hinge: shared edge (x₀, x₁),
// x₂ opposite in triangle A = (x₀, x₁, x₂), x₃ opposite in triangle
// B = (x₀, x₁, x₃). With the rest angles α₀, α₁ of A at x₀, x₁ and β₀, β₁ of
// B at x₀, x₁ (the paper's c₀₁ = cot α₀, c₀₂ = cot β₀, c₀₃ = cot α₁,
// c₀₄ = cot β₁):
//
//   K = [cot α₁ + cot β₁,  cot α₀ + cot β₀,  −(cot α₀ + cot α₁),  −(cot β₀ + cot β₁)]
//   Q = 3 k_b / (A₀ + A₁) · (K Kᵀ ⊗ I₃)          (A₀, A₁ the rest triangle areas)
//   E = ½ (x − x̄)ᵀ Q (x − x̄) = ½ xᵀQx − (Q x̄)ᵀx + ½ x̄ᵀQx̄,   x̄ the rest positions
//
// ΣK = 0 and, for a flat rest hinge, Σ Kⱼ X̄ⱼ = 0 (K is the cotangent
// combination that reproduces linear functions), so Q annihilates every
// affine image x = M X̄ + t of a flat rest hinge (rigid motions, in-plane
// stretch and shear, tilts) and E = ½ xᵀQx there. Geometrically
// Σ Kⱼ xⱼ = ‖e‖ (u_A + u_B) when both triangles keep their rest shape, with u_A,
// u_B the unit in-plane normals of the edge pointing from x₂ resp. x₃ to it;
// so an isometric bend of a flat hinge by the dihedral angle θ has exactly
//
//   E = ½ k_b · 3‖e‖²/(A₀+A₁) · 4 sin²(θ/2)   ≈ ½ · [k_b · 3‖e‖²/(A₀+A₁) · θ²]
//
// i.e. one half of the "Discrete Shells" hinge energy k_b·3‖e‖²/(A₀+A₁)·θ²
// (Grinspun et al. 2003) for the same k_b: the paper's E = ½ xᵀQx carries the
// ½ of a quadratic form. The Hessian Q is constant, PSD, of rank 3.
//
// Exact only for flat rest shapes: for a curved rest hinge Q x̄ ≠ 0 and E is
// still zero and stationary at x̄ and invariant under translations, but it
// is not invariant under rotations (a rigidly rotated curved hinge stores
// energy) and it approximates the change of curvature only to first order.
//
// Bending stiffness. A flat sheet bent isometrically keeps zero Gaussian
// curvature (it can only bend developably), and Kirchhoff plate theory gives
// it the energy ∫ D/2 (κ₁+κ₂)² dA, D = E h³/(12(1 − ν²)); for a cylinder of
// curvature κ, D/2 κ² per area. The edge-based sum Σ ½ k_b 3‖e‖²θ²/(A₀+A₁)
// is a mesh-dependent approximation: for a cylinder it tends to
// c · ½ k_b κ² per area with (tests/actors/shell_element_test.cpp, measured)
//   c = 3  on equilateral meshes, in every direction;
//   c = 3  on MakeTriangleGrid's grid bent about either grid axis or about
//          the diagonals' direction (a one-row strip bent along its length:
//          only the rungs crease, θ = κ·cell, and 3‖e‖²/(A₀+A₁) = 3 w/cell);
//   c = 9  on that grid bent across its diagonals (axis ⟂ diagonals; 7.8 at
//          30°): the right-triangle grid is anisotropic, up to 3× stiffer.
// (On an equilateral sheet wrapped on a sphere, κ₁ = κ₂ = κ, the sum tends
// to ½ k_b (κ₁+κ₂)² per area, i.e. the edge energy there behaves like
// ½ k_b [(κ₁+κ₂)² + 2(κ₁−κ₂)²].) HingeBendingStiffness therefore returns
//   k_b = D/3 = E h³ / (36 (1 − ν²)),
// which makes a cylindrically bent sheet store the plate energy D/2 κ² per
// area on isotropic meshes and on MakeTriangleGrid bent about its axes. The
// "Discrete Shells" habit k_b = E h³/(24 (1 − ν²)) = D/2 would, with this
// model's ½, store 1.5× the plate energy; Steiner's reading θ‖e‖ = ∫ 2H dA
// over a diamond (c = 1, k_b = D) is 3× too stiff on every mesh above.
#pragma once

#include <string_view>

#include <superdex/core/types.h>

namespace superdex {

/// The membrane's constitutive model (docs/deformables.md, "Membrane models").
enum class MembraneModel {
  /// Saint Venant–Kirchhoff in plane stress (above): resists compression as
  /// stretch; non-convex under compression, where a thin sheet buckles
  StVK,
  /// StVK relaxed by tension-field theory: no compressive stress (a
  /// compressed sheet wrinkles below the mesh's resolution). Taut (both
  /// principal stresses ≥ 0): StVK; wrinkled (only e₁ stretched): ½ Y e₁²,
  /// Y = (a² − b²)/a, a = 2μ + λ_s, b = λ_s, the energy of a strip free to
  /// contract sideways; slack (e₁ ≤ 0): 0. Convex in F, C¹: its exact
  /// Hessian is positive semi-definite, so Newton needs no projection
  TensionField,
};

std::string_view ToString(MembraneModel model);

}  // namespace superdex

namespace superdex::internal {

// The same aliases as actors/tet_element.h declares: an alias may be
// redeclared to the same type, so the two headers can be included together.
using Vector9 = Eigen::Matrix<real, 9, 1>;
using Matrix9 = Eigen::Matrix<real, 9, 9>;
using Vector12 = Eigen::Matrix<real, 12, 1>;
using Matrix12 = Eigen::Matrix<real, 12, 12>;

/// A triangle (or hinge triangle) is degenerate when its area <= kDegenerateAreaRatio · (max edge)².
inline constexpr real kDegenerateAreaRatio = 1e-12;

// ---------------------------------------------------------------- membrane

/// Rest data of a membrane triangle: D_m⁻¹ (2×2, in the orthonormal frame of the rest plane) and the rest area A.
struct TriangleRestData {
  Eigen::Matrix<real, 2, 2> restShapeInverse;
  real restArea = 0;
};

/// false when the rest triangle is degenerate (area <= 1e-12 · (max edge)²) or has non-finite coordinates; `rest` is written only on success.
bool MakeTriangleRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, TriangleRestData& rest);

/// F = D_s D_m⁻¹ (3×2) from the 9 current coordinates.
Eigen::Matrix<real, 3, 2> MembraneDeformationGradient(TriangleRestData const& rest, Vector9 const& x);

/// E = h A Ψ(E_G) [J] (StVK: Ψ = μ tr(E_G²) + λ_s/2 tr(E_G)²); μ, λ_s [Pa], h [m]. Zero for every rigid motion of the rest triangle.
real MembraneEnergy(MembraneModel model, real mu, real lambdaPlaneStress, real thickness, TriangleRestData const& rest, Vector9 const& x);

/// Energy, gradient (9) and Hessian (9×9). With `project` the Hessian is h A Gᵀ PSD(∂²Ψ/∂F²) G (negative eigenvalues of the 6×6 ∂²Ψ/∂F² clamped to 0), PSD; without it the exact Hessian (StVK: indefinite under compression; TensionField: PSD). The Hessian is exactly symmetric.
real MembraneEnergyGradientHessian(MembraneModel model, real mu, real lambdaPlaneStress, real thickness, TriangleRestData const& rest, Vector9 const& x, Vector9& gradient, Matrix9& hessian, bool project);

/// The exact ∂²Ψ/∂F² = ∂vec P/∂vec F (6×6, vec column-major: index 3j + i for F(i, j)), exactly symmetric.
Eigen::Matrix<real, 6, 6> MembraneStressDerivative(MembraneModel model, real mu, real lambdaPlaneStress, Eigen::Matrix<real, 3, 2> const& f);

/// ∂²Ψ/∂F² with its negative eigenvalues clamped to 0 (fixed-size SelfAdjointEigenSolver); the exact one, unchanged, when none is negative.
Eigen::Matrix<real, 6, 6> MembraneProjectedStressDerivative(MembraneModel model, real mu, real lambdaPlaneStress, Eigen::Matrix<real, 3, 2> const& f);

// ----------------------------------------------------------------- bending

/// Rest data of a hinge: K (see the file comment), A₀ + A₁, and x̄ = [X₀; X₁; X₂; X₃].
struct HingeRestData {
  Eigen::Matrix<real, 4, 1> cotangentWeights;
  real areaSum = 0;
  Vector12 restPositions;
};

/// false when either triangle (x0, x1, x2) or (x0, x1, x3) is degenerate (same rule as MakeTriangleRestData); `rest` is written only on success.
bool MakeHingeRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, Real3 const& x3, HingeRestData& rest);

/// E = ½ (x − x̄)ᵀ Q (x − x̄) [J], k_b [N·m = J].
real BendingEnergy(real bendingStiffness, HingeRestData const& rest, Vector12 const& x);

/// Energy, gradient Q (x − x̄) and Hessian Q (constant, PSD, exactly symmetric).
real BendingEnergyGradientHessian(real bendingStiffness, HingeRestData const& rest, Vector12 const& x, Vector12& gradient, Matrix12& hessian);

/// Signed dihedral angle θ ∈ (−π, π] between the normals n_A = (x₁−x₀)×(x₂−x₀) and n_B = (x₃−x₀)×(x₁−x₀) (parallel for a flat hinge with x₂, x₃ on opposite sides): the right-handed rotation about x₁ − x₀ taking n_A to n_B. 0 for a zero-length edge.
real HingeDihedralAngle(Vector12 const& x);

/// The divisor in k_b = E h³ / (36 (1 − ν²)): see "Bending stiffness" in the file comment.
inline constexpr real kHingeStiffnessDivisor = 36;

/// k_b = E h³ / (36 (1 − ν²)) = D/3 for E [Pa], ν, h [m] (caller validates).
real HingeBendingStiffness(real youngModulus, real poissonRatio, real thickness);

}  // namespace superdex::internal
