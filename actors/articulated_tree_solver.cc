#include <superdex/actors/articulated_tree_solver.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include <superdex/core/so3.h>
#include <superdex/core/symmetric_eigen.h>

namespace superdex::internal {

namespace {
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
  childStamp_.assign(n, 0);
  stamp_ = 0;
  metric_.resize(n);
  right_.resize(n);
  bias_.resize(n);
  motionSum_.resize(n);
  pivotFactor_.resize(n);
  pivotReciprocal_.resize(n);
  composite_.resize(n);
}

bool ArticulatedTreeSolver::Factorize(System const& system, bool makePositiveDefinite, int* failedJoint,
                                      Span<Matrix6> modifications) {
  int const numJoints = static_cast<int>(system.parent.size());
  if (static_cast<int>(articulated_.size()) != numJoints) Reserve(numJoints);
  modifiedPivots_ = 0;
  resumeJoint_ = -1;
  for (Matrix6& modification : modifications) modification.setZero();
  // a new stamp: no joint has had a child's term yet
  if (stamp_ == std::numeric_limits<int>::max()) {
    std::fill(childStamp_.begin(), childStamp_.end(), 0);
    stamp_ = 0;
  }
  ++stamp_;
  if (makePositiveDefinite) PrepareModification(system);
  return EliminateFrom(system, numJoints - 1, makePositiveDefinite, modifications, failedJoint);
}

bool ArticulatedTreeSolver::ContinueModified(System const& system, int* failedJoint) {
  if (resumeJoint_ < 0 || static_cast<int>(articulated_.size()) != static_cast<int>(system.parent.size()))
    return Factorize(system, true, failedJoint);
  int const first = resumeJoint_;
  resumeJoint_ = -1;
  PrepareModification(system);
  return EliminateFrom(system, first, true, {}, failedJoint);
}

void ArticulatedTreeSolver::PrepareModification(System const& system) {
  // the floor: 1e-10 of H's largest diagonal entry, from the composites Y_i;
  // as the dense modified Cholesky's floor, it keeps a pivot's eigenvalue
  // near zero from turning into a step of any length. And the metric's
  // composites over the subtrees (the bound on what a modified direction
  // takes from the parent)
  int const numJoints = static_cast<int>(system.parent.size());
  bool const bounded = system.metric.size() == static_cast<std::size_t>(numJoints);
  real scale = 0;
  for (int i = 0; i < numJoints; ++i) {
    composite_[i] = system.own[i];
    if (bounded) metric_[i] = system.metric[i];
  }
  for (int i = numJoints - 1; i >= 0; --i) {
    int const m = system.numDofs[i], parent = system.parent[i];
    if (bounded && parent >= 0) metric_[parent] += ShiftToParent(system.shift[i], metric_[i]);
    if (m > 0) {
      Columns const s = system.motion.middleCols(system.dofStart[i], m);
      Columns const ys = composite_[i] * s;
      for (int a = 0; a < m; ++a)
        scale = std::max(scale, std::abs(s.col(a).dot(ys.col(a)) + system.jointExtras[i](a, a)));
    }
    if (parent >= 0) composite_[parent] += ShiftToParent(system.shift[i], composite_[i]);
  }
  floor_ = 1e-10 * scale;
}

bool ArticulatedTreeSolver::EliminateFrom(System const& system, int first, bool makePositiveDefinite,
                                          Span<Matrix6> modifications, int* failedJoint) {
  // leaves up: each joint's pivot, then its contribution to its parent
  for (int i = first; i >= 0; --i) {
    int const parent = system.parent[i];
    Matrix6 passed = system.own[i];  // Yᴬ_i, then Yᴬ_i − Z_i: what the parent adds
    if (childStamp_[i] == stamp_) passed += articulated_[i];
    bool eliminated = true;
    switch (system.numDofs[i]) {
      case 0: break;
      case 1: eliminated = Eliminate<1>(system, i, makePositiveDefinite, modifications, passed); break;
      case 3: eliminated = Eliminate<3>(system, i, makePositiveDefinite, modifications, passed); break;
      case 6: eliminated = Eliminate<6>(system, i, makePositiveDefinite, modifications, passed); break;
      default:
        eliminated = Eliminate<Eigen::Dynamic>(system, i, makePositiveDefinite, modifications, passed);
        break;
    }
    if (!eliminated) {
      // what the joints after i passed up is intact: ContinueModified can go
      // on from here
      if (!makePositiveDefinite) resumeJoint_ = i;
      if (failedJoint != nullptr) *failedJoint = i;
      return false;
    }
    if (parent < 0) continue;
    if (childStamp_[parent] == stamp_) {
      articulated_[parent] += ShiftToParent(system.shift[i], passed);
    } else {
      articulated_[parent] = ShiftToParent(system.shift[i], passed);
      childStamp_[parent] = stamp_;
    }
  }
  return true;
}

template <int M>
bool ArticulatedTreeSolver::Eliminate(System const& system, int i, bool makePositiveDefinite,
                                      Span<Matrix6> modifications, Matrix6& passed) {
  // fixed-size kernels for one, three and six DoFs (the dynamic sizes' small
  // products went through Eigen's general matrix kernels: a third of a
  // chain's step)
  int const m = system.numDofs[i], parent = system.parent[i];
  Cols<M> const s = system.motion.middleCols(system.dofStart[i], m);
  Cols<M> ys;
  ys.noalias() = passed * s;
  right_[i] = ys;
  Square<M> pivot = system.jointExtras[i].topLeftCorner(m, m);
  pivot.noalias() += s.transpose() * ys;
  pivot = 0.5 * (pivot + pivot.transpose()).eval();  // Sᵀ Yᴬ S is symmetric up to round-off
  if (!pivot.allFinite()) return false;
  Eigen::LLT<Square<M>> factor(pivot);
  bool const definite = factor.info() == Eigen::Success && factor.matrixLLT().diagonal().minCoeff() > 0;
  if (!definite) {
    if (!makePositiveDefinite) return false;
    Square<M> modified = pivot;
    ModifyPivot<M>(system, i, modified);
    if (!modifications.empty()) modifications[i].topLeftCorner(m, m) = modified - pivot;
    pivot = modified;
    factor.compute(pivot);
    ++modifiedPivots_;
    if (factor.info() != Eigen::Success || !(factor.matrixLLT().diagonal().minCoeff() > 0)) return false;
  }
  // the Cholesky factor Lᵢ kept (the solves: triangular, of fixed size)
  pivotFactor_[i].topLeftCorner(m, m) = factor.matrixL();
  pivotReciprocal_[i].head(m) = factor.matrixLLT().diagonal().cwiseInverse();
  // H_ji = S_jᵀ Yᴬ_i S_i for every strict ancestor j, H_ij its transpose:
  // Z_i = (Yᴬ_i S_i) Dᵢ⁻¹ (Yᴬ_i S_i)ᵀ = Wᵀ W, W = Lᵢ⁻¹ (Yᴬ_i S_i)ᵀ
  if (parent >= 0) {
    // W by forward substitution, row by row (Eigen's triangular solve with a
    // matrix right-hand side goes through its general blocked kernel)
    auto const& lower = factor.matrixLLT();
    Vector6 const& reciprocal = pivotReciprocal_[i];
    Eigen::Matrix<real, M, 6, M == 1 ? Eigen::RowMajor : Eigen::ColMajor, Capacity(M), 6> w = ys.transpose();
    for (int r = 0; r < m; ++r) {
      for (int c = 0; c < r; ++c) w.row(r) -= lower(r, c) * w.row(c);
      w.row(r) *= reciprocal[r];
    }
    passed.noalias() -= w.transpose() * w;
  }
  return true;
}

template <int M>
void ArticulatedTreeSolver::ModifyPivot(System const& system, int i, Square<M>& pivot) {
  // V max(|Λ|, floor) Vᵀ of the symmetric pivot, each modified eigenvalue
  // also raised by the bound on what its direction takes from the parent
  // (fixed-size kernels: with a dynamic 6 × 6 solver the modification took
  // a tenth of a falling chain's step, every pivot modified)
  int const m = system.numDofs[i], parent = system.parent[i];
  int const numJoints = static_cast<int>(system.parent.size());
  auto const eigen = ComputeSymmetricEigen(pivot);
  Vec<M> values = eigen.values;
  int modified = 0;
  for (int a = 0; a < m; ++a) modified += values[a] < floor_;
  Eigen::LLT<Matrix6> metric;
  bool const bounded = parent >= 0 && system.metric.size() == static_cast<std::size_t>(numJoints);
  if (bounded) metric.compute(metric_[i]);
  for (int a = 0; a < m; ++a) {
    if (!(values[a] < floor_)) continue;
    values[a] = std::max(std::abs(values[a]), floor_);
    if (bounded && metric.info() == Eigen::Success) {
      // uᵀ W⁻¹ u = ‖L⁻¹ u‖², W = L Lᵀ: one forward substitution
      Vector6 y = Cols<M>(right_[i]) * eigen.vectors.col(a);
      auto const& lower = metric.matrixLLT();
      for (int r = 0; r < 6; ++r) {
        for (int c = 0; c < r; ++c) y[r] -= lower(r, c) * y[c];
        y[r] /= lower(r, r);
      }
      values[a] = std::max(values[a], 2 * modified * y.squaredNorm());
    }
  }
  pivot.noalias() = eigen.vectors * values.asDiagonal() * eigen.vectors.transpose();
}

void ArticulatedTreeSolver::Solve(System const& system, Span<real const> b, Span<real> x) {
  int const numJoints = static_cast<int>(system.parent.size());
  for (int i = 0; i < numJoints; ++i) bias_[i].setZero();
  // leaves up: yᵢ = Dᵢ⁻¹ (bᵢ − S_iᵀ Σ q), kept in x; q_i = Yᴬ_i S_i yᵢ
  for (int i = numJoints - 1; i >= 0; --i) {
    switch (system.numDofs[i]) {
      case 0: break;
      case 1: SolveUp<1>(system, i, b, x); break;
      case 3: SolveUp<3>(system, i, b, x); break;
      case 6: SolveUp<6>(system, i, b, x); break;
      default: SolveUp<Eigen::Dynamic>(system, i, b, x); break;
    }
    int const parent = system.parent[i];
    if (parent >= 0) bias_[parent] += ShiftForce(system.shift[i], bias_[i]);
  }
  // roots down: xᵢ = yᵢ − Dᵢ⁻¹ (Yᴬ_i S_i)ᵀ Σ_{j strict ancestor} S_j x_j,
  // the sum carried to each joint's point
  for (int i = 0; i < numJoints; ++i) {
    int const parent = system.parent[i];
    motionSum_[i] = parent >= 0 ? ShiftMotion(system.shift[i], motionSum_[parent]) : Vector6::Zero();
    switch (system.numDofs[i]) {
      case 0: break;
      case 1: SolveDown<1>(system, i, x); break;
      case 3: SolveDown<3>(system, i, x); break;
      case 6: SolveDown<6>(system, i, x); break;
      default: SolveDown<Eigen::Dynamic>(system, i, x); break;
    }
  }
}

template <int M, class Vector>
void ArticulatedTreeSolver::PivotSolve(int i, int m, Vector& v) const {
  // Lᵢ Lᵢᵀ v = b: forward, then back substitution on the kept factor
  // (the diagonal's reciprocals kept: no division in the solves)
  Matrix6 const& lower = pivotFactor_[i];
  Vector6 const& reciprocal = pivotReciprocal_[i];
  int const size = M == Eigen::Dynamic ? m : M;  // a constant the loops unroll on
  for (int r = 0; r < size; ++r) {
    real sum = v[r];
    for (int c = 0; c < r; ++c) sum -= lower(r, c) * v[c];
    v[r] = sum * reciprocal[r];
  }
  for (int r = size - 1; r >= 0; --r) {
    real sum = v[r];
    for (int c = r + 1; c < size; ++c) sum -= lower(c, r) * v[c];
    v[r] = sum * reciprocal[r];
  }
}

template <int M>
void ArticulatedTreeSolver::SolveUp(System const& system, int i, Span<real const> b, Span<real> x) {
  int const m = system.numDofs[i], first = system.dofStart[i];
  Cols<M> const s = system.motion.middleCols(first, m);
  Vec<M> const reduced = Eigen::Map<Vec<M> const>(b.data() + first, m) - s.transpose() * bias_[i];
  Vec<M> y = reduced;
  PivotSolve<M>(i, m, y);
  Eigen::Map<Vec<M>>(x.data() + first, m) = y;
  bias_[i].noalias() += Cols<M>(right_[i]) * y;
}

template <int M>
void ArticulatedTreeSolver::SolveDown(System const& system, int i, Span<real> x) {
  int const m = system.numDofs[i], first = system.dofStart[i];
  Cols<M> const s = system.motion.middleCols(first, m);
  Eigen::Map<Vec<M>> xi(x.data() + first, m);
  if (system.parent[i] >= 0) {
    Vec<M> correction = Cols<M>(right_[i]).transpose() * motionSum_[i];
    PivotSolve<M>(i, m, correction);
    xi -= correction;
  }
  motionSum_[i].noalias() += s * xi;
}

}  // namespace superdex::internal
