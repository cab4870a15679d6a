#include <superdex/linsolve/petsc_pcg_solver.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

#include <petscksp.h>

#include <superdex/core/mpi.h>
#include <superdex/core/validate.h>
#include <superdex/linsolve/incomplete_cholesky.h>
#include <superdex/linsolve/petsc_distributed_matrix.h>
#include <superdex/linsolve/petsc_runtime.h>

namespace superdex::internal {

namespace {

/// Icc and BlockJacobi: the KSP's PC is a shell applying SuperDex's own
/// incomplete Cholesky (incomplete_cholesky.h): IC(k) of the Jacobi-scaled
/// matrix, in RCM order, its diagonal shifts bounded. PETSc's PCICC (with
/// PCBJACOBI around it) was used before; its positive-definite shift loop
/// never ended on a matrix the fuzzer found (tests/fuzz/findings).
PetscErrorCode ApplyIncompleteCholesky(PC pc, Vec r, Vec z) {
  void* context = nullptr;
  PetscCall(PCShellGetContext(pc, &context));
  PetscScalar const* in = nullptr;
  PetscScalar* out = nullptr;
  PetscCall(VecGetArrayRead(r, &in));
  PetscCall(VecGetArrayWrite(z, &out));
  static_cast<IncompleteCholesky*>(context)->Apply(in, out);
  PetscCall(VecRestoreArrayWrite(z, &out));
  PetscCall(VecRestoreArrayRead(r, &in));
  return 0;
}

}  // namespace

struct PetscPcgSolver::Impl {
  Mat matrix = nullptr;    ///< SeqAIJ, or the distributed MPIAIJ (a reference to it)
  KSP ksp = nullptr;
  Vec rhs = nullptr;       ///< one rank: owns its storage; b is copied in
  Vec solution = nullptr;  ///< one rank: no storage of its own: wraps the caller's x
  int size = 0;
  /// AIJ value position of each upper-triangle CSC entry k of A, as entry
  /// (i, j) of row i, and as its mirror (j, i) of row j (-1 on the diagonal)
  DynamicArray<PetscInt> upperSlot, lowerSlot;
  DynamicArray<PetscInt> blockSizes;  ///< A's DoF blocks (PCVPBJACOBI)
  bool hasNearNullSpace = false;
  int setUps = 0;  ///< Factorize calls since Analyze
  real relativeTolerance = 0;

  std::string prefix;                      ///< this solver's options prefix, "sdx<N>_"
  DynamicArray<std::string> defaultNames;  ///< options SuperDex inserted
  DynamicArray<std::string> userNames;     ///< PcgParams::options, checked for use
  bool optionsChecked = false;
  /// Icc, BlockJacobi: the shell PC's factor, and whether it holds one
  bool usesIncomplete = false;
  IncompleteCholesky incomplete;
  bool incompleteFactored = false;

  /// SetDistribution; on more than one rank the matrix, its vectors and the
  /// gather of x are `distributed`'s
  RowDistribution distribution;
  PetscDistributedMatrix distributed;
  /// BlockJacobi on more than one rank: the diagonal block of the owned rows
  /// (upper CSC, local numbering), which `incomplete` factors on this rank,
  /// and A's value index of each of its entries
  SparseSymmetricMatrix ownedBlock;
  DynamicArray<int> ownedBlockSource;

  bool IsDistributed() const { return distribution.IsDistributed(); }
  LinearSolveResult CreateSequentialMatrix(SparseSymmetricMatrix const& a);
  LinearSolveResult CreateDistributedMatrix(SparseSymmetricMatrix const& a);
  void BuildOwnedBlock(SparseSymmetricMatrix const& a);
  void SetDistributedNearNullSpace(MatrixX const& modes);

