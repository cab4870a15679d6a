// Scene: owns actors and constraints and steps them (docs/architecture.md,
// "One step, through the code").
//
//   Scene::Step → integrator builds the stage → NewtonSolver over the stage's
//   terms (every actor, the constraints): assembly fills values into the
//   cached pattern → linear solver → line search → commit.
//
// A step is transactional: if any stage fails, every actor (and constraint
// state) is restored exactly to its pre-step state and Step returns false
// with an Error naming the stage, the Newton iteration and the cause. With
// SceneParams::substeps (off by default) a failed step first retries itself
// from that exact state as 2, 4, ... sub-steps.
#pragma once

#include <functional>
#include <memory>
#include <type_traits>

#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/deformable_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/constraints/constraint.h>
#include <superdex/constraints/constraint_set.h>
#include <superdex/constraints/constraint_type_headers.h>  // generated from constraint_types.h
#include <superdex/constraints/constraint_validation.h>
#include <superdex/contact/contact_system.h>
#include <superdex/core/error.h>
#include <superdex/core/slot_map.h>
#include <superdex/scene/scene_params.h>

namespace superdex {

class Scene;
namespace internal {
class NewtonSolver;
struct FaultInjection;
struct ActorSnapshot;
/// Test hook: injects a linear-solver failure (see FaultInjection).
void SetFaultInjectionForTesting(Scene& scene, FaultInjection const& fault);
/// Adds a term of the stage's potential that is neither an actor nor a
/// constraint (stage/stage_term.h; a contact set is one), after the
/// constraints; it must outlive the scene's steps. A topology change: the
/// next step analyses the pattern again.
void AttachStageTerm(Scene& scene, StageTerm& term);
/// Calls a ForEach callback with `object` as T& or, when it takes that, T*.
template <class T, class Fn>
void CallVisitor(Fn& fn, T& object) {
  if constexpr (std::is_invocable_v<Fn&, T&>) {
    fn(object);
  } else {
    static_assert(std::is_invocable_v<Fn&, T*>, "the callback must take T& or T*");
    fn(&object);
  }
}
}  // namespace internal

class Scene : private internal::ActorLookup {
 public:
  /// Validates `params` (finite gravity, positive Newton settings, a
  /// compiled-in linear solver, maxSubsteps a power of two); nullptr and
  /// `error` on bad input.
  static std::unique_ptr<Scene> Create(SceneParams const& params, Error& error);
  ~Scene();
  Scene(Scene const&) = delete;
  Scene& operator=(Scene const&) = delete;

  // ---- actors ----
  RigidActor* CreateRigidActor(RigidActorParams const& params, Error& error);
  DeformableActor* CreateDeformableActor(DeformableActorParams const& params, Error& error);
  RodActor* CreateRodActor(RodActorParams const& params, Error& error);
  ArticulatedActor* CreateArticulatedActor(ArticulatedActorParams const& params, Error& error);
  /// The actor, or nullptr for a null or stale handle.
  Actor* GetActor(ActorHandle handle) const;
  /// Destroys the actor and every constraint that references it.
  bool DestroyActor(ActorHandle handle, Error& error);
  /// Calls fn(Actor&) or fn(Actor*) on every live actor, in creation order.
  /// fn may create, destroy and step: the actors visited are those alive
  /// when the call began and still alive when their turn comes (an actor
  /// destroyed by an earlier callback is skipped, one created is not
  /// visited); docs/lifetime.md.
  template <class Fn>
  void ForEachActor(Fn&& fn) const {
    VisitActors([&fn](Actor& actor) { internal::CallVisitor(fn, actor); });
  }
  int GetNumActors() const { return static_cast<int>(actorOrder_.size()); }

