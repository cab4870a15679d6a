// ContactSystem: the colliders of a scene and their contacts, as one term of
// every stage's incremental potential (stage/stage_term.h; docs/contact.md).
//
// Per stage (BeginStage) it finds the candidate pairs of primitives that can
// come within d̂ during the stage — pairs closer than d̂ plus the stage's
// displacement bound of their bodies' vertices — and lags each one's normal
// force λ and tangent basis for friction. The candidates are the term's
// changing contributors (HessianAssembler's second family): one per pair,
// over the DoFs of the body it moves. Per Newton iteration it prices the
// barrier and the friction of every candidate; the line search's safe step
// (LargestSafeStep) is continuous collision detection of every candidate
// along the step and the displacement bound of every vertex, so the
// candidate set stays complete and no trial passes one surface through
// another. At the stage end it moves each sliding contact's stick anchor.
//
// Contacts: bodies (rigid actors' and articulated links' shapes, the
// surfaces of deformable and rod actors) against static obstacles and
// against each other, and a deformable or rod actor against itself. A link
// moves with its path's joints: its contacts act on those DoFs through the
// link frame's Jacobian (stage/link_path.h), and the links of one actor do
// not touch each other. A contact with an obstacle touches only its body's own DoF block, so
// the analysed pattern always fits; one between two bodies joins their
// blocks (the pattern grows in its kept order).
//
// Its loops over pairs (the candidate search's tree queries and filtering,
// lagged friction, energies, assembly, CCD) run on the stage's threads
// (StageContext::executor), each pair's result in its own slot and anything
// summed summed in pair order: bit-identical for any thread count
// (docs/contact.md, "Threads").
#pragma once

#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <utility>

#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/contact/collider.h>
#include <superdex/contact/barrier.h>
#include <superdex/contact/bvh.h>
#include <superdex/contact/ccd.h>
#include <superdex/contact/contact_params.h>
#include <superdex/contact/distance.h>
#include <superdex/stage/stage_term.h>

namespace superdex {

namespace internal {
class ContactSystem;
}

/// The most joint DoFs a link collider's link may move with (its path from
/// the root): a contact's block is at most two of them.
inline constexpr int kMaxLinkPathDofs = 24;

/// One active contact of the last step (Scene::GetContacts).
struct ContactInfo {
  int colliderA = -1, colliderB = -1;  ///< collider ids (B: the obstacle)
  Real3 point = Real3::Zero();         ///< closest point on B [m]
  Real3 normal = Real3::Zero();        ///< from B towards A (unit)
  real distance = 0;                   ///< gap d [m]
  real normalForce = 0;                ///< on A along normal [N]
  Real3 frictionForce = Real3::Zero(); ///< on A [N]
};

/// A collider as the user sees it; created by Scene::CreateCollider.
class Collider {
 public:
  int GetId() const { return id_; }
  ShapeType GetShape() const { return shape_; }
  /// The carrying actor (null for a static obstacle).
  ActorHandle GetActor() const { return actor_; }
  real GetFriction() const { return friction_; }
  int GetNumVertices() const { return static_cast<int>(local_.size()); }
  int GetNumTriangles() const { return static_cast<int>(triangles_.size()); }
  /// Carried by an actor (a body), not a static obstacle.
  bool Moves() const { return rigid_ != nullptr || nodal_ != nullptr || articulated_ != nullptr; }
  /// The link of an articulated actor carrying it (−1: none).
  int GetLink() const { return path_.link; }
  std::uint32_t GetGroup() const { return group_; }
  std::uint32_t GetMask() const { return mask_; }
  /// Whether this collider and `other` may touch (docs/contact.md,
  /// "Filtering"): not two static obstacles; not two colliders of one actor,
  /// except links of one articulated actor that are neither the same link
  /// nor parent and child (a mechanism's self contact); a collider with
  /// itself only as a Surface whose group is in its mask (self contact); and
  /// each one's group in the other's mask.
  bool MayTouch(Collider const& other) const;

