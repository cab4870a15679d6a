// A rod: a discrete elastic rod on a polyline (docs/design.md §4.3; energies and
// frames in actors/rod_element.h). Nodes 0..N−1 and elements e = (e, e+1).
//
// DoFs, 4 per node: node i's displacement uᵢ (3, world frame: a rod's actor
// transform is the identity, so its position is Xᵢ + uᵢ) and the twist θᵢ of
// element (i, i+1). The last node's twist belongs to no element: it is inert
// (inertia only), so that every node has the same layout.
//
// Mass: lumped, mᵢ = ρA(l̄ᵢ₋₁ + l̄ᵢ)/2 per node; twist inertia of element e
// ρ(I₁ + I₂) l̄ₑ (the section's polar moment of area times length; the inert
// last twist gets the last element's). Gravity acts on the positions.
//
// Stage terms (scene/integrator.h), per node with Δ = q − qⁿ over all 4 DoFs:
//   ½ w Σ M (Δ − Δ̂)² − mᵢ g·uᵢ  + stretching + bending + twisting,
// the twist angle integrated like a coordinate (its reference frame turns with
// the tangent; DER's usual approximation of the twist kinetic energy).
//
// Reference frames: each element's stage reference frame (t⁰, u⁰) is held
// fixed within a stage and carried to the element's new tangent by parallel
// transport when the stage ends (time-parallel transport); the reference
// twist of every interior node is tracked continuously at the same time.
// The material frame of element e is RodMaterialFrame(eₑ, ref, θₑ).
//
// Rest shape: the creation-time polyline, with material frames from the
// given director(s); its curvature and twist are the natural (rest) ones.
#pragma once

#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rod_element.h>
#include <superdex/core/error.h>
#include <superdex/stage/integrator.h>

namespace superdex {

struct RodActorParams {
  DynamicArray<Real3> nodes;  ///< rest positions, world [m]; >= 2 nodes, no zero-length element
  /// Section: circular with this radius [m] (A = πr², I₁ = I₂ = πr⁴/4,
  /// J = πr⁴/2), unless sectionArea > 0.
  real radius = 0.01;
  /// Explicit section (all > 0 when sectionArea > 0): area A [m²], second
  /// moments of area about d₁ and d₂ [m⁴], torsion constant J [m⁴].
  real sectionArea = 0;
  real secondMomentOfArea1 = 0;
  real secondMomentOfArea2 = 0;
  real torsionConstant = 0;
  real youngModulus = 1e9;   ///< E [Pa], > 0
  /// G [Pa]; <= 0 means G = E / (2(1 + ν)) from poissonRatio.
  real shearModulus = 0;
  real poissonRatio = 0.5;   ///< ν in (−1, 0.5], used when shearModulus <= 0
  real density = 1000;       ///< ρ [kg/m³], > 0
  /// Material director d₁ of element 0 at rest (world; projected normal to
  /// the element; zero chooses one). The other elements' rest frames follow
  /// by parallel transport along the polyline (no rest twist).
  Real3 materialDirector = Real3::Zero();
  /// Optional: one rest director d₁ per element (projected normal to its
  /// element); overrides materialDirector and defines a natural twist.
  DynamicArray<Real3> materialDirectors;
  /// Optional initial velocities of the nodes (world), one per node, or empty.
  DynamicArray<Real3> initialVelocities;
};

class RodActor final : public NodalActor {
 public:
  /// Validates everything; nullptr and an Error naming the field on bad input.
  static std::unique_ptr<RodActor> Create(RodActorParams const& params, Error& error);

