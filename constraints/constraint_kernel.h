// ConstraintKernel: a constraint type's kinematics, apart from the runtime
// interface (constraint.h) and from the stage's state (constraint_stage.h).
//
// A type declares its layout — m, its kind of target, whether it is a range
// type, whether g has curvature, and for each actor the local DoFs it
// touches — and writes, at the actors' current configuration, g and the
// dense local J (columns in DoF-list order, w.r.t. the DoF increments of
// docs/design.md §3; DoEvaluate), the curvature of g contracted with weights
// (DoAddCurvature) and, for range types, its bounds (DoGetLimits). It never
// sees global indices or the global matrix. The kernel maps its DoF lists
// onto the scene's DoFs (RefreshDofs, at topology changes) and, where a body
// is an articulated link, J and the curvature onto the joint DoFs of the
// link's path (LinkPath; docs/articulated.md, "Links in constraints").
//
// Its only state beyond the immutable layout is that mapping and the link
// frames of the last evaluation (a cache of the actors' kinematics).
#pragma once

#include <array>
#include <string_view>

#include <superdex/constraints/constraint_types.h>
#include <superdex/core/types.h>
#include <superdex/stage/link_path.h>
#include <superdex/stage/term_workspace.h>

namespace superdex {

class Actor;

/// The constraint types (constraint_types.h: one line each).
enum class ConstraintType {
#define SUPERDEX_CONSTRAINT_TYPE_VALUE(Name, Class, file) Name,
  SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_CONSTRAINT_TYPE_VALUE)
#undef SUPERDEX_CONSTRAINT_TYPE_VALUE
};

std::string_view ToString(ConstraintType type);

namespace internal {

/// A rigid body a constraint acts on: a RigidActor (link −1) or link `link`
/// of an ArticulatedActor.
struct RigidBodySlot {
  Actor* actor = nullptr;
  int link = -1;
};

class ConstraintKernel {
 public:
  enum class TargetKind { None, Position, Rotation, Transform, Dof };
  /// Target storage of a type: position (3), rotation quaternion (w,x,y,z),
  /// transform (position then quaternion), or one DoF value.
  static constexpr int kMaxTargetSize = 7;
  using Target = std::array<real, kMaxTargetSize>;

  virtual ~ConstraintKernel() = default;
  ConstraintKernel(ConstraintKernel const&) = delete;
  ConstraintKernel& operator=(ConstraintKernel const&) = delete;

  ConstraintType GetType() const { return type_; }
  int GetNumActors() const { return numActors_; }
  /// The i-th actor, or nullptr when i is not in [0, GetNumActors()).
  Actor* GetActor(int i) const { return (i >= 0 && i < numActors_) ? actors_[i] : nullptr; }
  /// Global DoF indices this constraint touches on actor i (empty span when
  /// i is out of range). Valid until the scene's topology changes.
  Span<int const> GetDofIndicesForActor(int i) const;
  /// m, the dimension of g.
  int GetDimension() const { return dimension_; }
  /// n, the number of DoFs coupled.
  int GetNumDofs() const { return static_cast<int>(dofs_.size()); }
  /// True for range (unilateral) types.
  bool IsRange() const { return isRange_; }
  /// True when g is nonlinear in the DoF increments (its curvature G can be
  /// non-zero); false for the deformable couplings and single-DoF types.
  bool HasCurvature() const { return hasCurvature_; }
  TargetKind GetTargetKind() const { return targetKind_; }

  // ---- internal: the scene and the stage ----
  /// The global DoF list: actor 0's, then actor 1's not listed yet (two
  /// links of one articulated actor, a kinematic loop, share their common
  /// path DoFs).
  DynamicArray<int> const& GetDofs() const { return dofs_; }
  /// Actor a's local DoFs (on a link: its path's joint DoFs).
  DynamicArray<int> const& GetLocalDofs(int a) const { return localDofs_[a]; }
  /// Recomputes the global DoF indices from the actors' offsets.
  void RefreshDofs();
  /// g and J (ws.g, ws.jacobian: m × n, DoF-list order) at the actors'
  /// current configuration for `target`; ws Reserve(m, n)d.
  void Evaluate(Span<real const> target, TermWorkspace& ws) const;
  /// Adds Σᵢ wᵢ ∂²gᵢ/∂q² over the n DoFs to `hessian`, after an Evaluate at
  /// `target` with the same `ws` (links: Bᵀ G B plus the link frames' own
  /// curvature against the type's wrench Jᵀw).
  void AddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights, TermWorkspace& ws,
                    Eigen::Ref<MatrixX> hessian) const;
  /// g alone at `target` (no workspace).
  VectorX Value(Span<real const> target) const;
  /// The range types' bounds of each component of g's measure (±∞ otherwise).
  void GetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const { DoGetLimits(lower, upper); }