  /// The shape as primitives, each thickened by GetThickness(): its
  /// vertices in the world at the carrying actor's current state (a rigid
  /// actor's pose, a deformable or rod actor's nodes: vertex i is node i),
  /// the edges and triangles between them, and its points — vertices on no
  /// edge that touch as spheres (a Sphere's centre; a solid's interior nodes
  /// are vertices but no points). A Plane has no vertices: its half-space
  /// n·x <= c (GetPlaneNormal, GetPlaneOffset) is inside.
  void GetWorldVertices(DynamicArray<Real3>& vertices) const;
  DynamicArray<std::array<int, 2>> const& GetEdges() const { return edges_; }
  DynamicArray<std::array<int, 3>> const& GetTriangles() const { return triangles_; }
  bool IsPoint(int vertex) const { return freeVertex_[vertex] && vertexArea_[vertex] > 0; }
  /// The thickness around every primitive [m]: a Sphere's, Capsule's or
  /// rod's radius, otherwise ColliderParams::thickness.
  real GetThickness() const { return thickness_; }
  Real3 GetPlaneNormal() const { return planeNormal_; }
  real GetPlaneOffset() const { return planeOffset_; }

  /// The pose of the shape's frame (ColliderParams::position, rotation):
  /// local to its actor, or a static obstacle's in the world, now.
  Real3 GetPosition() const { return now_.position; }
  Quat GetRotation() const { return now_.rotation; }
  /// Moves a static obstacle to `position`, `rotation` at once (a teleport:
  /// no bodies are pushed). InvalidArgument, naming the field, for a
  /// collider carried by an actor (move the actor) or a bad pose, and,
  /// naming both colliders and where, when the obstacle would then intersect
  /// a body; nothing changes then. Cancels a pending SetTargetTransform.
  bool SetTransform(Real3 const& position, Quat const& rotation, Error& error);
  /// Moves a static obstacle kinematically over the next Scene::Step: from
  /// its pose at the step start to this one, the position linearly in time
  /// and the rotation along the shortest arc (substeps take their share). It
  /// is infinitely heavy: bodies in its way are pushed through the barrier,
  /// never passed through. The pose holds after the step; a failed step
  /// leaves the target pending. InvalidArgument as SetTransform for a body's
  /// collider or a bad pose.
  bool SetTargetTransform(Real3 const& position, Quat const& rotation, Error& error);

 private:
  /// A vertex as the contact system reads it
  struct Vertex {
    Real3 local = Real3::Zero();  ///< body or link frame (rigid, link) or world (static, at creation)
    int node = -1;                ///< node index (Surface)
  };
  struct Pose {
    Real3 position = Real3::Zero();
    Quat rotation = Quat::Identity();
    bool operator==(Pose const& o) const {
      return position == o.position && rotation.coeffs() == o.rotation.coeffs();
    }
  };
  /// The pose a fraction f of the way from a to b.
  static Pose Interpolate(Pose const& a, Pose const& b, real f) {
    return {a.position + f * (b.position - a.position), a.rotation.slerp(f, b.rotation)};
  }
  /// A static obstacle's vertex at pose `p` (its creation-time vertex while
  /// it has never moved, bit for bit).
  Real3 PlaceVertex(int i, Pose const& p) const {
    return p == created_ ? local_[i].local : Real3(p.position + p.rotation * shapeVertices_[i]);
  }
  /// Moves a static obstacle's pose (and a Plane's normal and offset) to `p`.
  void Place(Pose const& p);
  friend class internal::ContactSystem;
  Collider() = default;

