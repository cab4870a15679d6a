// The contact scenes of docs/contact.md, built once for everyone who runs
// them: the tests (tests/contact: their physics at one time step, every scene
// at dt = 1/30, 1/60 and 1/120), the perf harness's contact families
// (perf/harness) and the fuzz target. Not part of the installed library: the
// builders use only its public API (<superdex/superdex.h>).
//
// Every builder reports a failure as the library does: the scene is null and
// `error` says which call failed and why. Builder chains the calls: after
// its first failure every call does nothing and returns null, so a scene is
// written without a check after each line.
#pragma once

#include <array>
#include <functional>
#include <memory>

#include <superdex/superdex.h>

namespace superdex::scenes {

inline constexpr real kGravity = 9.81;

/// Adds actors, colliders and constraints to a scene, keeping the first error.
class Builder {
 public:
  /// Creates the scene (Scene::Create).
  explicit Builder(SceneParams const& params);
  /// Adds to an existing scene.
  explicit Builder(Scene& scene) : scene_(&scene) {}

  bool Ok() const { return ok_; }
  Error const& GetError() const { return error_; }
  Scene* GetScene() { return ok_ ? scene_ : nullptr; }
  /// The scene's d̂ (ContactParams::activationDistance) [m].
  real ActivationDistance() const;
  /// The created scene (null after a failure, or when adding to another's).
  std::unique_ptr<Scene> TakeScene() { return ok_ ? std::move(owned_) : nullptr; }

  Collider* AddCollider(ColliderParams const& params);
  /// The plane y = 0, friction μ.
  Collider* AddGround(real friction = 0.5);
  RigidActor* AddRigid(RigidActorParams const& params);
  /// A rigid box of `half` extents and `mass` (its inertia a solid box's)
  /// with its Box collider.
  RigidActor* AddRigidBox(Real3 const& position, Quat const& rotation, Real3 const& half, real mass,
                          real friction = 0.5);
  DeformableActor* AddDeformable(DeformableActorParams const& params);
  RodActor* AddRod(RodActorParams const& params);
  ArticulatedActor* AddArticulated(ArticulatedActorParams const& params);
  /// A target holding joint `joint` of `arm` (a one-DoF joint) at `target`
  /// with `stiffness` and `damping`.
  Constraint* AddJointTarget(ArticulatedActor const& arm, int joint, real target, real stiffness, real damping);
  /// The Surface collider of a deformable or rod actor; without self contact
  /// its own group is left out of its mask.
  Collider* AddSurface(Actor const* actor, bool selfContact = true);
  /// A tet box mesh (MakeTetBox) as the nodes and tetrahedra of `params`.
  bool MakeBox(Real3 const& lower, Real3 const& size, std::array<int, 3> const& cells, DeformableActorParams& params);
  /// A square cloth of n × n nodes, `size` m wide, in the x–z plane at
  /// height y centred on the y axis, turned by `rotation` about its centre:
  /// the perf harness's cloth (hinge bending, E = 1e6 Pa, ν = 0.3, h = 1 mm,
  /// 300 kg/m³), with its self contact; its membrane the tension field (a
  /// cloth pressed into folds wrinkles; with StVK the compressed membrane's
  /// saddles cost Newton far more iterations, docs/contact.md "Measured").
  DeformableActor* AddCloth(int n, real size, real y, Quat const& rotation,
                            MembraneModel membrane = MembraneModel::TensionField);

 private:
  /// Records the first failure; false.
  bool Fail(Error const& error);
  template <class T>
  T* Check(T* created, Error const& error) {
    if (!created) Fail(error);
    return created;
  }

