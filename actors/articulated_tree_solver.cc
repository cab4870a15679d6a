#include <superdex/actors/articulated_tree_solver.h>

namespace superdex::internal {

void ArticulatedTreeSolver::Reserve(int numJoints) {
  articulated_.resize(static_cast<std::size_t>(numJoints));
  eliminated_.resize(static_cast<std::size_t>(numJoints));
  bias_.resize(static_cast<std::size_t>(numJoints));
  motionSum_.resize(static_cast<std::size_t>(numJoints));
  pivots_.resize(static_cast<std::size_t>(numJoints));
}

bool ArticulatedTreeSolver::Solve(System const& system, Span<real const> b, Span<real> x, int* failedJoint) {
  int const numJoints = static_cast<int>(system.parent.size());
  if (static_cast<int>(articulated_.size()) != numJoints) Reserve(numJoints);
  using Columns = Eigen::Matrix<real, 6, Eigen::Dynamic, 0, 6, 6>;
  using Block = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
  using Local = Eigen::Matrix<real, Eigen::Dynamic, 1, 0, 6, 1>;
  for (int i = 0; i < numJoints; ++i) {
    articulated_[i] = system.own[i];
    eliminated_[i].setZero();
    bias_[i].setZero();
  }
  // leaves up: each joint's pivot, then its contribution to its parent
  for (int i = numJoints - 1; i >= 0; --i) {
    int const m = system.numDofs[i], first = system.dofStart[i], parent = system.parent[i];
    Matrix6 passed = articulated_[i];  // Yᴬ_i − Z_i, what the parent adds
    Vector6 carried = bias_[i];        // Σ q over i's subtree, q_i included
    if (m > 0) {
      auto const s = system.motion.middleCols(first, m);
      Block pivot = system.jointBlocks[i].topLeftCorner(m, m) - s.transpose() * eliminated_[i] * s;
      pivots_[i].compute(pivot);
      if (pivots_[i].info() != Eigen::Success || !(pivots_[i].matrixLLT().diagonal().minCoeff() > 0)) {
        if (failedJoint != nullptr) *failedJoint = i;
        return false;
      }
      // H_ji = S_jᵀ Yᴬ_i S_i for every strict ancestor j, H_ij its transpose:
      // Z_i = (Yᴬ_i S_i) Dᵢ⁻¹ (Yᴬ_i S_i)ᵀ, symmetric though Yᴬ_i is not
      Columns const right = articulated_[i] * s;
      Matrix6 const z = right * pivots_[i].solve(Block(right.transpose()));
      Local const reduced = Eigen::Map<Local const>(b.data() + first, m) - s.transpose() * bias_[i];
      carried += right * pivots_[i].solve(reduced);
      passed -= z;
      if (parent >= 0) eliminated_[parent] += eliminated_[i] + z;
    } else if (parent >= 0) {
      eliminated_[parent] += eliminated_[i];
    }
    if (parent >= 0) {
      articulated_[parent] += passed;
      bias_[parent] += carried;
    }
  }
  // roots down: x_i = Dᵢ⁻¹ (b̃_i − S_iᵀ Yᴬ_iᵀ Σ_{j strict ancestor} S_j x_j)
  for (int i = 0; i < numJoints; ++i) {
    int const m = system.numDofs[i], first = system.dofStart[i], parent = system.parent[i];
    Vector6 const above = parent >= 0 ? motionSum_[parent] : Vector6::Zero();
    motionSum_[i] = above;
    if (m == 0) continue;
    auto const s = system.motion.middleCols(first, m);
    Local const reduced = Eigen::Map<Local const>(b.data() + first, m) - s.transpose() * bias_[i] -
                          s.transpose() * (articulated_[i].transpose() * above);
    Local const solved = pivots_[i].solve(reduced);
    Eigen::Map<Local>(x.data() + first, m) = solved;
    motionSum_[i] += s * solved;
  }
  return true;
}

}  // namespace superdex::internal
