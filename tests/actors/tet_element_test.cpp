// Linear tetrahedron kernels (actors/tet_element.h), both material models:
//
// (a) Lamé parameters, MakeTetRestData (accepts a well-shaped element at any
//     scale; rejects coplanar, inverted, sliver and non-finite ones), and F
//     of an affine map;
// (b) at rest (F = I): energy 0, gradient 0;
// (c) stretched, compressed, sheared, rotated, inverted (a node pushed
//     through the opposite face, J < 0) and flat (J = 0) elements: the
//     gradient against central differences of the energy, the UNPROJECTED
//     Hessian against central differences of the gradient, P against
//     central differences of Ψ, translation invariance;
// (d) the projected Hessian: exactly symmetric, PSD, equal to the exact one
//     where that is PSD (rest, stretch), different where it is not
//     (compression, inversion), analytic eigensystem = Eigen's 9×9 solver;
// (e) SNH linearized at rest = LinearElastic (the choice λ' = λ + μ);
// (f) rotations: SNH is invariant (energy, gradient and Hessian rotate);
//     LinearElastic is NOT: a rigidly rotated element stores energy and
//     pushes back with spurious forces, the known defect of small strain;
// (g) no heap allocation in the kernels.
//
// The element is realistic: edges ~0.1 m, E = 1e5 Pa, so V ~ 2e-4 m³,
// energies ~1e-2..1 J, gradients ~1..1e2 N and Hessians ~1e3..1e4 N/m.
// Derivative comparisons divide both sides by the largest entry of the
// analytic value and then use |a − b| <= tol·max(|a|, |b|, 1): relative to the
// entry itself where it is large, to the largest entry where it is small.
#include <superdex/actors/tet_element.h>

#include <Eigen/LU>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>

#include "allocation_recorder.h"
#include "test_support.h"

using namespace superdex;
using namespace superdex::test;
using internal::LameParameters;
using internal::Matrix12;
using internal::Matrix9;
using internal::TetPsdProjection;
using internal::TetRestData;
using internal::Vector12;