  int GetNumNodes() const override { return static_cast<int>(reference_.size()); }
  int GetNumElements() const { return GetNumNodes() - 1; }
  Real3 GetNodePosition(int i) const override { return reference_[i] + state_.displacement[i]; }
  Real3 GetNodeVelocity(int i) const override { return state_.velocity[i]; }
  real GetNodeMass(int i) const override { return mass_[i]; }
  Quat const& GetTransformRotation() const override { return identity_; }
  Real3 const& GetNodeReferencePosition(int i) const override { return reference_[i]; }
  DynamicArray<Real3> GetNodePositions() const;
  /// θ of element e (node e's 4th DoF) [rad], relative to its reference frame.
  real GetTwist(int i) const { return state_.twist[i]; }
  real GetTwistVelocity(int i) const { return state_.twistVelocity[i]; }
  real GetTwistInertia(int i) const { return twistInertia_[i]; }
  real GetTotalMass() const;
  real GetRestLength(int e) const { return restLength_[e]; }
  /// The section's radius (RodActorParams::radius) [m]: a rod collider's thickness.
  real GetRadius() const { return radius_; }
  /// Material frame [d₁ d₂ t] of element e, 0 <= e < GetNumElements().
  Real33 GetMaterialFrame(int e) const;
  /// World angular increment of element e's material frame per increment of
  /// its nodes' 8 DoFs (see internal::RodMaterialFrameJacobian).
  internal::Matrix38 GetMaterialFrameJacobian(int e) const;
  /// Element e's material frame with its first and second derivatives w.r.t.
  /// (edge vector, twist) (see internal::RodMaterialFrameJet).
  internal::JetMatrix3<4> GetMaterialFrameJet(int e) const;
  /// (κ₁, κ₂, m) at interior node i, 1 <= i <= GetNumNodes() − 2, and at rest.
  Real3 GetStrain(int i) const;
  Real3 const& GetRestStrain(int i) const { return stencilRest_[i - 1].strain; }
  internal::RodStiffness const& GetStiffness() const { return stiffness_; }

  real GetKineticEnergy() const;
  /// Stretching + bending + twisting energy at the current configuration.
  real GetElasticEnergy() const { return ElasticEnergy({}); }

 private:
  explicit RodActor(int numNodes) : NodalActor(ActorType::Rod, numNodes, 4) {}

  struct State {
    DynamicArray<Real3> displacement, velocity;
    DynamicArray<real> twist, twistVelocity;
    /// Stage reference frames (per element) and the reference twist at the
    /// stage start (per interior node), carried between stages.
    DynamicArray<internal::RodReferenceFrame> frames;
    DynamicArray<real> referenceTwist;
    bool hasHistory = false;
    DynamicArray<Real3> previousDisplacement, previousVelocity;
    DynamicArray<real> previousTwist, previousTwistVelocity;
  };

  void AppendDofBlockSizes(DynamicArray<int>& sizes) const override;
  void WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const override;
  void WriteDofInverseMasses(Span<real> inverseMasses) const override;
  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  void BeginStage(internal::StageContext const& context) override;
  void MoveToFirstIterate() override;
  real Energy(internal::OwnedContributors owned) const override;
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                             internal::AssemblyOptions const& options) const override;
  void SaveIterate() override;
  void RestoreIterate() override;
  void ApplyIncrementFromSaved(Span<real const> delta, real alpha) override;
  bool IsStateFinite() const override;
  void EndStage() override;
  void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const override;
  void RestoreSnapshot(internal::ActorSnapshot const& snapshot) override;

  Real3 Edge(int e) const { return GetNodePosition(e + 1) - GetNodePosition(e); }
  /// Bending–twisting energy of the stencil at interior node i.
  real StencilEnergy(int i) const;
  /// Stretching + bending + twisting energy of the `owned` elements and
  /// stencils (Energy's argument; empty: all).
  real ElasticEnergy(internal::OwnedContributors owned) const;

  // definition (immutable after creation)
  DynamicArray<Real3> reference_;
  DynamicArray<real> mass_, twistInertia_, restLength_;
  DynamicArray<internal::RodStencilRest> stencilRest_;  ///< interior node i at [i − 1]
  internal::RodStiffness stiffness_;
  real radius_ = 0;
  Quat identity_ = Quat::Identity();

  State state_;
  // stage scratch (sized at creation)
  internal::StageCoefficients stage_;
  real weight_ = 0;
  Real3 gravity_ = Real3::Zero();
  DynamicArray<Real3> stageStart_, target_, previousOffset_, saved_;
  DynamicArray<real> twistStart_, twistTarget_, twistPreviousOffset_, twistSaved_;
};

}  // namespace superdex
