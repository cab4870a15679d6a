// TermWorkspace: dense scratch for evaluating one term's local block — a
// constraint's g, J, forces and Hessian over its DoF list, and the terms an
// own-block solve takes into its tree (stage/own_block_solve.h). Owned by
// whoever drives the evaluation, one per thread, sized once per pattern build
// to the largest term: nothing is allocated while Newton runs.
#pragma once

#include <superdex/core/types.h>

namespace superdex::internal {

struct TermWorkspace {
  /// The most DoFs a constraint type's kinematics couple (RigidSphericalJoint:
  /// 12, six per rigid body); with an articulated link in place of a rigid
  /// body a constraint's n is larger (its path's joint DoFs), its type's is not.
  static constexpr int kMaxDofs = 12;
  using Block = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDofs, kMaxDofs>;
  /// A term taken into an articulated link (LinkTerm::AddLinkTerms): the link
  /// frame's six increments and the other body's DoFs (at most kMaxDofs: a
  /// rod element's eight)
  using FoldedBlock = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 6 + kMaxDofs, 6 + kMaxDofs>;

  VectorX g, f, r;
  MatrixX jacobian, hessian;
  MatrixX curvature;  ///< G over the term's n DoFs (or a folded type's, at most kMaxDofs)
  // a term on articulated links: the type's J and G over its rigid DoFs, the
  // map from the term's DoFs to them, and a product
  MatrixX typeJacobian, linkMap, product;
  Block typeCurvature;
  /// Sizes every buffer for terms of dimension <= maxDimension and
  /// <= maxDofs DoFs.
  void Reserve(int maxDimension, int maxDofs);
};

}  // namespace superdex::internal
