// An articulated actor: a tree of rigid links in reduced coordinates
// (docs/design.md §4.4). Link 0 is the root; every link names a parent earlier in
// the list (the root's parent is the world) and the joint between them.
//
// Kinematics. Link i's world transform is
//
//   T_i = T_p(i) · X_pj · J(q_i) · X_jc,
//
// T_p the parent's (identity for the root), X_pj the joint frame in the
// parent frame, X_jc the link frame in the joint's child-side frame, J the
// joint motion:
//
//   Fixed      0 DoFs  J = I
//   Revolute   1 DoF   J = Rot(a, θ)            a the unit axis in the joint frame
//   Prismatic  1 DoF   J = Trans(a d)
//   Spherical  3 DoFs  J = Rot(R_j)             increments R_j ← R_j Exp(δ) (local)
//   Free       6 DoFs  J = Trans(p) Rot(R_j)    p ← p + δ_p (joint frame), R_j ← R_j Exp(δ_r)
//
// A Free root is a floating base; any other root joint attaches the tree to
// the world (fixed base). The DoFs are the joints' in link order.
//
// Dynamics: the stage inertia term is each link's rigid-body inertia term
// (actors/rigid_actor.h) evaluated at the link pose the reduced coordinates
// give,
//
//   E(q) = Σ_i [½ w m_i ‖Δc_i − Δ̂c_i‖² + ½ w (φ_i − φ̂_i)ᵀ I_i (φ_i − φ̂_i) − m_i g·c_i]
//          + Σ_dofs ½ w a_k (Δq_k − Δ̂q_k)² + d_k/(2h) Δq_k²,
//
// c_i the link's centre of mass, φ_i = Log(R_iⁿᵀ R_i) its body-frame rotation
// in the stage, Δ̂/φ̂ the integrator's predictions from the link's own
// velocity (with the same gyroscopic treatment as a free rigid body), a_k the
// joint armature and d_k the joint damping. This is how the configuration-
// dependent mass matrix enters: the Gauss–Newton part of ∇²E is w·M(q), M(q)
// the joint-space mass matrix at the current iterate (the composite-rigid-
// body algorithm computes it), and E itself is the maximal-coordinate
// incremental potential restricted to the joint manifold — a chain of rigid
// bodies with infinitely stiff joints, stepped by the same integrator. The
// gradient is a recursive Newton–Euler backward pass of the link wrenches
// (inertia residual and gravity). The Hessian adds the kinematic curvature
// of the link poses against those wrenches (exact; it may be indefinite);
// with `projectHessian` only the PSD part w·M(q) + armature + damping is
// kept.
//
// Solving. With ArticulatedBlockSolve::Tree (the default) the actor's Newton
// block is not formed: its Hessian has the structure H_ab = s_aᵀ Y_c s_b (a
// in an ancestor of b's joint c, Y a subtree sum), which
// internal::ArticulatedTreeSolver factorizes and solves in O(N) per Newton
// iteration; the scene's matrix holds only each joint's diagonal block, where
// the actor's joint constraints add theirs, and single-body constraints on
// its links (GetLinkPath) are folded in as wrenches and stiffnesses at the
// links (FoldConstraint). ArticulatedBlockSolve::Dense assembles the dense
// block into the scene's matrix (O(N²) assembly, O(N³) factorization);
// across MPI ranks, and where a constraint couples two joints or the actor
// with other actors (a link as a body of a two-body type), the dense block
// is used.
// docs/articulated.md, "Solving on the tree" and "Links in constraints".
#pragma once

#include <Eigen/Cholesky>

#include <superdex/actors/articulated_tree_solver.h>
#include <superdex/stage/link_path.h>

#include <superdex/actors/actor.h>
#include <superdex/actors/rigid_inertia.h>
#include <superdex/core/error.h>
#include <superdex/stage/integrator.h>
#include <superdex/stage/own_block_solve.h>