  void DestroyObjects() {
    if (IsPetscFinalized()) {  // PETSc is gone; so are its objects
      matrix = nullptr, ksp = nullptr, rhs = nullptr, solution = nullptr;
      distributed.Destroy();
      return;
    }
    KSPDestroy(&ksp);
    MatDestroy(&matrix);
    VecDestroy(&rhs);
    VecDestroy(&solution);
    distributed.Destroy();
  }
  void ClearOptions() {
    if (IsPetscFinalized()) return;
    for (auto const& name : defaultNames) PetscOptionsClearValue(nullptr, name.c_str());
    for (auto const& name : userNames) PetscOptionsClearValue(nullptr, name.c_str());
    defaultNames.clear();
    userNames.clear();
  }
};

namespace {

// "-ksp_monitor" → "-sdx3_ksp_monitor"
std::string Prefixed(std::string const& prefix, std::string const& option) {
  return "-" + prefix + option.substr(1);
}

// an option name is '-' followed by a letter; "-1e-3" is a value
bool IsOptionName(std::string const& token) {
  return token.size() >= 2 && token[0] == '-' && std::isalpha(static_cast<unsigned char>(token[1]));
}

struct OptionPair {
  std::string name, value;
};

// Splits "-a 1 -b -c x" into {-a 1} {-b} {-c x}. Returns false and names the
// token when a value does not follow an option name.
bool ParseOptions(std::string const& text, DynamicArray<OptionPair>& pairs, std::string& bad) {
  std::size_t pos = 0;
  auto nextToken = [&](std::string& token) {
    pos = text.find_first_not_of(" \t\n", pos);
    if (pos == std::string::npos) return false;
    std::size_t const end = text.find_first_of(" \t\n", pos);
    token = text.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end;
    return true;
  };
  std::string token;
  while (nextToken(token)) {
    if (IsOptionName(token)) {
      pairs.push_back({token, {}});
    } else if (!pairs.empty() && pairs.back().value.empty()) {
      pairs.back().value = token;
    } else {
      bad = token;
      return false;
    }
  }
  return true;
}

char const* PcTypeName(PcgPreconditioner preconditioner) {
  switch (preconditioner) {
    case PcgPreconditioner::None: return PCNONE;
    case PcgPreconditioner::Jacobi: return PCJACOBI;
    case PcgPreconditioner::PointBlockJacobi: return PCVPBJACOBI;
    case PcgPreconditioner::BlockJacobi:  // SuperDex's own (IncompleteCholesky)
    case PcgPreconditioner::Icc: return PCSHELL;
    case PcgPreconditioner::Gamg: return PCGAMG;
    case PcgPreconditioner::BoomerAmg: return PCHYPRE;
  }
  return PCNONE;
}

// Most of A's DoFs are in 4-DoF blocks: rod nodes (position + twist), today
// the only DoF blocks of that size
bool IsRodDominated(SparseSymmetricMatrix const& a) {
  long rodDofs = 0;
  for (int size : a.blockSizes)
    if (size == 4) rodDofs += size;
  return a.size > 0 && 2 * rodDofs > a.size;
}

// Block Jacobi's groups: `numGroups` contiguous runs of whole DoF blocks
// (`blockSizes`, adding to `size`) with about equal DoF counts
DynamicArray<int> BlockJacobiGroups(Span<int const> blockSizes, int size, int numGroups) {
  DynamicArray<int> groupSizes;
  int start = 0, dof = 0;
  for (int blockSize : blockSizes) {
    dof += blockSize;
    long const target = static_cast<long>(size) * (static_cast<long>(groupSizes.size()) + 1) / numGroups;
    if (dof >= target) {
      groupSizes.push_back(dof - start);
      start = dof;
    }
  }
  if (dof > start) groupSizes.push_back(dof - start);
  return groupSizes;
}

std::atomic<int> nextSolverId{0};

}  // namespace

PetscPcgSolver::PetscPcgSolver(PcgParams const& params) : params_(params), impl_(new Impl) {
  impl_->prefix = "sdx" + std::to_string(nextSolverId++) + "_";
  impl_->relativeTolerance = params.relativeTolerance;
}

PetscPcgSolver::~PetscPcgSolver() {
  impl_->DestroyObjects();
  impl_->ClearOptions();
}

std::string PetscPcgSolver::GetDescription() const {
  char rtol[32];
  std::snprintf(rtol, sizeof(rtol), "%.3g", params_.relativeTolerance);
  std::string text = "PETSc " + std::to_string(PETSC_VERSION_MAJOR) + "." +
                     std::to_string(PETSC_VERSION_MINOR) + "." +
                     std::to_string(PETSC_VERSION_SUBMINOR) + " CG + " +
                     std::string(ToString(params_.preconditioner));
  if (params_.preconditioner == PcgPreconditioner::Gamg)
    text += impl_->hasNearNullSpace ? " (rigid-body near-null space)" : " (no near-null space)";
  text += ", rtol " + std::string(rtol);
  if (params_.adaptiveTolerance) text += " (adaptive)";
  if (impl_->IsDistributed()) {
    text += " on " + std::to_string(impl_->distribution.GetNumRanks()) + " ranks";
    if (params_.preconditioner == PcgPreconditioner::BlockJacobi) text += " (IC(k) blocks within each rank)";
  }
  return text;
}

IncompleteCholesky const* PetscPcgSolver::GetIncompleteFactor() const {
  return impl_->usesIncomplete ? &impl_->incomplete : nullptr;
}

void PetscPcgSolver::SetRelativeTolerance(real relativeTolerance) {
  impl_->relativeTolerance = relativeTolerance;
  if (impl_->ksp)
    KSPSetTolerances(impl_->ksp, relativeTolerance, params_.absoluteTolerance, PETSC_DEFAULT,
                     params_.maxIterations);
}

bool PetscPcgSolver::WantsNearNullSpace() const {
  return params_.preconditioner == PcgPreconditioner::Gamg;
}

void PetscPcgSolver::SetNearNullSpace(MatrixX const& modes) {
  Impl& impl = *impl_;
  if (!impl.matrix || modes.rows() != impl.size || modes.cols() == 0) return;
  if (impl.IsDistributed()) return impl.SetDistributedNearNullSpace(modes);
  // orthonormal basis of the modes' span (PETSc requires it), dropping
  // directions that are numerically dependent (e.g. rotations of one node)
  // (a system of fewer unknowns than modes, e.g. one revolute joint against
  // the six rigid-body modes, spans at most `rows` directions)
  Eigen::HouseholderQR<MatrixX> qr(modes);
  Eigen::Index const rank = std::min(modes.rows(), modes.cols());
  MatrixX const q = qr.householderQ() * MatrixX::Identity(modes.rows(), rank);
  real const largest = qr.matrixQR().diagonal().cwiseAbs().maxCoeff();
  DynamicArray<Vec> vectors;
  for (Eigen::Index k = 0; k < rank; ++k) {
    if (std::abs(qr.matrixQR()(k, k)) <= 1e-10 * largest) continue;
    Vec v = nullptr;
    if (VecCreateSeq(PETSC_COMM_SELF, impl.size, &v) != 0) break;
    PetscScalar* values = nullptr;
    VecGetArrayWrite(v, &values);
    std::memcpy(values, q.col(k).data(), sizeof(real) * static_cast<std::size_t>(impl.size));
    VecRestoreArrayWrite(v, &values);
    vectors.push_back(v);
  }
  MatNullSpace space = nullptr;
  if (!vectors.empty() &&
      MatNullSpaceCreate(PETSC_COMM_SELF, PETSC_FALSE, static_cast<PetscInt>(vectors.size()),
                         vectors.data(), &space) == 0) {
    impl.hasNearNullSpace = MatSetNearNullSpace(impl.matrix, space) == 0;
    MatNullSpaceDestroy(&space);  // the matrix keeps its own reference
  }
  for (Vec& v : vectors) VecDestroy(&v);
}

// More than one rank: the owned rows of the modes, orthonormalized by
// Gram–Schmidt with reorthogonalization (two passes per mode; the dot
// products and norms are PETSc's global reductions, so every rank computes
// the same numbers and keeps the same modes). A mode whose remainder is at
// most 1e-10 of the largest mode's norm is dependent and dropped, as the
// one-rank QR drops a column with a small R diagonal.
void PetscPcgSolver::Impl::SetDistributedNearNullSpace(MatrixX const& modes) {
  int const rowBegin = distributed.GetRowBegin(), ownedRows = distributed.GetNumOwnedRows();
  auto const numModes = static_cast<int>(modes.cols());
  DynamicArray<Vec> candidates(static_cast<std::size_t>(numModes), nullptr), kept;
  DynamicArray<PetscScalar> dots(static_cast<std::size_t>(numModes));
  real largest = 0;
  bool ok = true;
  for (int c = 0; c < numModes && ok; ++c) {
    PetscScalar* values = nullptr;
    PetscReal norm = 0;
    ok = VecDuplicate(distributed.GetSolution(), &candidates[c]) == 0 &&
         VecGetArrayWrite(candidates[c], &values) == 0;
    if (!ok) break;
    for (int i = 0; i < ownedRows; ++i) values[i] = modes(rowBegin + i, c);
    ok = VecRestoreArrayWrite(candidates[c], &values) == 0 && VecNorm(candidates[c], NORM_2, &norm) == 0;
    largest = std::max(largest, static_cast<real>(norm));
  }
  for (int c = 0; c < numModes && ok; ++c) {
    Vec v = candidates[c];
    auto const numKept = static_cast<PetscInt>(kept.size());
    for (int pass = 0; pass < 2 && numKept > 0 && ok; ++pass) {
      ok = VecMDot(v, numKept, kept.data(), dots.data()) == 0;
      for (PetscInt k = 0; k < numKept; ++k) dots[k] = -dots[k];
      ok = ok && VecMAXPY(v, numKept, dots.data(), kept.data()) == 0;
    }
    PetscReal norm = 0;
    ok = ok && VecNorm(v, NORM_2, &norm) == 0;
    if (!ok || norm <= 1e-10 * largest) continue;
    ok = VecScale(v, 1 / norm) == 0;
    kept.push_back(v);
  }
  MatNullSpace space = nullptr;
  if (ok && !kept.empty() &&
      MatNullSpaceCreate(ToMpiComm(distribution.communicator), PETSC_FALSE,
                         static_cast<PetscInt>(kept.size()), kept.data(), &space) == 0) {
    hasNearNullSpace = MatSetNearNullSpace(matrix, space) == 0;
    MatNullSpaceDestroy(&space);  // the matrix keeps its own reference
  }
  for (Vec& v : candidates) VecDestroy(&v);
}

bool PetscPcgSolver::DoSetDistribution(Communicator const& communicator, int rowBegin, int rowEnd) {
  impl_->distribution = {communicator, rowBegin, rowEnd};
  return true;
}

// One rank: the full-storage SeqAIJ of A, the map from A's entries to its
// value array, and the vectors
LinearSolveResult PetscPcgSolver::Impl::CreateSequentialMatrix(SparseSymmetricMatrix const& a) {
  int const n = a.size;

  // full CSR of the symmetric A: row r holds its lower entries (from CSC
  // column r, rows < r, in order), then the diagonal and upper entries (from
  // CSC columns >= r, appended as the columns are visited in order)
  DynamicArray<PetscInt> rowStart(static_cast<std::size_t>(n) + 1, 0);
  DynamicArray<PetscInt> lowerCount(n), cursor(n);
  for (int j = 0; j < n; ++j) {
    lowerCount[j] = a.colStart[j + 1] - a.colStart[j] - 1;
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) ++rowStart[a.rowIndex[k] + 1];
  }
  for (int r = 0; r < n; ++r) {
    rowStart[r + 1] += rowStart[r] + lowerCount[r];
    cursor[r] = rowStart[r] + lowerCount[r];
  }
  DynamicArray<PetscInt> columns(static_cast<std::size_t>(rowStart[n]));
  upperSlot.assign(a.rowIndex.size(), -1);
  lowerSlot.assign(a.rowIndex.size(), -1);
  for (int j = 0; j < n; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
      int const i = a.rowIndex[k];
      if (i < j) {
        PetscInt const mirror = rowStart[j] + (k - a.colStart[j]);
        columns[mirror] = i;
        lowerSlot[k] = mirror;
      }
      PetscInt const slot = cursor[i]++;
      columns[slot] = j;
      upperSlot[k] = slot;
    }
  }

  // DoF blocks: variable sizes for point-block Jacobi, their gcd as the
  // matrix block size (AMG aggregates whole nodes)
  if (a.blockSizes.empty())
    blockSizes.assign(n, 1);
  else
    blockSizes.assign(a.blockSizes.begin(), a.blockSizes.end());
  int blockSize = 0;
  for (int size : a.blockSizes) blockSize = std::gcd(blockSize, size);
  if (blockSize <= 0 || n % blockSize != 0) blockSize = 1;

  SUPERDEX_PETSC(MatCreate(PETSC_COMM_SELF, &matrix));
  SUPERDEX_PETSC(MatSetSizes(matrix, n, n, n, n));
  SUPERDEX_PETSC(MatSetBlockSize(matrix, blockSize));
  SUPERDEX_PETSC(MatSetType(matrix, MATSEQAIJ));
  SUPERDEX_PETSC(MatSeqAIJSetPreallocationCSR(matrix, rowStart.data(), columns.data(), nullptr));
  // symmetric, but not flagged SPD: with exact element Hessians Newton may
  // hand over an indefinite matrix, on which GAMG's CG eigenvalue estimates
  // (chosen for SPD matrices) break down inside the set-up
  SUPERDEX_PETSC(MatSetOption(matrix, MAT_SYMMETRIC, PETSC_TRUE));
  SUPERDEX_PETSC(MatSetOption(matrix, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  SUPERDEX_PETSC(MatSetOption(matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
  if (n > 0)
    SUPERDEX_PETSC(MatSetVariableBlockSizes(matrix, static_cast<PetscInt>(blockSizes.size()),
                                            blockSizes.data()));
  SUPERDEX_PETSC(MatCreateVecs(matrix, &solution, &rhs));
  // the solution Vec only ever wraps the caller's x: free its own storage
  VecDestroy(&solution);
  SUPERDEX_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, nullptr, &solution));
  return {};
}

// More than one rank: the MPIAIJ of the owned rows (PetscDistributedMatrix),
// referenced as `matrix`, with the owned DoF blocks for point-block Jacobi
LinearSolveResult PetscPcgSolver::Impl::CreateDistributedMatrix(SparseSymmetricMatrix const& a) {
  if (LinearSolveResult created = distributed.Create(a, distribution); !created.Ok()) return created;
  matrix = distributed.GetMatrix();
  SUPERDEX_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(matrix)));
  Span<int const> const owned = distributed.GetOwnedBlockSizes();
  blockSizes.assign(owned.begin(), owned.end());
  if (!blockSizes.empty())
    SUPERDEX_PETSC(MatSetVariableBlockSizes(matrix, static_cast<PetscInt>(blockSizes.size()),
                                            blockSizes.data()));
  return {};
}

