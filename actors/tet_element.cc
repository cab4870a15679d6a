#include <superdex/actors/tet_element.h>

#include <superdex/core/symmetric_eigen.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace superdex {

std::string_view ToString(TetMaterialModel model) {
  switch (model) {
    case TetMaterialModel::StableNeoHookean:
      return "StableNeoHookean";
    case TetMaterialModel::LinearElastic:
      return "LinearElastic";
  }
  return "Unknown";
}

namespace internal {
namespace {

using Vector9 = Eigen::Matrix<real, 9, 1>;

/// [v]×: [v]× w = v × w.
Real33 Hat(Real3 const& v) {
  Real33 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// cof F = J F⁻ᵀ, column-wise [f₁×f₂, f₂×f₀, f₀×f₁]; defined for any F.
Real33 Cofactor(Real33 const& f) {
  Real33 c;
  c.col(0) = f.col(1).cross(f.col(2));
  c.col(1) = f.col(2).cross(f.col(0));
  c.col(2) = f.col(0).cross(f.col(1));
  return c;
}

Vector9 Vec(Real33 const& m) {
  return Eigen::Map<Vector9 const>(m.data());
}

/// λ' = λ + μ of the stable Neo-Hookean model.
real SnhLambda(LameParameters const& lame) {
  return lame.lambda + lame.mu;
}

/// SNH Ψ and P from F, J and cof F.
real SnhEnergyDensity(LameParameters const& lame, Real33 const& f, real j) {
  real const lambdaP = SnhLambda(lame);
  return real(0.5) * lame.mu * (f.squaredNorm() - 3) - lame.mu * (j - 1) +
         real(0.5) * lambdaP * (j - 1) * (j - 1);
}

Real33 SnhStress(LameParameters const& lame, Real33 const& f, real j, Real33 const& cof) {
  return lame.mu * f + (SnhLambda(lame) * (j - 1) - lame.mu) * cof;
}

/// SNH ∂²Ψ/∂F² = μ I + s ∂²J/∂F² + λ' vec(cof) vec(cof)ᵀ, s = λ'(J − 1) − μ.
Matrix9 SnhStressDerivative(LameParameters const& lame, Real33 const& f, real j,
                            Real33 const& cof) {
  real const lambdaP = SnhLambda(lame);
  real const s = lambdaP * (j - 1) - lame.mu;
  Vector9 const g = Vec(cof);
  Matrix9 a = lambdaP * g * g.transpose();
  a.diagonal().array() += lame.mu;
  // s ∂²J/∂F²: block (r, c) couples column r of F with column c
  Real33 const h0 = s * Hat(f.col(0)), h1 = s * Hat(f.col(1)), h2 = s * Hat(f.col(2));
  a.block<3, 3>(0, 3) -= h2;
  a.block<3, 3>(0, 6) += h1;
  a.block<3, 3>(3, 0) += h2;
  a.block<3, 3>(3, 6) -= h0;
  a.block<3, 3>(6, 0) -= h1;
  a.block<3, 3>(6, 3) += h0;
  return a;
}

/// Small strain ε = sym(F) − I.
Real33 SmallStrain(Real33 const& f) {
  return real(0.5) * (f + f.transpose()) - Real33::Identity();
}

/// LinearElastic ∂²Ψ/∂F² = μ (I + T) + λ vec(I) vec(I)ᵀ.
Matrix9 LinearStressDerivative(LameParameters const& lame) {
  Matrix9 a = Matrix9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      a(i + 3 * j, i + 3 * j) += lame.mu;  // identity
      a(i + 3 * j, j + 3 * i) += lame.mu;  // transpose: ∂(Fᵀ)_ij/∂F_ji
    }
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) a(4 * i, 4 * k) += lame.lambda;  // vec(I) at 0, 4, 8
  return a;
}

/// PSD(LinearElastic ∂²Ψ/∂F²) from its analytic eigensystem: 0 on skew
/// gradients, 2μ on symmetric traceless ones, 2μ + 3λ on vec(I)/√3.
Matrix9 LinearProjectedStressDerivative(LameParameters const& lame) {
  real const deviatoric = 2 * lame.mu, volumetric = 2 * lame.mu + 3 * lame.lambda;
  if (deviatoric >= 0 && volumetric >= 0) return LinearStressDerivative(lame);
  // projector on symmetric matrices ½(I + T) and on vec(I)/√3
  Matrix9 symmetric = Matrix9::Zero(), trace = Matrix9::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      symmetric(i + 3 * j, i + 3 * j) += real(0.5);
      symmetric(i + 3 * j, j + 3 * i) += real(0.5);
    }
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) trace(4 * i, 4 * k) = real(1) / 3;
  return std::max(deviatoric, real(0)) * (symmetric - trace) +
         std::max(volumetric, real(0)) * trace;
}