namespace superdex {

enum class JointType { Fixed, Revolute, Prismatic, Spherical, Free };

std::string_view ToString(JointType type);
/// DoFs of a joint type: 0, 1, 1, 3, 6.
int JointDofs(JointType type);

/// How the actor's Newton block is solved (the file comment).
enum class ArticulatedBlockSolve { Tree, Dense };

/// The largest ratio h/hₚ of a step to the one before it at which Newton's
/// first iterate is extrapolated (ArticulatedActorParams::
/// extrapolateFirstIterate): the last step's velocity difference estimates
/// the acceleration only where hₚ is not much shorter than h.
inline constexpr real kMaxExtrapolationRatio = 4;
std::string_view ToString(ArticulatedBlockSolve solve);

struct ArticulatedLinkParams {
  int parent = -1;                      ///< earlier link, or −1 for the world (root only)
  JointType joint = JointType::Revolute;
  Real3 axis = Real3::UnitZ();          ///< revolute/prismatic axis, joint frame (normalized)
  Real3 parentToJointPosition = Real3::Zero();   ///< X_pj, in the parent link frame (world for the root) [m]
  Quat parentToJointRotation = Quat::Identity();
  Real3 jointToChildPosition = Real3::Zero();    ///< X_jc, in the joint's child-side frame [m]
  Quat jointToChildRotation = Quat::Identity();
  real mass = 1;                        ///< [kg], > 0
  Real3 inertia = Real3::Ones();        ///< principal moments about the centre of mass, link axes [kg·m²], > 0
  Real3 centerOfMass = Real3::Zero();   ///< in the link frame [m]
  real armature = 0;                    ///< added joint-space inertia per DoF [kg·m² or kg], >= 0
  real damping = 0;                     ///< joint damping per DoF [N·m·s/rad or N·s/m], >= 0
  /// Initial joint position: revolute angle / prismatic offset in [0];
  /// spherical: rotation vector of R_j in [0..2]; free: p in [0..2], rotation
  /// vector in [3..5]. Empty: zero (rest). Otherwise JointDofs entries.
  DynamicArray<real> initialPosition;
  /// Initial joint velocity (JointDofs entries, in the increment coordinates) or empty.
  DynamicArray<real> initialVelocity;
};

struct ArticulatedActorParams {
  DynamicArray<ArticulatedLinkParams> links;  ///< at least one; link 0 is the root
  /// Tree: the O(N) recursion (in one process; the dense block across
  /// ranks or under constraints on more than one joint); Dense: the dense
  /// block in the scene's matrix (docs/articulated.md, "Solving on the tree").
  ArticulatedBlockSolve blockSolve = ArticulatedBlockSolve::Tree;
  /// Newton's first iterate of a step: the joint velocity extrapolated at the
  /// last step's acceleration (true), or the constant-velocity prediction
  /// Δ̂q (false). Both converge to the same state (to the Newton tolerance);
  /// the extrapolated one in fewer iterations while the motion is smooth
  /// (docs/articulated.md, "Newton's first iterate"). A step more than
  /// kMaxExtrapolationRatio times longer than the last one starts from the
  /// prediction.
  bool extrapolateFirstIterate = true;
};

class ArticulatedActor final : public Actor, private internal::OwnBlockSolve {
 public:
  /// Validates everything (a tree: each parent an earlier link, only the
  /// root on the world; unit quaternions, non-zero axes, positive mass and
  /// inertia, initial state sizes; at least one DoF); nullptr and an Error
  /// naming the field on bad input.
  static std::unique_ptr<ArticulatedActor> Create(ArticulatedActorParams const& params, Error& error);

  int GetNumLinks() const { return static_cast<int>(links_.size()); }
  /// Preconditions for every link accessor: 0 <= link < GetNumLinks().
  JointType GetJointType(int link) const { return links_[link].joint; }
  int GetParent(int link) const { return links_[link].parent; }
  /// First local DoF of the link's joint and its number of DoFs.
  int GetJointDofOffset(int link) const { return links_[link].dofStart; }
  int GetJointNumDofs(int link) const { return links_[link].numDofs; }
  bool IsFloatingBase() const { return links_[0].joint == JointType::Free; }
  ArticulatedBlockSolve GetBlockSolve() const { return blockSolve_; }
  /// True while the stage solver solves the actor by the tree recursion
  /// (Tree requested, one process, no constraint coupling two joints but
  /// through a link: docs/articulated.md, "Links in constraints").
  bool IsSolvedOnTree() const { return IsActive(); }
  /// Constraints between a link and another body that the tree couples to
  /// the scene's matrix by a Schur complement (IsSolvedOnTree), and the DoFs
  /// of those other bodies (the dense block the complement adds), as of the
  /// last pattern build.
  int GetNumCoupledConstraints() const { return numCoupled_; }
  int GetNumCoupledDofs() const { return static_cast<int>(couplingDofs_.size()); }
  /// Tree factorizations made positive definite (the exact Hessian was
  /// indefinite, or the scene projects every Hessian) since creation.
  long GetNumModifiedTreeFactorizations() const { return modifiedTreeFactorizations_; }
  /// Tree factorizations that fell back to the Gauss–Newton Hessian (the
  /// modified one failed; docs/articulated.md, "Indefinite iterates")
  long GetNumGaussNewtonTreeFactorizations() const { return gaussNewtonTreeFactorizations_; }