// The owned rows' diagonal block of A in local numbering (rows and columns
// minus rowBegin), upper CSC, with its DoF blocks; its values are filled
// from A's through ownedBlockSource at each Factorize
void PetscPcgSolver::Impl::BuildOwnedBlock(SparseSymmetricMatrix const& a) {
  int const begin = distribution.rowBegin, end = distribution.rowEnd;
  ownedBlock = SparseSymmetricMatrix{};
  ownedBlock.size = end - begin;
  ownedBlock.patternVersion = a.patternVersion;
  ownedBlock.colStart.assign(static_cast<std::size_t>(ownedBlock.size) + 1, 0);
  ownedBlockSource.clear();
  for (int j = begin; j < end; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k)
      if (a.rowIndex[k] >= begin) {
        ownedBlock.rowIndex.push_back(a.rowIndex[k] - begin);
        ownedBlockSource.push_back(k);
      }
    ownedBlock.colStart[j - begin + 1] = static_cast<int>(ownedBlock.rowIndex.size());
  }
  ownedBlock.values.assign(ownedBlock.rowIndex.size(), 0);
  Span<int const> const owned = distributed.GetOwnedBlockSizes();
  ownedBlock.blockSizes.assign(owned.begin(), owned.end());
}

LinearSolveResult PetscPcgSolver::DoAnalyze(SparseSymmetricMatrix const& a) {
  Impl& impl = *impl_;
  impl.DestroyObjects();
  impl.ClearOptions();
  impl.hasNearNullSpace = false;
  impl.optionsChecked = false;
  impl.setUps = 0;
  int const n = a.size;
  impl.size = n;
  if (impl.IsDistributed() && params_.preconditioner == PcgPreconditioner::Icc)
    return SolveFailure(LinearSolveStatus::InvalidInput,
                        "PcgParams.preconditioner Icc (SuperDex's incomplete Cholesky of the whole "
                        "matrix, sequential) cannot run across " +
                            std::to_string(impl.distribution.GetNumRanks()) +
                            " MPI ranks; BlockJacobi (IC(k) within each rank), Gamg or BoomerAmg can");
  if (LinearSolveResult built =
          impl.IsDistributed() ? impl.CreateDistributedMatrix(a) : impl.CreateSequentialMatrix(a);
      !built.Ok())
    return built;

  // KSP: CG on the unpreconditioned residual, zero initial guess
  SUPERDEX_PETSC(KSPCreate(impl.IsDistributed() ? ToMpiComm(impl.distribution.communicator)
                                                : PETSC_COMM_SELF,
                           &impl.ksp));
  SUPERDEX_PETSC(KSPSetOptionsPrefix(impl.ksp, impl.prefix.c_str()));
  SUPERDEX_PETSC(KSPSetType(impl.ksp, KSPCG));
  SUPERDEX_PETSC(KSPSetOperators(impl.ksp, impl.matrix, impl.matrix));
  SUPERDEX_PETSC(KSPSetNormType(impl.ksp, KSP_NORM_UNPRECONDITIONED));
  SUPERDEX_PETSC(KSPSetInitialGuessNonzero(impl.ksp, PETSC_FALSE));
  SUPERDEX_PETSC(KSPSetTolerances(impl.ksp, impl.relativeTolerance, params_.absoluteTolerance,
                                  PETSC_DEFAULT, params_.maxIterations));
  PC pc = nullptr;
  SUPERDEX_PETSC(KSPGetPC(impl.ksp, &pc));
  impl.usesIncomplete = params_.preconditioner == PcgPreconditioner::Icc ||
                        params_.preconditioner == PcgPreconditioner::BlockJacobi;
  impl.incompleteFactored = false;
  if (impl.usesIncomplete) {
    // block Jacobi: contiguous groups of whole DoF blocks with about equal
    // DoF counts, each its own incomplete factor; ICC: one group. Across
    // ranks, each rank factors the diagonal block of its own rows, in its
    // share of max(blockJacobiBlocks, R) groups, and the shell PC applies
    // it to the owned entries of the residual
    if (impl.IsDistributed()) impl.BuildOwnedBlock(a);
    SparseSymmetricMatrix const& factored = impl.IsDistributed() ? impl.ownedBlock : a;
    DynamicArray<int> groupSizes;
    if (params_.preconditioner == PcgPreconditioner::BlockJacobi) {
      int groups = params_.blockJacobiBlocks;
      if (impl.IsDistributed()) {
        int const ranks = impl.distribution.GetNumRanks();
        int const rank = impl.distribution.communicator.GetRank();
        long const total = std::max(params_.blockJacobiBlocks, ranks);
        groups = static_cast<int>(total * (rank + 1) / ranks - total * rank / ranks);
      }
      groups = std::max(1, std::min(groups, factored.size));
      groupSizes = BlockJacobiGroups(factored.blockSizes.empty()
                                         ? DynamicArray<int>(factored.size, 1)
                                         : factored.blockSizes,
                                     factored.size, groups);
    }
    IncompleteCholesky::Result const analyzed =
        impl.incomplete.Analyze(factored, params_.iccLevels, groupSizes);
    LinearSolveResult analyzedResult;
    if (!analyzed.ok)
      analyzedResult = SolveFailure(LinearSolveStatus::InvalidInput, "incomplete Cholesky: " + analyzed.reason);
    if (impl.IsDistributed()) analyzedResult = AgreeOnResult(impl.distribution.communicator, analyzedResult);
    if (!analyzedResult.Ok()) return analyzedResult;
    SUPERDEX_PETSC(PCSetType(pc, PCSHELL));
    SUPERDEX_PETSC(PCShellSetContext(pc, &impl.incomplete));
    SUPERDEX_PETSC(PCShellSetApply(pc, ApplyIncompleteCholesky));
    SUPERDEX_PETSC(PCShellSetName(pc, params_.preconditioner == PcgPreconditioner::Icc
                                          ? "SuperDex IC(k), RCM order"
                                          : "SuperDex block Jacobi with IC(k), RCM order"));
  } else {
    SUPERDEX_PETSC(PCSetType(pc, PcTypeName(params_.preconditioner)));
  }

  // preconditioner settings SuperDex chooses, as options under this solver's
  // prefix so that PcgParams::options (inserted after them) can override them
  auto setDefault = [&](std::string const& option, std::string const& value) {
    std::string const name = Prefixed(impl.prefix, option);
    impl.defaultNames.push_back(name);
    return PetscOptionsSetValue(nullptr, name.c_str(), value.c_str());
  };
  switch (params_.preconditioner) {
    case PcgPreconditioner::Gamg:
      SUPERDEX_PETSC(PCGAMGSetReuseInterpolation(pc, params_.reuseAmgInterpolation ? PETSC_TRUE
                                                                                    : PETSC_FALSE));
      // GAMG's Chebyshev smoothers take their spectrum from the smoothed-
      // aggregation estimate of λmax(D⁻¹A) (10 GMRES iterations) times 1.1,
      // PETSc's defaults. On the rods that bound is below λmax: the smoother
      // amplifies the top of the spectrum and the V-cycle is an indefinite
      // preconditioner (KSP_DIVERGED_INDEFINITE_PC from 50 nodes per rod on).
      // A better estimate (30 iterations) and a wider bound (1.3 ×) converge
      // on every rods size and cost the other families little; SOR smoothing
      // fails on the rods' singular coarse operators (zero diagonals).
      // Measured in docs/linear_solvers.md.
      SUPERDEX_PETSC(setDefault("-pc_gamg_esteig_ksp_max_it", "30"));
      SUPERDEX_PETSC(setDefault("-mg_levels_ksp_chebyshev_esteig", "0,0.1,0,1.3"));
      if (IsRodDominated(a)) {
        // rods (thin, bending): GAMG's first coarsening on the squared
        // graph (aggregates of ~7 nodes along a rod) needs 88-354 CG
        // iterations per solve from 4x50 to 100x250, and more than 200 in
        // 6 of the 9 cells of the harness's 16x50 stability map. Aggregates
        // on the graph itself, a 0.02 threshold on the first coarse level's
        // graph and a direct solve below 2000 equations need 1.4-10x fewer
        // and less time per step up to 49x125 (the same at 100x250). A
        // threshold on every coarse level cut iterations further but made
        // the coarse levels dense (every rod coupled to the others through
        // the plate): 100x250 took 218 s per step instead of 122. The beam,
        // the cloth and the chains, whose DoF blocks are not rod nodes,
        // keep GAMG's coarsening: there the unsquared graph with that
        // threshold on every coarse level cost 2-3x the time per step for
        // at most 2x fewer iterations (more on the articulated chain).
        // Measured in docs/linear_solvers.md
        SUPERDEX_PETSC(setDefault("-pc_gamg_square_graph", "0"));
        SUPERDEX_PETSC(setDefault("-pc_gamg_threshold", "-1,0.02,-1"));
        SUPERDEX_PETSC(setDefault("-pc_gamg_coarse_eq_limit", "2000"));
      }
      break;
    case PcgPreconditioner::BoomerAmg:
      SUPERDEX_PETSC(PCHYPRESetType(pc, "boomeramg"));
      SUPERDEX_PETSC(setDefault("-pc_hypre_boomeramg_strong_threshold", "0.5"));
      break;
    default:
      break;
  }
  DynamicArray<OptionPair> userOptions;
  std::string bad;
  ParseOptions(params_.options, userOptions, bad);  // validated by ValidatePcgParams
  for (auto const& option : userOptions) {
    std::string const name = Prefixed(impl.prefix, option.name);
    impl.userNames.push_back(name);
    SUPERDEX_PETSC(PetscOptionsSetValue(nullptr, name.c_str(),
                                        option.value.empty() ? nullptr : option.value.c_str()));
  }
  SUPERDEX_PETSC(KSPSetFromOptions(impl.ksp));
  ++numObjectBuilds_;
  return {};
}

