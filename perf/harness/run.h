// One run of the perf harness: its specification (what to simulate, with
// which solver, for how long), its result row (the CSV / JSON columns), and
// the in-process execution the `run` sub-command performs.
//
// A RunSpec travels from the parent (the suite driver) to the child process
// as command-line options; both directions use one option table
// (SpecOptions), so the parser, the serializer and `--help` cannot drift.
#pragma once

#include <superdex/superdex.h>

#include <array>
#include <concepts>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace superdex::perf {

/// Everything that defines one run. Labels (size, method, dt) are kept as
/// the strings the suites and the CSV use; they are parsed where needed.
struct RunSpec {
  std::string suite = "run";          ///< tiny | quick | full | run (a single run)
  std::string study = "scaling";      ///< scaling | work_precision | stability | bullet | reference
  std::string family = "cantilever";  ///< families.h
  std::string size = "10x2x2";        ///< family size label
  double stiffnessRatio = 1;          ///< multiplies the family's base stiffness
  std::string method = "cholmod";     ///< solver configuration label (Method below)
  std::string integrator = "be";      ///< be | bdf2
  std::string dt = "1/60";            ///< "1/N" or a decimal number [s]
  int steps = 3;                      ///< steps to take
  double endTime = 0;                 ///< > 0: overrides steps with round(endTime / dt)
  double rtol = 1e-8;                 ///< PCG relative tolerance (PCG methods only)
  double newtonTol = 1e-6;            ///< Newton velocityTolerance [m/s]
  int newtonMaxIterations = 0;        ///< 0: the family's default
  std::string constraintHessian = "gs";  ///< gn | gs | gsd: NewtonParams::constraintHessian
  double nearRigid = 0;               ///< NewtonParams::nearRigidBeta: the near-rigid cap β, 0 = off
  int pcgMaxIterations = 10000;       ///< PCG iteration cap
  int threads = 0;                    ///< SceneParams::numThreads: assembly threads, 0 = every CPU
  /// reserve | rebuild: SceneParams::patternPolicy (ReserveAndGrow, RebuildWhenChanged)
  std::string patternPolicy = "reserve";
  std::string referenceOut;           ///< write the final tracked positions here
  std::string referenceIn;            ///< compare the final tracked positions with this file
  std::string referenceDesc;          ///< the `reference` column when referenceIn is used
};

/// One option of the `run` sub-command, bound to a RunSpec field.
struct SpecOption {
  std::string_view name;  ///< "--family"
  std::string_view arg;   ///< placeholder in --help
  std::string_view help;
  std::variant<std::string RunSpec::*, double RunSpec::*, int RunSpec::*> field;
};

/// The steps the run takes: round(endTime / dt) when endTime > 0, else
/// `steps` (0 for a malformed dt).
int PlannedSteps(RunSpec const& spec);

/// The option table of RunSpec (every field, in the order of RunSpec).
std::vector<SpecOption> const& SpecOptions();

/// The RunSpec as `--name value` pairs (every field, round-trips exactly).
std::vector<std::string> SpecToArgs(RunSpec const& spec);

/// Parses `--name value` pairs into `spec` (fields not named keep their
/// value) and validates the result; false and a message on bad input.
/// Unknown options are errors, except the ones listed in `extra`, which are
/// returned in `extraValues` (name → value).
bool ParseSpecArgs(std::vector<std::string> const& args, RunSpec& spec, std::string& message,
                   std::vector<std::string_view> const& extra,
                   std::vector<std::pair<std::string, std::string>>& extraValues);

/// The `field` of every entry of a table (the names of a table of definitions).
template <class Table, class Entry>
std::vector<std::string_view> FieldOf(Table const& table, std::string_view Entry::*field) {
  std::vector<std::string_view> values;
  for (Entry const& entry : table) values.push_back(entry.*field);
  return values;
}

/// "1/60" → 1/60, "0.01" → 0.01; false unless finite and > 0.
bool ParseDt(std::string const& text, double& dt);
/// 1/60 → "1/60" (when 1/dt is an integer), else "%g".
std::string DtLabel(double dt);
/// Compact scientific label: 1e5 → "1e5", 2.5e-3 → "2.5e-3", 1 → "1".
std::string ShortNumber(double value);