/// Eigen-decomposition a = W diag(values) Wᵀ of the symmetric 3×3 `a` by
/// cyclic Jacobi rotations (W a rotation). Accurate to ~ε‖a‖ in every
/// eigenvalue, and several times faster here than Eigen's iterative 3×3
/// solver; no ordering.
void SymmetricEigen3(Real33 a, Real3& values, Real33& w) {
  w.setIdentity();
  for (int sweep = 0; sweep < 12; ++sweep) {
    real const off = a(0, 1) * a(0, 1) + a(0, 2) * a(0, 2) + a(1, 2) * a(1, 2);
    real const diagonal = a(0, 0) * a(0, 0) + a(1, 1) * a(1, 1) + a(2, 2) * a(2, 2);
    if (!(off > real(1e-36) * diagonal)) break;  // converged (or zero, or not finite)
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        real const apq = a(p, q);
        if (apq == 0) continue;
        // the rotation that zeroes a(p, q) (Numerical Recipes, "jacobi")
        real const theta = (a(q, q) - a(p, p)) / (2 * apq);
        real const t =
            std::abs(theta) > real(1e150)
                ? real(0.5) / theta
                : std::copysign(real(1), theta) / (std::abs(theta) + std::sqrt(theta * theta + 1));
        real const c = 1 / std::sqrt(t * t + 1), s = t * c;
        int const r = 3 - p - q;
        a(p, p) -= t * apq;
        a(q, q) += t * apq;
        a(p, q) = a(q, p) = 0;
        real const arp = a(r, p), arq = a(r, q);
        a(r, p) = a(p, r) = c * arp - s * arq;
        a(r, q) = a(q, r) = s * arp + c * arq;
        for (int k = 0; k < 3; ++k) {
          real const wkp = w(k, p), wkq = w(k, q);
          w(k, p) = c * wkp - s * wkq;
          w(k, q) = s * wkp + c * wkq;
        }
      }
  }
  values = a.diagonal();
}

/// Rotation-variant SVD F = U diag(σ) Vᵀ: U, V rotations, σ₀ >= σ₁ >= |σ₂|,
/// the sign of det F on σ₂. V from the eigenvectors of FᵀF, U from the
/// columns of F V (so σ is accurate to ~ε‖F‖ even where it is tiny); where
/// F is rank-deficient the free columns of U complete a right-handed frame.
void RotationVariantSvd(Real33 const& f, Real33& u, Real3& sigma, Real33& v) {
  Real3 values;
  Real33 w;
  SymmetricEigen3(f.transpose() * f, values, w);
  // descending order, kept a rotation: an odd permutation negates a column
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return values[a] > values[b]; });
  for (int k = 0; k < 3; ++k) v.col(k) = w.col(order[k]);
  if (v.determinant() < 0) v.col(2) = -v.col(2);
  Real33 const b = f * v;
  sigma[0] = b.col(0).norm();
  if (!(sigma[0] > 0)) {  // F = 0
    u.setIdentity();
    sigma.setZero();
    return;
  }
  u.col(0) = b.col(0) / sigma[0];
  Real3 const b1 = b.col(1) - u.col(0).dot(b.col(1)) * u.col(0);
  real const n1 = b1.norm();
  if (n1 > std::numeric_limits<real>::epsilon() * sigma[0]) {
    u.col(1) = b1 / n1;
  } else {  // rank 1: any unit vector orthogonal to u₀
    Eigen::Index smallest;
    u.col(0).cwiseAbs().minCoeff(&smallest);
    u.col(1) = u.col(0).cross(Real3::Unit(smallest)).normalized();
  }
  u.col(2) = u.col(0).cross(u.col(1));
  sigma[1] = u.col(1).dot(b.col(1));
  sigma[2] = u.col(2).dot(b.col(2));
}