LinearSolveResult PetscPcgSolver::DoFactorize(SparseSymmetricMatrix const& a) {
  Impl& impl = *impl_;
  bool const distributed = impl.IsDistributed();
  // a positive definite matrix has a positive diagonal: a zero, negative or
  // missing diagonal entry is reported before PETSc sees the matrix. (GAMG
  // set up on a 1×1 zero matrix without a failed reason, then KSPSolve
  // failed with "Arguments are incompatible", and destroying that KSP read
  // freed memory: tests/fuzz/corpus/scene_api/gamg-zero-diagonal.bin)
  {
    int const begin = distributed ? impl.distribution.rowBegin : 0;
    int const end = distributed ? impl.distribution.rowEnd : a.size;
    LinearSolveResult diagonal;
    for (int j = begin; j < end && diagonal.Ok(); ++j) {
      real value = 0;
      for (int k = a.colStart[j + 1] - 1; k >= a.colStart[j] && a.rowIndex[k] >= j; --k)
        if (a.rowIndex[k] == j) value = a.values[k];
      if (!(value > 0)) {
        diagonal = SolveFailure(LinearSolveStatus::NotPositiveDefinite,
                                "column " + std::to_string(j) + ": diagonal entry " + Format(value) +
                                    ", not positive (the matrix is not positive definite)");
        diagonal.failingColumn = j;
      }
    }
    if (distributed) diagonal = AgreeOnResult(impl.distribution.communicator, diagonal);
    if (!diagonal.Ok()) return diagonal;
  }
  if (distributed) {
    // the owned rows' values in place (PetscDistributedMatrix::SetValues)
    if (LinearSolveResult set = impl.distributed.SetValues(a); !set.Ok()) return set;
  } else {
    // values in place: both triangles of the AIJ storage from A's upper CSC
    PetscScalar* values = nullptr;
    SUPERDEX_PETSC(MatSeqAIJGetArrayWrite(impl.matrix, &values));
    std::size_t const numEntries = a.values.size();
    for (std::size_t k = 0; k < numEntries; ++k) {
      values[impl.upperSlot[k]] = a.values[k];
      if (impl.lowerSlot[k] >= 0) values[impl.lowerSlot[k]] = a.values[k];
    }
    SUPERDEX_PETSC(MatSeqAIJRestoreArrayWrite(impl.matrix, &values));
  }

  // rebuild the preconditioner every preconditionerLag-th set-up (and after
  // a failed one)
  bool const reuse = impl.setUps % params_.preconditionerLag != 0 &&
                     (!impl.usesIncomplete || impl.incompleteFactored);
  ++impl.setUps;
  if (impl.usesIncomplete && !reuse) {
    impl.incompleteFactored = false;
    // across ranks: this rank's diagonal block, its values from A's
    if (distributed)
      for (std::size_t m = 0; m < impl.ownedBlockSource.size(); ++m)
        impl.ownedBlock.values[m] = a.values[impl.ownedBlockSource[m]];
    IncompleteCholesky::Result const factored =
        impl.incomplete.Factorize(distributed ? impl.ownedBlock : a);
    LinearSolveResult result;
    if (!factored.ok) {
      result = SolveFailure(LinearSolveStatus::NotPositiveDefinite,
                  "PETSc preconditioner " + std::string(ToString(params_.preconditioner)) + ": " +
                      factored.reason);
      result.failingColumn = factored.failingColumn;
      if (distributed && factored.failingColumn >= 0) result.failingColumn += impl.distribution.rowBegin;
    }
    // a rank's factor fails alone: every rank reports it
    if (distributed) result = AgreeOnResult(impl.distribution.communicator, result);
    if (!result.Ok()) return result;
    impl.incompleteFactored = true;
  }
  PC pc = nullptr;
  SUPERDEX_PETSC(KSPGetPC(impl.ksp, &pc));
  SUPERDEX_PETSC(PCSetReusePreconditioner(pc, reuse ? PETSC_TRUE : PETSC_FALSE));
  // same objects: marks the operator as changed so that KSPSetUp sets the
  // preconditioner up here rather than inside the next KSPSolve
  SUPERDEX_PETSC(KSPSetOperators(impl.ksp, impl.matrix, impl.matrix));
  SUPERDEX_PETSC(KSPSetUp(impl.ksp));
  PCFailedReason failed = PC_NOERROR;
  SUPERDEX_PETSC(PCGetFailedReason(pc, &failed));
  LinearSolveResult setUp;
  if (failed != PC_NOERROR)
    // every PCFailedReason is a factorization breaking down inside the
    // preconditioner (an AMG coarse-grid or smoother factorization): what an indefinite matrix causes, and what Newton
    // answers by projecting the element Hessians
    setUp = SolveFailure(LinearSolveStatus::NotPositiveDefinite,
                   "PETSc preconditioner " + std::string(ToString(params_.preconditioner)) +
                       " set-up failed: PC_" + PCFailedReasons[failed] +
                       " (a factorization inside it broke down: the matrix is not positive "
                       "definite, or too badly conditioned for it)");
  // the failed reason is this rank's: every rank resets and reports it
  if (distributed) setUp = AgreeOnResult(impl.distribution.communicator, setUp);
  if (!setUp.Ok()) {
    // a failed set-up leaves the PC unusable: start its next set-up afresh
    PCReset(pc);
    return setUp;
  }

  // every option of PcgParams::options must have been read by now
  if (!impl.optionsChecked) {
    impl.optionsChecked = true;
    for (std::size_t i = 0; i < impl.userNames.size(); ++i) {
      PetscBool used = PETSC_FALSE;
      // the database stores names without their leading '-'
      SUPERDEX_PETSC(PetscOptionsUsed(nullptr, impl.userNames[i].c_str() + 1, &used));
      if (!used) {
        std::string const option = "-" + impl.userNames[i].substr(1 + impl.prefix.size());
        return SolveFailure(LinearSolveStatus::InvalidInput,
                       "PcgParams.options: PETSc did not use the option '" + option +
                           "' (unknown, or not applicable to preconditioner " +
                           std::string(ToString(params_.preconditioner)) + ")");
      }
    }
  }
  return {};
}

