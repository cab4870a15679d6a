#include <superdex/actors/shell_element.h>

#include <algorithm>
#include <cmath>

#include <superdex/core/symmetric_eigen.h>

namespace superdex {

std::string_view ToString(MembraneModel model) {
  switch (model) {
    case MembraneModel::StVK:
      return "StVK";
    case MembraneModel::TensionField:
      return "TensionField";
  }
  return "Unknown";
}

}  // namespace superdex

namespace superdex::internal {

namespace {

/// Degeneracy rule shared by triangles and hinges: twice the area
/// ‖(b − a) × (c − a)‖ must exceed 2·1e-12·(max edge)². Written as a negated
/// `>` so that NaN coordinates count as degenerate.
bool IsNonDegenerateTriangle(Real3 const& a, Real3 const& b, Real3 const& c) {
  real const twiceArea = (b - a).cross(c - a).norm();
  real const maxEdgeSquared =
      std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
  return twiceArea > 2 * kDegenerateAreaRatio * maxEdgeSquared && std::isfinite(maxEdgeSquared);
}

/// cot of the angle between u and v (both non-zero, not parallel).
real Cotangent(Real3 const& u, Real3 const& v) { return u.dot(v) / u.cross(v).norm(); }

using Matrix32 = Eigen::Matrix<real, 3, 2>;
using Matrix22 = Eigen::Matrix<real, 2, 2>;
using Matrix6 = Eigen::Matrix<real, 6, 6>;
using Matrix69 = Eigen::Matrix<real, 6, 9>;

/// D_s = [x1 − x0, x2 − x0].
Matrix32 EdgeMatrix(Vector9 const& x) {
  Matrix32 ds;
  ds.col(0) = x.segment<3>(3) - x.segment<3>(0);
  ds.col(1) = x.segment<3>(6) - x.segment<3>(0);
  return ds;
}

/// The second Piola–Kirchhoff stress S = 2μ E_G + λ_s tr(E_G) I₂ (StVK, and
/// the taut state of the tension field; linear in E_G, so also dS from dE).
Matrix22 SecondPiola(real mu, real lambdaPlaneStress, Matrix22 const& greenStrain) {
  return 2 * mu * greenStrain + lambdaPlaneStress * greenStrain.trace() * Matrix22::Identity();
}

real StvkEnergyDensity(real mu, real lambdaPlaneStress, Matrix22 const& greenStrain) {
  real const trace = greenStrain.trace();
  return mu * greenStrain.squaredNorm() + 0.5 * lambdaPlaneStress * trace * trace;
}

/// The membrane's stress at one Green strain E_G, for either model
/// (docs/deformables.md, "Membrane models"): StVK is always taut; the
/// tension field takes E_G's principal strains e₁ ≥ e₂ and directions v₁, v₂
/// (2×2 closed form) and which of its three states holds, once per element
/// evaluation.
class MembraneStress {
 public:
  MembraneStress(MembraneModel model, real mu, real lambdaPlaneStress, Matrix22 const& greenStrain)
      : mu_(mu), lambda_(lambdaPlaneStress), strain_(greenStrain) {
    if (model == MembraneModel::TensionField) {
      Matrix22 const& e = greenStrain;
      real const mean = 0.5 * (e(0, 0) + e(1, 1)), half = 0.5 * (e(0, 0) - e(1, 1));
      real const radius = std::hypot(half, e(0, 1));
      e1_ = mean + radius;
      e2_ = mean - radius;
      real const angle = 0.5 * std::atan2(e(0, 1), half);
      v1_ << std::cos(angle), std::sin(angle);
      v2_ << -v1_(1), v1_(0);
      // taut while the lesser principal stress b e₁ + a e₂ (a = 2μ + λ_s,
      // b = λ_s) is not compressive (then neither is the greater); wrinkled
      // while only e₁ stretches
      real const a = 2 * mu + lambdaPlaneStress, b = lambdaPlaneStress;
      uniaxial_ = (a * a - b * b) / a;  // Y: a strip free to narrow (E)
      state_ = !(e1_ > 0) ? Slack : b * e1_ + a * e2_ >= 0 ? Taut : Wrinkled;
    }
    switch (state_) {
      case Slack: s_.setZero(); break;
      case Wrinkled: s_ = uniaxial_ * e1_ * v1_ * v1_.transpose(); break;
      case Taut: s_ = SecondPiola(mu_, lambda_, strain_); break;
    }
  }

