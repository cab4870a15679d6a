#include <superdex/actors/articulated_tree_solver.h>

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include <superdex/core/so3.h>

namespace superdex::internal {

namespace {
using Block = Eigen::Matrix<real, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
using Local = Eigen::Matrix<real, Eigen::Dynamic, 1, 0, 6, 1>;
using Vector6 = ArticulatedTreeSolver::Vector6;

/// X m: a motion (ω; v) about a point, about the point r after it
Vector6 ShiftMotion(Real3 const& r, Vector6 const& m) {
  Vector6 out;
  out << m.head<3>(), m.tail<3>() - r.cross(m.head<3>());
  return out;
}

/// Xᵀ f: a force (n; f) about a point, about the point r before it
Vector6 ShiftForce(Real3 const& r, Vector6 const& f) {
  Vector6 out;
  out << f.head<3>() + r.cross(f.tail<3>()), f.tail<3>();
  return out;
}
}  // namespace

ArticulatedTreeSolver::Matrix6 ArticulatedTreeSolver::ShiftToParent(Real3 const& r, Matrix6 const& y) {
  // X = [[I, 0], [−R, I]], R = [r]×: Y X = [[A − B R, B], [C − D R, D]],
  // Xᵀ (Y X) = [[I, R], [0, I]] (Y X)
  Real33 const hat = Hat(r);
  Matrix6 yx;
  yx.leftCols<3>() = y.leftCols<3>() - y.rightCols<3>() * hat;
  yx.rightCols<3>() = y.rightCols<3>();
  Matrix6 out;
  out.topRows<3>() = yx.topRows<3>() + hat * yx.bottomRows<3>();
  out.bottomRows<3>() = yx.bottomRows<3>();
  return out;
}

void ArticulatedTreeSolver::Reserve(int numJoints) {
  std::size_t const n = static_cast<std::size_t>(numJoints);
  articulated_.resize(n);
  metric_.resize(n);
  right_.resize(n);
  bias_.resize(n);
  motionSum_.resize(n);
  pivots_.resize(n);
}

bool ArticulatedTreeSolver::Factorize(System const& system, bool makePositiveDefinite, int* failedJoint,
                                      Span<Matrix6> modifications) {
  int const numJoints = static_cast<int>(system.parent.size());
  if (static_cast<int>(articulated_.size()) != numJoints) Reserve(numJoints);
  modifiedPivots_ = 0;
  for (Matrix6& modification : modifications) modification.setZero();
  auto const fail = [&](int joint) {
    if (failedJoint != nullptr) *failedJoint = joint;
    return false;
  };
  // the modification's floor: 1e-10 of H's largest diagonal entry, from the
  // composites Y_i (a pass only where pivots may be modified); as the dense
  // modified Cholesky's floor, it keeps a pivot's eigenvalue near zero from
  // turning into a step of any length
  real scale = 0;
  for (int i = 0; i < numJoints; ++i) articulated_[i] = system.own[i];
  if (makePositiveDefinite) {
    bool const bounded = system.metric.size() == static_cast<std::size_t>(numJoints);
    for (int i = 0; i < numJoints && bounded; ++i) metric_[i] = system.metric[i];
    for (int i = numJoints - 1; i >= 0; --i) {
      int const m = system.numDofs[i], parent = system.parent[i];
      if (bounded && parent >= 0) metric_[parent] += ShiftToParent(system.shift[i], metric_[i]);
      if (m > 0) {
        Columns const s = system.motion.middleCols(system.dofStart[i], m);
        Columns const ys = articulated_[i] * s;
        for (int a = 0; a < m; ++a)
          scale = std::max(scale, std::abs(s.col(a).dot(ys.col(a)) + system.jointExtras[i](a, a)));
      }
      if (parent >= 0) articulated_[parent] += ShiftToParent(system.shift[i], articulated_[i]);
    }
    for (int i = 0; i < numJoints; ++i) articulated_[i] = system.own[i];
  }
  real const floor = 1e-10 * scale;
  // leaves up: each joint's pivot, then its contribution to its parent
  for (int i = numJoints - 1; i >= 0; --i) {
    int const m = system.numDofs[i], parent = system.parent[i];
    Matrix6 passed = articulated_[i];  // Yᴬ_i − Z_i, what the parent adds
    if (m > 0) {
      // (a copy of fixed capacity: products with it need no heap temporaries)
      Columns const s = system.motion.middleCols(system.dofStart[i], m);
      right_[i].noalias() = articulated_[i] * s;
      Block pivot = system.jointExtras[i].topLeftCorner(m, m);
      pivot.noalias() += s.transpose() * right_[i];
      pivot = 0.5 * (pivot + pivot.transpose()).eval();  // Sᵀ Yᴬ S is symmetric up to round-off
      if (!pivot.allFinite()) return fail(i);
      pivots_[i].compute(pivot);
      bool const definite = pivots_[i].info() == Eigen::Success && pivots_[i].matrixLLT().diagonal().minCoeff() > 0;
      if (!definite) {
        if (!makePositiveDefinite) return fail(i);
        // V max(|Λ|, floor) Vᵀ of the symmetric pivot
        Eigen::SelfAdjointEigenSolver<Block> eigen(pivot);
        Local values = eigen.eigenvalues();
        int modified = 0;
        for (int a = 0; a < m; ++a) modified += values[a] < floor;
        // the bound on what a modified direction takes from the parent
        Eigen::LLT<Matrix6> metric;
        bool const bounded = parent >= 0 && system.metric.size() == static_cast<std::size_t>(numJoints);
        if (bounded) metric.compute(metric_[i]);
        for (int a = 0; a < m; ++a) {
          if (!(values[a] < floor)) continue;
          values[a] = std::max(std::abs(values[a]), floor);
          if (bounded && metric.info() == Eigen::Success) {
            Vector6 const u = right_[i] * eigen.eigenvectors().col(a);
            values[a] = std::max(values[a], 2 * modified * u.dot(metric.solve(u)));
          }
        }
        Block const original = pivot;
        pivot.noalias() = eigen.eigenvectors() * values.asDiagonal() * eigen.eigenvectors().transpose();
        if (!modifications.empty()) modifications[i].topLeftCorner(m, m) = pivot - original;
        pivots_[i].compute(pivot);
        ++modifiedPivots_;
        if (pivots_[i].info() != Eigen::Success || !(pivots_[i].matrixLLT().diagonal().minCoeff() > 0))
          return fail(i);
      }
      // H_ji = S_jᵀ Yᴬ_i S_i for every strict ancestor j, H_ij its transpose:
      // Z_i = (Yᴬ_i S_i) Dᵢ⁻¹ (Yᴬ_i S_i)ᵀ, symmetric though Yᴬ_i is not
      if (parent >= 0) passed.noalias() -= right_[i] * pivots_[i].solve(Block(right_[i].transpose()));
    }
    if (parent >= 0) articulated_[parent] += ShiftToParent(system.shift[i], passed);
  }
  return true;
}

void ArticulatedTreeSolver::Solve(System const& system, Span<real const> b, Span<real> x) {
  int const numJoints = static_cast<int>(system.parent.size());
  for (int i = 0; i < numJoints; ++i) bias_[i].setZero();
  // leaves up: yᵢ = Dᵢ⁻¹ (bᵢ − S_iᵀ Σ q), kept in x; q_i = Yᴬ_i S_i yᵢ
  for (int i = numJoints - 1; i >= 0; --i) {
    int const m = system.numDofs[i], first = system.dofStart[i], parent = system.parent[i];
    if (m > 0) {
      Columns const s = system.motion.middleCols(first, m);
      Local const reduced = Eigen::Map<Local const>(b.data() + first, m) - s.transpose() * bias_[i];
      Local const y = pivots_[i].solve(reduced);
      Eigen::Map<Local>(x.data() + first, m) = y;
      bias_[i] += right_[i] * y;
    }
    if (parent >= 0) bias_[parent] += ShiftForce(system.shift[i], bias_[i]);
  }
  // roots down: xᵢ = yᵢ − Dᵢ⁻¹ (Yᴬ_i S_i)ᵀ Σ_{j strict ancestor} S_j x_j,
  // the sum carried to each joint's point
  for (int i = 0; i < numJoints; ++i) {
    int const m = system.numDofs[i], first = system.dofStart[i], parent = system.parent[i];
    motionSum_[i] = parent >= 0 ? ShiftMotion(system.shift[i], motionSum_[parent]) : Vector6::Zero();
    if (m == 0) continue;
    Columns const s = system.motion.middleCols(first, m);
    Eigen::Map<Local> xi(x.data() + first, m);
    if (parent >= 0) xi -= pivots_[i].solve(Local(right_[i].transpose() * motionSum_[i]));
    motionSum_[i] += s * xi;
  }
}

}  // namespace superdex::internal