// ------------------------------------------------------------------ methods

/// A solver configuration named by a method label.
struct Method {
  LinearSolverType solver = LinearSolverType::Cholmod;
  PcgParams pcg;  ///< PetscPcg only
  OrderingMethod ordering = OrderingMethod::Metis;
  bool isPcg = false;
  bool reuseFactorization = true;  ///< NewtonParams::reuseFactorization (direct solvers)
  bool reuseForcingTerms = true;   ///< NewtonParams::reuseForcingTerms (direct solvers)
  bool singlePrecisionReusedFactor = true;  ///< NewtonParams::singlePrecisionReusedFactor
};

/// The method labels the harness knows, in display order.
std::vector<std::string_view> const& MethodLabels();
/// The configuration of `label` (rtol and iteration cap from `spec`); false
/// for an unknown label.
bool MakeMethod(RunSpec const& spec, Method& method);
/// Whether `label` can run in this build: false for PCG methods without the
/// PETSc backend and for pcg-hypre without hypre (`why` says which).
bool MethodAvailable(std::string_view label, std::string& why);
/// The dense backend is only used up to this many DoFs (else: skipped).
inline constexpr int kDenseMaxDofs = 2000;

// ------------------------------------------------------------- result rows

/// The result columns, in CSV order.
// clang-format off
enum Column : int {
  kSuite, kStudy, kFamily, kSize, kDofs, kMaterial, kStiffnessRatio, kMethod, kSolver,
  kPreconditioner, kRtol, kNewtonTol, kConstraintHessian, kNearRigid, kIntegrator, kDt, kSteps, kEndTime,
  kNewtonIterations, kLinearIterations, kLinearSolves, kTruncatedSolves, kFactorizations, kReusedSolves, kNearRigidCapped, kPatternBuilds, kSymbolicAnalyses, kSolverObjectBuilds,
  kNnzH, kNnzL, kFactorFlops, kAnalysisS, kOrderingS, kPatternS, kSlotTablesS, kSymbolicS, kAssemblyS, kFactorizationS, kSolveS, kLineSearchS,
  kOtherS, kWallPerStepS, kSteadyPerStepS, kTotalS, kRanks, kOwnedDofs, kPeakRssMb, kSceneRssMb, kError, kReference, kJointDrift, kEnergyGain, kStateHash,
  kContactCandidates, kActiveContacts, kMinContactDistance, kContactPatternBuilds, kPatternPolicy, kBroadPhaseS, kNarrowPhaseS, kCcdS, kContactAssemblyS,
  kPenetrationChecks, kInterpenetrations, kMinGap, kCreepUmPerS,
  kStatus, kReason, kNumColumns
};
// clang-format on

/// This process's rank in the MPI job that launched it (mpirun, mpiexec:
/// their environment says so), or 0 outside one. Under a launcher ExecuteRun
/// runs the scene on the job's ranks (SceneParams::communicator) and every
/// rank must call it; only rank 0 reports.
int LaunchRank();

/// Column names (the CSV header, the JSON keys).
extern std::array<std::string_view, kNumColumns> const kColumnNames;
/// Whether a column holds a number (JSON: a number, or null when empty).
bool IsNumericColumn(int column);

/// A result row: one text cell per column; empty = unknown.
using Row = std::array<std::string, kNumColumns>;

/// A row with the columns the spec alone determines (labels, settings)
/// filled in; the run fills the measured ones.
Row RowFromSpec(RunSpec const& spec);

/// A number as a cell: `digits` significant digits ("%.6g").
std::string Cell(double value, int digits = 6);
/// An integer as a cell.
template <std::integral T>
std::string Cell(T value) {
  return std::to_string(value);
}
/// Makes free text safe for one CSV / log line: newlines become spaces and
/// the text is cut to `maxChars`.
std::string OneLine(std::string_view text, std::size_t maxChars = 160);

// ------------------------------------------------------------ running

/// Executes the run in this process (the child's job): builds the scene,
/// steps it, measures, writes or compares the reference. Never throws;
/// failures are reported in the row (status `failed` / `skipped`, reason).
Row ExecuteRun(RunSpec const& spec);

}  // namespace superdex::perf
