// superdex_dense_vs_sparse: times the dense and the CHOLMOD backend of
// LinearSolver on systems shaped like SuperDex's Newton Hessians for
// articulated rigid bodies, to choose kDenseSolverMaxSize.
//
// The systems are chains of rigid bodies (6 DoFs each) joined by joints: each
// body contributes a diagonal mass block, each joint a dense 12 x 12 block
// J' K J (J a 6 x 12 Jacobian) coupling its two bodies. The matrix is
// block-tridiagonal with 6 x 6 blocks, in chain order (which is also what a
// fill-reducing ordering of a chain gives: no fill).
//
// Per size and backend it reports Analyze (once, on a fresh solver), and the
// per-Newton-iteration cost Factorize, Solve and Factorize + Solve, each the
// best of several batches of many repetitions (best, because the machine may
// be shared). It prints what really ran (the backend's own description, the
// BLAS and its threads) and the largest size up to which dense is not slower.
//
// Usage: superdex_dense_vs_sparse [--quick] [--bodies 1,2,5,...]
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <superdex/linsolve/linear_solver.h>

namespace {

using superdex::CreateLinearSolver;
using superdex::Error;
using superdex::LinearSolver;
using superdex::LinearSolverType;
using superdex::real;
using superdex::SparseSymmetricMatrix;
using superdex::VectorX;
using Clock = std::chrono::steady_clock;

// The Hessian of a chain of numBodies rigid bodies: diagonal masses and
// inertias in [1, 2], and per joint 100 J' J with J a random 6 x 12 Jacobian.
// Stored as the upper triangle in CSC; deterministic for a given size.
SparseSymmetricMatrix RigidChainHessian(int numBodies) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<real> uniform(-1, 1);
  int const n = 6 * numBodies;
  // dense scratch for the block-tridiagonal band: test-harness code
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) dense(i, i) = 1.5 + 0.5 * uniform(rng);
  for (int joint = 0; joint + 1 < numBodies; ++joint) {
    Eigen::Matrix<real, 6, 12> jacobian;
    for (Eigen::Index k = 0; k < jacobian.size(); ++k) jacobian.data()[k] = uniform(rng);
    dense.block<12, 12>(6 * joint, 6 * joint) += 100 * jacobian.transpose() * jacobian;
  }
  SparseSymmetricMatrix a;
  a.size = n;
  a.patternVersion = 1;
  a.colStart.push_back(0);
  for (int j = 0; j < n; ++j) {
    // column j of the upper triangle: rows of this body and the previous one
    int const firstRow = std::max(0, (j / 6 - 1) * 6);
    for (int i = firstRow; i <= j; ++i) {
      a.rowIndex.push_back(i);
      a.values.push_back(dense(i, j));
    }
    a.colStart.push_back(static_cast<int>(a.rowIndex.size()));
  }
  return a;
}

real RelativeResidual(SparseSymmetricMatrix const& a, VectorX const& x, VectorX const& b) {
  VectorX r = -b;
  for (int j = 0; j < a.size; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
      int const i = a.rowIndex[k];
      r[i] += a.values[k] * x[j];
      if (i != j) r[j] += a.values[k] * x[i];
    }
  }
  return r.norm() / b.norm();
}

double Seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// Best (smallest) mean time per call of `body` over `numBatches` batches of
// enough repetitions to last about `batchSeconds` each.
template <class Body>
double BestMeanSeconds(Body&& body, double batchSeconds, int numBatches) {
  // calibrate the repetition count on a short run
  int reps = 1;
  for (;;) {
    auto const start = Clock::now();
    for (int r = 0; r < reps; ++r) body();
    double const elapsed = Seconds(Clock::now() - start);
    if (elapsed > batchSeconds / 20 || reps >= (1 << 24)) {
      reps = std::max(1, static_cast<int>(reps * batchSeconds / std::max(elapsed, 1e-9)));
      break;
    }
    reps *= 4;
  }
  double best = 1e300;
  for (int batch = 0; batch < numBatches; ++batch) {
    auto const start = Clock::now();
    for (int r = 0; r < reps; ++r) body();
    best = std::min(best, Seconds(Clock::now() - start) / reps);
  }
  return best;
}

struct Timing {
  double analyze = 0;    // s, one Analyze on a fresh solver (best of a few)
  double factorize = 0;  // s per call
  double solve = 0;      // s per call
  double iteration = 0;  // s per Factorize + Solve
  double factorNonzeros = 0;
  real residual = 0;
  std::string description;
};

bool Measure(LinearSolverType type, SparseSymmetricMatrix const& a, VectorX const& b,
             double batchSeconds, Timing& timing) {
  Error error;
  // Analyze: a fresh solver each time, as after a topology change
  timing.analyze = 1e300;
  std::unique_ptr<LinearSolver> solver;
  for (int trial = 0; trial < 5; ++trial) {
    solver = CreateLinearSolver(type, error);
    if (!solver) {
      std::fprintf(stderr, "CreateLinearSolver(%s): %s\n", std::string(ToString(type)).c_str(),
                   error.ToString().c_str());
      return false;
    }
    auto const start = Clock::now();
    superdex::LinearSolveResult const result = solver->Analyze(a);
    timing.analyze = std::min(timing.analyze, Seconds(Clock::now() - start));
    if (!result.Ok()) {
      std::fprintf(stderr, "Analyze: %s\n", result.reason.c_str());
      return false;
    }
  }

  VectorX x(a.size);
  superdex::Span<real const> const bView(b.data(), b.size());
  superdex::Span<real> const xView(x.data(), x.size());
  bool ok = true;
  auto const factorize = [&] { ok = solver->Factorize(a).Ok() && ok; };
  auto const solve = [&] { ok = solver->Solve(bView, xView).Ok() && ok; };
  // warm-up (first Solve allocates CHOLMOD's workspaces)
  for (int r = 0; r < 3; ++r) {
    factorize();
    solve();
  }
  timing.factorize = BestMeanSeconds(factorize, batchSeconds, 5);
  timing.solve = BestMeanSeconds(solve, batchSeconds, 5);
  timing.iteration = BestMeanSeconds(
      [&] {
        factorize();
        solve();
      },
      batchSeconds, 5);
  if (!ok) {
    std::fprintf(stderr, "%s: Factorize or Solve failed\n", std::string(ToString(type)).c_str());
    return false;
  }
  timing.residual = RelativeResidual(a, x, b);
  timing.factorNonzeros = solver->GetFactorNonzeros();
  timing.description = solver->GetDescription();
  return true;
}

