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
// R ← Exp(δθ) R, docs/architecture.md "Degrees of freedom"). ArticulatedActor::ComputeLinkFrame refreshes
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

  /// The link frame's own curvature against a wrench (F at t, pure moment M)
  /// on it, between path DoFs i and j: with the DoFs' columns (u; ω) of the
  /// Jacobian, a the outer DoF (an ancestor's, or a free joint's translation
  /// before its rotation), ∂²t/∂q_a∂q_b = ω_a × u_b and ∂²θ/∂q_a∂q_b =
  /// ½ ω_a × ω_b; two rotations of one spherical or free joint (commuting to
  /// second order in Exp) take the symmetric mean, ½ (ω_a × u_b + ω_b × u_a)
  /// and 0. i <= j.
  real Curvature(int i, int j, Real3 const& force, Real3 const& moment) const {
    Real3 const ui = jacobian.col(i).head<3>(), wi = jacobian.col(i).tail<3>();
    Real3 const uj = jacobian.col(j).head<3>(), wj = jacobian.col(j).tail<3>();
    bool const sameJoint = dofLink[i] == dofLink[j] && dofRotates[i] && dofRotates[j];
    return sameJoint ? 0.5 * force.dot(wi.cross(uj) + wj.cross(ui))
                     : force.dot(wi.cross(uj)) + 0.5 * moment.dot(wi.cross(wj));
  }

  /// Adds Curvature(i, j, force, moment) of every two path DoFs i, j to
  /// `hessian` at (column(i), column(j)) and its mirror.
  template <class Column, class Matrix>
  void AddCurvature(Real3 const& force, Real3 const& moment, Column const& column, Matrix&& hessian) const {
    int const size = static_cast<int>(dofs.size());
    for (int i = 0; i < size; ++i)
      for (int j = i; j < size; ++j) {
        real const value = Curvature(i, j, force, moment);
        hessian(column(i), column(j)) += value;
        if (j != i) hessian(column(j), column(i)) += value;
      }
  }
};

}  // namespace superdex::internal
