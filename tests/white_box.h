// White-box access for the derivative tests, in one place: ConstraintTestAccess
// drives a constraint's kernel and stage state (constraints/constraint_stage.h)
// and ActorTestAccess one actor through the stage contract (stage/stage_term.h),
// as the Newton solver does. Nothing here adds behaviour.
//
// Also holds the small dense helpers the derivative tests share: reading an
// assembled Hessian back into natural DoF order, and the tangent-space
// perturbation of a rigid body (docs/design.md §3: t ± ε e_j, R ← Exp(±ε e_j) R).
#pragma once

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/constraints/constraint_stage.h>
#include <superdex/stage/own_block_solve.h>
#include <superdex/stage/stage_term.h>
#include <superdex/superdex.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>

namespace superdex::internal {

/// A constraint's kernel and its stage state (constraints/constraint_stage.h)
/// driven by hand, as the ConstraintSet drives them in a stage. Each
/// constraint gets one ConstraintStage here, made at its first use.
struct ConstraintTestAccess {
  static ConstraintStage& Stage(Constraint const& c) {
    static std::map<Constraint const*, std::unique_ptr<ConstraintStage>> stages;
    std::unique_ptr<ConstraintStage>& stage = stages[&c];
    if (!stage || &stage->GetConstraint() != &c) stage = std::make_unique<ConstraintStage>(const_cast<Constraint&>(c));
    return *stage;
  }
  /// g and J at the actors' current configuration for `target`, into ws.g /
  /// ws.jacobian (ws must be Reserve(m, n)d).
  static void Evaluate(Constraint const& c, Span<real const> target, TermWorkspace& ws) {
    c.Evaluate(target, ws);
  }
  /// The same, for the constraint's current target p̂.
  static void EvaluateCurrent(Constraint const& c, TermWorkspace& ws) { c.Evaluate(c.GetState().target, ws); }
  static Span<real const> Target(Constraint const& c) { return c.GetState().target; }
  static Span<real const> OldTarget(Constraint const& c) { return c.GetState().oldTarget; }
  /// Stores g(q⁰, p̂⁰) (the current configuration, the old target) as the
  /// stage-start value.
  static void BeginStage(Constraint& c, TermWorkspace& ws) { BeginStage(c, 1, 0, {}, ws); }
  /// The same with the near-rigid cap β for a stage of duration h and the
  /// scene's per-DoF inverse masses; returns whether the cap applied.
  static bool BeginStage(Constraint& c, real h, real beta, Span<real const> inverseMasses, TermWorkspace& ws) {
    StageContext stage;
    stage.coefficients.duration = h;
    stage.nearRigidBeta = beta;
    stage.inverseMasses = inverseMasses;
    return Stage(c).Begin(stage, ws);
  }
  /// w, the largest diagonal entry of J diag(inverseMasses) Jᵀ, at the
  /// current configuration and old target (evaluates into ws).
  static real InverseEffectiveMass(Constraint const& c, Span<real const> inverseMasses, TermWorkspace& ws) {
    c.Evaluate(c.GetState().oldTarget, ws);
    return Stage(c).InverseEffectiveMass(inverseMasses, ws);
  }
  /// Φᶜ at the current configuration, for a stage of duration h.
  static real Energy(Constraint const& c, real h, TermWorkspace& ws) {
    Stage(c).SetStage(h, ConstraintHessian::GaussNewton);
    return Stage(c).Energy(ws);
  }
  static void AddGradientAndHessian(Constraint const& c, real h, Span<real> gradient, HessianAssembler& assembler,
                                    int contributor, TermWorkspace& ws,
                                    ConstraintHessian mode = ConstraintHessian::GaussNewton, bool project = true) {
    Stage(c).SetStage(h, mode);
    assembler.BeginAssembly(gradient);
    Stage(c).AddGradientAndHessian(assembler, contributor, project, ws);
    assembler.FinishAssembly();
  }
  /// Σᵢ wᵢ ∂²gᵢ/∂q² at the current configuration and target (n×n).
  /// (Through the kernel: on an articulated link, the type's curvature
  /// mapped onto the joint DoFs.)
  static MatrixX Curvature(Constraint const& c, VectorX const& weights) {
    TermWorkspace ws;
    ws.Reserve(c.GetDimension(), c.GetNumDofs());
    c.Evaluate(c.GetState().target, ws);
    MatrixX hessian = MatrixX::Zero(c.GetNumDofs(), c.GetNumDofs());
    c.AddCurvature(c.GetState().target, weights, ws, hessian);
    return hessian;
  }
  static CompliantParams const& Params(Constraint const& c) { return c.GetState().params; }
  static VectorX const& StageStartValue(Constraint const& c) { return Stage(c).GetStageStartValue(); }
  /// Global DoF list (actor 0's, then actor 1's).
  static DynamicArray<int> const& Dofs(Constraint const& c) { return c.GetDofs(); }
  /// Local DoF list of actor `a` (indices into that actor's own DoFs).
  static DynamicArray<int> const& LocalDofs(Constraint const& c, int a) { return c.GetLocalDofs(a); }
};

/// The stage contract of an actor (stage/stage_term.h), as the Newton solver
/// drives it, for tests that drive one actor by hand.
struct ActorTestAccess {
  static void WriteDofInverseMasses(Actor const& a, Span<real> inverseMasses) {
    a.GetStageDofs().WriteDofInverseMasses(inverseMasses);
  }
  /// BeginStage at the committed configuration, then the first iterate.
  static void BeginStage(Actor& a, StageCoefficients const& stage, Real3 const& gravity) {
    StageContext context;
    context.coefficients = stage;
    context.gravity = gravity;
    a.GetStageTerm().BeginStage(context);
    a.GetStageDofs().MoveToFirstIterate();
  }
  /// The whole energy (one process: every contributor counted).
  static real Energy(Actor const& a) { return Energy(a, HessianAssembler{}, 0); }
  /// The energy of the contributors `assembler` says this process owns,
  /// those of the actor numbered from `firstContributor`.
  static real Energy(Actor const& a, HessianAssembler const& assembler, int firstContributor) {
    EnergySum sum;
    a.GetStageTerm().AddEnergy(assembler, firstContributor, sum);
    return sum.energy;
  }
  static void AddGradientAndHessian(Actor const& a, Span<real> gradient, HessianAssembler& assembler,
                                    int firstContributor, bool projectHessian = true) {
    assembler.BeginAssembly(gradient);
    a.GetStageTerm().AddGradientAndHessian(assembler, firstContributor, AssemblyOptions{projectHessian});
    assembler.FinishAssembly();
  }
  static void AppendContributorDofs(Actor const& a, DynamicArray<DynamicArray<int>>& dofLists) {
    a.GetStageTerm().AppendContributorDofs(dofLists);
  }
  static void AppendDofBlockSizes(Actor const& a, DynamicArray<int>& sizes) { a.GetStageDofs().AppendDofBlockSizes(sizes); }
  /// Moves the actor by `delta` (a global-size vector, entries at the actor's
  /// DoFs) from its saved iterate; SaveIterate first, RestoreIterate after.
  static void SaveIterate(Actor& a) { a.GetStageDofs().SaveIterate(); }
  static void RestoreIterate(Actor& a) { a.GetStageDofs().RestoreIterate(); }
  static void ApplyIncrementFromSaved(Actor& a, Span<real const> delta, real alpha) {
    a.GetStageDofs().ApplyIncrementFromSaved(delta, alpha);
  }
  static void EndStage(Actor& a) { a.GetStageTerm().EndStage(); }
  static void WriteRigidBodyModes(Actor const& a, Eigen::Ref<MatrixX> modes) { a.GetStageDofs().WriteRigidBodyModes(modes); }
  /// The actor's own-block solve (an articulated actor on its tree).
  static OwnBlockSolve& OwnBlock(Actor& a) { return *a.GetStageTerm().GetOwnBlockSolve(); }
  static void SetSolvesOwnBlock(Actor& a, bool solves) { OwnBlock(a).SetActive(solves); }
  static bool FactorizeOwnBlock(Actor& a, HessianAssembler& assembler, int firstContributor, bool projectHessian,
                                std::string& reason) {
    return OwnBlock(a).Factorize(assembler, firstContributor, projectHessian, /*separateCouplings=*/false, reason);
  }
  static void SolveOwnBlock(Actor& a, Span<real const> rhs, Span<real> delta) { OwnBlock(a).Solve(rhs, delta); }
};

}  // namespace superdex::internal