  /// Ψ [J/m³]
  real EnergyDensity() const {
    switch (state_) {
      case Slack: return 0;
      case Wrinkled: return 0.5 * uniaxial_ * e1_ * e1_;
      case Taut: break;
    }
    return StvkEnergyDensity(mu_, lambda_, strain_);
  }
  /// The second Piola–Kirchhoff stress S
  Matrix22 const& Stress() const { return s_; }
  /// dS along dE. Taut (StVK): linear. Wrinkled, S = Y e₁ v₁v₁ᵀ:
  /// Y (v₁ᵀdE v₁) v₁v₁ᵀ plus the turn of v₁, (s₁ − s₂)/(e₁ − e₂)
  /// (v₁ᵀdE v₂)(v₁v₂ᵀ + v₂v₁ᵀ), with e₁ − e₂ > e₁ > 0 there. Slack: 0.
  Matrix22 Differential(Matrix22 const& dE) const {
    switch (state_) {
      case Slack: return Matrix22::Zero();
      case Wrinkled: {
        Matrix22 const v12 = v1_ * v2_.transpose();
        real const turn = uniaxial_ * e1_ / (e1_ - e2_);
        return uniaxial_ * v1_.dot(dE * v1_) * v1_ * v1_.transpose() + turn * v1_.dot(dE * v2_) * (v12 + v12.transpose());
      }
      case Taut: break;
    }
    return SecondPiola(mu_, lambda_, dE);
  }

 private:
  enum State { Slack, Wrinkled, Taut } state_ = Taut;
  real mu_, lambda_;
  Matrix22 strain_, s_;
  real e1_ = 0, e2_ = 0, uniaxial_ = 0;
  Eigen::Matrix<real, 2, 1> v1_, v2_;
};

Matrix22 GreenStrain(Matrix32 const& f) { return 0.5 * (f.transpose() * f - Matrix22::Identity()); }

/// ∂²Ψ/∂F² = ∂vec P/∂vec F at F with the stress state there
Matrix6 StressDerivative(MembraneStress const& stress, Matrix32 const& f) {
  // column k = 3j + i of ∂vec P/∂vec F is vec(dP) for dF = e_i e_jᵀ:
  //   dP = dF S + F dS,  dS = MembraneStress::Differential(dE),  dE = sym(Fᵀ dF)
  Matrix6 a;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 3; ++i) {
      Matrix32 df = Matrix32::Zero();
      df(i, j) = 1;
      Matrix22 const ftdf = f.transpose() * df;
      Matrix22 const dE = 0.5 * (ftdf + ftdf.transpose());
      Matrix32 const dp = df * stress.Stress() + f * stress.Differential(dE);
      a.col(3 * j + i) = dp.reshaped();
    }
  }
  // symmetric in exact arithmetic; make it so bit for bit
  return 0.5 * (a + a.transpose());
}

/// `a` with its negative eigenvalues clamped to 0; `a` itself when none is
Matrix6 ClampedToPsd(Matrix6 const& a) {
  auto const eigen = ComputeSymmetricEigen(a);
  auto const& values = eigen.values;
  if (values.minCoeff() >= 0) return a;
  Matrix6 const& q = eigen.vectors;
  Matrix6 const projected = q * values.cwiseMax(0).asDiagonal() * q.transpose();
  return 0.5 * (projected + projected.transpose());
}

}  // namespace

// ---------------------------------------------------------------- membrane

bool MakeTriangleRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, TriangleRestData& rest) {
  if (!IsNonDegenerateTriangle(x0, x1, x2)) return false;
  Real3 const d1 = x1 - x0, d2 = x2 - x0;
  Real3 const normal = d1.cross(d2);
  // orthonormal frame of the rest plane: e1 along d1, e2 = n̂ × e1
  Real3 const e1 = d1.normalized();
  Real3 const e2 = normal.normalized().cross(e1);
  Matrix22 dm;
  dm << e1.dot(d1), e1.dot(d2),  //
      e2.dot(d1), e2.dot(d2);    // upper triangular up to rounding: e2·d1 ≈ 0
  rest.restShapeInverse = dm.inverse();
  rest.restArea = 0.5 * normal.norm();
  return true;
}

Eigen::Matrix<real, 3, 2> MembraneDeformationGradient(TriangleRestData const& rest, Vector9 const& x) {
  return EdgeMatrix(x) * rest.restShapeInverse;
}

real MembraneEnergy(MembraneModel model, real mu, real lambdaPlaneStress, real thickness,
                    TriangleRestData const& rest, Vector9 const& x) {
  Matrix22 const greenStrain = GreenStrain(MembraneDeformationGradient(rest, x));
  return thickness * rest.restArea * MembraneStress(model, mu, lambdaPlaneStress, greenStrain).EnergyDensity();
}

Eigen::Matrix<real, 6, 6> MembraneStressDerivative(MembraneModel model, real mu, real lambdaPlaneStress,
                                                   Eigen::Matrix<real, 3, 2> const& f) {
  return StressDerivative(MembraneStress(model, mu, lambdaPlaneStress, GreenStrain(f)), f);
}

Eigen::Matrix<real, 6, 6> MembraneProjectedStressDerivative(MembraneModel model, real mu, real lambdaPlaneStress,
                                                            Eigen::Matrix<real, 3, 2> const& f) {
  return ClampedToPsd(MembraneStressDerivative(model, mu, lambdaPlaneStress, f));
}