namespace {

using Model = TetMaterialModel;

constexpr real kYoung = 1e5;  // E [Pa]

// Central differences with step 1e-6 m (1e-5 of the element size).
// Gradient from energy: truncation h²/6·|E'''| ~ 1e-12/6 · V μ/L³ ~ 1e-9 N,
// round-off ε·|E|/h ~ 1e-11 N, against gradients ~1..1e2 N.
// Hessian from gradient: truncation h²/6·|E''''| ~ 1e-12/6 · Vμ/L⁴ ~ 1e-8,
// round-off ε·|g|/h ~ 1e-8, against Hessians ~1e3..1e4 N/m. Measured
// ~1e-10..1e-9 relative to the largest entry; the tolerance is 1e-6.
constexpr real kFdStep = 1e-6;
constexpr real kDerivativeTol = 1e-6;
// analytic vs analytic: different formulas for one quantity, round-off only
constexpr real kRoundoffTol = 1e-12;
// PSD: smallest eigenvalue >= −kPsdTol · largest
constexpr real kPsdTol = 1e-10;

/// An irregular, well-shaped element with edges ~0.1 m (det D_m > 0).
std::array<Real3, 4> RestNodes() {
  return {Real3(0.01, -0.02, 0.005), Real3(0.11, -0.01, 0.0), Real3(0.03, 0.075, 0.015),
          Real3(0.025, 0.0, 0.12)};
}

Vector12 Stack(std::array<Real3, 4> const& nodes) {
  Vector12 x;
  for (int a = 0; a < 4; ++a) x.segment<3>(3 * a) = nodes[a];
  return x;
}

/// The rest element mapped by x ↦ F x + t (uniform deformation gradient F).
Vector12 Affine(Real33 const& f, Real3 const& t = Real3(0.3, -0.2, 0.1)) {
  std::array<Real3, 4> nodes = RestNodes();
  for (Real3& p : nodes) p = f * p + t;
  return Stack(nodes);
}

TetRestData MakeRest() {
  auto const nodes = RestNodes();
  TetRestData rest;
  REQUIRE(internal::MakeTetRestData(nodes[0], nodes[1], nodes[2], nodes[3], rest));
  return rest;
}

Real33 Rotation(real angle, Real3 const& axis) {
  return Eigen::AngleAxis<real>(angle, axis.normalized()).toRotationMatrix();
}

Real33 StretchF() {
  Real33 f;
  f << 1.25, 0.04, -0.02, 0.03, 0.95, 0.05, -0.01, 0.02, 1.1;
  return f;
}

enum class State { Rest, Stretched, Compressed, Sheared, Rotated, Inverted, Flat };

char const* Name(State state) {
  switch (state) {
    case State::Rest:
      return "rest";
    case State::Stretched:
      return "stretched";
    case State::Compressed:
      return "compressed";
    case State::Sheared:
      return "sheared";
    case State::Rotated:
      return "rotated";
    case State::Inverted:
      return "inverted";
    case State::Flat:
      return "flat";
  }
  return "?";
}

/// Node 3 moved along the normal n of face (0, 1, 2) to signed height
/// `fraction` × its rest height: −0.5 pushes it through the face (J = −0.5),
/// 0 puts it in the face's plane (J = 0).
Vector12 MoveNode3(real fraction) {
  std::array<Real3, 4> nodes = RestNodes();
  Real3 const n = (nodes[1] - nodes[0]).cross(nodes[2] - nodes[0]).normalized();
  real const height = (nodes[3] - nodes[0]).dot(n);
  nodes[3] -= (1 - fraction) * height * n;
  return Stack(nodes);
}

Vector12 Configuration(State state) {
  switch (state) {
    case State::Rest:
      return Stack(RestNodes());
    case State::Stretched:
      return Affine(StretchF());
    case State::Compressed: {
      Real33 f;
      f << 0.7, 0.05, 0.02, -0.03, 0.85, 0.04, 0.02, -0.05, 0.8;
      return Affine(f);
    }
    case State::Sheared: {
      Real33 f = Real33::Identity();  // isochoric simple shear, J = 1
      f(0, 1) = 0.4;
      f(2, 0) = 0.2;
      return Affine(f);
    }
    case State::Rotated:
      return Affine(Rotation(0.7, Real3(1, 2, -1)) * StretchF());
    case State::Inverted:
      return MoveNode3(-0.5);
    case State::Flat:
      return MoveNode3(0);
  }
  return Stack(RestNodes());
}

LameParameters Lame(real poissonRatio) {
  return internal::LameFromYoungPoisson(kYoung, poissonRatio);
}

/// Largest entrywise |a − b| / max(|a|, |b|, 1) after dividing both by `scale`.
template <class A, class B>
real ScaledError(A const& a, B const& b, real scale) {
  REQUIRE(scale > 0);
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  real worst = 0;
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      real const x = a(i, j) / scale, y = b(i, j) / scale;
      // a NaN or infinity is an infinite error, never a silently skipped entry
      if (!std::isfinite(x) || !std::isfinite(y)) return std::numeric_limits<real>::infinity();
      worst = std::max(worst, std::abs(x - y) / std::max({std::abs(x), std::abs(y), real(1)}));
    }
  return worst;
}

/// The same, scaled by the largest entry of `a` (which must not be zero).
template <class A, class B>
real ErrorRelativeToLargest(A const& a, B const& b) {
  return ScaledError(a, b, a.cwiseAbs().maxCoeff());
}

struct Evaluation {
  real energy = 0;
  Vector12 gradient;
  Matrix12 hessian;
};

Evaluation Evaluate(Model model, LameParameters const& lame, TetRestData const& rest,
                    Vector12 const& x, bool project) {
  Evaluation e;
  e.energy =
      internal::TetEnergyGradientHessian(model, lame, rest, x, e.gradient, e.hessian, project);
  return e;
}

Vector12 FdGradient(Model model, LameParameters const& lame, TetRestData const& rest,
                    Vector12 const& x) {
  Vector12 fd;
  for (int i = 0; i < 12; ++i) {
    Vector12 plus = x, minus = x;
    plus[i] += kFdStep;
    minus[i] -= kFdStep;
    fd[i] = (internal::TetEnergy(model, lame, rest, plus) -
             internal::TetEnergy(model, lame, rest, minus)) /
            (2 * kFdStep);
  }
  return fd;
}

/// Central differences of the analytic gradient, column by column.
Matrix12 FdHessian(Model model, LameParameters const& lame, TetRestData const& rest,
                   Vector12 const& x) {
  Matrix12 fd;
  for (int i = 0; i < 12; ++i) {
    Vector12 plus = x, minus = x;
    plus[i] += kFdStep;
    minus[i] -= kFdStep;
    fd.col(i) = (Evaluate(model, lame, rest, plus, false).gradient -
                 Evaluate(model, lame, rest, minus, false).gradient) /
                (2 * kFdStep);
  }
  return fd;
}

