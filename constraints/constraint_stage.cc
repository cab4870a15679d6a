#include <superdex/constraints/constraint_stage.h>

#include <algorithm>

#include <superdex/actors/actor.h>
#include <superdex/assembly/hessian_assembler.h>

namespace superdex::internal {

bool ConstraintStage::Begin(StageContext const& stage, TermWorkspace& ws) {
  Constraint& c = *constraint_;
  ConstraintState& state = c.GetState();
  real const h = stage.coefficients.duration;
  duration_ = h;
  sceneHessian_ = stage.constraintHessian;
  // g(qᵢ⁰, p̂ᵢ⁰): the actors are at the stage start, the old target is p̂ᵢ⁰
  c.Evaluate(state.oldTarget, ws);
  stageStartValue_ = ws.g.head(c.GetDimension());
  linearValue_.resize(c.GetDimension());
  trialValue_.resize(c.GetDimension());
  linearJacobian_.resize(c.GetDimension(), c.GetNumDofs());
  forceEstimate_.resize(c.GetDimension());
  linearActive_ = false;
  forceEstimateValid_ = false;
  // the near-rigid cap from the stage-start Jacobian (off: k and d as set)
  state.nearRigidCapped = false;
  state.stageParams = state.params;
  if (stage.nearRigidBeta > 0)
    state.stageParams = NearRigidParams(state.params, h, stage.nearRigidBeta,
                                        InverseEffectiveMass(stage.inverseMasses, ws), state.nearRigidCapped);
  return state.nearRigidCapped;
}

real ConstraintStage::InverseEffectiveMass(Span<real const> inverseMasses, TermWorkspace const& ws) const {
  Constraint const& c = *constraint_;
  DynamicArray<int> const& dofs = c.GetDofs();
  // the largest diagonal entry of J diag(M⁻¹) Jᵀ: row i alone, with every
  // other row free, oscillates at ω² = k wᵢ
  int const n = c.GetNumDofs();
  real w = 0;
  for (int i = 0; i < c.GetDimension(); ++i) {
    real row = 0;
    for (int j = 0; j < n; ++j) row += ws.jacobian(i, j) * ws.jacobian(i, j) * inverseMasses[dofs[j]];
    w = std::max(w, row);
  }
  return w;
}

real ConstraintStage::Energy(TermWorkspace& ws) const {
  Constraint const& c = *constraint_;
  ConstraintState const& state = c.GetState();
  real const h = duration_;
  c.Evaluate(state.target, ws);
  auto const g = ws.g.head(c.GetDimension());
  if (c.IsRange() && IsRangeInactive(g, stageStartValue_)) return 0;
  return CompliantEnergy(state.stageParams, g, stageStartValue_, h);
}

real ConstraintStage::Linearize(TermWorkspace& ws) const {
  Constraint const& c = *constraint_;
  ConstraintState const& state = c.GetState();
  real const h = duration_;
  c.Evaluate(state.target, ws);
  int const m = c.GetDimension(), n = c.GetNumDofs();
  auto const g = ws.g.head(m);
  if (c.IsRange() && IsRangeInactive(g, stageStartValue_)) return -1;
  auto const jacobian = ws.jacobian.topLeftCorner(m, n);
  // range types are piecewise in q (one-sided): their curvature keeps f(g)
  // and they take no part in second-order corrections
  linearActive_ = !c.IsRange();
  if (linearActive_) {
    linearValue_ = g;
    linearJacobian_ = jacobian;
  }
  real const scale =
      CompliantForceCoefficients(state.stageParams, g, stageStartValue_, h, ws.f.head(m));
  ws.r.head(n).noalias() = jacobian.transpose() * ws.f.head(m);
  return scale;
}

Eigen::Ref<VectorX const> ConstraintStage::CurvatureWeights(TermWorkspace const& ws) const {
  // G = Σᵢ f̂ᵢ ∂²gᵢ/∂q², the joint forces' geometric stiffness. After the
  // first step of a stage f̂ is the linearized constraint's force, not f(g):
  // a step along a curved constraint manifold leaves g with a second-order
  // error that a stiff k turns into a large, spurious force (and an
  // indefinite G); f̂ is the estimate a primal–dual Newton method carries.
  if (forceEstimateValid_) return forceEstimate_;
  return ws.f.head(constraint_->GetDimension());
}

ConstraintHessian ConstraintStage::HessianMode() const {
  ConstraintHessian const own = constraint_->GetHessianApproximation();
  ConstraintHessian const mode = own == ConstraintHessian::SceneDefault ? sceneHessian_ : own;
  return constraint_->HasCurvature() ? mode : ConstraintHessian::GaussNewton;
}

void ConstraintStage::AddCurvatureTerm(Eigen::Ref<MatrixX const> const& curvature, bool diagonal,
                                  Eigen::Ref<MatrixX> hessian) {
  if (!diagonal) {
    hessian += curvature;
    return;
  }
  // PSD: G replaced by the diagonal of its column norms (Andrews et al.)
  for (Eigen::Index j = 0; j < curvature.cols(); ++j) hessian(j, j) += curvature.col(j).norm();
}

void ConstraintStage::AddGradientAndHessian(HessianAssembler& assembler, int contributor, bool projectHessian,
                                            TermWorkspace& ws) const {
  Constraint const& c = *constraint_;
  ConstraintState const& state = c.GetState();
  real const scale = Linearize(ws);
  if (scale < 0) return;
  int const m = c.GetDimension(), n = c.GetNumDofs();
  auto const jacobian = ws.jacobian.topLeftCorner(m, n);
  assembler.AddGradient(contributor, ws.r.head(n));
  auto hessian = ws.hessian.topLeftCorner(n, n);
  hessian.noalias() = scale * jacobian.transpose() * jacobian;

  ConstraintHessian const mode = HessianMode();
  if (mode != ConstraintHessian::GaussNewton) {
    auto curvature = ws.curvature.topLeftCorner(n, n);
    curvature.setZero();
    c.AddCurvature(state.target, CurvatureWeights(ws), ws, curvature);
    AddCurvatureTerm(curvature, projectHessian || mode == ConstraintHessian::GeometricStiffnessDiagonal, hessian);
  }
  assembler.AddBlock(contributor, hessian);
}

bool ConstraintStage::AddLinkTerms(bool projectHessian, TermWorkspace& ws, TermWorkspace::FoldedBlock& hessian,
                                   Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const {
  Constraint const& c = *constraint_;
  ConstraintState const& state = c.GetState();
  int const linkSlot = c.FoldableLinkSlot();
  int const numActors = c.GetNumActors();
  int const other = numActors == 2 ? 1 - linkSlot : -1;
  int const numOther = other >= 0 ? static_cast<int>(c.GetLocalDofs(other).size()) : 0;
  hessian.setZero(6 + numOther, 6 + numOther);
  curvatureWrench.setZero();
  exactCurvature = false;
  real const scale = Linearize(ws);
  if (scale < 0) return false;
  // the type's Hessian over its DoFs (slot order: the link's rigid DoFs, a
  // subset of the six, and the other body's), placed at the link frame's
  // six increments and then the other body's DoFs
  int const m = c.GetDimension(), k = c.GetTypeNumDofs();
  auto const typeJacobian = ws.typeJacobian.topLeftCorner(m, k);
  DynamicArray<int> const& rigid = c.GetTypeDofs(linkSlot);
  int const numRigid = static_cast<int>(rigid.size());
  int const linkColumn = linkSlot == 0 ? 0 : numOther;  // the link's first type column
  auto place = [&](int column) {
    return column >= linkColumn && column < linkColumn + numRigid ? rigid[column - linkColumn]
                                                                   : 6 + (column < linkColumn ? column : column - numRigid);
  };
  ws.typeCurvature.noalias() = scale * typeJacobian.transpose() * typeJacobian;
  ConstraintHessian const mode = HessianMode();
  if (mode != ConstraintHessian::GaussNewton) {
    Eigen::Ref<VectorX const> const weights = CurvatureWeights(ws);
    // (ws.curvature's corner: the type's curvature over its DoFs)
    auto curvature = ws.curvature.topLeftCorner(k, k);
    curvature.setZero();
    c.AddTypeCurvature(state.target, weights, curvature);
    bool const diagonal = projectHessian || mode == ConstraintHessian::GeometricStiffnessDiagonal;
    AddCurvatureTerm(curvature, diagonal, ws.typeCurvature);
    exactCurvature = !diagonal;
    for (int r = 0; r < numRigid; ++r) curvatureWrench[rigid[r]] = typeJacobian.col(linkColumn + r).dot(weights);
  }
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b) hessian(place(a), place(b)) = ws.typeCurvature(a, b);
  return true;
}

void ConstraintStage::AddLinearizedChange(Span<real const> delta, real alpha, Eigen::Ref<VectorX> g) const {
  DynamicArray<int> const& dofs = constraint_->GetDofs();
  for (std::size_t j = 0; j < dofs.size(); ++j) g += (alpha * delta[dofs[j]]) * linearJacobian_.col(j);
}

void ConstraintStage::PredictForce(AcceptedStep const& step) {
  Span<real const> const delta = step.delta;
  real const alpha = step.alpha, h = duration_;
  bool const corrected = step.corrected;
  ConstraintState const& state = constraint_->GetState();
  if (!linearActive_) return;
  forceEstimate_ = corrected ? trialValue_ : linearValue_;
  AddLinearizedChange(delta, alpha, forceEstimate_);
  // f is evaluated in place: CompliantForceCoefficients reads g before it writes f
  CompliantForceCoefficients(state.stageParams, forceEstimate_, stageStartValue_, h, forceEstimate_);
  forceEstimateValid_ = true;
}

void ConstraintStage::AddCorrectionForce(Span<real const> delta, Span<real> gradient, TermWorkspace& ws) {
  Constraint const& c = *constraint_;
  ConstraintState const& state = c.GetState();
  real const h = duration_;
  if (!linearActive_) return;
  int const m = c.GetDimension(), n = c.GetNumDofs();
  c.Evaluate(state.target, ws);
  trialValue_ = ws.g.head(m);
  // ws.r ← f(g + J δ), ws.f ← f(g(q + δ)) − ws.r
  auto predicted = ws.r.head(m);
  predicted = linearValue_;
  AddLinearizedChange(delta, 1, predicted);
  CompliantForceCoefficients(state.stageParams, ws.g.head(m), stageStartValue_, h, ws.f.head(m));
  CompliantForceCoefficients(state.stageParams, predicted, stageStartValue_, h, predicted);
  ws.f.head(m) -= predicted;
  DynamicArray<int> const& dofs = c.GetDofs();
  for (int j = 0; j < n; ++j) gradient[dofs[j]] += linearJacobian_.col(j).dot(ws.f.head(m));
}

void ConstraintStage::End(TermWorkspace& ws) {
  Constraint& c = *constraint_;
  ConstraintState& state = c.GetState();
  real const h = duration_;
  if (state.forceQueryRegistered) {
    int const m = c.GetDimension(), n = c.GetNumDofs();
    c.Evaluate(state.target, ws);
    auto const g = ws.g.head(m);
    if (c.IsRange() && IsRangeInactive(g, stageStartValue_)) {
      std::fill(state.force.begin(), state.force.end(), 0);
    } else {
      CompliantForceCoefficients(state.stageParams, g, stageStartValue_, h, ws.f.head(m));
      ws.r.head(n).noalias() = ws.jacobian.topLeftCorner(m, n).transpose() * ws.f.head(m);
      for (int i = 0; i < n; ++i) state.force[i] = -ws.r[i];
    }
    state.forceValid = true;
  }
  state.oldTarget = state.target;
}

// ---- LinkTerm ----

StageDofs const* ConstraintStage::GetLinkOwner() const {
  return &constraint_->GetActor(constraint_->FoldableLinkSlot())->GetStageDofs();
}

LinkPath const& ConstraintStage::GetLinkPath() const {
  return constraint_->GetLinkPath(constraint_->FoldableLinkSlot());
}

Span<int const> ConstraintStage::GetPathDofs() const {
  return constraint_->GetDofIndicesForActor(constraint_->FoldableLinkSlot());
}

Span<int const> ConstraintStage::GetPathColumns() const {
  return constraint_->GetSlotColumns(constraint_->FoldableLinkSlot());
}

Span<int const> ConstraintStage::GetOtherDofs() const {
  if (constraint_->GetNumActors() < 2) return {};
  return constraint_->GetDofIndicesForActor(1 - constraint_->FoldableLinkSlot());
}

Span<int const> ConstraintStage::GetOtherColumns() const {
  if (constraint_->GetNumActors() < 2) return {};
  return constraint_->GetSlotColumns(1 - constraint_->FoldableLinkSlot());
}

}  // namespace superdex::internal
