#include <superdex/constraints/constraint.h>

#include <algorithm>
#include <limits>

#include <superdex/actors/actor.h>
#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/validate.h>

namespace superdex {

std::string_view ToString(ConstraintType type) {
  switch (type) {
    case ConstraintType::RigidSphericalJoint: return "RigidSphericalJoint";
    case ConstraintType::RigidPrismaticJoint: return "RigidPrismaticJoint";
    case ConstraintType::JointRotationRange: return "JointRotationRange";
    case ConstraintType::JointRotationTracking: return "JointRotationTracking";
    case ConstraintType::RigidPivotPosition: return "RigidPivotPosition";
    case ConstraintType::RigidPivotToRigidTarget: return "RigidPivotToRigidTarget";
    case ConstraintType::RigidPivotRotation: return "RigidPivotRotation";
    case ConstraintType::DeformableNodePosition: return "DeformableNodePosition";
    case ConstraintType::DeformableNodeToDeformableNode: return "DeformableNodeToDeformableNode";
    case ConstraintType::DeformableNodeToRigid: return "DeformableNodeToRigid";
    case ConstraintType::ArticulatedSingleDofTarget: return "ArticulatedSingleDofTarget";
    case ConstraintType::ArticulatedSingleDofRange: return "ArticulatedSingleDofRange";
    case ConstraintType::Articulated3dRotationTarget: return "Articulated3dRotationTarget";
    case ConstraintType::Articulated3dRotationRange: return "Articulated3dRotationRange";
    case ConstraintType::RodElementRotationToRigid: return "RodElementRotationToRigid";
  }
  return "Unknown";
}

std::string_view ToString(QueryType type) {
  switch (type) {
    case QueryType::ConstraintForce: return "ConstraintForce";
  }
  return "Unknown";
}

Constraint::Constraint(Layout layout, internal::CompliantParams const& params)
    : type_(layout.type),
      dimension_(layout.dimension),
      numActors_(layout.actors[1] ? 2 : 1),
      targetKind_(layout.targetKind),
      isRange_(layout.isRange),
      hasCurvature_(layout.hasCurvature),
      actors_(layout.actors),
      localDofs_(std::move(layout.localDofs)),
      params_(params),
      stageParams_(params),
      stageStartValue_(VectorX::Zero(layout.dimension)) {
  // an articulated link: the type's DoFs are its frame's rigid increments,
  // the constraint's the joint DoFs of its path
  for (int a = 0; a < numActors_; ++a) {
    typeNumDofs_ += static_cast<int>(localDofs_[a].size());
    if (layout.links[a] < 0) continue;
    links_[a] = layout.links[a];
    paths_[a] = static_cast<ArticulatedActor const*>(actors_[a])->GetLinkPath(links_[a]);
    typeDofs_[a] = std::move(localDofs_[a]);
    localDofs_[a] = paths_[a].dofs;
  }
  RefreshDofs();
  force_.assign(dofs_.size(), 0);
}

Actor* Constraint::GetActor(int i) const { return (i >= 0 && i < numActors_) ? actors_[i] : nullptr; }

Span<int const> Constraint::GetDofIndicesForActor(int i) const {
  if (i < 0 || i >= numActors_) return {};
  return slotDofs_[i];
}

void Constraint::RefreshDofs() {
  // actor 0's DoFs, then actor 1's not listed yet (two links of one
  // articulated actor share their paths' common DoFs: one column each)
  dofs_.clear();
  for (int a = 0; a < numActors_; ++a) {
    slotDofs_[a].clear();
    slotColumns_[a].clear();
    for (int local : localDofs_[a]) {
      int const dof = actors_[a]->GetDofOffset() + local;
      auto const found = std::find(dofs_.begin(), dofs_.end(), dof);
      slotDofs_[a].push_back(dof);
      slotColumns_[a].push_back(static_cast<int>(found - dofs_.begin()));
      if (found == dofs_.end()) dofs_.push_back(dof);
    }
  }
}

bool Constraint::SetStiffness(real stiffness, Error& error) {
  if (!internal::CheckNonNegative(stiffness, "stiffness", error)) return false;
  params_.stiffness = stiffness;
  stageParams_ = params_;
  nearRigidCapped_ = false;
  return true;
}

bool Constraint::SetDamping(real damping, Error& error) {
  if (!internal::CheckNonNegative(damping, "damping", error)) return false;
  params_.damping = damping;
  stageParams_ = params_;
  nearRigidCapped_ = false;
  return true;
}

bool Constraint::SetSaturation(real saturation, Error& error) {
  if (!internal::CheckFinite(saturation, "saturation", error)) return false;
  params_.saturation = saturation;
  stageParams_ = params_;
  nearRigidCapped_ = false;
  return true;
}

bool Constraint::SetHessianApproximation(ConstraintHessian hessian, Error& error) {
  if (!internal::CheckConstraintHessian(hessian, "hessianApproximation", true, error)) return false;
  hessian_ = hessian;
  return true;
}

void Constraint::ReportNotSupported(std::string_view method, std::string_view why,
                                    Error& error) const {
  error.Set(ErrorCode::NotSupported, std::string(method) + " does not apply to a " +
                                         std::string(ToString(type_)) + " constraint" +
                                         std::string(why));
}

bool Constraint::RequireTarget(TargetKind kind, std::string_view method, Error& error) const {
  if (targetKind_ == kind) return true;
  ReportNotSupported(method, "", error);
  return false;
}

bool Constraint::SetTargetPosition(Real3 const& position, Error& error) {
  if (!RequireTarget(TargetKind::Position, "SetTargetPosition", error) ||
      !internal::CheckFinite(position, "position", error))
    return false;
  for (int i = 0; i < 3; ++i) target_[i] = position[i];
  return true;
}

bool Constraint::SetTargetRotation(Quat const& rotation, Error& error) {
  if (!RequireTarget(TargetKind::Rotation, "SetTargetRotation", error) ||
      !internal::CheckUnitQuat(rotation, "rotation", error))
    return false;
  Quat const q = rotation.normalized();
  target_[0] = q.w(), target_[1] = q.x(), target_[2] = q.y(), target_[3] = q.z();
  return true;
}

bool Constraint::SetTargetTransform(Real3 const& position, Quat const& rotation, Error& error) {
  if (!RequireTarget(TargetKind::Transform, "SetTargetTransform", error) ||
      !internal::CheckFinite(position, "position", error) ||
      !internal::CheckUnitQuat(rotation, "rotation", error))
    return false;
  Quat const q = rotation.normalized();
  for (int i = 0; i < 3; ++i) target_[i] = position[i];
  target_[3] = q.w(), target_[4] = q.x(), target_[5] = q.y(), target_[6] = q.z();
  return true;
}

bool Constraint::SetTargetDof(real value, Error& error) {
  if (!RequireTarget(TargetKind::Dof, "SetTargetDof", error) ||
      !internal::CheckFinite(value, "value", error))
    return false;
  target_[0] = value;
  return true;
}

bool Constraint::UpdateOldTarget(Error& error) {
  if (targetKind_ == TargetKind::None) {
    ReportNotSupported("UpdateOldTarget", " (it has no target)", error);
    return false;
  }
  oldTarget_ = target_;
  return true;
}

void Constraint::InitializeTarget(Target const& target) {
  target_ = target;
  oldTarget_ = target;
}

namespace {
// out[i] = a[i] + s (b[i] − a[i]) for i in [first, first + count)
template <class Target>
void Lerp(Target const& a, Target const& b, real s, int first, int count, Target& out) {
  for (int i = first; i < first + count; ++i) out[i] = a[i] + s * (b[i] - a[i]);
}

// the unit quaternion (w, x, y, z) at `first`: slerp from a's to b's (shortest arc)
template <class Target>
void Slerp(Target const& a, Target const& b, real s, int first, Target& out) {
  Quat const qa(a[first], a[first + 1], a[first + 2], a[first + 3]);
  Quat const qb(b[first], b[first + 1], b[first + 2], b[first + 3]);
  Quat const q = qa.slerp(s, qb).normalized();
  out[first] = q.w(), out[first + 1] = q.x(), out[first + 2] = q.y(), out[first + 3] = q.z();
}
}  // namespace

void Constraint::SetTargetBetween(Target const& from, Target const& to, real s) {
  if (s == 1 || from == to) {
    target_ = to;
    return;
  }
  switch (targetKind_) {
    case TargetKind::None: break;
    case TargetKind::Position: Lerp(from, to, s, 0, 3, target_); break;
    case TargetKind::Dof: Lerp(from, to, s, 0, 1, target_); break;
    case TargetKind::Rotation: Slerp(from, to, s, 0, target_); break;
    case TargetKind::Transform:
      Lerp(from, to, s, 0, 3, target_);
      Slerp(from, to, s, 3, target_);
      break;
  }
}

Real3 Constraint::TargetPosition(Span<real const> target) { return {target[0], target[1], target[2]}; }

Quat Constraint::TargetRotation(Span<real const> target, int offset) {
  return Quat(target[offset], target[offset + 1], target[offset + 2], target[offset + 3]);
}

Real3 Constraint::BodyPosition(int i) const {
  return links_[i] >= 0 ? paths_[i].position : static_cast<RigidActor const*>(actors_[i])->GetPosition();
}

Quat Constraint::BodyRotation(int i) const {
  return links_[i] >= 0 ? paths_[i].rotation : static_cast<RigidActor const*>(actors_[i])->GetRotation();
}

void Constraint::RefreshLinkFrames() const {
  for (int a = 0; a < numActors_; ++a)
    if (links_[a] >= 0) static_cast<ArticulatedActor const*>(actors_[a])->ComputeLinkFrame(paths_[a]);
}

DynamicArray<real> Constraint::GetDeviation() const {
  RefreshLinkFrames();
  VectorX g(dimension_);
  MatrixX jacobian(dimension_, typeNumDofs_);
  DoEvaluate(target_, g, jacobian);
  return DynamicArray<real>(g.begin(), g.end());
}

bool Constraint::IsQuerySupported(QueryType type) const { return type == QueryType::ConstraintForce; }

bool Constraint::RegisterQuery(QueryType type, Error& error) {
  if (!IsQuerySupported(type)) {
    ReportNotSupported("RegisterQuery(" + std::string(ToString(type)) + ")", "", error);
    return false;
  }
  forceQueryRegistered_ = true;
  return true;
}

Span<real const> Constraint::GetForce(Error& error) const {
  if (!forceQueryRegistered_) {
    error.Set(ErrorCode::InvalidState,
              "GetForce needs RegisterQuery(QueryType::ConstraintForce) before stepping");
    return {};
  }
  if (!forceValid_) {
    error.Set(ErrorCode::InvalidState,
              "GetForce: no step has completed since the ConstraintForce query was registered");
    return {};
  }
  return force_;
}

void Constraint::DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const {
  lower.assign(dimension_, -std::numeric_limits<real>::infinity());
  upper.assign(dimension_, std::numeric_limits<real>::infinity());
}

void Constraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const&,
                                Eigen::Ref<MatrixX>) const {}