  /// The path of `link` for a constraint acting on it as a rigid body
  /// (internal: stage/link_path.h), its frame evaluated at the current
  /// iterate.
  internal::LinkPath GetLinkPath(int link) const;
  /// Refreshes path.position, path.rotation and path.jacobian at the current
  /// iterate: O(path length), no allocation.
  void ComputeLinkFrame(internal::LinkPath& path) const;
  /// The frame of `path`'s link at the current iterate moved by α d, d the
  /// actor's local increment (GetNumDofs() entries, applied as a Newton step
  /// applies it): O(path length), no allocation. A link collider's
  /// continuous collision detection (contact/contact_system.h).
  void ComputeLinkFrameAlong(internal::LinkPath const& path, real const* d, real alpha, Real3& position,
                             Quat& rotation) const;
  /// A bound on the speed |dx/dα| of every point of `path`'s link within
  /// `arm` of its frame origin while α runs over [0, alphaMax] along α d:
  /// the sum over the path's joints of a translation's rate and a
  /// rotation's rate times the farthest the point can be from that joint's
  /// origin (the offsets along the path, which rotations keep, and the
  /// prismatic and free translations reached).
  real LinkSpeedBound(internal::LinkPath const& path, real const* d, real alphaMax, real arm) const;

  /// Link frame (origin and axes) in the world, at the committed
  /// configuration (the end of the last step).
  Real3 GetLinkPosition(int link) const;
  Quat GetLinkRotation(int link) const;
  /// Centre of mass, world.
  Real3 GetLinkCenterOfMass(int link) const { return state_.links[link].position; }
  /// Velocity of the centre of mass and angular velocity, world.
  Real3 const& GetLinkLinearVelocity(int link) const { return state_.links[link].linearVelocity; }
  Real3 const& GetLinkAngularVelocity(int link) const { return state_.links[link].angularVelocity; }
  real GetLinkMass(int link) const { return links_[link].mass; }

  /// Joint positions, GetNumDofs() entries in DoF order: revolute angle,
  /// prismatic offset, spherical rotation vector Log(R_j), free p then Log(R_j).
  DynamicArray<real> GetJointPositions() const;
  /// Joint velocities in the increment coordinates (spherical and free
  /// rotations: local angular velocity, free translation: in the joint frame).
  DynamicArray<real> GetJointVelocities() const;
  /// R_j of a spherical or free joint (identity = rest); identity otherwise.
  Quat GetJointRotation(int link) const { return state_.joints[link].rotation; }
  /// A translational or single-rotation coordinate: the revolute angle or
  /// prismatic offset (dof 0), or a free joint's translation p[dof] (dof 0..2).
  real GetJointCoordinate(int link, int dof) const {
    return links_[link].joint == JointType::Free ? state_.joints[link].translation[dof] : state_.joints[link].scalar;
  }

  real GetKineticEnergy() const;
  Real3 GetLinearMomentum() const;
  /// About the world origin.
  Real3 GetAngularMomentum() const;

  /// The joint-space mass matrix M(q) at the current configuration
  /// (composite-rigid-body algorithm), GetNumDofs() square, armature included.
  MatrixX ComputeMassMatrix() const;
  /// The bias forces C(q, q̇) q̇ − τ_g(q) at the current configuration and
  /// joint velocities with gravity `gravity` (recursive Newton–Euler with
  /// q̈ = 0): M(q) q̈ + bias = τ is the equation of motion, τ the joint forces.
  VectorX ComputeBiasForces(Real3 const& gravity) const;

 private:
  explicit ArticulatedActor(int numDofs) : Actor(ActorType::Articulated, numDofs) {}

