// ArticulatedTreeSolver: the O(N) solve of a matrix with an articulated
// actor's Hessian structure, against a dense Cholesky of the same matrix
// formed entry by entry, on random trees (chains, branches, several roots,
// joints of 0, 1, 2, 3 and 6 DoFs, non-symmetric Y).
#include "test_support.h"

#include <random>


#include <superdex/actors/articulated_tree_solver.h>

using namespace superdex;
using internal::ArticulatedTreeSolver;
using Matrix6 = ArticulatedTreeSolver::Matrix6;

namespace {

struct RandomTree {
  DynamicArray<int> parent, dofStart, numDofs;
  // about one origin (what Dense forms H from) and about each joint's point
  Eigen::Matrix<real, 6, Eigen::Dynamic> motion, localMotion;
  DynamicArray<Matrix6> own, localOwn, jointExtras;
  DynamicArray<Real3> point, shift;
  int n = 0;

  ArticulatedTreeSolver::System View() const {
    return {parent, dofStart, numDofs, localMotion, localOwn, jointExtras, shift};
  }

  /// H formed entry by entry from the definition (the file comment of
  /// articulated_tree_solver.h), about the one origin
  MatrixX Dense() const {
    int const numJoints = static_cast<int>(parent.size());
    DynamicArray<Matrix6> composite(own);
    for (int i = numJoints - 1; i > 0; --i)
      if (parent[i] >= 0) composite[parent[i]] += composite[i];
    MatrixX h = MatrixX::Zero(n, n);
    for (int i = 0; i < numJoints; ++i) {
      int const m = numDofs[i];
      if (m == 0) continue;
      auto const si = motion.middleCols(dofStart[i], m);
      MatrixX const diagonal = si.transpose() * composite[i] * si;
      h.block(dofStart[i], dofStart[i], m, m) =
          0.5 * (diagonal + diagonal.transpose()) + jointExtras[i].topLeftCorner(m, m);
      for (int j = parent[i]; j >= 0; j = parent[j]) {
        if (numDofs[j] == 0) continue;
        auto const sj = motion.middleCols(dofStart[j], numDofs[j]);
        MatrixX const block = sj.transpose() * composite[i] * si;
        h.block(dofStart[j], dofStart[i], numDofs[j], m) = block;
        h.block(dofStart[i], dofStart[j], m, numDofs[j]) = block.transpose();
      }
    }
    return h;
  }

  /// The local quantities from the ones about the origin: motion about
  /// o_i (v − o_i × ω) and own_i = X(−o_i)ᵀ own X(−o_i)
  void MakeLocal() {
    localMotion = motion;
    localOwn = own;
    shift.assign(parent.size(), Real3::Zero());
    for (std::size_t i = 0; i < parent.size(); ++i) {
      for (int c = dofStart[i]; c < dofStart[i] + numDofs[i]; ++c)
        localMotion.col(c).tail<3>() -= point[i].cross(Real3(motion.col(c).head<3>()));
      localOwn[i] = ArticulatedTreeSolver::ShiftToParent(-point[i], own[i]);
      if (parent[i] >= 0) shift[i] = point[i] - point[parent[i]];
    }
  }
};

/// `numJoints` joints; shape 0: a chain, 1: random parents, 2: random
/// parents and a second root. The joint blocks make H positive definite
/// with smallest eigenvalue `smallest` (the off-diagonal part's spectrum
/// shifted), so the condition stays moderate.
RandomTree MakeTree(int numJoints, int shape, unsigned seed, real smallest = 1) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<real> uniform(-1, 1);
  int const dofChoices[] = {1, 1, 3, 6, 0, 2};
  RandomTree t;
  for (int i = 0; i < numJoints; ++i) {
    int p = i - 1;
    if (shape >= 1 && i > 0) p = static_cast<int>(random() % static_cast<unsigned>(i));
    if (shape == 2 && i == numJoints / 2) p = -1;
    t.parent.push_back(p);
    t.dofStart.push_back(t.n);
    t.numDofs.push_back(dofChoices[random() % 6]);
    t.n += t.numDofs.back();
  }
  t.motion.resize(6, t.n);
  for (int c = 0; c < t.n; ++c)
    for (int r = 0; r < 6; ++r) t.motion(r, c) = uniform(random);
  for (int i = 0; i < numJoints; ++i) {
    Matrix6 y;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) y(r, c) = uniform(random);
    // a symmetric positive part, like a link's stiffness, and a smaller
    // non-symmetric one, like the kinematic curvature
    t.own.push_back(y * y.transpose() * 0.5 + 0.2 * Matrix6::NullaryExpr([&] { return uniform(random); }));
    Matrix6 a;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) a(r, c) = uniform(random);
    t.jointExtras.push_back(a * a.transpose());
    // reference points far from the origin, as a long chain's are
    t.point.push_back(Real3(uniform(random), uniform(random), uniform(random)) * 30.0);
  }
  // shift the joint blocks by what makes the smallest eigenvalue `smallest`
  if (t.n > 0) {  // (joints without DoFs only: nothing to solve)
    real const lowest = SymmetricEigenvalues<MatrixX>(t.Dense()).minCoeff();
    for (auto& block : t.jointExtras) block += (smallest - lowest) * Matrix6::Identity();
  }
  t.MakeLocal();
  return t;
}

}  // namespace