namespace superdex::test {

/// Dense symmetric matrix, natural DoF order, of an assembler's current
/// values (upper-triangle CSC in the assembler's ordered positions). The
/// permutation is recovered through PermuteToOrdered of unit vectors, so
/// this works for any ordering method.
inline MatrixX DenseNaturalHessian(internal::HessianAssembler const& assembler) {
  SparseSymmetricMatrix const& matrix = assembler.GetMatrix();
  int const n = matrix.size;
  MatrixX ordered = MatrixX::Zero(n, n);
  for (int j = 0; j < n; ++j)
    for (int k = matrix.colStart[j]; k < matrix.colStart[j + 1]; ++k) {
      int const i = matrix.rowIndex[k];
      ordered(i, j) = matrix.values[k];
      ordered(j, i) = matrix.values[k];
    }
  // position[i]: ordered position of natural DoF i
  DynamicArray<int> position(n);
  VectorX unit(n), out(n);
  for (int i = 0; i < n; ++i) {
    unit.setZero();
    unit[i] = 1;
    assembler.PermuteToOrdered(Span<real const>(unit.data(), n), Span<real>(out.data(), n));
    Eigen::Index where;
    out.maxCoeff(&where);
    position[i] = static_cast<int>(where);
  }
  MatrixX natural(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) natural(i, j) = ordered(position[i], position[j]);
  return natural;
}

/// An actor's stage gradient and assembled Hessian (dense, natural order) at
/// its current iterate, alone in a pattern of its own (`ordering` for it).
struct ActorDerivatives {
  VectorX gradient;
  MatrixX hessian;
};

inline ActorDerivatives AssembleActor(Actor const& actor, bool projectHessian,
                                      OrderingMethod ordering = OrderingMethod::Natural) {
  int const n = actor.GetNumDofs();
  DynamicArray<DynamicArray<int>> contributors;
  DynamicArray<int> blocks;
  internal::ActorTestAccess::AppendContributorDofs(actor, contributors);
  internal::ActorTestAccess::AppendDofBlockSizes(actor, blocks);
  internal::HessianAssembler assembler;
  Error error;
  bool const analyzed = assembler.Analyze(n, blocks, contributors, ordering, error);
  INFO(error.ToString());
  REQUIRE(analyzed);
  DynamicArray<real> gradient(n, 0);
  assembler.ZeroValues();
  internal::ActorTestAccess::AddGradientAndHessian(actor, gradient, assembler, 0, projectHessian);
  return {Eigen::Map<VectorX const>(gradient.data(), n), DenseNaturalHessian(assembler)};
}

/// Moves `body` by the tangent increment ε e_dof from (position, rotation):
/// dof 0..2 translate, dof 3..5 rotate in the world frame, R ← Exp(ε e) R.
inline void SetPerturbedPose(RigidActor& body, Real3 const& position, Quat const& rotation, int dof,
                             real epsilon) {
  Real3 t = position;
  Quat r = rotation;
  if (dof < 3) {
    t[dof] += epsilon;
  } else {
    Real3 delta = Real3::Zero();
    delta[dof - 3] = epsilon;
    r = Exp(delta) * rotation;
  }
  Error error;
  bool const ok = body.SetPose(t, r, error);
  INFO(error.ToString());
  REQUIRE(ok);
}

/// Largest entrywise error of `a` against `b`, in units of
/// max(|a_ij|, |b_ij|, 1): the tolerance form of style habit 11.
inline real MaxScaledError(MatrixX const& a, MatrixX const& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  real worst = 0;
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      // a NaN or infinity is an infinite error, never a silently skipped entry
      if (!std::isfinite(a(i, j)) || !std::isfinite(b(i, j)))
        return std::numeric_limits<real>::infinity();
      real const scale = std::max({std::abs(a(i, j)), std::abs(b(i, j)), real(1)});
      worst = std::max(worst, std::abs(a(i, j) - b(i, j)) / scale);
    }
  return worst;
}

}  // namespace superdex::test