template <int N>
Eigen::Matrix<real, N, 1> Eigenvalues(Eigen::Matrix<real, N, N> const& m) {
  auto const eigen = ComputeSymmetricEigen(m);
  REQUIRE(eigen.converged);
  return eigen.values;
}

/// blockdiag(R, R, R, R)
Matrix12 NodeRotation(Real33 const& r) {
  Matrix12 q = Matrix12::Zero();
  for (int a = 0; a < 4; ++a) q.block<3, 3>(3 * a, 3 * a) = r;
  return q;
}

}  // namespace

// ---------------------------------------------------------------------------
// (a) parameters, rest data, deformation gradient
// ---------------------------------------------------------------------------

TEST_CASE("Lame parameters from Young's modulus and Poisson's ratio, model names",
          "[actors][tet]") {
  LameParameters const lame = internal::LameFromYoungPoisson(1e5, 0.3);
  REQUIRE(Near(lame.mu, 1e5 / 2.6, 1e-15));
  REQUIRE(Near(lame.lambda, 1e5 * 0.3 / (1.3 * 0.4), 1e-15));
  // bulk modulus K = λ + 2μ/3 = E / (3(1 − 2ν)), for a negative ν too
  for (real nu : {-0.5, 0.0, 0.3, 0.49}) {
    CAPTURE(nu);
    LameParameters const l = internal::LameFromYoungPoisson(2e6, nu);
    REQUIRE(Near(l.lambda + 2 * l.mu / 3, 2e6 / (3 * (1 - 2 * nu)), 1e-14));
    REQUIRE(Near(l.mu, 2e6 / (2 * (1 + nu)), 1e-15));
  }
  REQUIRE(ToString(Model::StableNeoHookean) == "StableNeoHookean");
  REQUIRE(ToString(Model::LinearElastic) == "LinearElastic");
}

TEST_CASE("MakeTetRestData accepts well-shaped elements at any scale and rejects degenerate ones",
          "[actors][tet]") {
  auto const x = RestNodes();
  Real33 dm;
  dm << x[1] - x[0], x[2] - x[0], x[3] - x[0];

  SECTION("well-shaped: D_m inverse and volume det(D_m)/6") {
    TetRestData const rest = MakeRest();
    REQUIRE(dm.determinant() > 1e-4);
    REQUIRE(Near(rest.restVolume, dm.determinant() / 6, 1e-15));
    REQUIRE((rest.restShapeInverse * dm - Real33::Identity()).cwiseAbs().maxCoeff() <= 1e-14);
    // the same shape at 1e-4 the size (volume 1e-12 of it) and translated far
    TetRestData small;
    Real3 const offset(1e3, -2e3, 5e2);
    REQUIRE(internal::MakeTetRestData(1e-4 * x[0] + offset, 1e-4 * x[1] + offset,
                                      1e-4 * x[2] + offset, 1e-4 * x[3] + offset, small));
    REQUIRE(Near(small.restVolume / rest.restVolume, 1e-12, 1e-6));
  }

  SECTION("rejected; rest left unchanged") {
    TetRestData rest;
    rest.restVolume = 42;
    Real3 const n = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    Real3 const inPlane = x[0] + 0.3 * (x[1] - x[0]) + 0.3 * (x[2] - x[0]);
    // coplanar
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[1], x[2], inPlane, rest));
    // inverted: two nodes swapped (det D_m < 0), and node 3 below face 012
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[2], x[1], x[3], rest));
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[1], x[2], inPlane - 0.05 * n, rest));
    // coincident nodes
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[0], x[0], x[0], rest));
    // non-finite
    Real3 const nan(std::numeric_limits<real>::quiet_NaN(), 0, 0);
    Real3 const inf(std::numeric_limits<real>::infinity(), 0, 0);
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[1], x[2], nan, rest));
    REQUIRE_FALSE(internal::MakeTetRestData(x[0], x[1], inf, x[3], rest));
    REQUIRE(rest.restVolume == 42);
  }

  SECTION("slivers: the threshold is 1e-12 (max edge)^3") {
    // node 3 at height δ above face 012: V = area·δ/3, the longest edge ~0.1
    Real3 const n = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    real const area = 0.5 * (x[1] - x[0]).cross(x[2] - x[0]).norm();
    Real3 const inPlane = x[0] + 0.3 * (x[1] - x[0]) + 0.3 * (x[2] - x[0]);
    real const maxEdge =
        std::max({(x[1] - x[0]).norm(), (x[2] - x[0]).norm(), (x[2] - x[1]).norm()});
    real const threshold = 1e-12 * maxEdge * maxEdge * maxEdge;
    auto sliver = [&](real volume) {
      TetRestData rest;
      return internal::MakeTetRestData(x[0], x[1], x[2], inPlane + 3 * volume / area * n, rest);
    };
    REQUIRE_FALSE(sliver(0.5 * threshold));
    REQUIRE(sliver(2 * threshold));
  }
}

