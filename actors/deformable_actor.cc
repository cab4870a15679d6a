#include <superdex/actors/deformable_actor.h>

#include <cmath>

#include <superdex/actors/mesh.h>
#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/so3.h>
#include <superdex/core/validate.h>

namespace superdex {

namespace {
std::string ElementText(char const* kind, std::size_t index) {
  return std::string("DeformableActorParams.") + kind + "[" + std::to_string(index) + "]";
}
}  // namespace

std::unique_ptr<DeformableActor> DeformableActor::Create(DeformableActorParams const& params,
                                                         Error& error) {
  using namespace internal;
  // material and transform
  if (!CheckPositive(params.density, "DeformableActorParams.density", error) ||
      !CheckPositive(params.youngModulus, "DeformableActorParams.youngModulus", error) ||
      !CheckFinite(params.position, "DeformableActorParams.position", error) ||
      !CheckUnitQuat(params.rotation, "DeformableActorParams.rotation", error))
    return nullptr;
  if (!(params.poissonRatio > -1 && params.poissonRatio < 0.5)) {
    error.Set(ErrorCode::InvalidArgument, "DeformableActorParams.poissonRatio must be in (-1, 0.5), got " +
                                              Format(params.poissonRatio));
    return nullptr;
  }
  if (params.material != TetMaterialModel::StableNeoHookean &&
      params.material != TetMaterialModel::LinearElastic) {
    error.Set(ErrorCode::InvalidArgument, "DeformableActorParams.material is not a TetMaterialModel (" +
                                              std::to_string(static_cast<int>(params.material)) + ")");
    return nullptr;
  }
  if (params.membrane != MembraneModel::StVK && params.membrane != MembraneModel::TensionField) {
    error.Set(ErrorCode::InvalidArgument, "DeformableActorParams.membrane is not a MembraneModel (" +
                                              std::to_string(static_cast<int>(params.membrane)) + ")");
    return nullptr;
  }
  if (params.tetrahedra.empty() && params.triangles.empty()) {
    error.Set(ErrorCode::InvalidArgument,
              "DeformableActorParams needs at least one tetrahedron or triangle, got none");
    return nullptr;
  }
  if (!params.triangles.empty() &&
      !CheckPositive(params.thickness, "DeformableActorParams.thickness", error))
    return nullptr;
  int const numNodes = static_cast<int>(params.nodes.size());
  for (auto const* optional : {&params.initialDisplacements, &params.initialVelocities}) {
    if (!optional->empty() && static_cast<int>(optional->size()) != numNodes) {
      error.Set(ErrorCode::InvalidArgument,
                std::string("DeformableActorParams.") +
                    (optional == &params.initialDisplacements ? "initialDisplacements" : "initialVelocities") +
                    " must be empty or hold one entry per node (" + std::to_string(numNodes) +
                    "), got " + std::to_string(optional->size()));
      return nullptr;
    }
    for (std::size_t i = 0; i < optional->size(); ++i)
      if (!(*optional)[i].allFinite()) {
        error.Set(ErrorCode::InvalidArgument, "DeformableActorParams initial state of node " +
                                                  std::to_string(i) + " is not finite");
        return nullptr;
      }
  }
  // mesh structure: indices in range, no repeats, finite coordinates
  if (!params.tetrahedra.empty() && !ValidateTetMesh(TetMesh{params.nodes, params.tetrahedra}, error))
    return nullptr;
  TriangleMesh const surface{params.nodes, params.triangles};
  if (!params.triangles.empty() && !ValidateTriangleMesh(surface, error)) return nullptr;

  std::unique_ptr<DeformableActor> actor(new DeformableActor(numNodes));
  DeformableActor& a = *actor;
  a.reference_ = params.nodes;
  a.transformPosition_ = params.position;
  a.transformRotation_ = params.rotation.normalized();
  a.material_ = params.material;
  a.membrane_ = params.membrane;
  a.lame_ = LameFromYoungPoisson(params.youngModulus, params.poissonRatio);
  a.lambdaPlaneStress_ = 2 * a.lame_.mu * a.lame_.lambda / (a.lame_.lambda + 2 * a.lame_.mu);
  a.thickness_ = params.thickness;
  a.bendingStiffness_ = HingeBendingStiffness(params.youngModulus, params.poissonRatio, params.thickness);
  a.mass_.assign(numNodes, 0);

  // rest data and lumped mass, element by element
  a.tetrahedra_ = params.tetrahedra;
  a.tetRest_.resize(a.tetrahedra_.size());
  for (std::size_t e = 0; e < a.tetrahedra_.size(); ++e) {
    auto const& t = a.tetrahedra_[e];
    if (!MakeTetRestData(params.nodes[t[0]], params.nodes[t[1]], params.nodes[t[2]], params.nodes[t[3]],
                         a.tetRest_[e])) {
      error.Set(ErrorCode::InvalidArgument,
                ElementText("tetrahedra", e) + " = {" + std::to_string(t[0]) + ", " + std::to_string(t[1]) +
                    ", " + std::to_string(t[2]) + ", " + std::to_string(t[3]) +
                    "} is degenerate or inverted in the reference configuration");
      return nullptr;
    }
    for (int node : t) a.mass_[node] += params.density * a.tetRest_[e].restVolume / 4;
  }
  a.triangles_ = params.triangles;
  a.triangleRest_.resize(a.triangles_.size());
  for (std::size_t e = 0; e < a.triangles_.size(); ++e) {
    auto const& t = a.triangles_[e];
    if (!MakeTriangleRestData(params.nodes[t[0]], params.nodes[t[1]], params.nodes[t[2]],
                              a.triangleRest_[e])) {
      error.Set(ErrorCode::InvalidArgument, ElementText("triangles", e) + " = {" + std::to_string(t[0]) +
                                                ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                                                "} is degenerate in the reference configuration");
      return nullptr;
    }
    for (int node : t) a.mass_[node] += params.density * params.thickness * a.triangleRest_[e].restArea / 3;
  }
  if (params.shellBending && !a.triangles_.empty()) {
    a.hinges_ = MakeHinges(surface);
    a.hingeRest_.resize(a.hinges_.size());
    for (std::size_t e = 0; e < a.hinges_.size(); ++e) {
      auto const& h = a.hinges_[e];
      // both triangles were checked above, so a hinge cannot be degenerate
      MakeHingeRestData(params.nodes[h[0]], params.nodes[h[1]], params.nodes[h[2]], params.nodes[h[3]],
                        a.hingeRest_[e]);
    }
  }
  DynamicArray<char> used(numNodes, 0);
  for (auto const& t : a.tetrahedra_)
    for (int node : t) used[node] = 1;
  for (auto const& t : a.triangles_)
    for (int node : t) used[node] = 1;
  for (int i = 0; i < numNodes; ++i) {
    if (!used[i]) {
      error.Set(ErrorCode::InvalidArgument, "DeformableActorParams.nodes[" + std::to_string(i) +
                                                "] belongs to no element (it would have no mass)");
      return nullptr;
    }
    if (!(std::isfinite(a.mass_[i]) && a.mass_[i] > 0)) {
      // density × volume (or × thickness × area) under- or overflowed
      error.Set(ErrorCode::InvalidArgument,
                "DeformableActorParams.nodes[" + std::to_string(i) + "] gets mass " + Format(a.mass_[i]) +
                    " from density " + Format(params.density) +
                    (a.triangles_.empty() ? std::string() : " (thickness " + Format(params.thickness) + ")") +
                    " and its elements' volumes: it must be finite and > 0 (are the units right?)");
      return nullptr;
    }
  }

  // state
  Quat const toLocal = a.transformRotation_.conjugate();
  a.state_.displacement.assign(numNodes, Real3::Zero());
  a.state_.velocity.assign(numNodes, Real3::Zero());
  for (int i = 0; i < numNodes; ++i) {
    if (!params.initialDisplacements.empty()) a.state_.displacement[i] = params.initialDisplacements[i];
    if (!params.initialVelocities.empty()) a.state_.velocity[i] = toLocal * params.initialVelocities[i];
  }
  for (auto* v : {&a.stageStart_, &a.target_, &a.previousOffset_, &a.saved_}) v->assign(numNodes, Real3::Zero());
  return actor;
}

Real3 DeformableActor::GetNodePosition(int i) const {
  return transformPosition_ + transformRotation_ * (reference_[i] + state_.displacement[i]);
}

Real3 DeformableActor::GetNodeVelocity(int i) const { return transformRotation_ * state_.velocity[i]; }

real DeformableActor::GetTotalMass() const {
  real total = 0;
  for (real m : mass_) total += m;
  return total;
}

DynamicArray<Real3> DeformableActor::GetNodePositions() const {
  DynamicArray<Real3> positions(reference_.size());
  for (int i = 0; i < GetNumNodes(); ++i) positions[i] = GetNodePosition(i);
  return positions;
}

real DeformableActor::GetKineticEnergy() const {
  real energy = 0;
  for (int i = 0; i < GetNumNodes(); ++i) energy += 0.5 * mass_[i] * state_.velocity[i].squaredNorm();
  return energy;
}

template <int N>
Eigen::Matrix<real, 3 * N, 1> DeformableActor::Gather(std::array<int, N> const& nodes) const {
  Eigen::Matrix<real, 3 * N, 1> x;
  for (int k = 0; k < N; ++k)
    x.template segment<3>(3 * k) = reference_[nodes[k]] + state_.displacement[nodes[k]];
  return x;
}

real DeformableActor::ElasticEnergy(internal::OwnedContributors owned) const {
  // contributors: nodes, tetrahedra, triangles, hinges (AppendContributorDofs)
  int const firstTet = GetNumNodes();
  int const numTets = static_cast<int>(tetrahedra_.size());
  int const firstTriangle = firstTet + numTets;
  int const numTriangles = static_cast<int>(triangles_.size());
  int const firstHinge = firstTriangle + numTriangles;
  real energy = 0;
  for (int e = 0; e < numTets; ++e)
    if (owned(firstTet + e))
      energy += internal::TetEnergy(material_, lame_, tetRest_[e], Gather<4>(tetrahedra_[e]));
  for (int e = 0; e < numTriangles; ++e)
    if (owned(firstTriangle + e))
      energy += internal::MembraneEnergy(membrane_, lame_.mu, lambdaPlaneStress_, thickness_, triangleRest_[e],
                                         Gather<3>(triangles_[e]));
  for (int e = 0; e < static_cast<int>(hinges_.size()); ++e)
    if (owned(firstHinge + e))
      energy += internal::BendingEnergy(bendingStiffness_, hingeRest_[e], Gather<4>(hinges_[e]));
  return energy;
}

int DeformableActor::CountInvertedTetrahedra() const {
  int count = 0;
  for (std::size_t e = 0; e < tetrahedra_.size(); ++e)
    if (internal::TetDeformationGradient(tetRest_[e], Gather<4>(tetrahedra_[e])).determinant() <= 0)
      ++count;
  return count;
}

// ---- stage interface ----

void DeformableActor::AppendDofBlockSizes(DynamicArray<int>& sizes) const {
  sizes.insert(sizes.end(), reference_.size(), 3);
}

void DeformableActor::WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const {
  // node velocity t + ω × p (world), expressed in the actor frame of u
  Real33 const toActor = transformRotation_.toRotationMatrix().transpose();
  for (int i = 0; i < GetNumNodes(); ++i) {
    auto block = modes.middleRows(dofOffset_ + 3 * i, 3);
    block.leftCols<3>() = toActor;
    block.rightCols<3>() = -toActor * Hat(GetNodePosition(i));
  }
}

void DeformableActor::WriteDofInverseMasses(Span<real> inverseMasses) const {
  // lumped: M = mᵢ I₃ per node, in the actor frame as in the world
  for (int i = 0; i < GetNumNodes(); ++i)
    for (int c = 0; c < 3; ++c) inverseMasses[dofOffset_ + 3 * i + c] = 1 / mass_[i];
}

void DeformableActor::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  // order: node inertia blocks, tetrahedra, triangles, hinges (AddGradientAndHessian follows it)
  auto dofsOf = [this](auto const& nodes) {
    DynamicArray<int> dofs;
    for (int node : nodes)
      for (int c = 0; c < 3; ++c) dofs.push_back(dofOffset_ + 3 * node + c);
    return dofs;
  };
  for (int i = 0; i < GetNumNodes(); ++i) dofLists.push_back(dofsOf(std::array<int, 1>{i}));
  for (auto const& t : tetrahedra_) dofLists.push_back(dofsOf(t));
  for (auto const& t : triangles_) dofLists.push_back(dofsOf(t));
  for (auto const& h : hinges_) dofLists.push_back(dofsOf(h));
}