DynamicArray<real> Constraint::GetLimits(bool upper, std::string_view method, Error& error) const {
  if (!isRange_) {
    ReportNotSupported(method, " (not a range type)", error);
    return {};
  }
  DynamicArray<real> lower, upperValues;
  DoGetLimits(lower, upperValues);
  return upper ? upperValues : lower;
}

DynamicArray<real> Constraint::GetLimitMinValues(Error& error) const {
  return GetLimits(false, "GetLimitMinValues", error);
}

DynamicArray<real> Constraint::GetLimitMaxValues(Error& error) const {
  return GetLimits(true, "GetLimitMaxValues", error);
}

// ---- stage interface ----

void Constraint::Evaluate(Span<real const> target, internal::ConstraintWorkspace& ws) const {
  int const m = dimension_, n = static_cast<int>(dofs_.size());
  if (!HasLinks()) {
    DoEvaluate(target, ws.g.head(m), ws.jacobian.topLeftCorner(m, n));
    return;
  }
  // J = J_type B: B maps the constraint's DoFs to the type's (the identity
  // on a rigid body or a deformable's DoFs; a link's kinematic Jacobian rows)
  RefreshLinkFrames();
  int const k = typeNumDofs_;
  auto typeJacobian = ws.typeJacobian.topLeftCorner(m, k);
  DoEvaluate(target, ws.g.head(m), typeJacobian);
  auto map = ws.linkMap.topLeftCorner(k, n);
  map.setZero();
  // (a DoF on both links' paths, a kinematic loop, sums its two columns)
  for (int a = 0, row = 0; a < numActors_; ++a) {
    DynamicArray<int> const& columns = slotColumns_[a];
    int const size = static_cast<int>(columns.size());
    if (links_[a] < 0) {
      for (int j = 0; j < size; ++j) map(row++, columns[j]) = 1;
    } else {
      for (int local : typeDofs_[a]) {
        for (int j = 0; j < size; ++j) map(row, columns[j]) += paths_[a].jacobian(local, j);
        ++row;
      }
    }
  }
  ws.jacobian.topLeftCorner(m, n).noalias() = typeJacobian * map;
}

