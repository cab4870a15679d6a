// A deformable actor: a mesh of nodes with 3 displacement DoFs each, u in
// the actor frame; a node's world position is T(X + u) with X its reference
// position and T the actor's fixed rigid transform (docs/design.md §3, §4.2).
//
// Elements, each a small dense block in the global Hessian:
//   tetrahedra  linear, hyperelastic (TetMaterialModel), energy V·Ψ(F)
//   triangles   shell membrane (StVK, plane stress, thickness h)
//   hinges      shell bending on every interior edge of the triangles
//               (quadratic bending), k_b = E h³/(36(1 − ν²)) = D/3 so that
//               a sheet bent into a cylinder stores the plate energy D/2 κ²
//               per area (shell_element.h)
// Mass is lumped: ρV/4 per tet node, ρhA/3 per triangle node.
//
// Stage terms, per node i with Δᵢ = uᵢ − uᵢⁿ (scene/integrator.h):
//   ½ w mᵢ ‖Δᵢ − Δ̂ᵢ‖² − mᵢ g_T·uᵢ    (g_T = R_Tᵀ g, gravity in the actor frame)
// plus the elastic energy; element Hessians are projected to PSD.
#pragma once

#include <array>

#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/shell_element.h>
#include <superdex/actors/tet_element.h>
#include <superdex/core/error.h>
#include <superdex/stage/integrator.h>

namespace superdex {

struct DeformableActorParams {
  DynamicArray<Real3> nodes;                        ///< reference positions X, actor frame [m]
  DynamicArray<std::array<int, 4>> tetrahedra;      ///< volumetric elements (positive volume)
  DynamicArray<std::array<int, 3>> triangles;       ///< shell elements
  Real3 position = Real3::Zero();                   ///< actor transform T: translation [m]
  Quat rotation = Quat::Identity();                 ///< actor transform T: rotation (unit)
  real density = 1000;                              ///< ρ [kg/m³], > 0
  real youngModulus = 1e5;                          ///< E [Pa], > 0
  real poissonRatio = 0.3;                          ///< ν, in (−1, 0.5)
  TetMaterialModel material = TetMaterialModel::StableNeoHookean;
  real thickness = 1e-3;                            ///< shell thickness h [m], > 0 with triangles
  MembraneModel membrane = MembraneModel::StVK;     ///< the triangles' membrane (TensionField for cloth)
  bool shellBending = true;                         ///< bending on interior edges of the triangles
  /// Optional initial displacements u (actor frame), one per node, or empty.
  DynamicArray<Real3> initialDisplacements;
  /// Optional initial velocities (world frame), one per node, or empty.
  DynamicArray<Real3> initialVelocities;
};

class DeformableActor final : public NodalActor {
 public:
  /// Validates everything (material parameters, mesh indices, non-degenerate
  /// and positively oriented rest elements, every node in some element);
  /// nullptr and an Error naming the field or element on bad input.
  static std::unique_ptr<DeformableActor> Create(DeformableActorParams const& params, Error& error);

  int GetNumNodes() const override { return static_cast<int>(reference_.size()); }
  int GetNumTetrahedra() const { return static_cast<int>(tetrahedra_.size()); }
  int GetNumTriangles() const { return static_cast<int>(triangles_.size()); }
  int GetNumHinges() const { return static_cast<int>(hinges_.size()); }
  DynamicArray<std::array<int, 4>> const& GetTetrahedra() const { return tetrahedra_; }
  DynamicArray<std::array<int, 3>> const& GetTriangles() const { return triangles_; }

  /// X of node i (actor frame). Preconditions for every node accessor: 0 <= i < GetNumNodes().
  Real3 const& GetNodeReferencePosition(int i) const override { return reference_[i]; }
  /// u of node i (actor frame).
  Real3 const& GetNodeDisplacement(int i) const { return state_.displacement[i]; }
  /// T(X + u), world frame.
  Real3 GetNodePosition(int i) const override;
  /// World-frame velocity of node i.
  Real3 GetNodeVelocity(int i) const override;
  real GetNodeMass(int i) const override { return mass_[i]; }
  real GetTotalMass() const;
  /// World positions of all nodes (one bulk copy).
  DynamicArray<Real3> GetNodePositions() const;
  Real3 const& GetTransformPosition() const { return transformPosition_; }
  Quat const& GetTransformRotation() const override { return transformRotation_; }

  real GetKineticEnergy() const;
  /// Elastic energy of every element at the current configuration.
  real GetElasticEnergy() const { return ElasticEnergy({}); }
  /// Tetrahedra with det F <= 0 now.
  int CountInvertedTetrahedra() const;

 private:
  DeformableActor(int numNodes) : NodalActor(ActorType::Deformable, numNodes, 3) {}

  struct State {
    DynamicArray<Real3> displacement, velocity;  ///< actor frame
    bool hasHistory = false;
    DynamicArray<Real3> previousDisplacement, previousVelocity;
  };

  void AppendDofBlockSizes(DynamicArray<int>& sizes) const override;
  void WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const override;
  void WriteDofInverseMasses(Span<real> inverseMasses) const override;
  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  /// Newton's first iterate is the inertial target û = u + c Δₚ + β h v (the
  /// free-flight prediction), not the stage start: measured on the clamped
  /// 40×8×8 beam (dt = 1/60, CHOLMOD) it takes 4.5 instead of 5.5 Newton
  /// iterations per step over steps 2–12.
  void BeginStage(internal::StageContext const& context) override;
  void MoveToFirstIterate() override;
  real Energy(internal::OwnedContributors owned) const override;
  /// Elastic energy of the `owned` elements (Energy's argument; empty: all).
  real ElasticEnergy(internal::OwnedContributors owned) const;
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                             internal::AssemblyOptions const& options) const override;
  void SaveIterate() override;
  void RestoreIterate() override;
  void ApplyIncrementFromSaved(Span<real const> delta, real alpha) override;
  bool IsStateFinite() const override;
  void EndStage() override;
  void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const override;
  void RestoreSnapshot(internal::ActorSnapshot const& snapshot) override;

  template <int N>
  Eigen::Matrix<real, 3 * N, 1> Gather(std::array<int, N> const& nodes) const;

  // definition (immutable after creation)
  DynamicArray<Real3> reference_;
  DynamicArray<real> mass_;
  Real3 transformPosition_;
  Quat transformRotation_;
  TetMaterialModel material_;
  MembraneModel membrane_ = MembraneModel::StVK;
  internal::LameParameters lame_;
  real lambdaPlaneStress_ = 0, thickness_ = 0, bendingStiffness_ = 0;
  DynamicArray<std::array<int, 4>> tetrahedra_;
  DynamicArray<internal::TetRestData> tetRest_;
  DynamicArray<std::array<int, 3>> triangles_;
  DynamicArray<internal::TriangleRestData> triangleRest_;
  DynamicArray<std::array<int, 4>> hinges_;
  DynamicArray<internal::HingeRestData> hingeRest_;

  State state_;
  // stage scratch (sized at creation)
  internal::StageCoefficients stage_;
  real weight_ = 0;
  Real3 gravityLocal_;
  DynamicArray<Real3> stageStart_, target_, previousOffset_, saved_;
};

}  // namespace superdex
