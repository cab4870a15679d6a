// Actor: an owner of a contiguous range of generalized DoFs in the scene's
// configuration (docs/architecture.md, "Degrees of freedom"). The public part
// is identity and introspection; the Newton solver drives the dynamics
// through the stage contract (stage/stage_term.h), which every kind of actor
// implements.
#pragma once

#include <memory>

#include <superdex/assembly/owned_contributors.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>
#include <superdex/stage/stage_term.h>

namespace superdex {

class Scene;

enum class ActorType { Rigid, Deformable, Rod, Articulated };

std::string_view ToString(ActorType type);

namespace internal {

/// Opaque copy of an actor's complete dynamic state (configuration,
/// velocities, integrator history), for transactional steps.
struct ActorSnapshot {
  virtual ~ActorSnapshot() = default;
};

/// The snapshot of an actor whose whole dynamic state is one copyable State.
template <class State>
struct StateSnapshot final : ActorSnapshot {
  State state;
};

/// Copies `state` into `snapshot`, allocating it on first use only.
template <class State>
void SaveStateSnapshot(State const& state, std::unique_ptr<ActorSnapshot>& snapshot) {
  auto* own = dynamic_cast<StateSnapshot<State>*>(snapshot.get());
  if (!own) {
    snapshot = std::make_unique<StateSnapshot<State>>();
    own = static_cast<StateSnapshot<State>*>(snapshot.get());
  }
  own->state = state;
}

template <class State>
void RestoreStateSnapshot(ActorSnapshot const& snapshot, State& state) {
  state = static_cast<StateSnapshot<State> const&>(snapshot).state;
}
}  // namespace internal

class Actor : protected internal::StageTerm, protected internal::StageDofs {
 public:
  ~Actor() override = default;
  Actor(Actor const&) = delete;
  Actor& operator=(Actor const&) = delete;

  ActorHandle GetHandle() const { return handle_; }
  ActorType GetType() const { return type_; }
  /// Number of generalized DoFs (6 for a rigid body).
  int GetNumDofs() const final { return numDofs_; }
  /// First global DoF index of this actor; its DoFs are [offset, offset + n).
  /// Global indices change when actors created before it are destroyed.
  int GetDofOffset() const final { return dofOffset_; }

  /// Internal: the actor as a term of the stage's incremental potential (its
  /// inertia, gravity and elastic energy) and as the owner of its DoFs, as
  /// the Newton solver drives it (stage/stage_term.h). Not part of the API.
  internal::StageTerm& GetStageTerm() { return *this; }
  internal::StageTerm const& GetStageTerm() const { return *this; }
  internal::StageDofs& GetStageDofs() { return *this; }
  internal::StageDofs const& GetStageDofs() const { return *this; }

 protected:
  Actor(ActorType type, int numDofs) : type_(type), numDofs_(numDofs) {}

  // The stage contract (stage/stage_term.h), implemented by each kind of
  // actor; the scene sets the handle and DoF offset and takes the snapshots.
  friend class Scene;

  /// The default writes 1 (every DoF a displacement or a joint coordinate).
  void WriteDofLengthScales(Span<real> scales) const override;
  /// Adds Energy(owned) with EnergyRoundOffScale() to the sum.
  void AddEnergy(internal::HessianAssembler const& assembler, int firstContributor,
                 internal::EnergySum& sum) const final;
  /// Inertia + gravity (+ internal elastic) energy at the current iterate,
  /// of the contributors `owned` says this process counts (in
  /// AppendContributorDofs's order): the whole energy when it is empty.
  virtual real Energy(internal::OwnedContributors owned) const = 0;
  /// The magnitude the round-off of the last Energy scales with beyond |E|
  /// itself (energy units; eps times it bounds that round-off): an energy
  /// made of differences of poses, or of terms that cancel, resolves
  /// changes far coarser than eps |E|. 0: |E| is the scale.
  virtual real EnergyRoundOffScale() const { return 0; }

  /// Copies the complete dynamic state into `snapshot` (allocated on first
  /// use, reused afterwards); RestoreSnapshot puts it back bit for bit
  /// (transactional steps, Scene::Step).
  virtual void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const = 0;
  virtual void RestoreSnapshot(internal::ActorSnapshot const& snapshot) = 0;

  ActorHandle handle_;
  ActorType type_;
  int numDofs_;
  int dofOffset_ = 0;
};

}  // namespace superdex