void Constraint::AddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                              internal::ConstraintWorkspace& ws, Eigen::Ref<MatrixX> hessian) const {
  if (!HasLinks()) {
    DoAddCurvature(target, weights, hessian);
    return;
  }
  int const m = dimension_, n = static_cast<int>(dofs_.size()), k = typeNumDofs_;
  // Bᵀ G B, G the type's curvature over its rigid DoFs
  ws.typeCurvature.setZero(k, k);
  DoAddCurvature(target, weights, ws.typeCurvature);
  auto const map = ws.linkMap.topLeftCorner(k, n);
  auto product = ws.product.topLeftCorner(k, n);
  product.noalias() = ws.typeCurvature * map;
  hessian.noalias() += map.transpose() * product;
  // each link frame's own curvature against the type's wrench (F; M) = J_typeᵀ w
  // on it (internal::LinkPath::Curvature)
  auto const typeJacobian = ws.typeJacobian.topLeftCorner(m, k);
  for (int a = 0, typeColumn = 0; a < numActors_; ++a) {
    DynamicArray<int> const& columns = slotColumns_[a];
    int const size = static_cast<int>(columns.size());
    if (links_[a] < 0) {
      typeColumn += size;
      continue;
    }
    Eigen::Matrix<real, 6, 1> wrench = Eigen::Matrix<real, 6, 1>::Zero();
    for (int local : typeDofs_[a]) wrench[local] = typeJacobian.col(typeColumn++).dot(weights);
    Real3 const force = wrench.head<3>(), moment = wrench.tail<3>();
    internal::LinkPath const& path = paths_[a];
    for (int i = 0; i < size; ++i) {
      for (int j = i; j < size; ++j) {
        real const value = path.Curvature(i, j, force, moment);
        hessian(columns[i], columns[j]) += value;
        if (j != i) hessian(columns[j], columns[i]) += value;
      }
    }
  }
}

