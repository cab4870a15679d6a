#include <superdex/constraints/constraint_set.h>

#include <algorithm>

namespace superdex::internal {

namespace {
/// Constraints per chunk of the parallel assembly (~1 µs each)
constexpr int kConstraintGrain = 32;
}  // namespace

void ConstraintSet::SetConstraints(DynamicArray<Constraint*> const& constraints) {
  constraints_ = constraints;
  stages_.clear();
  stages_.reserve(constraints_.size());
  for (Constraint* constraint : constraints_) stages_.emplace_back(*constraint);
  maxDimension_ = maxDofs_ = 1;
  for (Constraint const* constraint : constraints_) {
    maxDimension_ = std::max(maxDimension_, constraint->GetDimension());
    maxDofs_ = std::max(maxDofs_, constraint->GetNumDofs());
  }
  for (TermWorkspace& ws : workspaces_) ws.Reserve(maxDimension_, maxDofs_);
}

void ConstraintSet::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  for (Constraint const* constraint : constraints_) dofLists.emplace_back(constraint->GetDofs());
}

void ConstraintSet::ReserveThreads(int numThreads) {
  workspaces_.resize(std::max(numThreads, 1));
  for (TermWorkspace& ws : workspaces_) ws.Reserve(maxDimension_, maxDofs_);
}

void ConstraintSet::BeginStage(StageContext const& stage) {
  // g(qᵢ⁰, p̂ᵢ⁰) at the committed configuration (every term begins before
  // any actor moves to its first iterate), and the near-rigid cap there
  numNearRigid_ = 0;
  for (ConstraintStage& constraint : stages_) numNearRigid_ += constraint.Begin(stage, workspaces_[0]);
}

void ConstraintSet::AddEnergy(HessianAssembler const& assembler, int firstContributor, EnergySum& sum) const {
  int const count = static_cast<int>(constraints_.size());
  for (int c = 0; c < count; ++c) {
    if (!assembler.Owns(firstContributor + c)) continue;
    sum.Add(stages_[c].Energy(workspaces_[0]));
  }
}

void ConstraintSet::AddGradientAndHessian(HessianAssembler& assembler, int firstContributor,
                                          AssemblyOptions const& options) const {
  // a constraint an own-block solve took in has no DoFs here (its actor
  // assembles it): the assembler does not evaluate it
  assembler.ParallelFor(static_cast<int>(stages_.size()), kConstraintGrain, [&](int begin, int end, int thread) {
    for (int c = begin; c < end; ++c) {
      int const contributor = firstContributor + c;
      if (!assembler.Evaluates(contributor)) continue;
      stages_[c].AddGradientAndHessian(assembler, contributor, options.projectHessian, workspaces_[thread]);
    }
  });
}

void ConstraintSet::AcceptStep(AcceptedStep const& step) {
  for (ConstraintStage& constraint : stages_) constraint.PredictForce(step);
}

void ConstraintSet::AddCorrectionForce(Span<real const> step, Span<real> gradient) {
  for (ConstraintStage& constraint : stages_) constraint.AddCorrectionForce(step, gradient, workspaces_[0]);
}

void ConstraintSet::EndStage() {
  for (ConstraintStage& constraint : stages_) constraint.End(workspaces_[0]);
}

}  // namespace superdex::internal