LinearSolveResult PetscPcgSolver::DoSolve(Span<real const> b, Span<real> x) {
  Impl& impl = *impl_;
  Vec rhsVector = impl.rhs;
  if (impl.IsDistributed()) {
    // the owned entries of b, and of x (Resume's initial guess; KSPSolve
    // zeroes it otherwise); every rank gets all of x, also a truncated one
    rhsVector = impl.distributed.GetRhs();
    if (LinearSolveResult set = impl.distributed.SetRhs(b); !set.Ok()) return set;
    if (LinearSolveResult set = impl.distributed.SetSolution(x); !set.Ok()) return set;
    if (LinearSolveResult solved = AgreeOnPetscCall(
            impl.distribution.communicator,
            KSPSolve(impl.ksp, rhsVector, impl.distributed.GetSolution()), "KSPSolve");
        !solved.Ok())
      return solved;
    if (LinearSolveResult gathered = impl.distributed.GatherSolution(x); !gathered.Ok()) return gathered;
  } else {
    PetscScalar* rhs = nullptr;
    SUPERDEX_PETSC(VecGetArrayWrite(impl.rhs, &rhs));
    std::copy(b.begin(), b.end(), rhs);  // memcpy with null pointers (n = 0) is undefined
    SUPERDEX_PETSC(VecRestoreArrayWrite(impl.rhs, &rhs));
    SUPERDEX_PETSC(VecPlaceArray(impl.solution, x.data()));
    PetscErrorCode const code = KSPSolve(impl.ksp, impl.rhs, impl.solution);
    VecResetArray(impl.solution);
    if (code != 0)
      return SolveFailure(LinearSolveStatus::BackendError, "PETSc KSPSolve failed: " + PetscErrorText(code));
  }

  KSPConvergedReason reason = KSP_CONVERGED_ITERATING;
  PetscInt iterations = 0;
  PetscReal residual = 0, rhsNorm = 0;
  SUPERDEX_PETSC(KSPGetConvergedReason(impl.ksp, &reason));
  SUPERDEX_PETSC(KSPGetIterationNumber(impl.ksp, &iterations));
  SUPERDEX_PETSC(KSPGetResidualNorm(impl.ksp, &residual));
  SUPERDEX_PETSC(VecNorm(rhsVector, NORM_2, &rhsNorm));

  LinearSolveResult result;
  result.iterations = static_cast<int>(iterations);
  result.relativeResidual = rhsNorm > 0 ? residual / rhsNorm : 0;
  if (reason < 0) {
    char detail[160];
    std::snprintf(detail, sizeof(detail), " after %d iterations, relative residual %.3g (rtol %.3g)",
                  result.iterations, result.relativeResidual, impl.relativeTolerance);
    // negative curvature met by CG: the matrix (or the preconditioner built
    // from it) is not positive definite, which Newton answers by projection
    bool const indefinite = reason == KSP_DIVERGED_INDEFINITE_MAT || reason == KSP_DIVERGED_INDEFINITE_PC;
    result.status = indefinite ? LinearSolveStatus::NotPositiveDefinite : LinearSolveStatus::NotConverged;
    result.truncated = reason == KSP_DIVERGED_ITS;
    result.reason = "PETSc CG + " + std::string(ToString(params_.preconditioner)) +
                    " did not converge: KSP_" + KSPConvergedReasons[reason] + detail;
    if (reason == KSP_DIVERGED_PC_FAILED) {
      PC pc = nullptr;
      PCFailedReason failed = PC_NOERROR;
      KSPGetPC(impl.ksp, &pc);
      PCGetFailedReason(pc, &failed);
      result.reason += std::string(" (PC_") + PCFailedReasons[failed] + ")";
    }
  }
  return result;
}

