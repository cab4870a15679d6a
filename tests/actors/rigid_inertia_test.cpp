// One rigid body's stage inertia term (actors/rigid_inertia.h): its gradient
// against central differences of the energy, and its exact rotation Hessian
// H = ∂²E(Exp(x)R)/∂x² against second differences of the energy in those
// exponential coordinates, for rotations from none to 2.5 rad within the
// stage. (Differences of the gradient would not do: the gradient at
// Exp(εe)R lives in another tangent, and Exp(δ)Exp(εe) = Exp(δ + εe + ½δ×εe)
// adds the antisymmetric ½ τ·(eᵢ × eₖ), which the test checks too.) The
// Gauss–Newton block differs from H by the curvature term and is PSD.
#include "test_support.h"


#include <superdex/actors/rigid_inertia.h>
#include <superdex/core/so3_jet.h>

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
  REQUIRE(SymmetricEigenvalues(gaussNewton).minCoeff() >= 0);
}

TEST_CASE("rigid inertia term: the closed-form rotation Hessian equals second-order jets of Log(Exp(u) M0)",
          "[actors][rigid][derivatives]") {
  // H in closed form (J_l⁻¹ and its derivative) against the forward-mode
  // second derivative of E(u) = ½ w (φ(u) − φ̂)ᵀ I (φ(u) − φ̂), φ(u) =
  // Log(Exp(u) M₀): stage rotations on both sides of the 0.1 rad switch to
  // the series of γ(θ), up to 3 rad. w I and φ̂ are read back from the
  // Gauss–Newton block and the gradient (dφ/dδθ = J_l⁻¹(φ) Rⁿᵀ).
  real const stageAngle = GENERATE(0.0, 1e-7, 1e-3, 0.0999, 0.1001, 0.7, 2.0, 3.0);
  int const axisSeed = GENERATE(0, 1, 2);
  CAPTURE(stageAngle, axisSeed);
  RigidBodyMotion motion;
  motion.rotation = Quat(Eigen::AngleAxis<real>(0.4 + axisSeed, Real3(1, 2 - axisSeed, 0.5).normalized()));
  motion.angularVelocity = Real3(2 - axisSeed, 1.5, -0.7 * axisSeed);
  RigidInertiaStage stage;
  stage.Begin(MakeStage(IntegratorType::BackwardEuler, 0.02, false), 1.5, Real3(0.3, 0.45, 0.8), motion);
  Real3 const axis = Real3(0.2 + axisSeed, -1, 0.6).normalized();
  Quat const rotation = motion.rotation * Exp(stageAngle * axis);  // Rⁿᵀ R = Exp(stageAngle · axis)
  Real3 const phi = Log(motion.rotation.conjugate() * rotation);
  Real33 const rn = motion.rotation.toRotationMatrix();
  Real33 const dPhi = LeftJacobianInverse(phi) * rn.transpose();
  Real33 const weightedInertia = dPhi.transpose().inverse() * stage.RotationHessianGaussNewton(rotation) * dPhi.inverse();
  Real3 force, torque;
  stage.Gradient(motion.position, rotation, force, torque);
  Real3 const lambda = dPhi.transpose().inverse() * torque;  // w I (φ − φ̂)
  Real3 const target = phi - weightedInertia.inverse() * lambda;
  // the reference: jets in u = Rⁿᵀ δθ
  Real33 const m0 = (motion.rotation.conjugate() * rotation).normalized().toRotationMatrix();
  JetVector3<3> const jetPhi = LogJet(Multiply(ExpSecondOrder(JetIncrement<3>(0)), m0));
  Jet<3> energy;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      energy = energy + (0.5 * weightedInertia(i, k)) * ((jetPhi[i] - target[i]) * (jetPhi[k] - target[k]));
  Real33 const reference = rn * energy.hessian * rn.transpose();
  Real33 const hessian = stage.RotationHessian(rotation);
  CAPTURE(hessian, reference);
  REQUIRE(lambda.norm() > 1);  // the curvature term is exercised
  CHECK((hessian - reference).norm() <= 1e-12 * reference.norm());
}
