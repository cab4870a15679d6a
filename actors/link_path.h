// internal::LinkPath: an articulated link seen as a rigid body by a
// constraint (constraints/constraint.h). The link's frame moves with the
// joints from the root to the link; over their DoFs (`dofs`, the actor's
// local indices, ascending: root first) the frame's increments are
//
//   δt = Σₖ (v_k + ω_k × t) δq_k,   δθ = Σₖ ω_k δq_k,
//
// (ω_k; v_k) DoF k's world motion (v at the world origin), t the frame's
// origin: `jacobian` holds the columns (v_k + ω_k × t; ω_k), in the order of a
// rigid body's DoFs (translation, then the world rotation increment of
// R ← Exp(δθ) R, design.md §3). ArticulatedActor::ComputeLinkFrame refreshes
// position, rotation and jacobian at the actor's current iterate.
#pragma once

#include <superdex/core/types.h>

namespace superdex::internal {

struct LinkPath {
  int link = -1;
  DynamicArray<int> links;       ///< the links from the root to `link`, root first
  DynamicArray<int> dofs;        ///< their joints' DoFs (local indices), ascending
  DynamicArray<int> dofLink;     ///< the link whose joint holds each of `dofs`
  DynamicArray<char> dofRotates; ///< 1 where that DoF turns its joint (revolute, spherical, free rotation)
  Real3 position = Real3::Zero();  ///< the link frame's origin t, world
  Quat rotation = Quat::Identity();
  Eigen::Matrix<real, 6, Eigen::Dynamic> jacobian;  ///< (δt; δθ) per DoF of `dofs`
};

}  // namespace superdex::internal
