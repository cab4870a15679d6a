#include <superdex/stage/term_workspace.h>

#include <algorithm>

namespace superdex::internal {

void TermWorkspace::Reserve(int maxDimension, int maxDofs) {
  g.resize(maxDimension);
  f.resize(maxDimension);
  r.resize(std::max(maxDofs, maxDimension));
  jacobian.resize(maxDimension, maxDofs);
  hessian.resize(maxDofs, maxDofs);
  // (also the type's curvature of a folded constraint: up to kMaxDofs, more
  // than a short path's n)
  curvature.resize(std::max(maxDofs, kMaxDofs), std::max(maxDofs, kMaxDofs));
  typeJacobian.resize(maxDimension, kMaxDofs);
  linkMap.resize(kMaxDofs, maxDofs);
  product.resize(kMaxDofs, maxDofs);
}

}  // namespace superdex::internal