TEST_CASE("deformation gradient of an affine map is its matrix, whatever the translation",
          "[actors][tet]") {
  TetRestData const rest = MakeRest();
  Real33 const f = Rotation(0.4, Real3(0.2, 1, 0.3)) * StretchF();
  for (Real3 const& t : {Real3(0, 0, 0), Real3(10, -5, 3)}) {
    Real33 const computed = internal::TetDeformationGradient(rest, Affine(f, t));
    REQUIRE((computed - f).cwiseAbs().maxCoeff() <= 1e-13);
  }
  REQUIRE((internal::TetDeformationGradient(rest, Stack(RestNodes())) - Real33::Identity())
              .cwiseAbs()
              .maxCoeff() <= 1e-14);
  // the inverted and flat configurations have the intended J
  REQUIRE(Near(internal::TetDeformationGradient(rest, MoveNode3(-0.5)).determinant(), -0.5, 1e-13));
  REQUIRE(std::abs(internal::TetDeformationGradient(rest, MoveNode3(0)).determinant()) <= 1e-14);
}

// ---------------------------------------------------------------------------
// (b) rest
// ---------------------------------------------------------------------------

TEST_CASE("at rest the energy and the gradient are zero, the Hessian is not", "[actors][tet]") {
  Model const model = GENERATE(Model::StableNeoHookean, Model::LinearElastic);
  real const nu = GENERATE(0.3, 0.45);
  CAPTURE(ToString(model), nu);
  LameParameters const lame = Lame(nu);
  TetRestData const rest = MakeRest();
  Vector12 const x = Stack(RestNodes());
  // the scales the zeros are judged against: V μ (energy), V μ / L (force)
  real const energyScale = rest.restVolume * lame.mu;
  real const forceScale = energyScale / 0.1;
  REQUIRE(energyScale > 1);

  for (bool project : {false, true}) {
    CAPTURE(project);
    Evaluation const e = Evaluate(model, lame, rest, x, project);
    CAPTURE(e.energy, e.gradient.transpose());
    REQUIRE(std::abs(e.energy) <= 1e-14 * energyScale);
    REQUIRE(e.gradient.cwiseAbs().maxCoeff() <= 1e-13 * forceScale);
    REQUIRE(e.hessian.cwiseAbs().maxCoeff() > 1e-2 * energyScale / (0.1 * 0.1));
  }
  // central differences agree: the energy is stationary at rest
  Vector12 const fd = FdGradient(model, lame, rest, x);
  CAPTURE(fd.transpose());
  REQUIRE(fd.cwiseAbs().maxCoeff() <= 1e-8 * forceScale);
  REQUIRE(internal::TetFirstPiolaStress(model, lame, Real33::Identity()).cwiseAbs().maxCoeff() <=
          1e-12 * lame.mu);
}

// ---------------------------------------------------------------------------
// (c) derivatives against central differences
// ---------------------------------------------------------------------------