  struct Link {
    int parent = -1;
    JointType joint = JointType::Fixed;
    Real3 axis = Real3::UnitZ();
    Real3 parentToJointPosition, jointToChildPosition;
    Quat parentToJointRotation, jointToChildRotation;
    real mass = 1;
    Real3 inertia = Real3::Ones(), centerOfMass = Real3::Zero();
    real armature = 0, damping = 0;
    int dofStart = 0, numDofs = 0;
  };
  /// A joint's configuration: the scalar of revolute/prismatic joints, the
  /// translation p and rotation R_j of free (R_j of spherical) joints.
  struct JointState {
    real scalar = 0;
    Real3 translation = Real3::Zero();
    Quat rotation = Quat::Identity();
  };
  struct State {
    DynamicArray<JointState> joints;
    VectorX jointVelocity;
    DynamicArray<internal::RigidBodyMotion> links;  ///< committed pose, velocities, history per link
    bool hasHistory = false;
    DynamicArray<JointState> previousJoints;
    VectorX previousJointVelocity;
    real lastStageDuration = 0;  ///< h of the stage that set jointVelocity (0: none)
  };
  /// Forward kinematics of one configuration: link frames, centres of mass,
  /// joint frames and each DoF's world motion (ω, v at the origin).
  struct Kinematics {
    DynamicArray<Real3> linkPosition, com, jointOrigin;
    DynamicArray<Quat> linkRotation, preRotation, postRotation;
    Eigen::Matrix<real, 6, Eigen::Dynamic> motion;  ///< column k: DoF k's (ω; v_O)
    bool hasMotion = false;  ///< motion is computed (the energy needs the poses only)
  };

  void AppendDofBlockSizes(DynamicArray<int>& sizes) const override;
  void WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const override;
  void WriteDofInverseMasses(Span<real> inverseMasses) const override;
  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  void BeginStage(internal::StageContext const& context) override;
  void MoveToFirstIterate() override;
  real Energy(internal::OwnedContributors owned) const override;
  real EnergyRoundOffScale() const override { return energyRoundOffScale_; }
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                             internal::AssemblyOptions const& options) const override;
  // the own-block solve on the tree (stage/own_block_solve.h): offered with
  // ArticulatedBlockSolve::Tree
  internal::OwnBlockSolve* GetOwnBlockSolve() override {
    return blockSolve_ == ArticulatedBlockSolve::Tree ? this : nullptr;
  }
  internal::StageDofs const& GetDofs() const override { return *this; }
  int GetDofGroup(int dof) const override { return dofLink_[dof]; }
  bool Factorize(internal::HessianAssembler& assembler, int firstContributor, bool projectHessian,
                 bool separateCouplings, std::string& reason) override;
  void Solve(Span<real const> rhs, Span<real> delta) override;
  bool HasCoupling() const override { return !couplingDofs_.empty(); }
  void EliminateFromRhs(Span<real> rhs) override;
  bool Fold(internal::LinkTerm& term) override;
  void ClearFolded() override;
  void SaveIterate() override;
  void RestoreIterate() override;
  void ApplyIncrementFromSaved(Span<real const> delta, real alpha) override;
  bool IsStateFinite() const override;
  void EndStage() override;
  void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const override;
  void RestoreSnapshot(internal::ActorSnapshot const& snapshot) override;

  /// Link i's definition from its params, checked (Create); false and the
  /// error naming the field otherwise. Leaves l.dofStart to the caller.
  static bool LinkFromParams(int i, ArticulatedLinkParams const& p, Link& l, Error& error);
  void ComputeKinematics(DynamicArray<JointState> const& joints, Kinematics& k, bool withMotion = true) const;
  /// k.motion from k's poses
  void ComputeMotion(Kinematics& k) const;
  /// kinematics_ for state_.joints, computed only where the joints changed
  /// since the last call (the line search's accepted energy and the next
  /// assembly share one pass)
  void UpdateKinematics(bool withMotion = true) const;
  /// Link i's spatial velocity (ω; v at the origin): its parent's
  /// (`parentVelocity`, zero for a root) plus its joint's DoFs' world motion
  /// (kinematics_, with motion) times state_.jointVelocity.
  Eigen::Matrix<real, 6, 1> LinkVelocity(int i, Eigen::Matrix<real, 6, 1> const& parentVelocity) const;
  /// One link's pose from its parent's (the world's for the root) and its
  /// joint's state; its DoFs' world motion (ω; v_O) into `motion` (one
  /// column per DoF of the joint).
  struct LinkPose {
    Real3 linkPosition, jointOrigin;
    Quat linkRotation, preRotation, postRotation;
  };
  void PoseLink(int link, JointState const& q, Real3 const& parentPosition, Quat const& parentRotation,
                LinkPose& pose) const;
  /// Joint `link`'s DoF columns (ω; v_O) of the world motion, from its pose
  void JointMotion(int link, Quat const& preRotation, Quat const& postRotation, Real3 const& jointOrigin,
                   Eigen::Ref<Eigen::Matrix<real, 6, Eigen::Dynamic>> motion) const;
  /// q ⊖ q⁰ of joint `link` in its increment coordinates (spherical/free
  /// rotations: Log(R⁰ᵀ R), local), written at out[0..numDofs).
  void JointDifference(int link, JointState const& q, JointState const& q0, real* out) const;
  /// q ← saved ⊕ α d, d the actor's local increment (numDofs entries).
  void ApplyLocalIncrement(real const* d, real alpha);
  /// Joint `link`'s state q ⊕ α x, x its DoFs' increment.
  JointState Advance(int link, JointState const& q, real const* x, real alpha) const;

