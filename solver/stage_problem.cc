#include <superdex/solver/stage_problem.h>

#include <algorithm>

namespace superdex::internal {

void StageProblem::Set(DynamicArray<StageDofs*> dofs, DynamicArray<StageTerm*> terms) {
  dofs_ = std::move(dofs);
  terms_ = std::move(terms);
  numDofs_ = 0;
  for (StageDofs const* owner : dofs_) numDofs_ += owner->GetNumDofs();
  boundsSteps_ = std::any_of(terms_.begin(), terms_.end(), [](StageTerm const* t) { return t->BoundsSteps(); });
  firstContributor_.assign(terms_.size() + 1, 0);
  firstStageContributor_.assign(terms_.size() + 1, 0);
}

void StageProblem::FlattenPattern(DynamicArray<DynamicArray<DynamicArray<int>>>& termDofs,
                                  DynamicArray<int>& blockSizes, DynamicArray<DynamicArray<int>>& contributorDofs) {
  for (StageDofs const* owner : dofs_) owner->AppendDofBlockSizes(blockSizes);
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    firstContributor_[t] = static_cast<int>(contributorDofs.size());
    for (DynamicArray<int>& dofs : termDofs[t]) contributorDofs.push_back(std::move(dofs));
  }
  firstContributor_[terms_.size()] = static_cast<int>(contributorDofs.size());
}

void StageProblem::ReserveThreads(int numThreads) {
  for (StageTerm* term : terms_) term->ReserveThreads(numThreads);
}

void StageProblem::BeginStage(StageContext const& stage) {
  for (StageTerm* term : terms_) term->BeginStage(stage);
}

void StageProblem::AppendStageContributorDofs(StageDofLists& dofLists) {
  for (std::size_t t = 0; t < terms_.size(); ++t) {
    firstStageContributor_[t] = static_cast<int>(dofLists.size());
    terms_[t]->AppendStageContributorDofs(dofLists);
  }
  firstStageContributor_[terms_.size()] = static_cast<int>(dofLists.size());
}

void StageProblem::MoveToFirstIterate() {
  if (boundsSteps_) SaveIterate();
  for (StageDofs* owner : dofs_) owner->MoveToFirstIterate();
  if (boundsSteps_ && !std::all_of(terms_.begin(), terms_.end(),
                                   [](StageTerm const* t) { return !t->BoundsSteps() || t->AcceptsFirstIterate(); }))
    RestoreIterate();
}

EnergySum StageProblem::Energy(HessianAssembler const& assembler, RankGroup& ranks) const {
  EnergySum sum;
  for (std::size_t t = 0; t < terms_.size(); ++t) terms_[t]->AddEnergy(assembler, firstContributor_[t], sum);
  if (ranks.IsDistributed()) {
    real sums[2] = {sum.energy, sum.scale};
    ranks.SumInRankOrder(sums);
    sum.energy = sums[0];
    sum.scale = sums[1];
  }
  return sum;
}

void StageProblem::Assemble(HessianAssembler& assembler, Span<real> gradient, AssemblyOptions const& options) const {
  assembler.BeginAssembly(gradient);
  assembler.ParallelFor(static_cast<int>(terms_.size()), 1, [&](int begin, int end, int) {
    for (int t = begin; t < end; ++t) {
      AssemblyOptions termOptions = options;
      termOptions.firstStageContributor = firstStageContributor_[t];
      terms_[t]->AddGradientAndHessian(assembler, firstContributor_[t], termOptions);
    }
  });
  assembler.FinishAssembly();
}

void StageProblem::SaveIterate() {
  for (StageDofs* owner : dofs_) owner->SaveIterate();
}

void StageProblem::RestoreIterate() {
  for (StageDofs* owner : dofs_) owner->RestoreIterate();
}

void StageProblem::ApplyIncrementFromSaved(Span<real const> delta, real alpha) {
  for (StageDofs* owner : dofs_) owner->ApplyIncrementFromSaved(delta, alpha);
}

bool StageProblem::IsStateFinite() const {
  bool finite = true;
  for (StageDofs const* owner : dofs_) finite = finite && owner->IsStateFinite();
  return finite;
}

bool StageProblem::RecenterStepBounds() {
  bool recentered = false;
  for (StageTerm* term : terms_)
    if (term->BoundsSteps()) recentered = term->RecenterStepBounds() || recentered;
  return recentered;
}

real StageProblem::LargestSafeStep(Span<real const> delta, real alpha) const {
  for (StageTerm const* term : terms_)
    if (term->BoundsSteps()) alpha = std::min(alpha, term->LargestSafeStep(delta, alpha));
  return alpha;
}

void StageProblem::AcceptStep(AcceptedStep const& step) {
  for (StageTerm* term : terms_) term->AcceptStep(step);
}

bool StageProblem::AtTargets() const {
  return std::all_of(terms_.begin(), terms_.end(), [](StageTerm const* t) { return t->AtTarget(); });
}

bool StageProblem::AdvanceTargets(real fraction) {
  for (StageTerm* term : terms_)
    if (!term->AtTarget() && !term->AdvanceTarget(fraction)) return false;
  return true;
}

bool StageProblem::HasSecondOrderCorrection() const {
  return std::any_of(terms_.begin(), terms_.end(), [](StageTerm const* t) { return t->HasSecondOrderCorrection(); });
}

void StageProblem::AddCorrectionForce(Span<real const> step, Span<real> gradient) {
  for (StageTerm* term : terms_) term->AddCorrectionForce(step, gradient);
}

void StageProblem::EndStage() {
  for (StageTerm* term : terms_) term->EndStage();
}

void StageProblem::WriteDofLengthScales(Span<real> scales) const {
  for (StageDofs const* owner : dofs_) owner->WriteDofLengthScales(scales);
}

void StageProblem::WriteDofInverseMasses(Span<real> inverseMasses) const {
  for (StageDofs const* owner : dofs_) owner->WriteDofInverseMasses(inverseMasses);
}

void StageProblem::WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const {
  for (StageDofs const* owner : dofs_) owner->WriteRigidBodyModes(modes);
}

}  // namespace superdex::internal