TEST_CASE("gradient and exact Hessian match central differences, through inversion",
          "[actors][tet][derivatives]") {
  Model const model = GENERATE(Model::StableNeoHookean, Model::LinearElastic);
  State const state = GENERATE(State::Rest, State::Stretched, State::Compressed, State::Sheared,
                               State::Rotated, State::Inverted, State::Flat);
  real const nu = GENERATE(0.3, 0.45);
  CAPTURE(ToString(model), Name(state), nu);
  LameParameters const lame = Lame(nu);
  TetRestData const rest = MakeRest();
  Vector12 const x = Configuration(state);
  Real33 const f = internal::TetDeformationGradient(rest, x);
  real const j = f.determinant();
  CAPTURE(j);
  if (state == State::Inverted) REQUIRE(j < -0.4);
  if (state == State::Flat) REQUIRE(std::abs(j) <= 1e-14);

  Evaluation const e = Evaluate(model, lame, rest, x, false);
  CAPTURE(e.energy);
  REQUIRE(std::isfinite(e.energy));
  REQUIRE(Near(e.energy, rest.restVolume * internal::TetEnergyDensity(model, lame, f), 1e-15));
  REQUIRE(e.energy == internal::TetEnergy(model, lame, rest, x));

  // the gradient (not at rest, where it is zero: previous test case)
  if (state != State::Rest) {
    REQUIRE(e.energy > 1e-3);
    REQUIRE(e.gradient.cwiseAbs().maxCoeff() > 0.1);
    Vector12 const fd = FdGradient(model, lame, rest, x);
    real const gradientError = ErrorRelativeToLargest(e.gradient, fd);
    CAPTURE(e.gradient.transpose(), fd.transpose(), gradientError);
    REQUIRE(gradientError <= kDerivativeTol);

    // P against central differences of Ψ in F
    Real33 const p = internal::TetFirstPiolaStress(model, lame, f);
    Real33 fdStress;
    real const step = 1e-7;  // |F| ~ 1: truncation ~1e-14·|Ψ'''| ~ 1e-9 μ, round-off ~1e-9 μ
    for (int k = 0; k < 9; ++k) {
      Real33 plus = f, minus = f;
      plus.data()[k] += step;
      minus.data()[k] -= step;
      fdStress.data()[k] = (internal::TetEnergyDensity(model, lame, plus) -
                            internal::TetEnergyDensity(model, lame, minus)) /
                           (2 * step);
    }
    REQUIRE(p.cwiseAbs().maxCoeff() > 1e-2 * lame.mu);
    real const stressError = ErrorRelativeToLargest(p, fdStress);
    CAPTURE(stressError);
    REQUIRE(stressError <= kDerivativeTol);
  }

  // the exact Hessian against central differences of the analytic gradient
  REQUIRE(e.hessian.cwiseAbs().maxCoeff() > 100);
  Matrix12 const fdHessian = FdHessian(model, lame, rest, x);
  real const hessianError = ErrorRelativeToLargest(e.hessian, fdHessian);
  CAPTURE(hessianError);
  REQUIRE(hessianError <= kDerivativeTol);
  // exactly symmetric (the assembler may read one triangle)
  REQUIRE(e.hessian == e.hessian.transpose());

  // translation invariance: Σₐ gₐ = 0 per component, and every row of the
  // Hessian sums to zero per component
  real const gradientScale = std::max(e.gradient.cwiseAbs().maxCoeff(), real(1));
  Real3 const gradientSum = e.gradient.reshaped(3, 4).rowwise().sum();
  CAPTURE(gradientSum.transpose());
  REQUIRE(gradientSum.cwiseAbs().maxCoeff() <= 1e-14 * gradientScale);
  Eigen::Matrix<real, 12, 3> hessianSums = Eigen::Matrix<real, 12, 3>::Zero();
  for (int a = 0; a < 4; ++a) hessianSums += e.hessian.middleCols<3>(3 * a);
  REQUIRE(hessianSums.cwiseAbs().maxCoeff() <= 1e-13 * e.hessian.cwiseAbs().maxCoeff());
  // and the energy does not change under a translation (to round-off of x)
  Vector12 shifted = x;
  for (int a = 0; a < 4; ++a) shifted.segment<3>(3 * a) += Real3(0.5, -0.25, 2);
  // (absolute, against the energy's scale V·μ: Near's tolerance is relative)
  REQUIRE(std::abs(internal::TetEnergy(model, lame, rest, shifted) - e.energy) <=
          1e-12 * std::max(rest.restVolume * lame.mu, real(1)));
}

// ---------------------------------------------------------------------------
// (d) the projected Hessian
// ---------------------------------------------------------------------------