  // definition (immutable after creation)
  DynamicArray<Link> links_;
  ArticulatedBlockSolve blockSolve_ = ArticulatedBlockSolve::Tree;
  bool extrapolateFirstIterate_ = true;
  mutable real energyRoundOffScale_ = 0;  ///< of the last Energy
  DynamicArray<int> linkParent_, linkDofStart_, linkNumDofs_;  ///< links_' fields, for the tree solver
  DynamicArray<int> dofLink_;  ///< the link whose joint holds each DoF

  State state_;
  // stage scratch, sized at creation
  internal::StageCoefficients stage_;
  Real3 gravity_ = Real3::Zero();
  DynamicArray<internal::RigidInertiaStage> inertia_;
  DynamicArray<JointState> stageStart_, saved_;
  VectorX jointTarget_;  ///< Δ̂q, the reduced prediction (armature)
  VectorX firstIterate_;  ///< Newton's first iterate, as a local increment
  mutable Kinematics kinematics_;
  mutable DynamicArray<JointState> kinematicsJoints_;  ///< the joints kinematics_ was computed for
  /// the dense block (sized by SizeDenseBlock: at creation for Dense, at
  /// the first dense assembly for Tree)
  mutable MatrixX hessian_;
  mutable VectorX gradient_;  ///< of AddGradientAndHessian, over the actor's DoFs
  // the projected Hessian's modified factorization (sized at creation)
  mutable Eigen::LDLT<MatrixX> modifiedFactor_;
  mutable VectorX modifiedColumn_;
  mutable DynamicArray<int> modifiedOrder_;
  /// kinematics_ and composite_: the links' world poses and the composite
  /// spatial inertias of their subtrees about the origin (CRBA's first pass).
  void ComputeCompositeInertias() const;
  /// hessian_ ← Pᵀ L |D|₊ Lᵀ P from its pivoted LDLᵀ Pᵀ L D Lᵀ P (a
  /// modified Cholesky: equal where positive definite).
  void ModifyHessianToPositiveDefinite() const;
  /// The link wrenches and spatial stiffnesses at the current iterate, about
  /// each link's joint origin: own_ (each link's Y term) and, summed over
  /// subtrees, composite_ (Y_c) and the wrench sums; jointBlocks_ (each
  /// joint's E_c = H_cc − sym(S_cᵀ Y_c S_c), the joint-space terms included)
  /// and gradient_.
  void ComputeGradientAndTreeTerms(internal::HessianAssembler const& assembler, bool projectHessian) const;
  /// A constraint taken into the tree (FoldConstraint): on the link,
  /// which of its actor slots the link is; where it couples the link with
  /// another body, that body's DoFs' places in couplingDofs_ and the coupled
  /// link (coupledLinks_) it adds to.
  struct FoldedConstraint {
    internal::LinkTerm* term = nullptr;
    int coupledLink = -1;
    DynamicArray<int> couplingIndex;
  };
  /// A link coupled with other bodies: its path's DoFs (local), and at the
  /// last assembly the link frame's Jacobian B over them ((δt; δθ) rows, as
  /// internal::LinkPath) and the coupling W = H_lo, 6 × couplingDofs_, over
  /// the link frame's increments: the scene's Hessian holds Cᵀ = Σ Bᵀ W
  /// between the tree's DoFs and the other bodies'. The couplings' H_ll about
  /// the link's joint origin (`stiffness`) joins own_ only in
  /// FactorizeOwnBlock (`ownWithout`: own_ without it).
  struct CoupledLink {
    int link = -1;
    DynamicArray<int> dofs;
    Eigen::Matrix<real, 6, Eigen::Dynamic> jacobian, coupling;
    Eigen::Matrix<real, 6, 6> stiffness = Eigen::Matrix<real, 6, 6>::Zero();
    Eigen::Matrix<real, 6, 6> ownWithout = Eigen::Matrix<real, 6, 6>::Zero();
  };
  /// own_ at the coupled links with (or without) their couplings' stiffness.
  void JoinCouplingStiffness(bool join);
  /// A folded constraint's terms: Jᵀ f into gradient_ (and couplingGradient_),
  /// its stiffness at its link into own_, its curvature wrench into own_ and
  /// the subtree sums along the link's path (before the joints' blocks E_c
  /// are formed); a coupling's H_lo into its link's W, H_oo into
  /// couplingHessian_.
  void AddFoldedConstraint(FoldedConstraint const& folded, bool projectHessian) const;
  /// The Schur complement's term C A⁻¹ Cᵀ = Σ_ℓ Σ_ℓ' W_ℓᵀ B_ℓ A⁻¹ B_ℓ'ᵀ W_ℓ'
  /// into schurTerm_, with the last tree factorization: six tree solves per
  /// coupled link.
  void ComputeSchurTerm();
  /// treeSolution_ ← A⁻¹ treeRhs_ with the last tree factorization.
  void SolveTree();
  /// B_ℓ treeSolution_: the coupled link frame's increments (δt; δθ).
  Eigen::Matrix<real, 6, 1> LinkMotion(CoupledLink const& coupled) const;
  internal::ArticulatedTreeSolver::System TreeSystem() const;
  void SizeDenseBlock() const;
  mutable DynamicArray<Eigen::Matrix<real, 6, 6>> own_, jointBlocks_;
  /// each link's w·M about its joint origin, for a projected tree factorization
  DynamicArray<Eigen::Matrix<real, 6, 6>> linkMetric_;
  /// The DoFs' motion about their joint's origin o_i, and o_i − o_parent,
  /// of the last ComputeGradientAndTreeTerms (what treeSolver_ factorized:
  /// the line search's energies move kinematics_, not these)
  mutable Eigen::Matrix<real, 6, Eigen::Dynamic> localMotion_;
  mutable DynamicArray<Real3> shift_;
  internal::ArticulatedTreeSolver treeSolver_;
  /// single-body constraints on links taken into the tree (FoldConstraint),
  /// their workspace (sized when folded) and the scene's constraint Hessian
  DynamicArray<FoldedConstraint> folded_;
  mutable internal::TermWorkspace foldedWorkspace_;
  /// per DoF: the folded constraints' link-frame curvature by column norms
  /// (projected), added to the joints' diagonal blocks
  mutable VectorX foldedDiagonal_;
  // couplings with other bodies (a Schur complement of the tree's block;
  // sized at FoldConstraint, at pattern builds)
  mutable DynamicArray<CoupledLink> coupledLinks_;
  DynamicArray<int> couplingDofs_;  ///< the other bodies' DoFs (global), one contributor
  int numCoupled_ = 0;
  mutable VectorX couplingGradient_;   ///< over couplingDofs_
  mutable MatrixX couplingHessian_;    ///< H_oo, over couplingDofs_
  MatrixX schurTerm_;                  ///< C A⁻¹ Cᵀ
  Eigen::Matrix<real, Eigen::Dynamic, 6> schurColumns_;  ///< Σ_ℓ W_ℓᵀ B_ℓ A⁻¹ B_ℓ'ᵀ for one ℓ'
  VectorX treeRhs_, treeSolution_;     ///< over the actor's DoFs
  /// the tree's pivot modifications without the couplings' stiffness, per joint
  DynamicArray<Eigen::Matrix<real, 6, 6>> pivotChanges_;
  int foldedMaxDimension_ = 1, foldedMaxDofs_ = 1;
  long modifiedTreeFactorizations_ = 0;
  long gaussNewtonTreeFactorizations_ = 0;
  mutable DynamicArray<Eigen::Matrix<real, 6, 6>> composite_;
  mutable DynamicArray<Real3> wrenchForce_, wrenchMoment_, torqueSum_;
  mutable DynamicArray<Real33> forceMoment_;
};

}  // namespace superdex
