#include <superdex/solver/own_block_elimination.h>

#include <chrono>

#include <superdex/core/stopwatch.h>
#include <superdex/solver/newton_params.h>
#include <superdex/solver/scene_stats.h>

namespace superdex::internal {

namespace {

/// An own block and its global DoFs [begin, end).
struct OwnBlockRange {
  OwnBlockSolve* block;
  int begin, end;
};
}  // namespace

void OwnBlockElimination::Reset(StageProblem const& problem, bool distributed) {
  for (StageTerm* term : problem.GetTerms())
    if (OwnBlockSolve* block = term->GetOwnBlockSolve()) {
      block->SetActive(!distributed);
      block->ClearFolded();
    }
}

void OwnBlockElimination::Choose(StageProblem const& problem,
                                 DynamicArray<DynamicArray<DynamicArray<int>>>& termDofs) {
  DynamicArray<OwnBlockRange> ranges;
  for (StageTerm* term : problem.GetTerms())
    if (OwnBlockSolve* block = term->GetOwnBlockSolve(); block && block->IsActive()) {
      int const begin = block->GetDofs().GetDofOffset();
      ranges.push_back({block, begin, begin + block->GetDofs().GetNumDofs()});
    }
  if (ranges.empty()) return;
  DynamicArray<int> dofRange(problem.GetNumDofs(), -1);  ///< the range holding each DoF
  for (std::size_t r = 0; r < ranges.size(); ++r)
    for (int dof = ranges[r].begin; dof < ranges[r].end; ++dof) dofRange[dof] = static_cast<int>(r);
  struct Foldable {
    int term, contributor;
    LinkTerm* linkTerm;
    OwnBlockSolve* block;
  };
  DynamicArray<Foldable> foldable;
  DynamicArray<StageTerm*> const& terms = problem.GetTerms();
  for (int t = 0; t < static_cast<int>(terms.size()); ++t) {
    if (terms[t]->GetOwnBlockSolve()) continue;
    for (int k = 0; k < static_cast<int>(termDofs[t].size()); ++k) {
      // a term on a link of an own block: taken in where the block stays on
      if (LinkTerm* linkTerm = terms[t]->GetLinkTerm(k)) {
        for (OwnBlockRange const& range : ranges)
          if (range.block->IsActive() && &range.block->GetDofs() == linkTerm->GetLinkOwner())
            foldable.push_back({t, k, linkTerm, range.block});
        continue;
      }
      // any other contributor on an own block's DoFs keeps it on only within
      // one of its groups (a joint's diagonal block)
      DynamicArray<int> const& dofs = termDofs[t][k];
      int first = -1;
      for (int dof : dofs)
        if (dofRange[dof] >= 0 && ranges[dofRange[dof]].block->IsActive()) {
          first = dofRange[dof];
          break;
        }
      if (first < 0) continue;
      OwnBlockRange const& range = ranges[first];
      bool local = true;
      int group = -1;
      for (int dof : dofs) {
        if (dofRange[dof] != first) {
          local = false;
          break;
        }
        int const g = range.block->GetDofGroup(dof - range.begin);
        if (group >= 0 && g != group) local = false;
        group = g;
      }
      if (local) continue;
      for (int dof : dofs)
        if (dofRange[dof] >= 0) ranges[dofRange[dof]].block->SetActive(false);
    }
  }
  // taken in where the block is still on (another contributor may have
  // coupled it since)
  for (Foldable const& f : foldable)
    if (f.block->IsActive() && f.block->Fold(*f.linkTerm)) termDofs[f.term][f.contributor].clear();
}

void OwnBlockElimination::Prepare(StageProblem const& problem, bool distributed) {
  blocks_.clear();
  firstContributors_.clear();
  DynamicArray<StageTerm*> const& terms = problem.GetTerms();
  for (std::size_t t = 0; t < terms.size(); ++t)
    if (OwnBlockSolve* block = terms[t]->GetOwnBlockSolve(); block && block->IsActive()) {
      blocks_.push_back(block);
      firstContributors_.push_back(problem.GetFirstContributor(static_cast<int>(t)));
    }
  int const numDofs = problem.GetNumDofs();
  rhs_.setZero(blocks_.empty() ? 0 : numDofs);
  coupled_ = false;
  for (OwnBlockSolve const* block : blocks_) coupled_ = coupled_ || block->HasCoupling();
  // every DoF owner's DoFs in an own block, none coupled
  identity_ = !distributed && !blocks_.empty() && blocks_.size() == problem.GetDofs().size() && !coupled_;
}

LinearSolveResult OwnBlockElimination::Factorize(HessianAssembler& assembler, bool project, bool separateCouplings,
                                                 SceneStats& stats) {
  LinearSolveResult result;
  if (blocks_.empty()) return result;
  auto const start = std::chrono::steady_clock::now();
  for (std::size_t a = 0; a < blocks_.size(); ++a)
    if (!blocks_[a]->Factorize(assembler, firstContributors_[a], project, separateCouplings, result.reason)) {
      result.status = LinearSolveStatus::NotPositiveDefinite;
      if (project && result.reason.empty()) result.reason = "an actor's own block is not positive definite";
      break;
    }
  stats.factorizationSeconds += SecondsSince(start);
  return result;
}

void OwnBlockElimination::Solve(Span<real const> gradient, Span<real> delta) {
  if (blocks_.empty()) return;
  rhs_ = -Eigen::Map<VectorX const>(gradient.data(), static_cast<Eigen::Index>(gradient.size()));
  for (OwnBlockSolve* block : blocks_) block->Solve(Span<real const>(rhs_.data(), rhs_.size()), delta);
}

void OwnBlockElimination::EliminateFromRhs(Span<real const> gradient, Span<real> rhs) {
  Eigen::Map<VectorX>(rhs.data(), static_cast<Eigen::Index>(rhs.size())) =
      -Eigen::Map<VectorX const>(gradient.data(), static_cast<Eigen::Index>(gradient.size()));
  for (OwnBlockSolve* block : blocks_) block->EliminateFromRhs(rhs);
}

}  // namespace superdex::internal