  // ---- links ----
  bool HasLinks() const { return links_[0] >= 0 || links_[1] >= 0; }
  /// The actor slot of the articulated link the actor's tree recursion can
  /// take this constraint into, or −1: a single-body constraint on a link,
  /// or a two-body one between a link and a body that is not a link.
  int FoldableLinkSlot() const;
  /// Slot a's link path (its frame as of the last evaluation) and the
  /// columns of its DoFs in the DoF list.
  LinkPath const& GetLinkPath(int a) const { return paths_[a]; }
  Span<int const> GetSlotColumns(int a) const { return slotColumns_[a]; }
  /// The type's rigid DoFs on slot a where it is a link (a subset of 0..5),
  /// and the type's number of DoFs (n before the links' mapping).
  DynamicArray<int> const& GetTypeDofs(int a) const { return typeDofs_[a]; }
  int GetTypeNumDofs() const { return typeNumDofs_; }
  /// The type's own g, J and curvature over its rigid DoFs (a folded
  /// constraint's: AddFoldedTerms), at the current link frames.
  void EvaluateType(Span<real const> target, Eigen::Ref<VectorX> g, Eigen::Ref<MatrixX> jacobian) const {
    DoEvaluate(target, g, jacobian);
  }
  void AddTypeCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                        Eigen::Ref<MatrixX> hessian) const {
    DoAddCurvature(target, weights, hessian);
  }

 protected:
  /// A type declares m, its kind of target, whether it is a range type, and
  /// for each actor the local DoFs it touches (e.g. {3,4,5}: rotation only).
  /// Where actor i is an articulated link (links[i] >= 0), the type still
  /// writes J and G over the rigid-body DoFs it lists (a subset of 0..5 of
  /// the link frame's increments) and reads the frame through BodyPosition /
  /// BodyRotation; the constraint's DoFs on that actor are the joint DoFs
  /// from the root to the link, and J and G are mapped onto them through the
  /// link's kinematic Jacobian.
  struct Layout {
    ConstraintType type;
    int dimension;
    TargetKind targetKind = TargetKind::None;
    bool isRange = false;
    bool hasCurvature = false;  ///< g nonlinear: the type overrides DoAddCurvature
    std::array<Actor*, 2> actors{};
    std::array<int, 2> links{-1, -1};
    std::array<DynamicArray<int>, 2> localDofs;
  };
  explicit ConstraintKernel(Layout layout);

  /// g and J (m×n, columns in DoF-list order, w.r.t. the DoF increments of
  /// docs/design.md §3) at the actors' current configuration for `target`.
  virtual void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                          Eigen::Ref<MatrixX> jacobian) const = 0;
  /// Adds the curvature of g contracted with `weights` (m entries),
  /// Σᵢ wᵢ ∂²gᵢ/∂q² (n×n, DoF-list order, second derivatives w.r.t. the DoF
  /// increments of docs/design.md §3 at zero increment), to `hessian`, at the
  /// actors' current configuration for `target`. Types with hasCurvature
  /// override; range types include their one-sided slopes (∂²gᵢ = ±∂²xᵢ where
  /// a bound is violated, 0 inside).
  virtual void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                              Eigen::Ref<MatrixX> hessian) const;
  /// Range types override: bounds of each component of g's measure.
  virtual void DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const;

  static Real3 TargetPosition(Span<real const> target);
  static Quat TargetRotation(Span<real const> target, int offset = 0);
  /// The frame of the rigid body that is actor `i`: a RigidActor's pose, or
  /// an articulated link's frame at the current iterate (refreshed before
  /// every DoEvaluate and DoAddCurvature).
  Real3 BodyPosition(int i) const;
  Quat BodyRotation(int i) const;
  /// Recomputes the articulated links' frames and Jacobians at the current
  /// iterate (a type's public queries of the pose call it first).
  void RefreshLinkFrames() const;

 private:
  ConstraintType type_;
  int dimension_;
  int numActors_;
  TargetKind targetKind_;
  bool isRange_;
  bool hasCurvature_;
  std::array<Actor*, 2> actors_{};
  std::array<DynamicArray<int>, 2> localDofs_;
  DynamicArray<int> dofs_;
  /// per actor: its DoFs (global; GetDofIndicesForActor) and their columns in dofs_
  std::array<DynamicArray<int>, 2> slotDofs_, slotColumns_;
  /// per actor: the link it is (−1: the actor itself), the type's rigid DoFs
  /// on it where it is a link, and the link's path and frame
  std::array<int, 2> links_{-1, -1};
  std::array<DynamicArray<int>, 2> typeDofs_;
  mutable std::array<LinkPath, 2> paths_;
  int typeNumDofs_ = 0;
};

}  // namespace internal
}  // namespace superdex
