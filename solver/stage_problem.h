// StageProblem: one stage's unknowns and potential as the Newton solver sees
// them — the DoF owners (in DoF order) and the terms (in contributor order)
// of stage/stage_term.h, nothing more specific. It numbers the terms'
// contributors, and walks the lists for everything that concerns all of
// them: the stage's begin and end, Eᵢ and its round-off scale, one assembly,
// moving the configuration along a step.
#pragma once

#include <superdex/solver/collectives.h>
#include <superdex/stage/stage_term.h>

namespace superdex::internal {

class StageProblem {
 public:
  /// The DoF owners, contiguous in this order, and the terms, whose
  /// contributors are numbered in this order (at each topology change).
  void Set(DynamicArray<StageDofs*> dofs, DynamicArray<StageTerm*> terms);
  DynamicArray<StageDofs*> const& GetDofs() const { return dofs_; }
  DynamicArray<StageTerm*> const& GetTerms() const { return terms_; }
  int GetNumDofs() const { return numDofs_; }

  /// The DoF blocks of the ordering graph, and every contributor's DoF list
  /// in contributor order from each term's (termDofs[t], moved from),
  /// recording each term's first contributor.
  void FlattenPattern(DynamicArray<DynamicArray<DynamicArray<int>>>& termDofs, DynamicArray<int>& blockSizes,
                      DynamicArray<DynamicArray<int>>& contributorDofs);
  /// Term t's contributors are [GetFirstContributor(t), GetFirstContributor(t + 1)).
  int GetFirstContributor(int term) const { return firstContributor_[term]; }
  void ReserveThreads(int numThreads);

  /// Every term's BeginStage at the committed configuration.
  void BeginStage(StageContext const& stage);
  /// The terms' stage contributors (the second family) for this stage, in
  /// term order, recording each term's first.
  void AppendStageContributorDofs(StageDofLists& dofLists);
  /// Every DoF owner to its first iterate, or back to the stage start when a
  /// term that bounds steps refuses the move (StageTerm::AcceptsFirstIterate).
  void MoveToFirstIterate();
  /// Eᵢ at the current iterate: each contributor counted by the one rank
  /// that owns it, the ranks' sums added in rank order (every rank gets the
  /// same bits).
  EnergySum Energy(HessianAssembler const& assembler, RankGroup& ranks) const;
  /// ∇E into `gradient` and the Hessian into the assembler's values: every
  /// term on the assembler's threads (staged, each contributor in its own
  /// slots: the terms run concurrently, each one's loops nested).
  void Assemble(HessianAssembler& assembler, Span<real> gradient, AssemblyOptions const& options) const;

  void SaveIterate();
  void RestoreIterate();
  /// q ← saved ⊕ α δ for every DoF owner.
  void ApplyIncrementFromSaved(Span<real const> delta, real alpha);
  bool IsStateFinite() const;
  /// Whether some term bounds Newton's steps (StageTerm::BoundsSteps).
  bool BoundsSteps() const { return boundsSteps_; }
  /// The safe-step hook over the terms that bound steps: the largest
  /// α' <= alpha that none refuses, from the current configuration.
  real LargestSafeStep(Span<real const> delta, real alpha) const;
  /// StageTerm::RecenterStepBounds of every term that bounds steps: whether
  /// one found its region again (the stage contributors may have changed).
  bool RecenterStepBounds();
  /// StageTerm::LimitStepPerDof of every term that bounds steps, in turn.
  void LimitStepPerDof(Span<real> delta) const {
    for (StageTerm* term : terms_)
      if (term->BoundsSteps()) term->LimitStepPerDof(delta);
  }
  void AcceptStep(AcceptedStep const& step);
  /// Whether every term is at its stage target (StageTerm::AtTarget).
  bool AtTargets() const;
  /// Every term not at its target `fraction` of its remaining way there;
  /// false where one refused (the others may have moved: restore them by
  /// AdvanceTargets of the smaller fraction after RestoreIterate).
  bool AdvanceTargets(real fraction);
  bool HasSecondOrderCorrection() const;
  /// Σ over terms of their second-order correction force (into `gradient`).
  void AddCorrectionForce(Span<real const> step, Span<real> gradient);
  void EndStage();

  void WriteDofLengthScales(Span<real> scales) const;
  void WriteDofInverseMasses(Span<real> inverseMasses) const;
  void WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const;

 private:
  DynamicArray<StageDofs*> dofs_;
  DynamicArray<StageTerm*> terms_;
  int numDofs_ = 0;
  bool boundsSteps_ = false;
  DynamicArray<int> firstContributor_;  ///< per term, then the end of the last
  DynamicArray<int> firstStageContributor_;  ///< per term, then the end of the last
};

}  // namespace superdex::internal