/// PSD(SNH ∂²Ψ/∂F²) from the analytic eigensystem (file comment of the
/// header): the exact ∂²Ψ/∂F² minus αₖ qₖ qₖᵀ for each negative eigenpair,
/// so only the (usually one to three) negative modes cost anything.
Matrix9 SnhAnalyticProjectedStressDerivative(LameParameters const& lame, Real33 const& f) {
  real const j = f.determinant();
  Matrix9 a = SnhStressDerivative(lame, f, j, Cofactor(f));
  Real33 u, v;
  Real3 sigma;
  RotationVariantSvd(f, u, sigma, v);
  real const lambdaP = SnhLambda(lame);
  real const s = lambdaP * (j - 1) - lame.mu;

  // twist (μ + sσₘ) and flip (μ − sσₘ) modes of the pair {i, k} = {m+1, m+2}
  real const invSqrt2 = real(1) / std::sqrt(real(2));
  for (int m = 0; m < 3; ++m) {
    real const twist = lame.mu + s * sigma[m], flip = lame.mu - s * sigma[m];
    if (twist >= 0 && flip >= 0) continue;
    int const i = (m + 1) % 3, k = (m + 2) % 3;
    Real33 const uv = u.col(i) * v.col(k).transpose(), vu = u.col(k) * v.col(i).transpose();
    if (twist < 0) {
      Vector9 const q = Vec(invSqrt2 * (uv - vu));
      a.noalias() -= (twist * q) * q.transpose();
    }
    if (flip < 0) {
      Vector9 const q = Vec(invSqrt2 * (uv + vu));
      a.noalias() -= (flip * q) * q.transpose();
    }
  }

  // the scaling modes U diag(e) Vᵀ: μ I + s [[0, σ₂, σ₁], [σ₂, 0, σ₀], [σ₁, σ₀, 0]] + λ' c cᵀ
  Real3 const c(sigma[1] * sigma[2], sigma[0] * sigma[2], sigma[0] * sigma[1]);
  Real33 scaling = lambdaP * c * c.transpose();
  scaling.diagonal().array() += lame.mu;
  scaling(0, 1) += s * sigma[2];
  scaling(1, 0) += s * sigma[2];
  scaling(0, 2) += s * sigma[1];
  scaling(2, 0) += s * sigma[1];
  scaling(1, 2) += s * sigma[0];
  scaling(2, 1) += s * sigma[0];
  // usually positive definite (2μ I + λ 11ᵀ at rest): Sylvester's criterion
  // on the leading minors, then no eigen-decomposition at all
  real const minor2 = scaling(0, 0) * scaling(1, 1) - scaling(0, 1) * scaling(0, 1);
  if (scaling(0, 0) > 0 && minor2 > 0 && scaling.determinant() > 0) return a;
  Real3 scalingValues;
  Real33 scalingVectors;
  SymmetricEigen3(scaling, scalingValues, scalingVectors);
  for (int e = 0; e < 3; ++e) {
    if (scalingValues[e] >= 0) continue;
    Vector9 const q = Vec(u * scalingVectors.col(e).asDiagonal() * v.transpose());
    a.noalias() -= (scalingValues[e] * q) * q.transpose();
  }
  return a;
}

}  // namespace

LameParameters LameFromYoungPoisson(real youngModulus, real poissonRatio) {
  real const e = youngModulus, nu = poissonRatio;
  return {.mu = e / (2 * (1 + nu)), .lambda = e * nu / ((1 + nu) * (1 - 2 * nu))};
}