LinearSolveResult PetscPcgSolver::DoResume(Span<real const> b, Span<real> x) {
  SUPERDEX_PETSC(KSPSetInitialGuessNonzero(impl_->ksp, PETSC_TRUE));
  LinearSolveResult result = DoSolve(b, x);
  SUPERDEX_PETSC(KSPSetInitialGuessNonzero(impl_->ksp, PETSC_FALSE));
  return result;
}

}  // namespace superdex::internal

namespace superdex {

std::string_view ToString(PcgPreconditioner preconditioner) {
  switch (preconditioner) {
    case PcgPreconditioner::None: return "None";
    case PcgPreconditioner::Jacobi: return "Jacobi";
    case PcgPreconditioner::PointBlockJacobi: return "PointBlockJacobi";
    case PcgPreconditioner::BlockJacobi: return "BlockJacobi";
    case PcgPreconditioner::Icc: return "Icc";
    case PcgPreconditioner::Gamg: return "Gamg";
    case PcgPreconditioner::BoomerAmg: return "BoomerAmg";
  }
  return "Unknown";
}

DynamicArray<PcgPreconditioner> AvailablePcgPreconditioners() {
  DynamicArray<PcgPreconditioner> available{
      PcgPreconditioner::None, PcgPreconditioner::Jacobi, PcgPreconditioner::PointBlockJacobi,
      PcgPreconditioner::BlockJacobi, PcgPreconditioner::Icc, PcgPreconditioner::Gamg};
#if defined(PETSC_HAVE_HYPRE)
  available.push_back(PcgPreconditioner::BoomerAmg);
#endif
  return available;
}

bool ValidatePcgParams(PcgParams const& params, Error& error) {
  using internal::Format;
  auto const invalid = [&](std::string message) {
    error.Set(ErrorCode::InvalidArgument, "PcgParams." + std::move(message));
    return false;
  };
  auto const available = AvailablePcgPreconditioners();
  if (std::find(available.begin(), available.end(), params.preconditioner) == available.end()) {
    int const value = static_cast<int>(params.preconditioner);
    if (value < 0 || value > static_cast<int>(PcgPreconditioner::BoomerAmg))
      return invalid("preconditioner must be a PcgPreconditioner, got the value " +
                     std::to_string(value));
    error.Set(ErrorCode::NotSupported,
              "PcgParams.preconditioner " + std::string(ToString(params.preconditioner)) +
                  " is not in this build (PETSc without hypre)");
    return false;
  }
  if (!(params.relativeTolerance > 0 && params.relativeTolerance < 1))
    return invalid("relativeTolerance must be in (0, 1), got " + Format(params.relativeTolerance));
  if (!(params.absoluteTolerance >= 0) || !std::isfinite(params.absoluteTolerance))
    return invalid("absoluteTolerance must be finite and >= 0, got " +
                   Format(params.absoluteTolerance));
  if (params.maxIterations <= 0)
    return invalid("maxIterations must be > 0, got " + std::to_string(params.maxIterations));
  if (!(params.adaptiveMaxTolerance >= params.relativeTolerance && params.adaptiveMaxTolerance < 1))
    return invalid("adaptiveMaxTolerance must be in [relativeTolerance, 1) = [" +
                   Format(params.relativeTolerance) + ", 1), got " +
                   Format(params.adaptiveMaxTolerance));
  if (params.preconditionerLag < 1)
    return invalid("preconditionerLag must be >= 1, got " +
                   std::to_string(params.preconditionerLag));
  if (params.blockJacobiBlocks < 1)
    return invalid("blockJacobiBlocks must be >= 1, got " +
                   std::to_string(params.blockJacobiBlocks));
  if (params.iccLevels < 0)
    return invalid("iccLevels must be >= 0, got " + std::to_string(params.iccLevels));
  DynamicArray<internal::OptionPair> pairs;
  std::string bad;
  if (!internal::ParseOptions(params.options, pairs, bad))
    return invalid("options: '" + bad +
                   "' is neither a PETSc option name (-name) nor the value of the option before it"
                   ", in \"" + params.options + "\"");
  if (!pairs.empty()) {
    // an option PETSc does not use, or whose value it cannot read, shows
    // only in a set-up: one on a small SPD system (a 1-D Laplacian of 8
    // unknowns in blocks of 2) refuses it here, not at the next step
    if (!internal::EnsurePetscInitialized(error)) return false;
    SparseSymmetricMatrix a;
    a.size = 8;
    a.blockSizes.assign(4, 2);
    a.colStart.push_back(0);
    for (int j = 0; j < a.size; ++j) {
      if (j > 0) {
        a.rowIndex.push_back(j - 1);
        a.values.push_back(-1);
      }
      a.rowIndex.push_back(j);
      a.values.push_back(3);
      a.colStart.push_back(static_cast<int>(a.rowIndex.size()));
    }
    internal::PetscPcgSolver trial(params);
    LinearSolveResult result = trial.Analyze(a);
    if (result.Ok()) result = trial.Factorize(a);
    if (!result.Ok()) {
      std::string reason = result.reason;
      if (reason.rfind("PcgParams.options", 0) != 0) reason = "PcgParams.options: " + reason;
      error.Set(ErrorCode::InvalidArgument, reason + ", in \"" + params.options + "\"");
      return false;
    }
  }
  return true;
}

}  // namespace superdex