TEST_CASE("the tree solve equals a dense Cholesky solve on random trees", "[actors][articulated][tree]") {
  int const numJoints = GENERATE(1, 2, 7, 40);
  int const shape = GENERATE(0, 1, 2);
  unsigned const seed = GENERATE(1u, 2u, 3u);
  CAPTURE(numJoints, shape, seed);
  RandomTree const t = MakeTree(numJoints, shape, seed);
  CAPTURE(t.n);
  if (t.n == 0) {
    // a tree of fixed joints only: nothing to eliminate, and Factorize says so
    ArticulatedTreeSolver solver;
    solver.Reserve(numJoints);
    REQUIRE(solver.Factorize(t.View()));
    return;
  }
  MatrixX const h = t.Dense();
  REQUIRE((h - h.transpose()).norm() <= 1e-12 * h.norm());
  VectorX b(t.n);
  for (int i = 0; i < t.n; ++i) b[i] = std::sin(1.0 + i);
  Eigen::LLT<MatrixX> const dense(h);
  REQUIRE(dense.info() == Eigen::Success);
  VectorX const expected = dense.solve(b);

  ArticulatedTreeSolver solver;
  solver.Reserve(numJoints);
  VectorX x = VectorX::Constant(t.n, 99.0);
  REQUIRE(solver.Factorize(t.View()));
  solver.Solve(t.View(), Span<real const>(b.data(), t.n), Span<real>(x.data(), t.n));
  CAPTURE((x - expected).norm(), expected.norm());
  CHECK((x - expected).norm() <= 1e-10 * expected.norm());
  // and the residual against H, independently of the dense solve
  CHECK((h * x - b).norm() <= 1e-10 * h.norm() * expected.norm());
}

TEST_CASE("the tree solve reports a matrix that is not positive definite", "[actors][articulated][tree]") {
  // a chain shifted to smallest eigenvalue −1: some pivot fails, as block
  // Cholesky does; a shift to +1e-3 passes
  RandomTree const indefinite = MakeTree(12, 1, 7, -1);
  RandomTree const definite = MakeTree(12, 1, 7, 1e-3);
  REQUIRE(Eigen::LLT<MatrixX>(indefinite.Dense()).info() != Eigen::Success);
  ArticulatedTreeSolver solver;
  VectorX b = VectorX::Ones(indefinite.n), x(indefinite.n);
  int failedJoint = -1;
  CHECK_FALSE(solver.Factorize(indefinite.View(), false, &failedJoint));
  CHECK(failedJoint >= 0);
  CHECK(failedJoint < 12);
  CHECK(solver.Factorize(definite.View()));
}