  std::unique_ptr<Scene> owned_;
  Scene* scene_ = nullptr;
  bool ok_ = true;
  Error error_;
};

/// A tetrahedral ball: a cells³ grid box of 6 tets per cell (MakeTetBox)
/// around `center`, 2·radius wide, each node moved along its ray from the
/// centre onto the sphere its cube shell maps to (d ↦ d |d|∞ / |d|₂), so the
/// surface is round rather than a voxel staircase; false and `error` for a
/// bad size.
bool TetBall(Real3 const& center, real radius, int cells, DeformableActorParams& ball, Error& error);

/// A contact scene and how long it runs [s].
struct ContactScene {
  std::unique_ptr<Scene> scene;  ///< null when the build failed
  real seconds = 1;
  /// Called before each step with the times at its start and end [s]
  /// (targets that drive the scene; false and `error` when a target is
  /// refused); none: nothing to drive.
  std::function<bool(real from, real to, Error&)> drive;
};

/// The scene built by `builder` (null, and its error in `error`, after a failure).
ContactScene Finish(Builder& builder, real seconds, Error& error);

/// 1. A 0.2 m rigid box (1 kg) at rest on a plane incline of slope tan θ,
/// μ = 0.5 (it sticks at tan θ = 0.49), started 0.5 d̂ above it.
ContactScene InclineScene(SceneParams params, real tanTheta, Error& error);
/// 2. A solid sphere (r = 0.1 m) rolling from rest down a 15° incline.
ContactScene RollingScene(SceneParams params, Error& error);
/// The ball of scene 3: a rubber ball 1 m across (docs/contact.md, "Scene 3:
/// which ball bounces"). Its impact at 4.4 m/s is slow against its wave speed
/// √(E/ρ) = 32 m/s and lasts about 28 steps of 1/240 s.
inline constexpr real kBallRadius = 0.5;       // [m]
inline constexpr real kBallYoungModulus = 1e6;  // [Pa]
/// 3. An undamped stable Neo-Hookean tet ball (TetBall, r = kBallRadius,
/// E = kBallYoungModulus, ν = 0.3, 1000 kg/m³, `cells` across) whose lowest
/// point starts `drop` m above the ground, which has μ = 0.5; without self
/// contact (a solid ball does not fold onto itself).
ContactScene BallDropScene(SceneParams params, real drop, int cells, Error& error);
/// The ball of scene 3 alone: its nodes, tets and material.
bool BallParams(real drop, int cells, DeformableActorParams& ball, Error& error);
// Each scene: XScene builds it in a scene of its own; AddX adds it to a
// builder's scene (the harness's, whose parameters it sets) and returns its
// bodies.

/// 4a. A stack of `count` 0.2 m rigid boxes (1 kg), each started 0.9 d̂
/// above the one below (near where the barrier carries them: started at
/// 0.5 d̂ the barrier's stored energy launches them, docs/contact.md).
ContactScene BoxStackScene(SceneParams params, int count, Error& error);
DynamicArray<RigidActor*> AddBoxStack(Builder& builder, int count);
/// 4b. A stack of `count` tet cubes (0.1 m, cells³ cells of 6 tets, E = 1e6
/// Pa, 1000 kg/m³), each started 0.9 d̂ above the one below.
ContactScene CubeStackScene(SceneParams params, int count, int cells, Error& error);
DynamicArray<DeformableActor*> AddCubeStack(Builder& builder, int count, int cells);
/// 5a. An n × n cloth (0.6 m) dropped from 5 cm above a static sphere
/// (r = 0.2 m) resting on the ground: it drapes over it and folds.
ContactScene ClothOnSphereScene(SceneParams params, int n, Error& error);
DeformableActor* AddClothOnSphere(Builder& builder, int n);
/// 5b. A cloth (n × n, 0.4 m) falling edge-first, tilted 80° from the
/// ground: it lands, buckles and folds onto itself.
ContactScene ClothFoldScene(SceneParams params, int n, Error& error);
/// 6. A rod of `n` nodes (r = 4 mm, E = 1e7 Pa) in a helix of radius 5 cm,
/// three turns rising 2 cm each, dropped onto the ground: the upper turns
/// pile onto the lower.
ContactScene RodCoilScene(SceneParams params, int n, Error& error);
/// 6b. `rods` straight rods of `nodes` nodes (0.5 m, r = 4 mm, E = 1e7 Pa,
/// 1000 kg/m³) dropped into a bin (a 0.6 m square floor, static walls 0.3 m
/// high) in layers 2 cm apart, 10 rods 3 cm apart per layer, each layer
/// turned 100° from the one below: they fall, cross and pile. Rod against
/// rod, the walls and the floor; no self contact within a rod (a straight
/// rod does not fold onto itself in the second the scene runs).
ContactScene RodPileScene(SceneParams params, int rods, int nodes, Error& error);
DynamicArray<RodActor*> AddRodPile(Builder& builder, int rods, int nodes);

/// 7. A 0.1 m rigid box at 20 m/s onto a static 5 mm plate.
ContactScene FastBoxScene(SceneParams params, Error& error);

/// 8. A 5-link arm pushes a 1 kg, 0.2 m rigid box across the ground (μ =
/// 0.3): a carriage (link 0, prismatic along x, 0.55 m up) from which four
/// 0.1 m links hang on revolute joints about z, each with a capsule collider
/// (r = 15 mm) along its axis. Targets drive it: the carriage's position
/// moves at `speed` (it starts 0.15 m behind the box's face), the hanging
/// joints are held at 0 (stiffness 100 N·m/rad); the lowest capsule meets
/// the box's side.
struct ArmPush {
  ArticulatedActor* arm = nullptr;
  RigidActor* box = nullptr;
  Constraint* carriage = nullptr;
  real speed = 0.3;  ///< of the carriage's target [m/s]
  real start = 0;    ///< the carriage's target at t = 0 [m]
};

inline constexpr real kArmLink = 0.1;      ///< hanging link length [m]
inline constexpr real kArmRadius = 0.015;  ///< capsule radius [m]

/// The arm with its carriage at `carriage` [m].
ArticulatedActorParams ArmParams(real carriage);
/// The capsule of hanging link `link` (1..4): along the link's −y, between
/// 10 mm and 90 mm below its joint.
ColliderParams ArmCapsule(ArticulatedActor const& arm, int link);
/// The ground, the box and the arm with its targets, added by `builder`.
ArmPush AddArmPush(Builder& builder, real speed);
ContactScene ArmPushScene(SceneParams params, Error& error);

/// 8b. A mechanism's self contact: a 3-link planar arm (revolute joints
/// about z, no gravity, capsules of r = 15 mm, μ = 0.3) whose last link is
/// driven into its first. Link 0 (0.4 m) is held along +x, link 1 (0.1 m)
/// at 90° to it; link 2 starts folded back over link 0, 0.1 m above it
/// (joint 2 at 90°), and its target turns on to kFoldTarget over
/// kFoldSeconds: past about 101.5° its capsule would pass through link 0's,
/// so it comes to rest on it, joint 2 short of its target (links 0 and 2
/// are not parent and child: they touch; links 1 and 2, and 0 and 1, do not).
struct FoldingArm {
  ArticulatedActor* arm = nullptr;
  Constraint* fold = nullptr;  ///< joint 2's target
};

inline constexpr real kFoldTarget = 2.6;   ///< joint 2's final target [rad] (~149°)
inline constexpr real kFoldSeconds = 0.5;  ///< the target's turn [s]
/// Joint 2's angle where link 2's capsule first touches link 0's [rad]: its
/// far end (0.35 m from the joint, 0.1 m above link 0's axis) at two radii
/// from that axis, asin(0.07 / 0.35) past 90°.
inline constexpr real kFoldTouch = 1.7721;

/// The arm and its targets, added by `builder` (set the scene's gravity to zero).
FoldingArm AddFoldingArm(Builder& builder);
/// Turns joint 2's target to where it is at `to` (the step's end) [s].
bool DriveFoldingArm(FoldingArm const& fold, real to, Error& error);
ContactScene FoldingArmScene(SceneParams params, Error& error);

/// 9. A kinematic gripper lifts a soft cube against gravity: a tet cube (0.1
/// m, cells³ cells of 6 tets, stable Neo-Hookean, E = 1e5 Pa, 1000 kg/m³:
/// 1 kg) rests on the ground (μ = 0.5) between two static box paddles (2 cm
/// thick, 8 cm tall, 16 cm deep, μ = 0.8) whose faces start 3 mm from its
/// sides. Targets move them: they close 4.5 mm each until kGraspClosed (the
/// cube squeezed 1.5 mm a side), lift 0.1 m at constant speed until
/// kGraspLifted, and hold still after; the cube must hang between them, held
/// by friction alone (its weight 9.81 N against ~0.6 · 2 · 30 N).
struct Grasp {
  DeformableActor* cube = nullptr;
  std::array<Collider*, 2> paddles{};  ///< at −x and +x
};

inline constexpr real kGraspClosed = 0.25;  ///< the paddles closed [s]
inline constexpr real kGraspLifted = 0.5;   ///< the cube lifted [s]
inline constexpr real kGraspLift = 0.1;     ///< how far [m]

/// Where paddle `side` (0: −x, 1: +x) has its centre at `time` [s].
Real3 GraspPaddlePosition(int side, real time, real activationDistance);
/// The ground, the cube and the paddles (unmoved), added by `builder`.
Grasp AddGrasp(Builder& builder, int cells);
/// Moves the paddles to their targets at `to` (the step's end); the scene
/// runs 1.5 s (closed, lifted, then held 1 s).
bool DriveGrasp(Grasp const& grasp, real activationDistance, real to, Error& error);

}  // namespace superdex::scenes