bool MakeTetRestData(Real3 const& x0, Real3 const& x1, Real3 const& x2, Real3 const& x3,
                     TetRestData& rest) {
  Real33 dm;
  dm << x1 - x0, x2 - x0, x3 - x0;
  real const maxEdge = std::sqrt(
      std::max({dm.col(0).squaredNorm(), dm.col(1).squaredNorm(), dm.col(2).squaredNorm(),
                (x2 - x1).squaredNorm(), (x3 - x1).squaredNorm(), (x3 - x2).squaredNorm()}));
  real const volume = dm.determinant() / 6;
  // written as a negation so that NaN (non-finite input) is rejected too
  if (!(volume > real(1e-12) * maxEdge * maxEdge * maxEdge) || !std::isfinite(volume)) return false;
  rest.restShapeInverse = dm.inverse();
  rest.restVolume = volume;
  return true;
}

Real33 TetDeformationGradient(TetRestData const& rest, Vector12 const& x) {
  Real3 const x0 = x.segment<3>(0);
  Real33 ds;
  ds << x.segment<3>(3) - x0, x.segment<3>(6) - x0, x.segment<3>(9) - x0;
  return ds * rest.restShapeInverse;
}

real TetEnergyDensity(TetMaterialModel model, LameParameters const& lame, Real33 const& f) {
  switch (model) {
    case TetMaterialModel::StableNeoHookean:
      return SnhEnergyDensity(lame, f, f.determinant());
    case TetMaterialModel::LinearElastic: {
      Real33 const eps = SmallStrain(f);
      real const trace = eps.trace();
      return lame.mu * eps.squaredNorm() + real(0.5) * lame.lambda * trace * trace;
    }
  }
  return 0;
}

real TetEnergy(TetMaterialModel model, LameParameters const& lame, TetRestData const& rest,
               Vector12 const& x) {
  return rest.restVolume * TetEnergyDensity(model, lame, TetDeformationGradient(rest, x));
}

Real33 TetFirstPiolaStress(TetMaterialModel model, LameParameters const& lame, Real33 const& f) {
  switch (model) {
    case TetMaterialModel::StableNeoHookean:
      return SnhStress(lame, f, f.determinant(), Cofactor(f));
    case TetMaterialModel::LinearElastic: {
      Real33 const eps = SmallStrain(f);
      return 2 * lame.mu * eps + lame.lambda * eps.trace() * Real33::Identity();
    }
  }
  return Real33::Zero();
}

Matrix9 TetStressDerivative(TetMaterialModel model, LameParameters const& lame, Real33 const& f) {
  switch (model) {
    case TetMaterialModel::StableNeoHookean:
      return SnhStressDerivative(lame, f, f.determinant(), Cofactor(f));
    case TetMaterialModel::LinearElastic:
      return LinearStressDerivative(lame);
  }
  return Matrix9::Zero();
}

Matrix9 ProjectToPsdEigenSolver(Matrix9 const& a) {
  auto const eigen = ComputeSymmetricEigen(a);
  Vector9 const alpha = eigen.values;
  if (alpha.minCoeff() >= 0) return a;
  Matrix9 const scaled = eigen.vectors * alpha.cwiseMax(real(0)).asDiagonal();
  return scaled * eigen.vectors.transpose();
}

Matrix9 TetProjectedStressDerivative(TetMaterialModel model, LameParameters const& lame,
                                     Real33 const& f, TetPsdProjection projection) {
  switch (projection) {
    case TetPsdProjection::None:
      return TetStressDerivative(model, lame, f);
    case TetPsdProjection::EigenSolver:
      return ProjectToPsdEigenSolver(TetStressDerivative(model, lame, f));
    case TetPsdProjection::Analytic:
      return model == TetMaterialModel::StableNeoHookean
                 ? SnhAnalyticProjectedStressDerivative(lame, f)
                 : LinearProjectedStressDerivative(lame);
  }
  return TetStressDerivative(model, lame, f);
}