TEST_CASE("projected Hessian is symmetric PSD, and exact wherever the exact one is PSD",
          "[actors][tet][projection]") {
  Model const model = GENERATE(Model::StableNeoHookean, Model::LinearElastic);
  State const state = GENERATE(State::Rest, State::Stretched, State::Compressed, State::Sheared,
                               State::Rotated, State::Inverted, State::Flat);
  real const nu = GENERATE(0.3, 0.45);
  CAPTURE(ToString(model), Name(state), nu);
  LameParameters const lame = Lame(nu);
  TetRestData const rest = MakeRest();
  Vector12 const x = Configuration(state);

  Evaluation const exact = Evaluate(model, lame, rest, x, false);
  Evaluation const projected = Evaluate(model, lame, rest, x, true);
  // the same energy and gradient
  REQUIRE(projected.energy == exact.energy);
  REQUIRE(projected.gradient == exact.gradient);
  REQUIRE(projected.hessian.allFinite());
  REQUIRE(projected.hessian == projected.hessian.transpose());

  real const largest = projected.hessian.cwiseAbs().maxCoeff();
  REQUIRE(largest > 100);
  Eigen::Matrix<real, 12, 1> const eigenvalues = Eigenvalues<12>(projected.hessian);
  CAPTURE(eigenvalues.transpose());
  REQUIRE(eigenvalues.minCoeff() >= -kPsdTol * eigenvalues.maxCoeff());
  // the translations stay in the kernel: rows sum to zero per component
  Eigen::Matrix<real, 12, 3> rowSums = Eigen::Matrix<real, 12, 3>::Zero();
  for (int a = 0; a < 4; ++a) rowSums += projected.hessian.middleCols<3>(3 * a);
  REQUIRE(rowSums.cwiseAbs().maxCoeff() <= 1e-13 * largest);

  // V Bᵀ A B is PSD iff the 9×9 A is (B has rank 9 off the translations):
  // the projection must keep the exact Hessian where it is PSD and change it
  // where it is not. Known cases: PSD at rest (any ν) and for LinearElastic
  // (constant, eigenvalues 0, 2μ, 3K); indefinite for SNH in compression,
  // inversion and flat (twist modes μ + (λ'(J−1) − μ)σ < 0). Stretch and
  // shear depend on ν (shear: twist μ(1 − σ) < 0 for σ > 1).
  Eigen::Matrix<real, 12, 1> const exactEigenvalues = Eigenvalues<12>(exact.hessian);
  real const exactSmallest = exactEigenvalues.minCoeff() / exactEigenvalues.maxCoeff();
  CAPTURE(exactEigenvalues.transpose(), exactSmallest);
  bool const exactIsPsd = exactSmallest >= -kPsdTol;
  if (state == State::Rest || model == Model::LinearElastic) REQUIRE(exactIsPsd);
  if (model == Model::StableNeoHookean &&
      (state == State::Compressed || state == State::Inverted || state == State::Flat)) {
    REQUIRE(exactSmallest < -1e-2);
    REQUIRE(ErrorRelativeToLargest(exact.hessian, projected.hessian) > 1e-2);
  }
  if (exactIsPsd) {
    real const keptError = ErrorRelativeToLargest(exact.hessian, projected.hessian);
    CAPTURE(keptError);
    REQUIRE(keptError <= kRoundoffTol);
  } else {
    REQUIRE(exactSmallest < -1e-6);  // clearly indefinite, not a rounding case
    REQUIRE(projected.hessian != exact.hessian);
  }

  // the analytic eigensystem and Eigen's 9×9 solver give the same projection
  Real33 const f = internal::TetDeformationGradient(rest, x);
  Matrix9 const analytic =
      internal::TetProjectedStressDerivative(model, lame, f, TetPsdProjection::Analytic);
  Matrix9 const numeric =
      internal::TetProjectedStressDerivative(model, lame, f, TetPsdProjection::EigenSolver);
  real const projectionMismatch = ErrorRelativeToLargest(numeric, analytic);
  CAPTURE(projectionMismatch);
  REQUIRE(projectionMismatch <= 1e-11);
  Evaluation viaSolver;
  viaSolver.energy = internal::TetEnergyGradientHessian(
      model, lame, rest, x, viaSolver.gradient, viaSolver.hessian, TetPsdProjection::EigenSolver);
  REQUIRE(ErrorRelativeToLargest(projected.hessian, viaSolver.hessian) <= 1e-11);
}

