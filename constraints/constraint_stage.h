// ConstraintStage: one constraint's part in a stage — the compliant potential
// Φᶜᵢ of constraints.md over its kernel's g (constraint_kernel.h), and the
// state a stage needs beyond the constraint's runtime (constraint.h): the
// stage-start value g(qᵢ⁰, p̂ᵢ⁰), Newton's last linearization, the force
// estimate f̂ its geometric stiffness is weighted with, and this stage's Δtᵢ
// and scene Hessian. Owned by the ConstraintSet (one per constraint, made at
// each pattern build); the constraint itself holds only what its runtime
// interface shows (targets, parameters, the effective stiffness, forces).
//
// Where the constraint acts on an articulated link and an own-block solve
// takes it in, this is the LinkTerm that solve assembles (AddLinkTerms).
#pragma once

#include <superdex/constraints/constraint.h>
#include <superdex/stage/own_block_solve.h>
#include <superdex/stage/stage_term.h>

namespace superdex::internal {

class ConstraintStage final : public LinkTerm {
 public:
  explicit ConstraintStage(Constraint& constraint) : constraint_(&constraint) {}
  Constraint& GetConstraint() const { return *constraint_; }

  /// Records g(qᵢ⁰, p̂ᵢ⁰) and this stage's compliant parameters: with
  /// stage.nearRigidBeta > 0, k and d capped by the near-rigid rule with w
  /// the largest diagonal entry of J diag(stage.inverseMasses) Jᵀ at the
  /// stage start (Actor::WriteDofInverseMasses; unread when the cap is off).
  /// Returns whether the cap applied.
  bool Begin(StageContext const& stage, TermWorkspace& ws);
  /// w = maxᵢ Σⱼ J_ij² inverseMasses[dofⱼ] from the Jacobian in `ws`.
  real InverseEffectiveMass(Span<real const> inverseMasses, TermWorkspace const& ws) const;
  /// Φᶜᵢ at the current configuration.
  real Energy(TermWorkspace& ws) const;
  /// The gradient Jᵀ f and the block (κ + d/Δtᵢ) JᵀJ (+ the curvature G for
  /// the geometric stiffness: exact, or by its column norms when
  /// `projectHessian`) of contributor `contributor`. Also records Newton's
  /// linearization (g and J) for the calls below. The geometric stiffness is
  /// weighted with the force estimate f̂ (PredictForce) once one exists in
  /// this stage, else with f(g). Safe to run concurrently for different
  /// constraints, each with its own workspace.
  void AddGradientAndHessian(HessianAssembler& assembler, int contributor, bool projectHessian,
                             TermWorkspace& ws) const;
  /// After the line search accepted α δ: f̂ ← f(g + α J δ), the force of the
  /// linearized constraint at the new iterate (the multiplier update of a
  /// primal–dual Newton step). With step.corrected the step was δ + δc of a
  /// second-order correction and step.delta is δc: f̂ ← f(g(q + δ) + J δc).
  void PredictForce(AcceptedStep const& step);
  /// At a trial configuration q + δ: adds Jᵀ (f(g(q + δ)) − f(g + J δ)) to
  /// `gradient`, the force of g's second-order error along δ, with J from the
  /// last linearization (the right-hand side of a second-order correction),
  /// and records g(q + δ).
  void AddCorrectionForce(Span<real const> delta, Span<real> gradient, TermWorkspace& ws);
  /// The converged stage: the force −Jᵀf where the query is registered, the
  /// old target ← the target.
  void End(TermWorkspace& ws);

  // LinkTerm, on the link of the kernel's FoldableLinkSlot
  StageDofs const* GetLinkOwner() const override;
  LinkPath const& GetLinkPath() const override;
  Span<int const> GetPathDofs() const override;
  Span<int const> GetPathColumns() const override;
  Span<int const> GetOtherDofs() const override;
  Span<int const> GetOtherColumns() const override;
  int GetDimension() const override { return constraint_->GetDimension(); }
  int GetNumDofs() const override { return constraint_->GetNumDofs(); }
  /// The gradient Jᵀ f over the constraint's DoFs in ws.r (slot order), and
  /// the Hessian H = (κ + d/h) J_typeᵀ J_type + G_type (G's diagonal column
  /// norms when projecting or with GeometricStiffnessDiagonal; none for
  /// GaussNewton), (6 + n_o)², over the link frame's increments (δt; δθ) and
  /// the other body's n_o DoFs in their list order; the wrench (F; M) =
  /// J_typeᵀ w that weighs the link frame's own curvature (zero for
  /// GaussNewton), `exactCurvature` false where it is to be taken by its
  /// column norms. False when it adds nothing (an inactive range constraint).
  bool AddLinkTerms(bool projectHessian, TermWorkspace& ws, TermWorkspace::FoldedBlock& hessian,
                    Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const override;

  // (white-box tests: Begin sets the stage's Δtᵢ and scene Hessian; a test
  // evaluates at others, and reads g⁰)
  void SetStage(real duration, ConstraintHessian sceneHessian) {
    duration_ = duration;
    sceneHessian_ = sceneHessian;
  }
  VectorX const& GetStageStartValue() const { return stageStartValue_; }

 private:
  /// Newton's linearization at the current iterate, recorded for the force
  /// predictions: ws.g, ws.jacobian (Evaluate), ws.f = f(g) and ws.r = Jᵀ f;
  /// returns the Gauss–Newton scale κ + d/h, or −1 for an inactive range
  /// constraint (nothing recorded, nothing to add).
  real Linearize(TermWorkspace& ws) const;
  /// The weights of the curvature G: the force estimate f̂ once this stage
  /// has one, else f(g) (ws.f, after Linearize).
  Eigen::Ref<VectorX const> CurvatureWeights(TermWorkspace const& ws) const;
  /// This constraint's Hessian (SceneDefault: the scene's), GaussNewton for
  /// a type without curvature.
  ConstraintHessian HessianMode() const;
  /// hessian += G, or with `diagonal` the diagonal of G's column norms (PSD).
  static void AddCurvatureTerm(Eigen::Ref<MatrixX const> const& curvature, bool diagonal,
                               Eigen::Ref<MatrixX> hessian);
  /// g += α J δ with J of the last linearization (`delta` in global DoF order).
  void AddLinearizedChange(Span<real const> delta, real alpha, Eigen::Ref<VectorX> g) const;

  Constraint* constraint_;
  real duration_ = 1;  ///< Δtᵢ
  ConstraintHessian sceneHessian_ = ConstraintHessian::GeometricStiffness;
  VectorX stageStartValue_;  ///< g(qᵢ⁰, p̂ᵢ⁰)
  // Newton's last linearization (sized at Begin; a cache the const assembly
  // writes): g, J, whether the constraint takes part, and the force estimate
  // f̂ for the curvature
  mutable VectorX linearValue_;
  VectorX trialValue_;  ///< g(q + δ) at the last second-order correction
  mutable MatrixX linearJacobian_;
  mutable bool linearActive_ = false;
  VectorX forceEstimate_;
  bool forceEstimateValid_ = false;
};

}  // namespace superdex::internal