bool Constraint::BeginStage(real h, real nearRigidBeta, Span<real const> inverseMasses,
                            internal::ConstraintWorkspace& ws) {
  // g(qᵢ⁰, p̂ᵢ⁰): the actors are at the stage start, the old target is p̂ᵢ⁰
  stageDuration_ = h;
  Evaluate(oldTarget_, ws);
  stageStartValue_ = ws.g.head(dimension_);
  linearValue_.resize(dimension_);
  trialValue_.resize(dimension_);
  linearJacobian_.resize(dimension_, static_cast<Eigen::Index>(dofs_.size()));
  forceEstimate_.resize(dimension_);
  linearActive_ = false;
  forceEstimateValid_ = false;
  // the near-rigid cap from the stage-start Jacobian (off: k and d as set)
  nearRigidCapped_ = false;
  stageParams_ = params_;
  if (nearRigidBeta > 0)
    stageParams_ = internal::NearRigidParams(params_, h, nearRigidBeta,
                                             InverseEffectiveMass(inverseMasses, ws), nearRigidCapped_);
  return nearRigidCapped_;
}

real Constraint::InverseEffectiveMass(Span<real const> inverseMasses,
                                      internal::ConstraintWorkspace const& ws) const {
  // the largest diagonal entry of J diag(M⁻¹) Jᵀ: row i alone, with every
  // other row free, oscillates at ω² = k wᵢ
  int const n = static_cast<int>(dofs_.size());
  real w = 0;
  for (int i = 0; i < dimension_; ++i) {
    real row = 0;
    for (int j = 0; j < n; ++j) row += ws.jacobian(i, j) * ws.jacobian(i, j) * inverseMasses[dofs_[j]];
    w = std::max(w, row);
  }
  return w;
}

real Constraint::Energy(real h, internal::ConstraintWorkspace& ws) const {
  Evaluate(target_, ws);
  auto const g = ws.g.head(dimension_);
  if (isRange_ && internal::IsRangeInactive(g, stageStartValue_)) return 0;
  return internal::CompliantEnergy(stageParams_, g, stageStartValue_, h);
}

real Constraint::Linearize(real h, internal::ConstraintWorkspace& ws) const {
  Evaluate(target_, ws);
  int const m = dimension_, n = static_cast<int>(dofs_.size());
  auto const g = ws.g.head(m);
  if (isRange_ && internal::IsRangeInactive(g, stageStartValue_)) return -1;
  auto const jacobian = ws.jacobian.topLeftCorner(m, n);
  // range types are piecewise in q (one-sided): their curvature keeps f(g)
  // and they take no part in second-order corrections
  linearActive_ = !isRange_;
  if (linearActive_) {
    linearValue_ = g;
    linearJacobian_ = jacobian;
  }
  real const scale =
      internal::CompliantForceCoefficients(stageParams_, g, stageStartValue_, h, ws.f.head(m));
  ws.r.head(n).noalias() = jacobian.transpose() * ws.f.head(m);
  return scale;
}