TEST_CASE("analytic projection is the eigen-projection for random and extreme F",
          "[actors][tet][projection]") {
  // F = −I, F = 0, rank 1, near-repeated singular values, strong inversion,
  // compression, and random matrices (with both signs of J); together they
  // reach every branch: negative twist, flip and scaling modes, and none
  LameParameters const lame = Lame(0.4);
  DynamicArray<Real33> cases = {
      -Real33::Identity(), Real33::Zero(), Real3(1, 2, 3) * Real3(0.5, -1, 0.2).transpose(),
      Real33(Real3(1, 1 + 1e-9, 1 - 1e-9).asDiagonal()), Real33(Real3(-3, 0.2, 0.5).asDiagonal()),
      // uniform and mixed compression: a negative
      // (volumetric) scaling mode
      Real33(0.2 * Real33::Identity()), Real33(Real3(0.3, 0.5, -0.4).asDiagonal()),
      // rotated near-repeated and rank-1 cases
      Rotation(0.3, Real3(1, 0, 2)) * Real3(1, 1 + 1e-9, 1 - 1e-9).asDiagonal() *
          Rotation(-1.1, Real3(0, 1, 1)),
      Rotation(2.0, Real3(-1, 1, 0)) * Real3(2, 1e-12, 0).asDiagonal() *
          Rotation(0.5, Real3(1, 1, 1))};
  std::srand(7);
  for (int k = 0; k < 200; ++k) cases.push_back(Real33::Identity() + 0.8 * Real33::Random());
  int numProjected = 0;
  for (Real33 const& f : cases) {
    CAPTURE(f);
    Matrix9 const exact = internal::TetProjectedStressDerivative(Model::StableNeoHookean, lame, f,
                                                                 TetPsdProjection::None);
    Matrix9 const analytic = internal::TetProjectedStressDerivative(Model::StableNeoHookean, lame,
                                                                    f, TetPsdProjection::Analytic);
    Matrix9 const numeric = internal::ProjectToPsdEigenSolver(exact);
    REQUIRE(analytic.allFinite());
    real const scale = std::max(exact.cwiseAbs().maxCoeff(), lame.mu);
    real const mismatch = ScaledError(numeric, analytic, scale);
    CAPTURE(mismatch);
    REQUIRE(mismatch <= 1e-11);
    auto const eigenvalues = Eigenvalues<9>(exact);
    if (eigenvalues.minCoeff() < -1e-6 * scale) ++numProjected;
    auto const projectedEigenvalues =
        Eigenvalues<9>(Matrix9(0.5 * (analytic + analytic.transpose())));
    REQUIRE(projectedEigenvalues.minCoeff() >= -kPsdTol * scale);
  }
  // most of these needed a projection: the comparison was not vacuous
  REQUIRE(numProjected > 100);
}

// ---------------------------------------------------------------------------
// (e) linearization at rest
// ---------------------------------------------------------------------------

TEST_CASE("stable Neo-Hookean linearized at rest is linear elasticity (lambda' = lambda + mu)",
          "[actors][tet]") {
  real const nu = GENERATE(-0.3, 0.3, 0.45);
  CAPTURE(nu);
  LameParameters const lame = Lame(nu);
  TetRestData const rest = MakeRest();
  Vector12 const x = Stack(RestNodes());
  Evaluation const snh = Evaluate(Model::StableNeoHookean, lame, rest, x, false);
  Evaluation const linear = Evaluate(Model::LinearElastic, lame, rest, x, false);
  REQUIRE(linear.hessian.cwiseAbs().maxCoeff() > 100);
  real const mismatch = ErrorRelativeToLargest(linear.hessian, snh.hessian);
  CAPTURE(mismatch);
  REQUIRE(mismatch <= kRoundoffTol);
  // the 9×9 derivatives too, and the stresses agree to first order
  REQUIRE(ErrorRelativeToLargest(
              internal::TetStressDerivative(Model::LinearElastic, lame, Real33::Identity()),
              internal::TetStressDerivative(Model::StableNeoHookean, lame, Real33::Identity())) <=
          kRoundoffTol);
  Real33 const direction = StretchF() - Real33::Identity();
  for (real t : {1e-2, 1e-3}) {
    Real33 const f = Real33::Identity() + t * direction;
    real const difference = (internal::TetFirstPiolaStress(Model::StableNeoHookean, lame, f) -
                             internal::TetFirstPiolaStress(Model::LinearElastic, lame, f))
                                .cwiseAbs()
                                .maxCoeff();
    CAPTURE(t, difference);
    // second order: |P_SNH − P_lin| = O(t²), with a constant ~ (λ + μ)|ΔF|²
    REQUIRE(difference <= 2 * (lame.lambda + 2 * lame.mu) * t * t);
  }
  // away from rest they differ (the check above is not vacuous)
  Vector12 const stretched = Configuration(State::Stretched);
  REQUIRE(ErrorRelativeToLargest(
              Evaluate(Model::LinearElastic, lame, rest, stretched, false).hessian,
              Evaluate(Model::StableNeoHookean, lame, rest, stretched, false).hessian) > 1e-2);
}

// ---------------------------------------------------------------------------
// (f) rotations
// ---------------------------------------------------------------------------