  int id_ = -1;
  ShapeType shape_ = ShapeType::Surface;
  ActorHandle actor_;
  real friction_ = 0;
  real thickness_ = 0;
  std::uint32_t group_ = 1, mask_ = 0xffffffffu;
  // the carrying body (none: static)
  RigidActor* rigid_ = nullptr;
  NodalActor* nodal_ = nullptr;
  ArticulatedActor* articulated_ = nullptr;
  /// a link's path, its frame at the current iterate (ContactSystem::UpdatePositions)
  mutable internal::LinkPath path_;
  /// Moves as one rigid frame (a rigid actor or a link): its vertices are
  /// fixed in it
  bool IsRigid() const { return rigid_ != nullptr || articulated_ != nullptr; }
  /// That frame's origin and rotation at the current iterate (a rigid
  /// actor's centre of mass, a link's frame)
  Real3 FramePosition() const { return rigid_ ? rigid_->GetPosition() : path_.position; }
  Quat FrameRotation() const { return rigid_ ? rigid_->GetRotation() : path_.rotation; }
  /// Its DoFs: a rigid actor's 6 (δt, δθ), a link's path DoFs
  int NumFrameDofs() const { return rigid_ ? 6 : static_cast<int>(path_.dofs.size()); }
  int FrameDof(int k) const { return rigid_ ? rigid_->GetDofOffset() + k : articulated_->GetDofOffset() + path_.dofs[k]; }
  // Plane: world normal and the offset c of n·x = c
  Real3 planeNormal_ = Real3::Zero();
  real planeOffset_ = 0;
  DynamicArray<Vertex> local_;
  DynamicArray<std::array<int, 2>> edges_;
  DynamicArray<std::array<int, 3>> triangles_;
  DynamicArray<char> freeVertex_, freeEdge_;  ///< on no edge / on no triangle
  DynamicArray<real> vertexArea_, edgeArea_;  ///< area each stands for [m²]
  // a static obstacle's motion: its poses at creation, at the step start,
  // the step's target and now; its vertices and plane normal in its frame
  internal::ContactSystem* system_ = nullptr;
  Pose created_, start_, target_, now_;
  Pose stageStart_, stageTarget_;  ///< this stage's share of the step's motion
  std::uint64_t poseVersion_ = 0;  ///< counts changes of now_
  DynamicArray<Real3> shapeVertices_;
  Real3 shapeNormal_ = Real3::Zero();
};

namespace internal {

class ContactSystem final : public StageTerm {
 public:
  explicit ContactSystem(ContactParams const& params) : params_(params) {}

  /// Validates and adds a collider; `rigid` / `nodal` / `articulated` the
  /// carrying actor (all null: static). nullptr and an InvalidArgument naming
  /// the field on bad input, nothing added.
  Collider* Add(ColliderParams const& params, RigidActor* rigid, NodalActor* nodal, ArticulatedActor* articulated,
                Error& error);
  /// Removes every collider of `actor` (an actor being destroyed).
  void RemoveActor(ActorHandle actor);
  /// On a scene across `ranks` MPI ranks (> 1): only contact with static and
  /// kinematic obstacles, whose pairs touch one body's block of the analysed
  /// pattern (docs/distributed.md, "Contact across ranks"); Add refuses a
  /// collider that may touch another body or itself (NotSupported).
  void SetObstacleContactOnly(int ranks) { obstacleOnlyRanks_ = ranks; }
  bool Empty() const { return colliders_.empty(); }
  int GetNumColliders() const { return static_cast<int>(colliders_.size()); }
  Collider const* GetCollider(int id) const;
  Collider* GetCollider(int id) { return const_cast<Collider*>(std::as_const(*this).GetCollider(id)); }

  void GetContacts(DynamicArray<ContactInfo>& contacts) const;
  int GetNumCandidates() const { return static_cast<int>(pairs_.size()); }
  /// The seconds spent in each phase since the last ResetTimes (SceneStats'
  /// contact*Seconds).
  struct PhaseTimes {
    double broadPhase = 0, narrowPhase = 0, ccd = 0, assembly = 0;
  };
  PhaseTimes const& GetTimes() const { return times_; }
  void ResetTimes() { times_ = {}; }
  int GetNumActive() const { return active_; }
  real GetMinDistance() const { return minDistance_; }

  /// Friction anchors committed by the last EndStage, for transactional
  /// steps; RestoreState also returns the kinematic obstacles to their poses
  /// at the step start (their targets stay pending).
  void SaveState() { savedAnchors_ = anchors_; }
  void RestoreState();
  /// The part of the step the next stage covers, as fractions of the step
  /// [from, to] (substeps; 0 and 1 otherwise): kinematic obstacles move that
  /// share of their way to their targets.
  void SetStepFraction(real from, real to) {
    stepFrom_ = from;
    stepTo_ = to;
  }
  /// After a successful step: the kinematic obstacles' targets become their poses.
  void CommitStep();

