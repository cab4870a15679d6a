#include <superdex/constraints/constraint_kernel.h>

#include <algorithm>
#include <limits>

#include <superdex/actors/articulated_actor.h>
#include <superdex/actors/rigid_actor.h>

namespace superdex {

std::string_view ToString(ConstraintType type) {
  switch (type) {
#define SUPERDEX_CONSTRAINT_TYPE_NAME(Name, Class, file) \
  case ConstraintType::Name: return #Name;
    SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_CONSTRAINT_TYPE_NAME)
#undef SUPERDEX_CONSTRAINT_TYPE_NAME
  }
  return "Unknown";
}

namespace internal {

ConstraintKernel::ConstraintKernel(Layout layout)
    : type_(layout.type),
      dimension_(layout.dimension),
      numActors_(layout.actors[1] ? 2 : 1),
      targetKind_(layout.targetKind),
      isRange_(layout.isRange),
      hasCurvature_(layout.hasCurvature),
      actors_(layout.actors),
      localDofs_(std::move(layout.localDofs)) {
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
}

Span<int const> ConstraintKernel::GetDofIndicesForActor(int i) const {
  if (i < 0 || i >= numActors_) return {};
  return slotDofs_[i];
}

void ConstraintKernel::RefreshDofs() {
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

Real3 ConstraintKernel::TargetPosition(Span<real const> target) { return {target[0], target[1], target[2]}; }

Quat ConstraintKernel::TargetRotation(Span<real const> target, int offset) {
  return Quat(target[offset], target[offset + 1], target[offset + 2], target[offset + 3]);
}

Real3 ConstraintKernel::BodyPosition(int i) const {
  return links_[i] >= 0 ? paths_[i].position : static_cast<RigidActor const*>(actors_[i])->GetPosition();
}

Quat ConstraintKernel::BodyRotation(int i) const {
  return links_[i] >= 0 ? paths_[i].rotation : static_cast<RigidActor const*>(actors_[i])->GetRotation();
}

void ConstraintKernel::RefreshLinkFrames() const {
  for (int a = 0; a < numActors_; ++a)
    if (links_[a] >= 0) static_cast<ArticulatedActor const*>(actors_[a])->ComputeLinkFrame(paths_[a]);
}

VectorX ConstraintKernel::Value(Span<real const> target) const {
  RefreshLinkFrames();
  VectorX g(dimension_);
  MatrixX jacobian(dimension_, typeNumDofs_);
  DoEvaluate(target, g, jacobian);
  return g;
}

void ConstraintKernel::DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const {
  lower.assign(dimension_, -std::numeric_limits<real>::infinity());
  upper.assign(dimension_, std::numeric_limits<real>::infinity());
}

void ConstraintKernel::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const&,
                                Eigen::Ref<MatrixX>) const {}

// ---- g, J and curvature over the scene's DoFs ----

void ConstraintKernel::Evaluate(Span<real const> target, TermWorkspace& ws) const {
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

void ConstraintKernel::AddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                              TermWorkspace& ws, Eigen::Ref<MatrixX> hessian) const {
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
  // on it (LinkPath::Curvature)
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
    paths_[a].AddCurvature(wrench.head<3>(), wrench.tail<3>(), [&](int i) { return columns[i]; }, hessian);
  }
}

int ConstraintKernel::FoldableLinkSlot() const {
  if (numActors_ == 1) return links_[0] >= 0 ? 0 : -1;
  if ((links_[0] >= 0) == (links_[1] >= 0)) return -1;  // two links, or none
  return links_[0] >= 0 ? 0 : 1;
}

}  // namespace internal
}  // namespace superdex