// What BLAS runs, asked of the loaded library (CHOLMOD loads libblas.so.3).
void PrintBlas() {
  using ConfigFn = char* (*)();
  using ThreadsFn = int (*)();
  auto const config = reinterpret_cast<ConfigFn>(dlsym(RTLD_DEFAULT, "openblas_get_config"));
  auto const core = reinterpret_cast<ConfigFn>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  auto const threads = reinterpret_cast<ThreadsFn>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  if (config == nullptr) {
    std::printf("BLAS: not OpenBLAS (no openblas_get_config symbol)\n");
  } else {
    std::printf("BLAS: %s; core %s; %d threads\n", config(), core ? core() : "?",
                threads ? threads() : -1);
  }
  // CHOLMOD's OpenMP regions ask for 4 threads; only OMP_THREAD_LIMIT caps them
  std::printf("env:");
  for (char const* name :
       {"OPENBLAS_CORETYPE", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "OMP_THREAD_LIMIT"}) {
    char const* value = std::getenv(name);
    std::printf(" %s=%s", name, value ? value : "(unset)");
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::vector<int> bodies = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 12,
                             14, 16, 18, 20, 25, 30, 40, 50, 60, 80, 100};
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
      bodies = {1, 5, 10, 20, 50, 100};
    } else if (std::strcmp(argv[i], "--bodies") == 0 && i + 1 < argc) {
      bodies.clear();
      for (char* token = std::strtok(argv[++i], ","); token; token = std::strtok(nullptr, ",")) {
        int const value = std::atoi(token);
        if (value < 1) {
          std::fprintf(stderr, "--bodies: each count must be >= 1, got '%s'\n", token);
          return 2;
        }
        bodies.push_back(value);
      }
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--bodies 1,2,5,...]\n", argv[0]);
      return 2;
    }
  }
  double const batchSeconds = quick ? 0.005 : 0.05;

  std::printf("superdex_dense_vs_sparse: rigid chains, 6 DoFs per body, 12 x 12 joint blocks\n");
  PrintBlas();

  std::printf(
      "\n| n | bodies | nnz(triu A) | dense analyze | dense fact | dense solve | dense F+S "
      "| CHOLMOD analyze | CHOLMOD fact | CHOLMOD solve | CHOLMOD F+S | nnz(L) | F+S "
      "dense/CHOLMOD |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");

  int denseNotSlowerUpTo = 0;  // largest n with dense F+S <= CHOLMOD F+S at it and all below
  bool denseStillAhead = true;
  std::string denseDescription, cholmodDescription;
  for (int numBodies : bodies) {
    SparseSymmetricMatrix const a = RigidChainHessian(numBodies);
    VectorX b(a.size);
    for (int i = 0; i < a.size; ++i) b[i] = 1.0 + 0.01 * i;

    Timing dense, cholmod;
    if (!Measure(LinearSolverType::Dense, a, b, batchSeconds, dense)) return 1;
    if (!Measure(LinearSolverType::Cholmod, a, b, batchSeconds, cholmod)) return 1;
    if (dense.residual > 1e-10 || cholmod.residual > 1e-10) {
      std::fprintf(stderr, "n = %d: residual dense %.2e, CHOLMOD %.2e\n", a.size, dense.residual,
                   cholmod.residual);
      return 1;
    }
    denseDescription = dense.description;
    cholmodDescription = cholmod.description;

    double const ratio = dense.iteration / cholmod.iteration;
    if (denseStillAhead && ratio <= 1) denseNotSlowerUpTo = a.size;
    if (ratio > 1) denseStillAhead = false;

    auto const us = [](double s) { return s * 1e6; };
    std::printf(
        "| %d | %d | %lld | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.2f "
        "|\n",
        a.size, numBodies, static_cast<long long>(a.NumNonzeros()), us(dense.analyze),
        us(dense.factorize), us(dense.solve), us(dense.iteration), us(cholmod.analyze),
        us(cholmod.factorize), us(cholmod.solve), us(cholmod.iteration), cholmod.factorNonzeros,
        ratio);
    std::fflush(stdout);
  }
  std::printf(
      "\nTimes in microseconds: analyze once per pattern (fresh solver, best of 5); fact,"
      " solve and F+S per call (best of 5 batches).\n");
  std::printf("dense ran:   %s\n", denseDescription.c_str());
  std::printf("CHOLMOD ran: %s\n", cholmodDescription.c_str());
  std::printf(
      "dense Factorize+Solve is not slower than CHOLMOD up to n = %d "
      "(kDenseSolverMaxSize in this build: %d)\n",
      denseNotSlowerUpTo, superdex::kDenseSolverMaxSize);
  return 0;
}
