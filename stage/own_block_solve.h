// Own-block solves: a capability a term may offer (StageTerm::
// GetOwnBlockSolve) — an articulated actor on its tree, an O(N) recursion
// instead of a dense block in the scene's matrix (docs/articulated.md,
// "Solving on the tree").
//
// Its DoFs fall into groups (an articulated actor's joints). Other
// contributors may add to one group's diagonal block, and to nothing else of
// its DoFs; the solver turns the capability off where one does not
// (ChooseOwnBlockSolves, solver/own_block_elimination.h). A term on one of its
// links (LinkTerm: a constraint on a link, alone or with one body that is not
// such a link) is taken into the block instead: the owner assembles it, and
// where it couples the link with another body, the scene's matrix holds that
// body's DoFs with the block's Schur complement.
#pragma once

#include <string>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/types.h>
#include <superdex/stage/link_path.h>
#include <superdex/stage/term_workspace.h>

namespace superdex::internal {

class StageDofs;

/// A term on one rigid link of an articulated actor that the actor's
/// own-block solve can take in (Fold).
class LinkTerm {
 public:
  virtual ~LinkTerm() = default;
  /// The actor whose link it acts on.
  virtual StageDofs const* GetLinkOwner() const = 0;
  /// The link (its index in the actor) and the link's path: its joint DoFs,
  /// and the frame and its Jacobian as of the last AddLinkTerms.
  virtual LinkPath const& GetLinkPath() const = 0;
  /// The term's DoF list is the path's DoFs (global, GetPathDofs) and, for a
  /// two-body term, the other body's (GetOtherDofs, empty for one body);
  /// the columns of each in the term's DoF list.
  virtual Span<int const> GetPathDofs() const = 0;
  virtual Span<int const> GetPathColumns() const = 0;
  virtual Span<int const> GetOtherDofs() const = 0;
  virtual Span<int const> GetOtherColumns() const = 0;
  /// The largest g dimension and DoF count of the term (its workspace).
  virtual int GetDimension() const = 0;
  virtual int GetNumDofs() const = 0;
  /// The term's contributions at the link, at the current iterate: the
  /// gradient over its DoF list in ws.r; the Hessian, (6 + n_o)², over the
  /// link frame's increments (δt; δθ) and then the other body's n_o DoFs;
  /// the wrench (F; M) on the link that weighs the link frame's own
  /// curvature in `curvatureWrench` (zero without curvature), with
  /// `exactCurvature` false where that curvature is to be taken by its
  /// column norms. False when it adds nothing (an inactive range term).
  virtual bool AddLinkTerms(bool projectHessian, TermWorkspace& ws, TermWorkspace::FoldedBlock& hessian,
                            Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const = 0;
};

/// The own-block solve of a term that offers one.
class OwnBlockSolve {
 public:
  virtual ~OwnBlockSolve() = default;

  /// Set by the solver at each pattern build, before the term's
  /// AppendContributorDofs: while on, the term adds one contributor per
  /// group (that group's diagonal block) and keeps the coupling between
  /// groups to itself.
  void SetActive(bool active) { active_ = active; }
  bool IsActive() const { return active_; }
  /// The owner of the DoFs the block covers.
  virtual StageDofs const& GetDofs() const = 0;
  /// The group of local DoF `dof`.
  virtual int GetDofGroup(int dof) const = 0;

  /// Takes `term` into the block (a term on one of the owner's links); false
  /// where it cannot. Called at pattern builds after ClearFolded, before
  /// AppendContributorDofs.
  virtual bool Fold(LinkTerm& term) = 0;
  virtual void ClearFolded() = 0;

  /// After an assembly: reads its groups' assembled diagonal blocks (which
  /// hold the other contributors' terms too), factorizes the block (with
  /// `projectHessian` made positive definite, pivot by pivot) and overwrites
  /// those blocks in the assembled matrix with the identity, so that the
  /// scene's solver returns −∇E on its DoFs, which Solve then replaces.
  /// False when the block is not positive definite (or not finite); with
  /// `projectHessian`, where that failure is final, `reason` says why. With
  /// `separateCouplings` a block coupled with other DoFs is made positive
  /// definite without its couplings' terms, which then join it.
  virtual bool Factorize(HessianAssembler& assembler, int firstContributor, bool projectHessian,
                         bool separateCouplings, std::string& reason) = 0;
  /// delta ← (block)⁻¹ rhs on the owner's DoFs (global vectors), with the
  /// last Factorize. Where the block is coupled to other DoFs (HasCoupling),
  /// delta holds the scene's solution on them (x_o) and the block's part is
  /// A⁻¹(rhs_t − Cᵀ x_o).
  virtual void Solve(Span<real const> rhs, Span<real> delta) = 0;
  /// True where a folded term couples the block A with other bodies' DoFs
  /// (C): Factorize then adds −C A⁻¹ Cᵀ to their block in the scene's matrix
  /// (a Schur complement), and EliminateFromRhs turns the scene's right-hand
  /// side −∇E (natural order, global) into the complement's, rhs_o − C A⁻¹ rhs_t.
  virtual bool HasCoupling() const = 0;
  virtual void EliminateFromRhs(Span<real> rhs) = 0;

 private:
  bool active_ = false;
};

}  // namespace superdex::internal