void TetHessianFromStressDerivative(TetRestData const& rest, Matrix9 const& a, Matrix12& hessian) {
  Real33 const& g = rest.restShapeInverse;  // row a−1 is gₐ for nodes a = 1..3
  // C = A (Gᵀ ⊗ I₃): column block b is Σₗ A(:, block l) G(b, l)
  Matrix9 c;
  for (int b = 0; b < 3; ++b)
    c.middleCols<3>(3 * b) =
        g(b, 0) * a.middleCols<3>(0) + g(b, 1) * a.middleCols<3>(3) + g(b, 2) * a.middleCols<3>(6);
  // H' = V (Gᵀ ⊗ I₃)ᵀ C: the blocks of nodes 1..3; row block a is Σⱼ G(a, j) C(block j, :)
  Matrix9 h;
  for (int r = 0; r < 3; ++r)
    h.middleRows<3>(3 * r) =
        g(r, 0) * c.middleRows<3>(0) + g(r, 1) * c.middleRows<3>(3) + g(r, 2) * c.middleRows<3>(6);
  // symmetrized through a temporary (h = h + hᵀ would alias)
  Matrix9 const symmetric = (real(0.5) * rest.restVolume) * (h + h.transpose());
  // node 0: g₀ = −(g₁ + g₂ + g₃), so its blocks are minus the sums of the others'
  Eigen::Matrix<real, 3, 9> const row0 =
      -(symmetric.middleRows<3>(0) + symmetric.middleRows<3>(3) + symmetric.middleRows<3>(6));
  Real33 const h00 = -(row0.middleCols<3>(0) + row0.middleCols<3>(3) + row0.middleCols<3>(6));
  hessian.topLeftCorner<3, 3>() = real(0.5) * (h00 + h00.transpose());
  hessian.topRightCorner<3, 9>() = row0;
  hessian.bottomLeftCorner<9, 3>() = row0.transpose();
  hessian.bottomRightCorner<9, 9>() = symmetric;
}

real TetEnergyGradientHessian(TetMaterialModel model, LameParameters const& lame,
                              TetRestData const& rest, Vector12 const& x, Vector12& gradient,
                              Matrix12& hessian, TetPsdProjection projection) {
  Real33 const f = TetDeformationGradient(rest, x);
  real energyDensity = 0;
  Real33 stress;
  Matrix9 stressDerivative;
  if (model == TetMaterialModel::StableNeoHookean) {
    // J and cof F once for Ψ, P and (unprojected) ∂²Ψ/∂F²
    real const j = f.determinant();
    Real33 const cof = Cofactor(f);
    energyDensity = SnhEnergyDensity(lame, f, j);
    stress = SnhStress(lame, f, j, cof);
    switch (projection) {
      case TetPsdProjection::None:
        stressDerivative = SnhStressDerivative(lame, f, j, cof);
        break;
      case TetPsdProjection::Analytic:
        stressDerivative = SnhAnalyticProjectedStressDerivative(lame, f);
        break;
      case TetPsdProjection::EigenSolver:
        stressDerivative = ProjectToPsdEigenSolver(SnhStressDerivative(lame, f, j, cof));
        break;
    }
  } else {
    energyDensity = TetEnergyDensity(model, lame, f);
    stress = TetFirstPiolaStress(model, lame, f);
    stressDerivative = TetProjectedStressDerivative(model, lame, f, projection);
  }
  // node a = 1..3: V P gₐ, i.e. the columns of V P Gᵀ; node 0 minus their sum
  Real33 const nodes123 = rest.restVolume * stress * rest.restShapeInverse.transpose();
  gradient.segment<9>(3) = Vec(nodes123);
  gradient.segment<3>(0) = -(nodes123.col(0) + nodes123.col(1) + nodes123.col(2));
  TetHessianFromStressDerivative(rest, stressDerivative, hessian);
  return rest.restVolume * energyDensity;
}

real TetEnergyGradientHessian(TetMaterialModel model, LameParameters const& lame,
                              TetRestData const& rest, Vector12 const& x, Vector12& gradient,
                              Matrix12& hessian, bool project) {
  return TetEnergyGradientHessian(model, lame, rest, x, gradient, hessian,
                                  project ? TetPsdProjection::Analytic : TetPsdProjection::None);
}

}  // namespace internal
}  // namespace superdex
