// ConstraintSet: the scene's constraints as one term of the stage
// (stage/stage_term.h), Σ Φᶜᵢ over every constraint, one contributor per
// constraint in creation order (constraints.md: the compliant potential with
// stiffness, damping against the stage start, saturation and ranges). It
// owns each constraint's stage state (ConstraintStage).
//
// It holds the per-thread workspaces the constraints are evaluated in (sized
// at each pattern build to the largest constraint) and runs their assembly
// on the assembler's threads, kConstraintGrain constraints per chunk.
#pragma once

#include <superdex/constraints/constraint.h>
#include <superdex/constraints/constraint_stage.h>
#include <superdex/stage/stage_term.h>

namespace superdex::internal {

class ConstraintSet final : public StageTerm {
 public:
  /// The constraints, in creation order (their contributor order); at every
  /// topology change, before the pattern build.
  void SetConstraints(DynamicArray<Constraint*> const& constraints);

  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  void ReserveThreads(int numThreads) override;
  void BeginStage(StageContext const& stage) override;
  void AddEnergy(HessianAssembler const& assembler, int firstContributor, EnergySum& sum) const override;
  void AddGradientAndHessian(HessianAssembler& assembler, int firstContributor,
                             AssemblyOptions const& options) const override;
  void AcceptStep(AcceptedStep const& step) override;
  /// Every constraint takes part (range types add nothing: one-sided, their
  /// curvature is not that of a smooth manifold).
  bool HasSecondOrderCorrection() const override { return !constraints_.empty(); }
  void AddCorrectionForce(Span<real const> step, Span<real> gradient) override;
  void EndStage() override;
  LinkTerm* GetLinkTerm(int k) override {
    return constraints_[k]->FoldableLinkSlot() >= 0 ? &stages_[k] : nullptr;
  }

  /// Constraints whose k and d the near-rigid cap lowered in the last
  /// BeginStage (NewtonParams::nearRigidBeta).
  int GetNumNearRigid() const { return numNearRigid_; }

 private:
  DynamicArray<Constraint*> constraints_;
  DynamicArray<ConstraintStage> stages_;  ///< one per constraint: its stage state
  int numNearRigid_ = 0;
  int maxDimension_ = 1, maxDofs_ = 1;
  /// one per assembly thread; the first serves the serial calls too
  mutable DynamicArray<TermWorkspace> workspaces_ = DynamicArray<TermWorkspace>(1);
};

}  // namespace superdex::internal