TEST_CASE("the modified tree factorization is positive definite, and H itself where H is",
          "[actors][articulated][tree]") {
  int const shape = GENERATE(0, 1, 2);
  CAPTURE(shape);
  ArticulatedTreeSolver solver;
  // positive definite: nothing modified, the same solution as unmodified
  RandomTree const definite = MakeTree(15, shape, 11, 1e-2);
  int const n = definite.n;
  VectorX b(n), plain(n), modified(n);
  for (int i = 0; i < n; ++i) b[i] = std::cos(0.5 + 2 * i);
  REQUIRE(solver.Factorize(definite.View()));
  solver.Solve(definite.View(), Span<real const>(b.data(), n), Span<real>(plain.data(), n));
  REQUIRE(solver.Factorize(definite.View(), true));
  CHECK(solver.GetNumModifiedPivots() == 0);
  solver.Solve(definite.View(), Span<real const>(b.data(), n), Span<real>(modified.data(), n));
  CHECK((plain - modified).norm() == 0);
  // indefinite: pivots modified; H₊⁻¹, formed column by column, is
  // symmetric positive definite, so every step it gives descends
  RandomTree const indefinite = MakeTree(15, shape, 11, -3);
  int const m = indefinite.n;
  REQUIRE(solver.Factorize(indefinite.View(), true));
  CHECK(solver.GetNumModifiedPivots() > 0);
  MatrixX inverse(m, m);
  for (int j = 0; j < m; ++j) {
    VectorX const e = VectorX::Unit(m, j);
    solver.Solve(indefinite.View(), Span<real const>(e.data(), m), Span<real>(inverse.col(j).data(), m));
  }
  CHECK((inverse - inverse.transpose()).norm() <= 1e-10 * inverse.norm());
  MatrixX const symmetric = 0.5 * (inverse + inverse.transpose());
  CHECK(SymmetricEigenvalues(symmetric).minCoeff() > 0);
}

TEST_CASE("a modified factorization continued from a failed exact one is the modified factorization",
          "[actors][articulated][tree]") {
  // ContinueModified keeps the joints the exact attempt eliminated (their
  // pivots were definite, so the modification leaves them): the same factors
  // as Factorize(…, true), to the last bit
  int const shape = GENERATE(0, 1, 2);
  CAPTURE(shape);
  RandomTree const indefinite = MakeTree(15, shape, 11, -3);
  int const n = indefinite.n;
  // with a metric, so that the modification's bound takes part
  DynamicArray<Matrix6> const metric(indefinite.parent.size(), Matrix6::Identity());
  ArticulatedTreeSolver::System system = indefinite.View();
  system.metric = metric;
  VectorX b(n), direct(n), continued(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(0.3 + 1.7 * i);
  ArticulatedTreeSolver solver;
  REQUIRE(solver.Factorize(system, true));
  int const modified = solver.GetNumModifiedPivots();
  solver.Solve(system, Span<real const>(b.data(), n), Span<real>(direct.data(), n));
  int failedJoint = -1;
  REQUIRE_FALSE(solver.Factorize(system, false, &failedJoint));
  REQUIRE(solver.ContinueModified(system));
  CHECK(solver.GetNumModifiedPivots() == modified);
  solver.Solve(system, Span<real const>(b.data(), n), Span<real>(continued.data(), n));
  CHECK((continued - direct).norm() == 0);
  // without a failed exact factorization to continue, it factorizes afresh
  ArticulatedTreeSolver fresh;
  REQUIRE(fresh.ContinueModified(system));
  fresh.Solve(system, Span<real const>(b.data(), n), Span<real>(continued.data(), n));
  CHECK((continued - direct).norm() == 0);
}