void DeformableActor::BeginStage(internal::StageContext const& context) {
  internal::StageCoefficients const& requested = context.coefficients;
  Real3 const& gravity = context.gravity;
  stage_ = requested.ForBody(state_.hasHistory);
  real const betaH = stage_.beta * stage_.duration;
  weight_ = stage_.InertiaWeight();
  gravityLocal_ = transformRotation_.conjugate() * gravity;
  for (int i = 0; i < GetNumNodes(); ++i) {
    Real3 velocity = stage_.aVelocity * state_.velocity[i];
    previousOffset_[i].setZero();
    if (stage_.usesHistory) {
      velocity += stage_.bVelocity * state_.previousVelocity[i];
      previousOffset_[i] = state_.previousDisplacement[i] - state_.displacement[i];
    }
    stageStart_[i] = state_.displacement[i];
    target_[i] = state_.displacement[i] + stage_.cPrevious * previousOffset_[i] + betaH * velocity;
  }
}

void DeformableActor::MoveToFirstIterate() {
  // Newton starts at the inertial target (see header)
  for (int i = 0; i < GetNumNodes(); ++i) state_.displacement[i] = target_[i];
}

real DeformableActor::Energy(internal::OwnedContributors owned) const {
  real energy = 0;
  for (int i = 0; i < GetNumNodes(); ++i) {
    if (!owned(i)) continue;
    Real3 const& u = state_.displacement[i];
    energy += mass_[i] * (0.5 * weight_ * (u - target_[i]).squaredNorm() - gravityLocal_.dot(u));
  }
  return energy + ElasticEnergy(owned);
}