Eigen::Ref<VectorX const> Constraint::CurvatureWeights(internal::ConstraintWorkspace const& ws) const {
  // G = Σᵢ f̂ᵢ ∂²gᵢ/∂q², the joint forces' geometric stiffness. After the
  // first step of a stage f̂ is the linearized constraint's force, not f(g):
  // a step along a curved constraint manifold leaves g with a second-order
  // error that a stiff k turns into a large, spurious force (and an
  // indefinite G); f̂ is the estimate a primal–dual Newton method carries.
  if (forceEstimateValid_) return forceEstimate_;
  return ws.f.head(dimension_);
}

ConstraintHessian Constraint::HessianMode(ConstraintHessian sceneHessian) const {
  ConstraintHessian const mode = hessian_ == ConstraintHessian::SceneDefault ? sceneHessian : hessian_;
  return hasCurvature_ ? mode : ConstraintHessian::GaussNewton;
}

void Constraint::AddCurvatureTerm(Eigen::Ref<MatrixX const> const& curvature, bool diagonal,
                                  Eigen::Ref<MatrixX> hessian) {
  if (!diagonal) {
    hessian += curvature;
    return;
  }
  // PSD: G replaced by the diagonal of its column norms (Andrews et al.)
  for (Eigen::Index j = 0; j < curvature.cols(); ++j) hessian(j, j) += curvature.col(j).norm();
}

void Constraint::AddGradientAndHessian(real h, internal::HessianAssembler& assembler, int contributor,
                                       ConstraintHessian sceneHessian, bool projectHessian,
                                       internal::ConstraintWorkspace& ws) const {
  real const scale = Linearize(h, ws);
  if (scale < 0) return;
  int const m = dimension_, n = static_cast<int>(dofs_.size());
  auto const jacobian = ws.jacobian.topLeftCorner(m, n);
  assembler.AddGradient(contributor, ws.r.head(n));
  auto hessian = ws.hessian.topLeftCorner(n, n);
  hessian.noalias() = scale * jacobian.transpose() * jacobian;

  ConstraintHessian const mode = HessianMode(sceneHessian);
  if (mode != ConstraintHessian::GaussNewton) {
    auto curvature = ws.curvature.topLeftCorner(n, n);
    curvature.setZero();
    AddCurvature(target_, CurvatureWeights(ws), ws, curvature);
    AddCurvatureTerm(curvature, projectHessian || mode == ConstraintHessian::GeometricStiffnessDiagonal, hessian);
  }
  assembler.AddBlock(contributor, hessian);
}

int Constraint::FoldableLinkSlot() const {
  if (numActors_ == 1) return links_[0] >= 0 ? 0 : -1;
  if ((links_[0] >= 0) == (links_[1] >= 0)) return -1;  // two links, or none
  return links_[0] >= 0 ? 0 : 1;
}

internal::StageDofs const* Constraint::GetLinkOwner() const {
  return &actors_[FoldableLinkSlot()]->GetStageDofs();
}

Span<int const> Constraint::GetOtherDofs() const {
  if (numActors_ < 2) return {};
  return slotDofs_[1 - FoldableLinkSlot()];
}

Span<int const> Constraint::GetOtherColumns() const {
  if (numActors_ < 2) return {};
  return slotColumns_[1 - FoldableLinkSlot()];
}