  // StageTerm
  /// One contributor per link collider over its path's DoFs: the block its
  /// contacts with obstacles fill stays in the analysed pattern, and an
  /// actor whose collider's path spans several joints is solved as a dense
  /// block (its tree solve takes no contributor across joints)
  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  void AppendStageContributorDofs(StageDofLists& dofLists) const override;
  void BeginStage(StageContext const& stage) override;
  void AddEnergy(HessianAssembler const& assembler, int firstContributor, EnergySum& sum) const override;
  void AddGradientAndHessian(HessianAssembler& assembler, int firstContributor,
                             AssemblyOptions const& options) const override;
  bool BoundsSteps() const override { return !colliders_.empty(); }
  real LargestSafeStep(Span<real const> delta, real alpha) const override;
  /// Once a vertex has used 90 % of its displacement bound (or of its self
  /// bound, relative to its body's mean): the candidate pairs found again
  /// with the same bounds around the current iterate (pairs kept keep their
  /// lagged friction, and one out of reach with a normal force stays for
  /// its friction; a new pair is beyond d̂, its barrier zero). Without
  /// it Newton stalls at the bound's edge when the stage's motion outruns
  /// the bound (a cloth landing edge first: the landed edge stops while the
  /// rest falls on).
  bool RecenterStepBounds() override;
  /// Each nodal vertex's share of δ scaled to the smallest of 1, the room
  /// its displacement bound leaves and the CCD fractions of its linear
  /// candidate pairs along δ; rigid bodies' and links' DoFs unchanged.
  void LimitStepPerDof(Span<real> delta) const override;
  bool AcceptsFirstIterate() const override;
  bool AtTarget() const override { return progress_ >= 1; }
  bool AdvanceTarget(real fraction) override;
  void EndStage() override;

  enum class PairKind : std::uint8_t { PlaneVertex, PointTriangle, EdgeEdge, PointEdge, PointPoint };
  /// A candidate pair: vertices v (world positions in x_), each of side A
  /// (the collider `body`, onBody) or side B (`obstacle`: a static obstacle
  /// or a second body).
  struct Pair {
    PairKind kind = PairKind::PlaneVertex;
    int body = -1, obstacle = -1;  ///< collider indices
    std::array<int, 4> v{-1, -1, -1, -1};  ///< global vertex indices
    std::array<bool, 4> onBody{false, false, false, false};
    int numVertices = 0;
    real thickness = 0, weight = 0, mu = 0;
    real mollifierThreshold = 0;  ///< edge–edge: IPC's ε× from the stage-start lengths
    std::uint64_t key = 0;
    // lagged at the stage start
    real lambda = 0;
    Eigen::Matrix<real, 3, 2> basis = Eigen::Matrix<real, 3, 2>::Zero();
    std::array<real, 4> gamma{0, 0, 0, 0};  ///< relative displacement weights
    Real3 slip0 = Real3::Zero();            ///< anchor offset at the stage start
    Real3 contactPoint0 = Real3::Zero();    ///< the body's point at the contact, stage start
    // a rigid body at the stage start: centre, rotation, arm of the contact point
    std::array<Real3, 2> center0{Real3::Zero(), Real3::Zero()};
    std::array<Quat, 2> rotation0{Quat::Identity(), Quat::Identity()};
    std::array<Real3, 2> arm0{Real3::Zero(), Real3::Zero()};
  };

 private:
  using Vector12 = contact::LocalVector<12>;
  /// A static obstacle's primitives in bounding-volume trees (built once).
  struct ObstacleTrees {
    contact::Bvh triangles, edges, vertices;
    std::uint64_t stamp = 0;  ///< a body's trees: the stage they were built for
    std::uint64_t poseVersion = 0;  ///< a static obstacle's: the pose they were built at
  };