void DeformableActor::AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                                         internal::AssemblyOptions const& options) const {
  bool const projectHessian = options.projectHessian;
  // contributors: nodes, tetrahedra, triangles, hinges (AppendContributorDofs)
  int const numNodes = GetNumNodes();
  int const firstTet = firstContributor + numNodes;
  int const numTets = static_cast<int>(tetrahedra_.size());
  int const firstTriangle = firstTet + numTets;
  int const numTriangles = static_cast<int>(triangles_.size());
  int const firstHinge = firstTriangle + numTriangles;
  // inertia and gravity, node by node
  assembler.ParallelFor(numNodes, internal::kNodeGrain, [&](int begin, int end, int) {
    for (int i = begin; i < end; ++i) {
      if (!assembler.Evaluates(firstContributor + i)) continue;
      Real3 const g = mass_[i] * (weight_ * (state_.displacement[i] - target_[i]) - gravityLocal_);
      assembler.AddGradient(firstContributor + i, g);
      assembler.AddBlock(firstContributor + i, Real33((weight_ * mass_[i]) * Real33::Identity()));
    }
  });
  assembler.ParallelFor(numTets, internal::kElementGrain, [&](int begin, int end, int) {
    internal::Vector12 g12;
    internal::Matrix12 h12;
    for (int e = begin; e < end; ++e) {
      if (!assembler.Evaluates(firstTet + e)) continue;
      internal::TetEnergyGradientHessian(material_, lame_, tetRest_[e], Gather<4>(tetrahedra_[e]), g12, h12,
                                         projectHessian);
      assembler.AddGradient(firstTet + e, g12);
      assembler.AddBlock(firstTet + e, h12);
    }
  });
  assembler.ParallelFor(numTriangles, internal::kElementGrain, [&](int begin, int end, int) {
    internal::Vector9 g9;
    internal::Matrix9 h9;
    for (int e = begin; e < end; ++e) {
      if (!assembler.Evaluates(firstTriangle + e)) continue;
      internal::MembraneEnergyGradientHessian(membrane_, lame_.mu, lambdaPlaneStress_, thickness_, triangleRest_[e],
                                              Gather<3>(triangles_[e]), g9, h9, projectHessian);
      assembler.AddGradient(firstTriangle + e, g9);
      assembler.AddBlock(firstTriangle + e, h9);
    }
  });
  assembler.ParallelFor(static_cast<int>(hinges_.size()), internal::kElementGrain, [&](int begin, int end, int) {
    internal::Vector12 g12;
    internal::Matrix12 h12;
    for (int e = begin; e < end; ++e) {
      if (!assembler.Evaluates(firstHinge + e)) continue;
      internal::BendingEnergyGradientHessian(bendingStiffness_, hingeRest_[e], Gather<4>(hinges_[e]), g12, h12);
      assembler.AddGradient(firstHinge + e, g12);
      assembler.AddBlock(firstHinge + e, h12);
    }
  });
}