  // ---- constraints ----
  // The deformable types accept deformable and rod actors alike (a rod node's
  // first 3 DoFs are its displacement). Each factory validates its params (live rigid actors, distinct for two-
  // actor types; finite vectors; unit quaternions; stiffness and damping
  // finite and >= 0; finite saturation; ordered limits) and returns nullptr
  // with an Error naming the field on bad input.
  // One factory per type of constraints/constraint_types.h:
  //   Constraint* Create<Name>Constraint(<Name>ConstraintParams const& params, Error& error);
  // (CreateRigidSphericalJointConstraint, CreateDeformableNodePositionConstraint, ...).
#define SUPERDEX_CONSTRAINT_FACTORY(Name, Class, file) \
  Constraint* Create##Name##Constraint(Name##ConstraintParams const& params, Error& error);
  SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_CONSTRAINT_FACTORY)
#undef SUPERDEX_CONSTRAINT_FACTORY
  /// The constraint, or nullptr for a null or stale handle.
  Constraint* GetConstraint(ConstraintHandle handle) const;
  /// Calls fn(Constraint&) or fn(Constraint*) on every live constraint, in
  /// creation order, with the rules of ForEachActor.
  template <class Fn>
  void ForEachConstraint(Fn&& fn) const {
    VisitConstraints([&fn](Constraint& c) { internal::CallVisitor(fn, c); });
  }
  /// Destroys a live constraint of this scene. The handle overload is the
  /// safe one: a stale or foreign handle is always refused. A pointer is
  /// looked up among this scene's live constraints and never dereferenced;
  /// one to a constraint destroyed in the last kPointerQuarantine
  /// destructions is refused as destroyed (its memory is not reused until
  /// then), an older one may name a new constraint at the same address
  /// (docs/lifetime.md).
  bool DestroyConstraint(Constraint* constraint, Error& error);
  bool DestroyConstraint(ConstraintHandle handle, Error& error);
  /// The reference page's forms without an Error: false on failure.
  bool DestroyConstraint(Constraint* constraint);
  bool DestroyConstraint(ConstraintHandle handle);
  /// How many destroyed constraints keep their memory, so that a pointer to
  /// one of them is recognised (DestroyConstraint(Constraint*)).
  static constexpr int kPointerQuarantine = 64;
  int GetNumConstraints() const { return static_cast<int>(constraintOrder_.size()); }

  // ---- contact (docs/contact.md) ----
  /// A collider on an actor (a rigid actor's shape, a deformable or rod
  /// actor's Surface) or, with a null actor, a static obstacle. Validates the
  /// shape (finite values, positive sizes, non-degenerate triangles) and
  /// refuses a collider that starts intersecting another one it may touch;
  /// nullptr and an Error naming the field (or both colliders) on bad input.
  Collider* CreateCollider(ColliderParams const& params, Error& error);
  int GetNumColliders() const { return contact_.GetNumColliders(); }
  /// The collider of that id, or nullptr (never created, or destroyed with its actor).
  Collider const* GetCollider(int id) const { return contact_.GetCollider(id); }
  /// A collider to move (a static obstacle's Collider::SetTransform,
  /// SetTargetTransform), or nullptr.
  Collider* GetCollider(int id) { return contact_.GetCollider(id); }
  /// The contacts closer than the activation distance at the last step's end.
  void GetContacts(DynamicArray<ContactInfo>& contacts) const { contact_.GetContacts(contacts); }