real MembraneEnergyGradientHessian(MembraneModel model, real mu, real lambdaPlaneStress, real thickness,
                                   TriangleRestData const& rest, Vector9 const& x,
                                   Vector9& gradient, Matrix9& hessian, bool project) {
  Matrix22 const& b = rest.restShapeInverse;
  Matrix32 const f = MembraneDeformationGradient(rest, x);
  MembraneStress const stress(model, mu, lambdaPlaneStress, GreenStrain(f));
  real const scale = thickness * rest.restArea;  // h·A

  // gradient: ∂E/∂D_s = h A P Bᵀ with P = F S; node 0 takes minus the sum
  Matrix32 const p = f * stress.Stress();
  Matrix32 const forces = scale * p * b.transpose();
  gradient.segment<3>(3) = forces.col(0);
  gradient.segment<3>(6) = forces.col(1);
  gradient.segment<3>(0) = -(forces.col(0) + forces.col(1));

  // Hessian: h A Gᵀ (∂²Ψ/∂F²) G with G = ∂vec F/∂x (6×9):
  // F = Σₐ xₐ gₐᵀ, g₁ᵀ, g₂ᵀ the rows of B, g₀ = −(g₁ + g₂)
  Eigen::Matrix<real, 3, 2> shapeGradients;  // row a = gₐᵀ
  shapeGradients.row(1) = b.row(0);
  shapeGradients.row(2) = b.row(1);
  shapeGradients.row(0) = -(b.row(0) + b.row(1));
  Matrix69 g = Matrix69::Zero();
  for (int node = 0; node < 3; ++node)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) g(3 * j + i, 3 * node + i) = shapeGradients(node, j);

  Matrix6 const exact = StressDerivative(stress, f);
  Matrix6 const stressDerivative = project ? ClampedToPsd(exact) : exact;
  hessian.noalias() = scale * (g.transpose() * stressDerivative * g);
  hessian = 0.5 * (hessian + hessian.transpose()).eval();

  return scale * stress.EnergyDensity();
}

// ----------------------------------------------------------------- bending

real HingeBendingStiffness(real youngModulus, real poissonRatio, real thickness) {
  return youngModulus * thickness * thickness * thickness /
         (kHingeStiffnessDivisor * (1 - poissonRatio * poissonRatio));
}

bool MakeHingeRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, Real3 const& x3,
                       HingeRestData& rest) {
  if (!IsNonDegenerateTriangle(x0, x1, x2) || !IsNonDegenerateTriangle(x0, x1, x3)) return false;
  Real3 const edge = x1 - x0;
  // angles of triangle (x0, x1, x2) at x0 and x1, and of (x0, x1, x3)
  real const cotA0 = Cotangent(edge, x2 - x0), cotA1 = Cotangent(-edge, x2 - x1);
  real const cotB0 = Cotangent(edge, x3 - x0), cotB1 = Cotangent(-edge, x3 - x1);
  rest.cotangentWeights << cotA1 + cotB1, cotA0 + cotB0, -(cotA0 + cotA1), -(cotB0 + cotB1);
  rest.areaSum = 0.5 * (edge.cross(x2 - x0).norm() + edge.cross(x3 - x0).norm());
  rest.restPositions << x0, x1, x2, x3;
  return true;
}

namespace {

/// v = Σⱼ Kⱼ (xⱼ − x̄ⱼ)
Real3 HingeBendVector(HingeRestData const& rest, Vector12 const& x) {
  Real3 v = Real3::Zero();
  for (int j = 0; j < 4; ++j)
    v += rest.cotangentWeights[j] * (x.segment<3>(3 * j) - rest.restPositions.segment<3>(3 * j));
  return v;
}

}  // namespace

real BendingEnergy(real bendingStiffness, HingeRestData const& rest, Vector12 const& x) {
  real const c = 3 * bendingStiffness / rest.areaSum;
  return 0.5 * c * HingeBendVector(rest, x).squaredNorm();
}

real BendingEnergyGradientHessian(real bendingStiffness, HingeRestData const& rest,
                                  Vector12 const& x, Vector12& gradient, Matrix12& hessian) {
  real const c = 3 * bendingStiffness / rest.areaSum;
  Real3 const v = HingeBendVector(rest, x);
  auto const& k = rest.cotangentWeights;
  for (int a = 0; a < 4; ++a) {
    gradient.segment<3>(3 * a) = c * k[a] * v;
    for (int b = 0; b < 4; ++b)
      hessian.block<3, 3>(3 * a, 3 * b) = (c * (k[a] * k[b])) * Real33::Identity();  // symmetric bit for bit
  }
  return 0.5 * c * v.squaredNorm();
}

real HingeDihedralAngle(Vector12 const& x) {
  Real3 const x0 = x.segment<3>(0), x1 = x.segment<3>(3), x2 = x.segment<3>(6),
              x3 = x.segment<3>(9);
  Real3 const edge = x1 - x0;
  Real3 const nA = edge.cross(x2 - x0);  // normal of (x0, x1, x2)
  Real3 const nB = (x3 - x0).cross(edge);  // normal of (x1, x0, x3)
  real const edgeLength = edge.norm();
  if (!(edgeLength > 0)) return 0;
  // sin θ ‖nA‖‖nB‖ and cos θ ‖nA‖‖nB‖; atan2 is scale-free
  return std::atan2(nA.cross(nB).dot(edge) / edgeLength, nA.dot(nB));
}

}  // namespace superdex::internal