void DeformableActor::SaveIterate() { saved_ = state_.displacement; }

void DeformableActor::RestoreIterate() { state_.displacement = saved_; }

void DeformableActor::ApplyIncrementFromSaved(Span<real const> delta, real alpha) {
  for (int i = 0; i < GetNumNodes(); ++i)
    for (int c = 0; c < 3; ++c)
      state_.displacement[i][c] = saved_[i][c] + alpha * delta[dofOffset_ + 3 * i + c];
}

bool DeformableActor::IsStateFinite() const {
  for (Real3 const& u : state_.displacement)
    if (!u.allFinite()) return false;
  return true;
}

void DeformableActor::EndStage() {
  real const betaH = stage_.beta * stage_.duration;
  state_.previousDisplacement = stageStart_;
  state_.previousVelocity = state_.velocity;
  state_.hasHistory = true;
  for (int i = 0; i < GetNumNodes(); ++i)
    state_.velocity[i] =
        (state_.displacement[i] - stageStart_[i] - stage_.cPrevious * previousOffset_[i]) / betaH;
}

void DeformableActor::SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const {
  internal::SaveStateSnapshot(state_, snapshot);
}

void DeformableActor::RestoreSnapshot(internal::ActorSnapshot const& snapshot) {
  internal::RestoreStateSnapshot(snapshot, state_);
}

}  // namespace superdex
