// One rigid body's stage inertia term (actors/rigid_inertia.h): its gradient
// against central differences of the energy, and its exact rotation Hessian
// H = ∂²E(Exp(x)R)/∂x² against second differences of the energy in those
// exponential coordinates, for rotations from none to 2.5 rad within the
// stage. (Differences of the gradient would not do: the gradient at
// Exp(εe)R lives in another tangent, and Exp(δ)Exp(εe) = Exp(δ + εe + ½δ×εe)
// adds the antisymmetric ½ τ·(eᵢ × eₖ), which the test checks too.) The
// Gauss–Newton block differs from H by the curvature term and is PSD.
#include "test_support.h"

#include <Eigen/Eigenvalues>

#include <superdex/actors/rigid_inertia.h>

using namespace superdex;
using namespace superdex::internal;

TEST_CASE("rigid inertia term: gradient and exact rotation Hessian match central differences",
          "[actors][rigid][derivatives]") {
  real const stageAngle = GENERATE(0.0, 1e-5, 0.3, 2.5);
  bool const bdf2 = GENERATE(false, true);
  CAPTURE(stageAngle, bdf2);
  RigidBodyMotion motion;
  motion.position = Real3(0.1, -0.3, 0.2);
  motion.rotation = Quat(Eigen::AngleAxis<real>(0.7, Real3(1, -1, 2).normalized()));
  motion.linearVelocity = Real3(0.5, 0.1, -0.2);
  motion.angularVelocity = Real3(3, -1, 2);
  motion.hasHistory = bdf2;
  motion.previousPosition = Real3(0.09, -0.31, 0.21);
  motion.previousRotation = Quat(Eigen::AngleAxis<real>(0.65, Real3(1, -1, 2.1).normalized()));
  motion.previousAngularVelocity = Real3(2.8, -1.1, 2.2);
  real const h = 0.02;
  RigidInertiaStage stage;
  Real3 const inertia(0.2, 0.5, 0.9);
  stage.Begin(MakeStage(bdf2 ? IntegratorType::Bdf2 : IntegratorType::BackwardEuler, h, bdf2), 2.0, inertia,
              motion);
  Real3 const position = motion.position + Real3(0.01, 0.02, -0.01);
  Quat const rotation = Exp(stageAngle * Real3(0.3, 0.9, -0.2).normalized()) * motion.rotation;

  real const eps = 1e-6;
  Real3 force, torque;
  stage.Gradient(position, rotation, force, torque);
  Real3 fdForce, fdTorque;
  Real33 fdHessian, fdOfGradient;
  auto energyAt = [&](Real3 const& x) { return stage.Energy(position, Exp(x) * rotation); };
  real const eps2 = 1e-4;  // second differences: truncation ε²E⁗ ~ 1e-8, round-off 1e-16 E/ε² ~ 1e-8 relative
  for (int k = 0; k < 3; ++k) {
    Real3 const e = eps * Real3::Unit(k);
    fdForce[k] = (stage.Energy(position + e, rotation) - stage.Energy(position - e, rotation)) / (2 * eps);
    fdTorque[k] = (energyAt(e) - energyAt(-e)) / (2 * eps);
    Real3 fPlus, tPlus, fMinus, tMinus;
    stage.Gradient(position, Exp(e) * rotation, fPlus, tPlus);
    stage.Gradient(position, Exp(-e) * rotation, fMinus, tMinus);
    fdOfGradient.col(k) = (tPlus - tMinus) / (2 * eps);
    for (int i = 0; i < 3; ++i) {
      Real3 const a = eps2 * Real3::Unit(i), b = eps2 * Real3::Unit(k);
      fdHessian(i, k) = (energyAt(a + b) - energyAt(a - b) - energyAt(b - a) + energyAt(-a - b)) / (4 * eps2 * eps2);
    }
  }
  real const scale = std::max(torque.norm(), force.norm());
  REQUIRE(scale > 1);
  REQUIRE((force - fdForce).norm() <= 1e-6 * scale);
  REQUIRE((torque - fdTorque).norm() <= 1e-6 * scale);
  Real33 const hessian = stage.RotationHessian(rotation);
  real const hScale = hessian.norm();
  CAPTURE(hessian, fdHessian);
  REQUIRE(hScale > 100);
  REQUIRE((hessian - fdHessian).norm() <= 1e-5 * hScale);
  REQUIRE((hessian - hessian.transpose()).norm() <= 1e-10 * hScale);
  // differences of the gradient: H plus the antisymmetric ½ Hat(τ)ᵀ
  REQUIRE((fdOfGradient - (hessian - 0.5 * Hat(torque))).norm() <= 1e-6 * hScale);
  // the Gauss–Newton block drops the curvature term, which grows with the
  // stage rotation (it is 1e-7 of H at 1e-5 rad), and is PSD
  Real33 const gaussNewton = stage.RotationHessianGaussNewton(rotation);
  if (stageAngle >= 0.3) REQUIRE((gaussNewton - hessian).norm() > 1e-3 * hScale);
  REQUIRE(Eigen::SelfAdjointEigenSolver<Real33>(gaussNewton).eigenvalues().minCoeff() >= 0);
}
