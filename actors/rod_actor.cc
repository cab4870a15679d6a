#include <superdex/actors/rod_actor.h>

#include <cmath>
#include <numbers>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/so3.h>
#include <superdex/core/validate.h>

namespace superdex {

namespace {
constexpr std::string_view kParams = "RodActorParams";

std::string Field(std::string_view name) { return std::string(kParams) + "." + std::string(name); }

/// `director` made a unit vector normal to `tangent`; false when it is (nearly) parallel.
bool NormalDirector(Real3 const& director, Real3 const& tangent, Real3& out) {
  Real3 const normal = director - director.dot(tangent) * tangent;
  if (!(normal.norm() > 1e-6 * director.norm())) return false;
  out = normal.normalized();
  return true;
}

/// A unit vector normal to `tangent`, along the coordinate axis least aligned with it.
Real3 AnyNormal(Real3 const& tangent) {
  int axis = 0;
  tangent.cwiseAbs().minCoeff(&axis);
  Real3 normal;
  NormalDirector(Real3::Unit(axis), tangent, normal);
  return normal;
}
}  // namespace

namespace {
/// The cross-section's area and moments (given, or of a circle of the radius).
bool Section(RodActorParams const& params, real& area, real& inertia1, real& inertia2, real& torsion,
             Error& error) {
  using namespace internal;
  if (params.sectionArea > 0) {
    if (!CheckPositive(params.sectionArea, Field("sectionArea"), error) ||
        !CheckPositive(params.secondMomentOfArea1, Field("secondMomentOfArea1"), error) ||
        !CheckPositive(params.secondMomentOfArea2, Field("secondMomentOfArea2"), error) ||
        !CheckPositive(params.torsionConstant, Field("torsionConstant"), error))
      return false;
    area = params.sectionArea;
    inertia1 = params.secondMomentOfArea1;
    inertia2 = params.secondMomentOfArea2;
    torsion = params.torsionConstant;
  } else {
    if (!CheckFinite(params.sectionArea, Field("sectionArea"), error) ||
        !CheckPositive(params.radius, Field("radius"), error))
      return false;
    real const r2 = params.radius * params.radius;
    area = std::numbers::pi_v<real> * r2;
    inertia1 = inertia2 = area * r2 / 4;
    torsion = area * r2 / 2;
  }
  return true;
}

/// The elements' tangents (every element of non-zero length, none folding
/// back) and rest material frames (given directors, or one transported along).
bool RestFrames(RodActorParams const& params, DynamicArray<internal::RodReferenceFrame>& frames, Error& error) {
  using namespace internal;
  int const numElements = static_cast<int>(frames.size());
  DynamicArray<Real3> tangents(numElements);
  for (int e = 0; e < numElements; ++e) {
    Real3 const edge = params.nodes[e + 1] - params.nodes[e];
    if (!std::isfinite(edge.norm())) {
      error.Set(ErrorCode::InvalidArgument, Field("nodes") + ": element " + std::to_string(e) + " (nodes " +
                                                std::to_string(e) + ", " + std::to_string(e + 1) + " at " +
                                                Format(params.nodes[e]) + " and " + Format(params.nodes[e + 1]) +
                                                ") is too long: its length overflows");
      return false;
    }
    real const scale = std::max(params.nodes[e].norm(), params.nodes[e + 1].norm());
    if (!(edge.norm() > 1e-12 * std::max<real>(scale, 1e-300))) {
      error.Set(ErrorCode::InvalidArgument, Field("nodes") + ": element " + std::to_string(e) + " (nodes " +
                                                std::to_string(e) + ", " + std::to_string(e + 1) +
                                                ") has zero length");
      return false;
    }
    tangents[e] = edge.normalized();
    if (e > 0 && 1 + tangents[e - 1].dot(tangents[e]) < 1e-8) {
      error.Set(ErrorCode::InvalidArgument, Field("nodes") + ": the rod folds back on itself at node " +
                                                std::to_string(e) + " (its elements are antiparallel)");
      return false;
    }
  }
  // rest material frames
  if (!params.materialDirectors.empty()) {
    if (static_cast<int>(params.materialDirectors.size()) != numElements) {
      error.Set(ErrorCode::InvalidArgument, Field("materialDirectors") +
                                                " must be empty or hold one director per element (" +
                                                std::to_string(numElements) + "), got " +
                                                std::to_string(params.materialDirectors.size()));
      return false;
    }
    for (int e = 0; e < numElements; ++e) {
      std::string const name = Field("materialDirectors[" + std::to_string(e) + "]");
      if (!CheckFinite(params.materialDirectors[e], name, error)) return false;
      frames[e].tangent = tangents[e];
      if (!NormalDirector(params.materialDirectors[e], tangents[e], frames[e].director)) {
        error.Set(ErrorCode::InvalidArgument, name + " = " + Format(params.materialDirectors[e]) +
                                                  " is zero or parallel to its element");
        return false;
      }
    }
  } else {
    frames[0].tangent = tangents[0];
    if (params.materialDirector.isZero()) {
      frames[0].director = AnyNormal(tangents[0]);
    } else if (!NormalDirector(params.materialDirector, tangents[0], frames[0].director)) {
      error.Set(ErrorCode::InvalidArgument, Field("materialDirector") + " = " +
                                                Format(params.materialDirector) +
                                                " is parallel to the first element");
      return false;
    }
    for (int e = 1; e < numElements; ++e) {
      frames[e].tangent = tangents[e];
      frames[e].director =
          TransportDirector(tangents[e - 1], tangents[e], frames[e - 1].director).normalized();
    }
  }
  return true;
}

}  // namespace

std::unique_ptr<RodActor> RodActor::Create(RodActorParams const& params, Error& error) {
  using namespace internal;
  int const numNodes = static_cast<int>(params.nodes.size());
  if (numNodes < 2) {
    error.Set(ErrorCode::InvalidArgument, Field("nodes") + " needs at least 2 nodes, got " +
                                              std::to_string(numNodes));
    return nullptr;
  }
  for (int i = 0; i < numNodes; ++i)
    if (!CheckFinite(params.nodes[i], Field("nodes[" + std::to_string(i) + "]"), error)) return nullptr;
  if (!CheckPositive(params.youngModulus, Field("youngModulus"), error) ||
      !CheckPositive(params.density, Field("density"), error) ||
      !CheckFinite(params.shearModulus, Field("shearModulus"), error) ||
      !CheckFinite(params.materialDirector, Field("materialDirector"), error))
    return nullptr;
  if (params.shearModulus <= 0 && !(params.poissonRatio > -1 && params.poissonRatio <= 0.5)) {
    error.Set(ErrorCode::InvalidArgument, Field("poissonRatio") + " must be in (-1, 0.5] (shearModulus <= 0 "
                                                                  "takes G from it), got " +
                                              Format(params.poissonRatio));
    return nullptr;
  }
  // section
  real area, inertia1, inertia2, torsion;
  if (!Section(params, area, inertia1, inertia2, torsion, error)) return nullptr;
  int const numElements = numNodes - 1;
  DynamicArray<RodReferenceFrame> frames(numElements);
  if (!RestFrames(params, frames, error)) return nullptr;
  if (!params.initialVelocities.empty() && static_cast<int>(params.initialVelocities.size()) != numNodes) {
    error.Set(ErrorCode::InvalidArgument, Field("initialVelocities") +
                                              " must be empty or hold one entry per node (" +
                                              std::to_string(numNodes) + "), got " +
                                              std::to_string(params.initialVelocities.size()));
    return nullptr;
  }
  for (std::size_t i = 0; i < params.initialVelocities.size(); ++i)
    if (!CheckFinite(params.initialVelocities[i], Field("initialVelocities[" + std::to_string(i) + "]"), error))
      return nullptr;

  std::unique_ptr<RodActor> actor(new RodActor(numNodes));
  RodActor& a = *actor;
  real const shear = params.shearModulus > 0 ? params.shearModulus
                                             : params.youngModulus / (2 * (1 + params.poissonRatio));
  a.stiffness_ = {params.youngModulus * area, params.youngModulus * inertia1, params.youngModulus * inertia2,
                  shear * torsion};
  a.reference_ = params.nodes;
  a.radius_ = params.radius;
  a.restLength_.resize(numElements);
  a.mass_.assign(numNodes, 0);
  a.twistInertia_.assign(numNodes, 0);
  for (int e = 0; e < numElements; ++e) {
    a.restLength_[e] = (params.nodes[e + 1] - params.nodes[e]).norm();
    real const elementMass = params.density * area * a.restLength_[e];
    a.mass_[e] += elementMass / 2;
    a.mass_[e + 1] += elementMass / 2;
    a.twistInertia_[e] = params.density * (inertia1 + inertia2) * a.restLength_[e];
  }
  a.twistInertia_[numNodes - 1] = a.twistInertia_[numElements - 1];
  // the products of the inputs must stay representable: a radius of 1e300
  // overflows the masses, 1e-300 (or a density of 5e-324) underflows them
  std::string const section =
      params.sectionArea > 0 ? "sectionArea " + Format(area)
                             : "radius " + Format(params.radius) + " (section area " + Format(area) + ")";
  for (int i = 0; i < numNodes; ++i)
    if (!(std::isfinite(a.mass_[i]) && a.mass_[i] > 0 && std::isfinite(a.twistInertia_[i]) &&
          a.twistInertia_[i] > 0)) {
      error.Set(ErrorCode::InvalidArgument,
                "RodActorParams: node " + std::to_string(i) + " gets mass " + Format(a.mass_[i]) +
                    " and twist inertia " + Format(a.twistInertia_[i]) + " from density " +
                    Format(params.density) + ", " + section +
                    " and its elements' lengths: both must be finite and > 0 (are the units right?)");
      return nullptr;
    }
  std::pair<char const*, real> const stiffnesses[4] = {{"stretching E·A", a.stiffness_.stretch},
                                                        {"bending E·I1", a.stiffness_.bend1},
                                                        {"bending E·I2", a.stiffness_.bend2},
                                                        {"twisting G·J", a.stiffness_.twist}};
  for (auto const& [name, value] : stiffnesses)
    if (!(std::isfinite(value) && value > 0)) {
      error.Set(ErrorCode::InvalidArgument, "RodActorParams: the " + std::string(name) + " stiffness " +
                                                Format(value) + " from youngModulus " +
                                                Format(params.youngModulus) + " and " + section +
                                                " must be finite and > 0 (are the units right?)");
      return nullptr;
    }

  State& s = a.state_;
  s.displacement.assign(numNodes, Real3::Zero());
  s.velocity.assign(numNodes, Real3::Zero());
  for (std::size_t i = 0; i < params.initialVelocities.size(); ++i) s.velocity[i] = params.initialVelocities[i];
  s.twist.assign(numNodes, 0);
  s.twistVelocity.assign(numNodes, 0);
  s.frames = frames;
  s.referenceTwist.assign(std::max(numNodes - 2, 0), 0);
  a.stencilRest_.resize(s.referenceTwist.size());
  for (int i = 1; i + 1 < numNodes; ++i) {
    Real3 const edgeA = a.Edge(i - 1), edgeB = a.Edge(i);
    s.referenceTwist[i - 1] = RodReferenceTwist(edgeA, edgeB, frames[i - 1], frames[i], 0);
    a.stencilRest_[i - 1].voronoiLength = (a.restLength_[i - 1] + a.restLength_[i]) / 2;
    a.stencilRest_[i - 1].strain =
        RodStencilStrain(edgeA, edgeB, 0, 0, frames[i - 1], frames[i], s.referenceTwist[i - 1]);
  }
  for (auto* v : {&a.stageStart_, &a.target_, &a.previousOffset_, &a.saved_}) v->assign(numNodes, Real3::Zero());
  for (auto* v : {&a.twistStart_, &a.twistTarget_, &a.twistPreviousOffset_, &a.twistSaved_})
    v->assign(numNodes, 0);
  return actor;
}

DynamicArray<Real3> RodActor::GetNodePositions() const {
  DynamicArray<Real3> positions(reference_.size());
  for (int i = 0; i < GetNumNodes(); ++i) positions[i] = GetNodePosition(i);
  return positions;
}

real RodActor::GetTotalMass() const {
  real total = 0;
  for (real m : mass_) total += m;
  return total;
}

Real33 RodActor::GetMaterialFrame(int e) const {
  return internal::RodMaterialFrame(Edge(e), state_.frames[e], state_.twist[e]);
}

internal::JetMatrix3<4> RodActor::GetMaterialFrameJet(int e) const {
  return internal::RodMaterialFrameJet(Edge(e), state_.frames[e], state_.twist[e]);
}

internal::Matrix38 RodActor::GetMaterialFrameJacobian(int e) const {
  return internal::RodMaterialFrameJacobian(Edge(e), state_.frames[e]);
}

Real3 RodActor::GetStrain(int i) const {
  return internal::RodStencilStrain(Edge(i - 1), Edge(i), state_.twist[i - 1], state_.twist[i],
                                    state_.frames[i - 1], state_.frames[i], state_.referenceTwist[i - 1]);
}

real RodActor::GetKineticEnergy() const {
  real energy = 0;
  for (int i = 0; i < GetNumNodes(); ++i)
    energy += 0.5 * (mass_[i] * state_.velocity[i].squaredNorm() +
                     twistInertia_[i] * state_.twistVelocity[i] * state_.twistVelocity[i]);
  return energy;
}

real RodActor::StencilEnergy(int i) const {
  return internal::RodBendTwistEnergy(stiffness_, stencilRest_[i - 1], Edge(i - 1), Edge(i), state_.twist[i - 1],
                                      state_.twist[i], state_.frames[i - 1], state_.frames[i],
                                      state_.referenceTwist[i - 1]);
}

real RodActor::ElasticEnergy(internal::OwnedContributors owned) const {
  // contributors: nodes, elements, stencils (AppendContributorDofs); stencil
  // s has interior node s + 1
  int const firstElement = GetNumNodes();
  int const firstStencil = firstElement + GetNumElements();
  real energy = 0;
  for (int e = 0; e < GetNumElements(); ++e)
    if (owned(firstElement + e)) energy += internal::RodStretchEnergy(stiffness_.stretch, restLength_[e], Edge(e));
  for (int i = 1; i + 1 < GetNumNodes(); ++i)
    if (owned(firstStencil + i - 1)) energy += StencilEnergy(i);
  return energy;
}

// ---- stage interface ----

void RodActor::AppendDofBlockSizes(DynamicArray<int>& sizes) const {
  sizes.insert(sizes.end(), reference_.size(), 4);
}

void RodActor::WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const {
  // positions: t + ω × x; twist: the change of θ that keeps the material
  // frame turning with ω (the last node's twist is inert: zero)
  for (int i = 0; i < GetNumNodes(); ++i) {
    auto block = modes.middleRows(dofOffset_ + 4 * i, 4);
    block.setZero();
    block.topLeftCorner<3, 3>().setIdentity();
    block.topRightCorner<3, 3>() = -Hat(GetNodePosition(i));
    if (i < GetNumElements())
      for (int axis = 0; axis < 3; ++axis)
        block(3, 3 + axis) = internal::RodTwistUnderRotation(Edge(i), state_.frames[i], Real3::Unit(axis));
  }
}

void RodActor::WriteDofInverseMasses(Span<real> inverseMasses) const {
  // lumped: mᵢ for the node's displacement, the twist inertia for its twist
  for (int i = 0; i < GetNumNodes(); ++i) {
    for (int c = 0; c < 3; ++c) inverseMasses[dofOffset_ + 4 * i + c] = 1 / mass_[i];
    inverseMasses[dofOffset_ + 4 * i + 3] = 1 / twistInertia_[i];
  }
}

void RodActor::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  // order: node inertia blocks (4 DoFs), element stretching (the two nodes'
  // positions), interior-node stencils [xᵢ₋₁, θᵢ₋₁, xᵢ, θᵢ, xᵢ₊₁] (11
  // consecutive DoFs); AddGradientAndHessian follows it
  auto range = [this](int first, std::initializer_list<int> offsets) {
    DynamicArray<int> dofs;
    for (int k : offsets) dofs.push_back(dofOffset_ + first + k);
    return dofs;
  };
  for (int i = 0; i < GetNumNodes(); ++i) dofLists.push_back(range(4 * i, {0, 1, 2, 3}));
  for (int e = 0; e < GetNumElements(); ++e) dofLists.push_back(range(4 * e, {0, 1, 2, 4, 5, 6}));
  for (int i = 1; i + 1 < GetNumNodes(); ++i)
    dofLists.push_back(range(4 * (i - 1), {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
}

void RodActor::BeginStage(internal::StageContext const& context) {
  internal::StageCoefficients const& requested = context.coefficients;
  Real3 const& gravity = context.gravity;
  stage_ = requested.ForBody(state_.hasHistory);
  real const betaH = stage_.beta * stage_.duration;
  weight_ = stage_.InertiaWeight();
  gravity_ = gravity;
  for (int i = 0; i < GetNumNodes(); ++i) {
    Real3 velocity = stage_.aVelocity * state_.velocity[i];
    real twistVelocity = stage_.aVelocity * state_.twistVelocity[i];
    previousOffset_[i].setZero();
    twistPreviousOffset_[i] = 0;
    if (stage_.usesHistory) {
      velocity += stage_.bVelocity * state_.previousVelocity[i];
      twistVelocity += stage_.bVelocity * state_.previousTwistVelocity[i];
      previousOffset_[i] = state_.previousDisplacement[i] - state_.displacement[i];
      twistPreviousOffset_[i] = state_.previousTwist[i] - state_.twist[i];
    }
    stageStart_[i] = state_.displacement[i];
    twistStart_[i] = state_.twist[i];
    target_[i] = state_.displacement[i] + stage_.cPrevious * previousOffset_[i] + betaH * velocity;
    twistTarget_[i] = state_.twist[i] + stage_.cPrevious * twistPreviousOffset_[i] + betaH * twistVelocity;
  }
}

void RodActor::MoveToFirstIterate() {
  // Newton starts at the inertial target, as for deformable actors
  for (int i = 0; i < GetNumNodes(); ++i) {
    state_.displacement[i] = target_[i];
    state_.twist[i] = twistTarget_[i];
  }
}

real RodActor::Energy(internal::OwnedContributors owned) const {
  real energy = 0;
  for (int i = 0; i < GetNumNodes(); ++i) {
    if (!owned(i)) continue;
    Real3 const& u = state_.displacement[i];
    real const dTwist = state_.twist[i] - twistTarget_[i];
    energy += 0.5 * weight_ * (mass_[i] * (u - target_[i]).squaredNorm() + twistInertia_[i] * dTwist * dTwist) -
              mass_[i] * gravity_.dot(u);
  }
  return energy + ElasticEnergy(owned);
}

void RodActor::AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                                         internal::AssemblyOptions const& options) const {
  bool const projectHessian = options.projectHessian;
  // contributors: nodes, elements, stencils (AppendContributorDofs)
  int const numNodes = GetNumNodes(), numElements = GetNumElements();
  int const firstElement = firstContributor + numNodes;
  int const firstStencil = firstElement + numElements;
  // inertia, twist inertia and gravity, node by node
  assembler.ParallelFor(numNodes, internal::kNodeGrain, [&](int begin, int end, int) {
    for (int i = begin; i < end; ++i) {
      if (!assembler.Evaluates(firstContributor + i)) continue;
      Real3 const g = mass_[i] * (weight_ * (state_.displacement[i] - target_[i]) - gravity_);
      Eigen::Matrix<real, 4, 1> const gradient(g[0], g[1], g[2],
                                               twistInertia_[i] * weight_ * (state_.twist[i] - twistTarget_[i]));
      Eigen::Matrix<real, 4, 1> const diagonal(mass_[i], mass_[i], mass_[i], twistInertia_[i]);
      assembler.AddGradient(firstContributor + i, gradient);
      assembler.AddBlock(firstContributor + i, Eigen::Matrix<real, 4, 4>((weight_ * diagonal).asDiagonal()));
    }
  });
  assembler.ParallelFor(numElements, internal::kElementGrain, [&](int begin, int end, int) {
    internal::Vector6 g6;
    internal::Matrix6 h6;
    for (int e = begin; e < end; ++e) {
      if (!assembler.Evaluates(firstElement + e)) continue;
      internal::RodStretchGradientHessian(stiffness_.stretch, restLength_[e], Edge(e), g6, h6, projectHessian);
      assembler.AddGradient(firstElement + e, g6);
      assembler.AddBlock(firstElement + e, h6);
    }
  });
  assembler.ParallelFor(numNodes - 2, internal::kElementGrain, [&](int begin, int end, int) {
    internal::Vector11 g11;
    internal::Matrix11 h11;
    // stencil s couples elements s and s + 1: each element's frame
    // derivatives are made once per chunk and serve both of its stencils
    // (the same numbers in any chunking: the thread count changes nothing)
    internal::RodFrameDerivatives frames[2];
    auto makeFrame = [&](int e, internal::RodFrameDerivatives& frame) {
      internal::MakeRodFrameDerivatives(Edge(e), state_.frames[e], state_.twist[e], frame);
    };
    // (across MPI ranks a stencil that this rank does not evaluate breaks the
    // chain: the next one it does makes its first frame again)
    int lastFrame = -1;
    for (int s = begin; s < end; ++s) {
      if (!assembler.Evaluates(firstStencil + s)) continue;
      int const i = s + 1;  // the stencil's interior node
      if (lastFrame != i - 1) makeFrame(i - 1, frames[(i - 1) % 2]);
      makeFrame(i, frames[i % 2]);
      lastFrame = i;
      internal::RodBendTwistGradientHessian(stiffness_, stencilRest_[i - 1], frames[(i - 1) % 2],
                                            frames[i % 2], state_.twist[i - 1], state_.twist[i],
                                            state_.referenceTwist[i - 1], g11, h11, projectHessian);
      assembler.AddGradient(firstStencil + s, g11);
      assembler.AddBlock(firstStencil + s, h11);
    }
  });
}

void RodActor::SaveIterate() {
  saved_ = state_.displacement;
  twistSaved_ = state_.twist;
}

void RodActor::RestoreIterate() {
  state_.displacement = saved_;
  state_.twist = twistSaved_;
}

void RodActor::ApplyIncrementFromSaved(Span<real const> delta, real alpha) {
  for (int i = 0; i < GetNumNodes(); ++i) {
    real const* d = delta.data() + dofOffset_ + 4 * i;
    for (int c = 0; c < 3; ++c) state_.displacement[i][c] = saved_[i][c] + alpha * d[c];
    state_.twist[i] = twistSaved_[i] + alpha * d[3];
  }
}

bool RodActor::IsStateFinite() const {
  for (int i = 0; i < GetNumNodes(); ++i)
    if (!state_.displacement[i].allFinite() || !std::isfinite(state_.twist[i])) return false;
  return true;
}

void RodActor::EndStage() {
  real const betaH = stage_.beta * stage_.duration;
  state_.previousDisplacement = stageStart_;
  state_.previousVelocity = state_.velocity;
  state_.previousTwist = twistStart_;
  state_.previousTwistVelocity = state_.twistVelocity;
  state_.hasHistory = true;
  for (int i = 0; i < GetNumNodes(); ++i) {
    state_.velocity[i] =
        (state_.displacement[i] - stageStart_[i] - stage_.cPrevious * previousOffset_[i]) / betaH;
    state_.twistVelocity[i] =
        (state_.twist[i] - twistStart_[i] - stage_.cPrevious * twistPreviousOffset_[i]) / betaH;
  }
  // carry the reference frames to the new tangents (time-parallel transport);
  // the reference twist follows continuously from its stage-start branch
  for (int e = 0; e < GetNumElements(); ++e) {
    internal::RodReferenceFrame& frame = state_.frames[e];
    Real3 const t = Edge(e).normalized();
    Real3 u = internal::TransportDirector(frame.tangent, t, frame.director);
    u = (u - u.dot(t) * t).normalized();  // remove round-off drift
    frame = {t, u};
  }
  for (int i = 1; i + 1 < GetNumNodes(); ++i)
    state_.referenceTwist[i - 1] = internal::RodReferenceTwist(Edge(i - 1), Edge(i), state_.frames[i - 1],
                                                               state_.frames[i], state_.referenceTwist[i - 1]);
}

void RodActor::SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const {
  internal::SaveStateSnapshot(state_, snapshot);
}

void RodActor::RestoreSnapshot(internal::ActorSnapshot const& snapshot) {
  internal::RestoreStateSnapshot(snapshot, state_);
}

}  // namespace superdex