  /// The shape's vertices (and a Plane's normal, a Box's triangles),
  /// validated; SetPrimitives then its triangles, edges and areas.
  static bool MakeShape(ColliderParams const& params, Collider& collider,
                        DynamicArray<std::array<int, 3>>& triangles, Error& error);
  bool SetPrimitives(Collider& collider, DynamicArray<std::array<int, 3>> triangles, Error& error) const;
  /// Whether collider a (side A) and b are a candidate pair of colliders:
  /// a is a body, b an obstacle or a later body of another actor, and their
  /// groups and masks let them touch.
  bool MayTouch(int a, int b) const;
  /// pairs_: every candidate pair of primitives at x_ within the bounds.
  void FindPairs();
  /// Vertex numbering and positions (x_ = x0_) of the current colliders.
  void PrepareVertices();
  friend class superdex::Collider;
  /// InvalidArgument naming both colliders where collider `index` starts at
  /// or below zero gap with another it may touch; `what` names the call.
  bool CheckSeparated(int index, std::string const& what, Error& error);
  /// InvalidArgument where an edge of collider `index` passes through a
  /// triangle of a collider it may touch, or the other way.
  bool CheckNoCrossing(int index, std::string const& what, Error& error);
  int IndexOf(Collider const& collider) const;
  /// Whether a static obstacle moves in this stage.
  static bool Sweeps(Collider const& c) { return !(c.stageStart_ == c.stageTarget_); }
  /// The farthest a moving obstacle's surface travels this stage [m] (0 with none).
  real KinematicTravel() const;
  /// displacement_ of the moving obstacles' vertices and planeShift_ over
  /// the rest of their way this stage (zero once there).
  void KinematicDisplacements() const;
  /// displacement_ of every vertex along δ (after UpdatePositions), the
  /// obstacles' kinematic travel included: LargestSafeStep's and
  /// LimitStepPerDof's start
  void StepDisplacements(Span<real const> delta) const;
  /// The first DoF of nodal collider c's vertex i (its node's x)
  int NodeDof(int c, int i) const;
  /// How far vertex i may still move within its displacement bound (>= 0)
  real BoundRoom(int i) const;
  /// A kinematic side's displacement of its material point y0 (at the
  /// stage start) since the stage start.
  static Real3 KinematicDisplacement(Collider const& c, Real3 const& y0);
  void UpdatePositions(DynamicArray<Real3>& x) const;
  ObstacleTrees const& TreesOf(int obstacleIndex);
  /// A body's trees for its self contact (this stage, inflated by its self bound).
  ObstacleTrees const& SelfTrees(int index);
  /// Whether collider c's vertices have self bounds this stage (its self
  /// contact is on: each is at least d̂).
  bool HasSelfBound(int c) const {
    return firstVertex_[c] < firstVertex_[c + 1] && vertexSelfBound_[firstVertex_[c]] > 0;
  }
  /// The box of `vertices` inflated by `margin` and their largest self bound.
  contact::Aabb SelfBox(std::initializer_list<int> vertices, real margin) const;
  /// How far a self pair's gap can close this stage: the largest self bound
  /// of each of its two sides, added.
  real SelfReach(Pair const& pair) const;
  /// The largest α' <= alpha that keeps collider c's vertices within its
  /// self bound of its mean displacement (x_ + α' displacement_).
  real SelfSafeStep(int c, real alpha) const;
  /// Appends the candidate pairs of a body and an obstacle (vertices within
  /// the body's displacement bound, d̂ and the thickness).
  void AddPairs(int body, int obstacle);
  void LagFriction(Pair& pair) const;
  /// The gap (distance less thickness; signed against a plane) at
  /// positions x, and with `gradient` its derivative w.r.t. the pair's
  /// vertices (3·numVertices of 12).
  real Gap(Pair const& pair, DynamicArray<Real3> const& x, Vector12* gradient = nullptr) const;
  /// Where a pair's vertices split into its two sides (the point and the
  /// triangle, the two edges, the point and the edge, the two points): the
  /// first vertex of the second side.
  static int SideSplit(PairKind kind) { return kind == PairKind::EdgeEdge ? 2 : 1; }
  /// A lower bound of the gap at x_ (not a PlaneVertex pair): the distance
  /// between the boxes of the pair's two sides, less the thickness.
  real BoxGap(Pair const& pair) const;
  /// As Gap with the pair's vertices at `p` (p[k]: vertex k of the pair).
  real GapAt(Pair const& pair, std::array<Real3, 4> const& p, Vector12* gradient = nullptr) const;
  /// The slip from the pair's anchor at positions x (world, not projected).
  Real3 Slip(Pair const& pair, DynamicArray<Real3> const& x) const;
  /// The barrier energy of the pair at x_ and, with `derivatives`, its
  /// gradient and Hessian w.r.t. the pair's vertex positions: exact, or
  /// with `projected` its negative eigenvalues clamped to 0 (PSD).
  contact::ValueGradientHessian<12> PairBarrier(Pair const& pair, bool derivatives, bool projected = true) const;
  /// The friction energy at positions x, its gradient and Hessian in the
  /// tangential slip u (zero without a lagged normal force).
  contact::TangentialFriction PairFriction(Pair const& pair, DynamicArray<Real3> const& x) const;
  /// A rigid side's rotation since the stage start, φ = Log(R R⁰ᵀ) (world).
  Real3 StageTurn(Pair const& pair, int side) const;
  /// Whether two of the pair's vertices are one.
  static bool SharesVertex(std::array<int, 4> const& v, int count);
  /// The gap of a self-contact pair of a nodal collider in its rest shape.
  real RestGap(int colliderIndex, PairKind kind, std::array<int, 4> const& v) const;
  /// The columns of the pair's derivatives: each side's DoFs, side A's then
  /// side B's (PairDofs' list, but for two links of one mechanism).
  int PairColumnCount(Pair const& pair) const;
  /// Whether a and b are two links of one articulated actor, whose paths
  /// share their common joints: a pair of them moves with the union of the
  /// two paths' DoFs (PairDofs' list, ascending).
  static bool LinksOfOneActor(Collider const& a, Collider const& b) {
    return a.articulated_ && a.articulated_ == b.articulated_;
  }
  /// That union's size and, in `place`, the index in it of each of a's then
  /// b's path DoFs.
  static int MergePaths(Collider const& a, Collider const& b, std::array<int, 2 * kMaxLinkPathDofs>& place);
  /// Appends that union's DoFs (the scene's indices) to `dofs`.
  static void AppendPathUnion(Collider const& a, Collider const& b, DynamicArray<int>& dofs);
  /// The safe fraction of a linear move of the pair's vertices from x by
  /// scale · displacement_ (CCD; in [0, 1]).
  real LinearPairCcd(Pair const& pair, DynamicArray<Real3> const& x, real scale) const;
  /// The safe step (≤ tMax, in units of δ) of a rigid body's step δ for one
  /// pair: conservative advancement on the vertices' arcs.
  real RigidPairCcd(Pair const& pair, Span<real const> delta, real tMax) const;
  void PairDofs(Pair const& pair, DynamicArray<int>& dofs) const;