  // ---- stepping ----
  /// Advances by dt (finite, > 0). Transactional: on failure nothing changes.
  /// With SubstepParams::maxSubsteps > 1, a failed step is retried from the
  /// exact pre-step state as 2, 4, ... sub-steps of dt/2, dt/4, ... (up to
  /// the cap) before it fails; the error then is the last attempt's, naming
  /// its sub-step. GetTime advances by exactly dt either way. A scene
  /// without actors only advances its time.
  bool Step(real dt, Error& error);
  /// Sets the sub-stepping policy between steps (maxSubsteps a power of two
  /// >= 1; 1 turns it off). On invalid input nothing changes.
  bool SetSubstepParams(SubstepParams const& substeps, Error& error);
  /// Threads of the assembly (SceneParams::numThreads): 0 = every CPU this
  /// process may use. Results do not depend on it. InvalidArgument below 0.
  bool SetNumThreads(int numThreads, Error& error);
  /// The threads the assembly runs on (0 resolved to the CPU count).
  int GetNumThreads() const;
  /// Switches the linear solver between steps; the new backend analyzes the
  /// cached pattern at the next step. `pcg` configures PetscPcg (validated
  /// even when another type is chosen). On failure nothing changes.
  bool SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error);
  /// Keeps the current PcgParams.
  bool SetLinearSolver(LinearSolverType type, Error& error) {
    return SetLinearSolver(type, params_.pcg, error);
  }

  real GetTime() const { return time_; }
  /// The number stamped on this scene's handles (Handle::scene), unique in
  /// the process; a handle of another scene is refused with InvalidHandle.
  std::uint32_t GetId() const { return id_; }
  SceneParams const& GetParams() const { return params_; }
  SceneStats const& GetStats() const { return stats_; }
  /// Total DoFs of all actors.
  int GetNumDofs() const;

 private:
  explicit Scene(SceneParams const& params);
  friend void internal::SetFaultInjectionForTesting(Scene&, internal::FaultInjection const&);
  friend void internal::AttachStageTerm(Scene&, internal::StageTerm&);

  void VisitActors(std::function<void(Actor&)> const& fn) const;
  void VisitConstraints(std::function<void(Constraint&)> const& fn) const;
  /// Removes a live constraint and keeps its memory in the quarantine.
  void RemoveConstraint(Constraint* constraint);

  ActorHandle AddActor(std::unique_ptr<Actor> actor);
  Constraint* AddConstraint(std::unique_ptr<Constraint> constraint);
  // internal::ActorLookup: the constraint types' Create look the actors up here
  Actor* FindActor(ActorHandle handle) const override { return actors_.Get(handle); }
  std::string WhyNotFound(ActorHandle handle) const override;
  void OnTopologyChanged();
  /// One attempt at a step of dt as `substeps` equal sub-steps from the
  /// current (pre-step) state; on failure `failedSubstep` is the 1-based
  /// sub-step that failed and the scene is left at some iterate.
  /// Across ranks: false on every rank, with InvalidArgument, where the
  /// ranks step with different arguments or settings (one reduction).
  bool CheckRanksAgree(real dt, Error& error);
  bool AdvanceSubsteps(real dt, int substeps, real& historyStep, int& failedSubstep, Error& error);
  /// Puts back the actors and the old targets saved at the step start.
  void RestorePreStepState();
  /// Saves (`save`) or restores the constraint targets and forces, which a
  /// sub-stepped attempt changes (interpolated targets; a sub-step's forces).
  void SaveOrRestoreSubstepState(bool save);
  /// Sets each target of sub-step `index` (1-based) of `substeps`: the
  /// point at index/substeps on the way from the old target (the step
  /// start's) to the target the caller set, which is the last sub-step's.
  void SetSubstepTargets(int index, int substeps);

  std::uint32_t const id_;  ///< stamped on every handle this scene issues
  SceneParams params_;
  internal::SlotMap<Actor, ActorTag> actors_;
  internal::SlotMap<Constraint, ConstraintTag> constraints_;
  DynamicArray<Actor*> actorOrder_;            ///< creation order = DoF order
  DynamicArray<Constraint*> constraintOrder_;  ///< creation order = contributor order
  /// the last kPointerQuarantine destroyed constraints (a ring), so that
  /// their addresses are not reused while a stale pointer is most likely
  DynamicArray<std::unique_ptr<Constraint>> quarantine_;
  int quarantineNext_ = 0;
  bool topologyChanged_ = true;
  std::unique_ptr<internal::NewtonSolver> solver_;
  /// the constraints as one term of the stage (in constraintOrder_)
  internal::ConstraintSet constraintTerm_;
  /// terms attached after the constraints (AttachStageTerm)
  DynamicArray<internal::StageTerm*> attachedTerms_;
  internal::ContactSystem contact_;
  SceneStats stats_;
  real time_ = 0;
  /// Step size over which the actors' integrator history was recorded (the
  /// last committed stage's duration; 0 before the first step).
  real historyStep_ = 0;
  // pre-step copies for transactional steps (reused across steps)
  DynamicArray<std::unique_ptr<internal::ActorSnapshot>> actorSnapshots_;
  DynamicArray<Constraint::Target> constraintSnapshots_;
  // what a sub-stepped attempt changes besides (sized on the first retry)
  DynamicArray<Constraint::Target> targetSnapshots_;
  DynamicArray<DynamicArray<real>> forceSnapshots_;
  DynamicArray<char> forceValidSnapshots_;
};

}  // namespace superdex