bool Constraint::AddLinkTerms(bool projectHessian, internal::TermWorkspace& ws,
                              internal::TermWorkspace::FoldedBlock& hessian,
                              Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const {
  return AddFoldedTerms(stageDuration_, sceneHessian_, projectHessian, FoldableLinkSlot(), ws, hessian,
                        curvatureWrench, exactCurvature);
}

bool Constraint::AddFoldedTerms(real h, ConstraintHessian sceneHessian, bool projectHessian, int linkSlot,
                                internal::ConstraintWorkspace& ws, internal::TermWorkspace::FoldedBlock& hessian,
                                Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const {
  int const other = numActors_ == 2 ? 1 - linkSlot : -1;
  int const numOther = other >= 0 ? static_cast<int>(localDofs_[other].size()) : 0;
  hessian.setZero(6 + numOther, 6 + numOther);
  curvatureWrench.setZero();
  exactCurvature = false;
  real const scale = Linearize(h, ws);
  if (scale < 0) return false;
  // the type's Hessian over its DoFs (slot order: the link's rigid DoFs, a
  // subset of the six, and the other body's), placed at the link frame's
  // six increments and then the other body's DoFs
  int const m = dimension_, k = typeNumDofs_;
  auto const typeJacobian = ws.typeJacobian.topLeftCorner(m, k);
  DynamicArray<int> const& rigid = typeDofs_[linkSlot];
  int const numRigid = static_cast<int>(rigid.size());
  int const linkColumn = linkSlot == 0 ? 0 : numOther;  // the link's first type column
  auto place = [&](int c) {
    return c >= linkColumn && c < linkColumn + numRigid ? rigid[c - linkColumn] : 6 + (c < linkColumn ? c : c - numRigid);
  };
  ws.typeCurvature.noalias() = scale * typeJacobian.transpose() * typeJacobian;
  ConstraintHessian const mode = HessianMode(sceneHessian);
  if (mode != ConstraintHessian::GaussNewton) {
    Eigen::Ref<VectorX const> const weights = CurvatureWeights(ws);
    // (ws.curvature's corner: the type's curvature over its DoFs)
    auto curvature = ws.curvature.topLeftCorner(k, k);
    curvature.setZero();
    DoAddCurvature(target_, weights, curvature);
    bool const diagonal = projectHessian || mode == ConstraintHessian::GeometricStiffnessDiagonal;
    AddCurvatureTerm(curvature, diagonal, ws.typeCurvature);
    exactCurvature = !diagonal;
    for (int c = 0; c < numRigid; ++c) curvatureWrench[rigid[c]] = typeJacobian.col(linkColumn + c).dot(weights);
  }
  for (int a = 0; a < k; ++a)
    for (int b = 0; b < k; ++b) hessian(place(a), place(b)) = ws.typeCurvature(a, b);
  return true;
}

void Constraint::AddLinearizedChange(Span<real const> delta, real alpha, Eigen::Ref<VectorX> g) const {
  for (std::size_t j = 0; j < dofs_.size(); ++j) g += (alpha * delta[dofs_[j]]) * linearJacobian_.col(j);
}

void Constraint::PredictForce(real h, Span<real const> delta, real alpha, bool corrected) {
  if (!linearActive_) return;
  forceEstimate_ = corrected ? trialValue_ : linearValue_;
  AddLinearizedChange(delta, alpha, forceEstimate_);
  // f is evaluated in place: CompliantForceCoefficients reads g before it writes f
  internal::CompliantForceCoefficients(stageParams_, forceEstimate_, stageStartValue_, h, forceEstimate_);
  forceEstimateValid_ = true;
}

void Constraint::AddCorrectionForce(real h, Span<real const> delta, Span<real> gradient,
                                    internal::ConstraintWorkspace& ws) {
  if (!linearActive_) return;
  int const m = dimension_, n = static_cast<int>(dofs_.size());
  Evaluate(target_, ws);
  trialValue_ = ws.g.head(m);
  // ws.r ← f(g + J δ), ws.f ← f(g(q + δ)) − ws.r
  auto predicted = ws.r.head(m);
  predicted = linearValue_;
  AddLinearizedChange(delta, 1, predicted);
  internal::CompliantForceCoefficients(stageParams_, ws.g.head(m), stageStartValue_, h, ws.f.head(m));
  internal::CompliantForceCoefficients(stageParams_, predicted, stageStartValue_, h, predicted);
  ws.f.head(m) -= predicted;
  for (int j = 0; j < n; ++j) gradient[dofs_[j]] += linearJacobian_.col(j).dot(ws.f.head(m));
}

void Constraint::EndStage(real h, internal::ConstraintWorkspace& ws) {
  if (forceQueryRegistered_) {
    int const m = dimension_, n = static_cast<int>(dofs_.size());
    Evaluate(target_, ws);
    auto const g = ws.g.head(m);
    if (isRange_ && internal::IsRangeInactive(g, stageStartValue_)) {
      std::fill(force_.begin(), force_.end(), 0);
    } else {
      internal::CompliantForceCoefficients(stageParams_, g, stageStartValue_, h, ws.f.head(m));
      ws.r.head(n).noalias() = ws.jacobian.topLeftCorner(m, n).transpose() * ws.f.head(m);
      for (int i = 0; i < n; ++i) force_[i] = -ws.r[i];
    }
    forceValid_ = true;
  }
  oldTarget_ = target_;
}

}  // namespace superdex