TEST_CASE("stable Neo-Hookean is rotation invariant, linear elasticity is not", "[actors][tet]") {
  LameParameters const lame = Lame(0.3);
  TetRestData const rest = MakeRest();
  Real33 const r = Rotation(0.7, Real3(1, 2, -1));
  Matrix12 const q = NodeRotation(r);
  real const energyScale = rest.restVolume * lame.mu;

  SECTION("SNH: E(Rx) = E(x), g(Rx) = R g(x), H(Rx) = R H(x) Rᵀ, projected or not") {
    for (State state : {State::Stretched, State::Compressed, State::Inverted}) {
      CAPTURE(Name(state));
      Vector12 const x = Configuration(state);
      for (bool project : {false, true}) {
        CAPTURE(project);
        Evaluation const e = Evaluate(Model::StableNeoHookean, lame, rest, x, project);
        Evaluation const rotated = Evaluate(Model::StableNeoHookean, lame, rest, q * x, project);
        REQUIRE(e.energy > 1e-3);
        REQUIRE(Near(rotated.energy, e.energy, 1e-13));
        REQUIRE(ErrorRelativeToLargest(Vector12(q * e.gradient), rotated.gradient) <= kRoundoffTol);
        REQUIRE(ErrorRelativeToLargest(Matrix12(q * e.hessian * q.transpose()), rotated.hessian) <=
                1e-11);
      }
    }
    // a rigidly rotated rest element: no energy, no force
    Evaluation const e =
        Evaluate(Model::StableNeoHookean, lame, rest, q * Stack(RestNodes()), true);
    REQUIRE(std::abs(e.energy) <= 1e-13 * energyScale);
    REQUIRE(e.gradient.cwiseAbs().maxCoeff() <= 1e-12 * energyScale / 0.1);
  }

  SECTION("LinearElastic: a rigid rotation stores energy and produces spurious forces") {
    // documented behaviour of the small-strain model (header): ε = sym(R) − I
    // ≠ 0, here Ψ ~ 0.1 μ for a 40° rotation. Use it for small rotations only.
    Evaluation const e = Evaluate(Model::LinearElastic, lame, rest, q * Stack(RestNodes()), false);
    CAPTURE(e.energy, energyScale);
    REQUIRE(e.energy > 1e-2 * energyScale);
    REQUIRE(e.gradient.cwiseAbs().maxCoeff() > 1e-2 * energyScale / 0.1);
    real const expected =
        rest.restVolume * internal::TetEnergyDensity(Model::LinearElastic, lame, r);
    REQUIRE(Near(e.energy, expected, 1e-13));
    // and its Hessian is constant: the same rotated or not
    Evaluation const atRest = Evaluate(Model::LinearElastic, lame, rest, Stack(RestNodes()), false);
    REQUIRE(ErrorRelativeToLargest(atRest.hessian, e.hessian) <= kRoundoffTol);
  }
}

// ---------------------------------------------------------------------------
// (g) no heap allocation
// ---------------------------------------------------------------------------

TEST_CASE("the kernels allocate nothing", "[actors][tet][allocation]") {
  TetRestData const rest = MakeRest();
  LameParameters const lame = Lame(0.3);
  DynamicArray<Vector12> const configurations = {Configuration(State::Compressed),
                                                 Configuration(State::Inverted),
                                                 Configuration(State::Stretched)};
  Vector12 gradient;
  Matrix12 hessian;
  real sink = 0;

  // the recorder works: an allocation made while recording is counted
  REQUIRE(CountAllocations([] {
            void* volatile probe = std::malloc(64);
            std::free(probe);
          }).total == 1);

  Allocations const kernels = CountAllocations([&] {
    for (Vector12 const& x : configurations)
      for (Model model : {Model::StableNeoHookean, Model::LinearElastic})
        for (TetPsdProjection projection :
             {TetPsdProjection::None, TetPsdProjection::Analytic, TetPsdProjection::EigenSolver}) {
          sink +=
              internal::TetEnergyGradientHessian(model, lame, rest, x, gradient, hessian, projection);
          sink += internal::TetEnergyGradientHessian(model, lame, rest, x, gradient, hessian, true);
          sink += internal::TetEnergy(model, lame, rest, x);
          sink += internal::TetFirstPiolaStress(model, lame,
                                                internal::TetDeformationGradient(rest, x))(0, 0);
        }
    TetRestData other;
    auto const nodes = RestNodes();
    sink += internal::MakeTetRestData(nodes[0], nodes[1], nodes[2], nodes[3], other);
  });
  REQUIRE(std::isfinite(sink));
  REQUIRE(kernels.total == 0);
}