  // ---- threads (the stage's executor; results bit-identical for any
  // number: each pair's result lands in its own slot, and what is summed is
  // summed in pair order) ----
  /// Pairs per chunk of the parallel loops over pairs and found box pairs
  static constexpr int kPairGrain = 128;
  /// Runs f(begin, end) over [0, count) on the stage's threads (serially
  /// without them).
  template <class F>
  void ForPairs(int count, F&& f) const {
    if (executor_) {
      executor_->For(count, kPairGrain, [&f](int begin, int end, int) { f(begin, end); });
    } else if (count > 0) {
      f(0, count);
    }
  }
  /// Appends to pairs_ the pairs make(k, out) appends to `out`, for k in
  /// [0, count) and in the order of k: chunks of k on the stage's threads,
  /// each into its own buffer (chunkPairs_), concatenated in chunk order.
  template <class Make>
  void AppendPairsInOrder(int count, Make&& make) {
    int const numChunks = (count + kPairGrain - 1) / kPairGrain;
    if (static_cast<int>(chunkPairs_.size()) < numChunks) chunkPairs_.resize(numChunks);
    auto const fill = [&](int begin, int end, int) {
      for (int chunk = begin; chunk < end; ++chunk) {
        DynamicArray<Pair>& out = chunkPairs_[chunk];
        out.clear();
        for (int k = chunk * kPairGrain, last = std::min(count, k + kPairGrain); k < last; ++k) make(k, out);
      }
    };
    if (executor_) {
      executor_->For(numChunks, 1, fill);
    } else {
      fill(0, numChunks, 0);
    }
    for (int chunk = 0; chunk < numChunks; ++chunk)
      pairs_.insert(pairs_.end(), chunkPairs_[chunk].begin(), chunkPairs_[chunk].end());
  }
  /// The pairs of a tree and query boxes (contact::Bvh::FindPairsWith), on
  /// the stage's threads.
  void FindBoxPairs(contact::Bvh const& tree, DynamicArray<contact::Aabb> const& boxes,
                    DynamicArray<contact::IndexPair>& found);

  ContactParams params_;
  int obstacleOnlyRanks_ = 0;  ///< SetObstacleContactOnly (0: any contact)
  DynamicArray<std::unique_ptr<Collider>> colliders_;
  int nextId_ = 0;
  DynamicArray<int> firstVertex_;        ///< every collider's vertices, concatenated
  mutable DynamicArray<Real3> x_;        ///< current positions (refreshed per evaluation)
  DynamicArray<Real3> x0_;               ///< stage start
  /// Where the bounds are centred: the stage start, or the iterate of the
  /// last RecenterStepBounds
  DynamicArray<Real3> boundCenter_;
  DynamicArray<Pair> keptPairs_;  ///< RecenterStepBounds' previous pairs (storage kept)
  DynamicArray<std::pair<std::uint64_t, int>> keptKeys_;  ///< their keys, sorted, and indices
  DynamicArray<char> keptFound_;  ///< per kept pair: found again
  DynamicArray<real> bound_;             ///< per vertex displacement bound for the stage [m]
  mutable PhaseTimes times_;
  DynamicArray<real> vertexSelfBound_;  ///< per vertex: bound relative to its body's mean (self contact) [m]
  ObstacleTrees selfTrees_;
  DynamicArray<Pair> pairs_;
  DynamicArray<std::unique_ptr<ObstacleTrees>> trees_;  ///< per collider (obstacles only)
  DynamicArray<contact::Aabb> boxScratch_, treeBoxScratch_;
  DynamicArray<Real3> sweepScratch_;
  std::uint64_t treeStamp_ = 0;
  DynamicArray<contact::IndexPair> pairScratch_;
  /// The friction anchors of the sticking and sliding contacts (pair key,
  /// slip offset), sorted by key: storage kept from stage to stage
  DynamicArray<std::pair<std::uint64_t, Real3>> anchors_, savedAnchors_;
  mutable DynamicArray<Real3> displacement_;
  ParallelExecutor const* executor_ = nullptr;  ///< the stage's threads (BeginStage)
  mutable DynamicArray<real> pairValue_;         ///< per pair: an energy or a fraction (storage kept)
  DynamicArray<DynamicArray<Pair>> chunkPairs_;  ///< AppendPairsInOrder's buffers (storage kept)
  DynamicArray<DynamicArray<contact::IndexPair>> queryChunks_;  ///< FindBoxPairs' (storage kept)
  int active_ = 0;
  real minDistance_ = 0;
  real stepFrom_ = 0, stepTo_ = 1;  ///< SetStepFraction
  /// per collider: a moving Plane's shift along its normal over the rest
  /// of its way this stage (the safe step's)
  mutable DynamicArray<real> planeShift_;
  mutable DynamicArray<real> vertexFraction_;  ///< LimitStepPerDof's per-vertex fractions (storage kept)
  real progress_ = 1;  ///< of the kinematic obstacles along this stage's move
};

}  // namespace internal
}  // namespace superdex
