// One run of the perf harness (run.h): spec options, methods, result rows,
// and the in-process execution.
#include "run.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include <superdex/core/mpi.h>

#include "families.h"
#include "scenes/interpenetration.h"

namespace superdex::perf {

// ------------------------------------------------------------------ spec

std::vector<SpecOption> const& SpecOptions() {
  static std::vector<SpecOption> const options{
      {"--suite", "NAME", "suite label of the row (default run)", &RunSpec::suite},
      {"--study", "NAME", "scaling, work_precision, stability, bullet, reference", &RunSpec::study},
      {"--family", "NAME", "a family (families.h; --help lists them; default cantilever)", &RunSpec::family},
      {"--size", "LABEL", "40x8x8 (cantilever), 32x32 (cloth), N=50 (chain), 100x250 (rods)",
       &RunSpec::size},
      {"--stiffness-ratio", "R", "times the base stiffness (default 1)", &RunSpec::stiffnessRatio},
      {"--method", "LABEL", "solver configuration, below (default cholmod)", &RunSpec::method},
      {"--integrator", "be|bdf2", "time integrator (default be)", &RunSpec::integrator},
      {"--dt", "DT", "time step, 1/N or seconds (default 1/60)", &RunSpec::dt},
      {"--steps", "N", "steps to take (default 3)", &RunSpec::steps},
      {"--end-time", "T", "> 0: round(T/dt) steps instead of --steps", &RunSpec::endTime},
      {"--rtol", "R", "PCG relative tolerance (default 1e-8)", &RunSpec::rtol},
      {"--newton-tol", "V", "Newton velocity tolerance, m/s (default 1e-6)", &RunSpec::newtonTol},
      {"--newton-max-it", "N", "Newton cap, 0: the family's", &RunSpec::newtonMaxIterations},
      {"--constraint-hessian", "gn|gs|gsd",
       "constraint Hessian: Gauss-Newton, geometric stiffness (default), its diagonal form",
       &RunSpec::constraintHessian},
      {"--near-rigid", "BETA",
       "near-rigid cap beta (NewtonParams::nearRigidBeta): constraints capped at a period of beta*dt; "
       "0 = off (default)",
       &RunSpec::nearRigid},
      {"--pcg-max-it", "N", "PCG iteration cap (default 10000)", &RunSpec::pcgMaxIterations},
      {"--threads", "N", "assembly threads (SceneParams::numThreads), 0 = every CPU (default)",
       &RunSpec::threads},
      {"--pattern-policy", "reserve|rebuild",
       "contact pairs in the pattern: reserved and grown (default), or rebuilt whenever they change",
       &RunSpec::patternPolicy},
      {"--reference-out", "FILE", "write the final tracked positions", &RunSpec::referenceOut},
      {"--reference-in", "FILE", "error against the positions in FILE", &RunSpec::referenceIn},
      {"--reference-desc", "TEXT", "reference column for --reference-in", &RunSpec::referenceDesc},
  };
  return options;
}

int PlannedSteps(RunSpec const& spec) {
  double dt = 0;
  if (!ParseDt(spec.dt, dt)) return 0;
  return spec.endTime > 0 ? static_cast<int>(std::llround(spec.endTime / dt)) : spec.steps;
}

std::vector<std::string> SpecToArgs(RunSpec const& spec) {
  std::vector<std::string> args;
  for (SpecOption const& option : SpecOptions()) {
    args.emplace_back(option.name);
    std::visit(
        [&](auto member) {
          auto const& value = spec.*member;
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, std::string>)
            args.push_back(value);
          else
            args.push_back(Cell(value, 17));
        },
        option.field);
  }
  return args;
}

namespace {

/// Sets the field of `option` from `text`; false if it is not a number of the
/// field's type.
bool SetField(SpecOption const& option, std::string const& text, RunSpec& spec) {
  return std::visit(
      [&](auto member) {
        auto& value = spec.*member;
        using T = std::decay_t<decltype(value)>;
        char* end = nullptr;
        if constexpr (std::is_same_v<T, std::string>) {
          value = text;
          return true;
        } else if constexpr (std::is_same_v<T, double>) {
          value = std::strtod(text.c_str(), &end);
        } else {
          long const v = std::strtol(text.c_str(), &end, 10);
          if (v < INT32_MIN || v > INT32_MAX) return false;
          value = static_cast<int>(v);
        }
        return !text.empty() && *end == '\0';
      },
      option.field);
}

bool IsOneOf(std::string const& value, std::initializer_list<std::string_view> allowed) {
  return std::find(allowed.begin(), allowed.end(), value) != allowed.end();
}

/// Checks `spec` and resolves --end-time into steps.
bool ValidateSpec(RunSpec& spec, std::string& message) {
  double dt = 0;
  Method method;
  if (!IsOneOf(spec.integrator, {"be", "bdf2"}))
    message = "--integrator must be be or bdf2, got '" + spec.integrator + "'";
  else if (!ParseDt(spec.dt, dt))
    message = "--dt must be 1/N or a number > 0, got '" + spec.dt + "'";
  else if (!(spec.endTime >= 0) || !std::isfinite(spec.endTime))
    message = "--end-time must be finite and >= 0";
  else if ((spec.steps = PlannedSteps(spec)) < 1)
    message = "--steps must be >= 1, and --end-time at least one --dt";
  else if (!(spec.stiffnessRatio > 0) || !std::isfinite(spec.stiffnessRatio))
    message = "--stiffness-ratio must be finite and > 0";
  else if (!(spec.rtol > 0 && spec.rtol < 1))
    message = "--rtol must be in (0, 1)";
  else if (!(spec.newtonTol > 0) || !std::isfinite(spec.newtonTol))
    message = "--newton-tol must be finite and > 0";
  else if (spec.newtonMaxIterations < 0 || spec.pcgMaxIterations < 1)
    message = "--newton-max-it must be >= 0 and --pcg-max-it >= 1";
  else if (!IsOneOf(spec.constraintHessian, {"gn", "gs", "gsd"}))
    message = "--constraint-hessian must be gn, gs or gsd, got '" + spec.constraintHessian + "'";
  else if (spec.threads < 0)
    message = "--threads must be >= 0 (0: every CPU)";
  else if (!IsOneOf(spec.patternPolicy, {"reserve", "rebuild"}))
    message = "--pattern-policy must be reserve or rebuild, got '" + spec.patternPolicy + "'";
  else if (!(spec.nearRigid >= 0) || !std::isfinite(spec.nearRigid))
    message = "--near-rigid must be finite and >= 0 (0: off)";
  else if (!MakeMethod(spec, method))
    message = "unknown --method '" + spec.method + "'";
  else if (!spec.referenceIn.empty() && !spec.referenceOut.empty())
    message = "--reference-in and --reference-out exclude each other";
  else
    CountDofs(spec.family, spec.size, message);
  return message.empty();
}

}  // namespace

bool ParseSpecArgs(std::vector<std::string> const& args, RunSpec& spec, std::string& message,
                   std::vector<std::string_view> const& extra,
                   std::vector<std::pair<std::string, std::string>>& extraValues) {
  for (std::size_t i = 0; i < args.size(); i += 2) {
    std::string const& name = args[i];
    if (i + 1 >= args.size()) {
      message = "option " + name + " needs a value";
      return false;
    }
    std::string const& value = args[i + 1];
    auto const& options = SpecOptions();
    auto const option = std::find_if(options.begin(), options.end(),
                                     [&](SpecOption const& o) { return o.name == name; });
    if (option != options.end()) {
      if (!SetField(*option, value, spec)) {
        message = "option " + name + " needs a number, got '" + value + "'";
        return false;
      }
    } else if (std::find(extra.begin(), extra.end(), name) != extra.end()) {
      extraValues.emplace_back(name, value);
    } else {
      message = "unknown option '" + name + "'";
      return false;
    }
  }
  return ValidateSpec(spec, message);
}

bool ParseDt(std::string const& text, double& dt) {
  char* end = nullptr;
  bool const fraction = text.starts_with("1/");
  double const x = std::strtod(text.c_str() + (fraction ? 2 : 0), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(x) || x <= 0) return false;
  dt = fraction ? 1 / x : x;
  return true;
}

std::string DtLabel(double dt) {
  double const inverse = 1 / dt;
  if (std::abs(inverse - std::round(inverse)) < 1e-9 * inverse)
    return "1/" + std::to_string(std::llround(inverse));
  return Cell(dt);
}

std::string ShortNumber(double value) {
  if (value == 0 || !std::isfinite(value)) return Cell(value);
  int const exponent = static_cast<int>(std::floor(std::log10(std::abs(value)) + 1e-12));
  if (exponent >= -2 && exponent <= 2) return Cell(value, 4);
  std::string const mantissa = Cell(value / std::pow(10.0, exponent), 4);
  return (mantissa == "1" ? "" : mantissa) + (mantissa == "1" ? "1e" : "e") +
         std::to_string(exponent);
}

// ------------------------------------------------------------------ methods

namespace {

struct MethodDef {
  std::string_view label;
  LinearSolverType solver;
  PcgPreconditioner preconditioner = PcgPreconditioner::None;  ///< PetscPcg only
  OrderingMethod ordering = OrderingMethod::Metis;
  bool reuseAmgInterpolation = false;
  bool adaptiveTolerance = false;
  bool reuseFactorization = true;  ///< direct solvers: NewtonParams::reuseFactorization
  bool reuseForcingTerms = true;   ///< NewtonParams::reuseForcingTerms
  bool singlePrecisionReusedFactor = true;  ///< NewtonParams::singlePrecisionReusedFactor
};

using Pc = PcgPreconditioner;
constexpr auto kPcg = LinearSolverType::PetscPcg;

std::array<MethodDef, 18> const kMethods{{
    {"cholmod", LinearSolverType::Cholmod},
    {"cholmod-refactor", LinearSolverType::Cholmod, Pc::None, OrderingMethod::Metis, false, false, false},
    {"cholmod-reuse-fixed", LinearSolverType::Cholmod, Pc::None, OrderingMethod::Metis, false, false, true,
     false},
    {"cholmod-reuse-f64", LinearSolverType::Cholmod, Pc::None, OrderingMethod::Metis, false, false, true,
     true, false},
    {"cholmod-amd", LinearSolverType::Cholmod, Pc::None, OrderingMethod::SolverDefault},
    {"dense", LinearSolverType::Dense},
    {"mumps", LinearSolverType::PetscMumps},
    {"mumps-refactor", LinearSolverType::PetscMumps, Pc::None, OrderingMethod::Metis, false, false, false},
    {"pcg-none", kPcg, Pc::None},
    {"pcg-jacobi", kPcg, Pc::Jacobi},
    {"pcg-pbjacobi", kPcg, Pc::PointBlockJacobi},
    {"pcg-bjacobi", kPcg, Pc::BlockJacobi},
    {"pcg-icc", kPcg, Pc::Icc},
    {"pcg-icc-ew", kPcg, Pc::Icc, OrderingMethod::Metis, false, true},
    {"pcg-gamg", kPcg, Pc::Gamg},
    {"pcg-gamg-reuse", kPcg, Pc::Gamg, OrderingMethod::Metis, true},
    {"pcg-gamg-ew", kPcg, Pc::Gamg, OrderingMethod::Metis, false, true},
    {"pcg-hypre", kPcg, Pc::BoomerAmg},
}};

MethodDef const* FindMethod(std::string_view label) {
  for (MethodDef const& m : kMethods)
    if (m.label == label) return &m;
  return nullptr;
}

template <class T>
bool Contains(DynamicArray<T> const& values, T value) {
  return std::find(values.begin(), values.end(), value) != values.end();
}

}  // namespace

std::vector<std::string_view> const& MethodLabels() {
  static std::vector<std::string_view> const labels = FieldOf(kMethods, &MethodDef::label);
  return labels;
}

bool MakeMethod(RunSpec const& spec, Method& method) {
  MethodDef const* def = FindMethod(spec.method);
  if (!def) return false;
  method = Method{};
  method.solver = def->solver;
  method.ordering = def->ordering;
  method.isPcg = def->solver == kPcg;
  method.pcg.preconditioner = def->preconditioner;
  method.pcg.relativeTolerance = spec.rtol;
  method.pcg.maxIterations = spec.pcgMaxIterations;
  method.pcg.reuseAmgInterpolation = def->reuseAmgInterpolation;
  method.pcg.adaptiveTolerance = def->adaptiveTolerance;
  method.reuseFactorization = def->reuseFactorization;
  method.reuseForcingTerms = def->reuseForcingTerms;
  method.singlePrecisionReusedFactor = def->singlePrecisionReusedFactor;
  // the Eisenstat–Walker cap must stay >= rtol
  method.pcg.adaptiveMaxTolerance = std::max(method.pcg.adaptiveMaxTolerance, spec.rtol);
  return true;
}

bool MethodAvailable(std::string_view label, std::string& why) {
  MethodDef const* def = FindMethod(label);
  if (!def) {
    why = "unknown method";
    return false;
  }
  if (!Contains(AvailableLinearSolvers(), def->solver)) {
    why = std::string(ToString(def->solver)) + " is not in this build";
    return false;
  }
  if (def->solver == kPcg && !Contains(AvailablePcgPreconditioners(), def->preconditioner)) {
    why = std::string(ToString(def->preconditioner)) + " is not in this build";
    return false;
  }
  return true;
}

// ------------------------------------------------------------- result rows

// clang-format off
std::array<std::string_view, kNumColumns> const kColumnNames{
    "suite", "study", "family", "size", "dofs", "material", "stiffness_ratio", "method", "solver",
    "preconditioner", "rtol", "newton_tol", "constraint_hessian", "near_rigid", "integrator", "dt", "steps",
    "end_time", "newton_iterations", "linear_iterations", "linear_solves", "truncated_solves", "factorizations", "reused_solves", "near_rigid_capped", "pattern_builds",
    "symbolic_analyses", "solver_object_builds", "nnz_h", "nnz_l", "factor_flops", "analysis_s",
    "ordering_s", "pattern_s", "slot_tables_s", "symbolic_s", "assembly_s", "factorization_s", "solve_s", "line_search_s", "other_s", "wall_per_step_s",
    "steady_per_step_s", "total_s", "ranks", "owned_dofs", "peak_rss_mb", "scene_rss_mb", "error", "reference", "joint_drift", "energy_gain", "state_hash",
    "contact_candidates", "active_contacts", "min_contact_distance", "contact_pattern_builds", "pattern_policy", "broad_phase_s", "narrow_phase_s", "ccd_s", "contact_assembly_s",
    "penetration_checks", "interpenetrations", "min_gap", "creep_um_per_s",
    "status", "reason"};
// clang-format on

bool IsNumericColumn(int column) {
  static constexpr std::array kText{kSuite,      kStudy,     kFamily, kSize,
                                    kMaterial,   kMethod,    kSolver, kPreconditioner,
                                    kIntegrator, kReference, kStatus, kReason,
                                    kConstraintHessian, kStateHash, kPatternPolicy};
  return std::find(kText.begin(), kText.end(), column) == kText.end();
}

std::string Cell(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::string OneLine(std::string_view text, std::size_t maxChars) {
  std::string line(text.substr(0, maxChars));
  std::replace_if(
      line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return line;
}

Row RowFromSpec(RunSpec const& spec) {
  Row row;
  double dt = 0;
  ParseDt(spec.dt, dt);
  Method method;
  bool const known = MakeMethod(spec, method);
  std::string message;
  int const dofs = CountDofs(spec.family, spec.size, message);
  row[kSuite] = spec.suite;
  row[kStudy] = spec.study;
  row[kFamily] = spec.family;
  row[kSize] = spec.size;
  row[kDofs] = dofs > 0 ? Cell(dofs) : "";
  row[kMaterial] = MaterialLabel(spec.family, spec.stiffnessRatio);
  row[kStiffnessRatio] = Cell(spec.stiffnessRatio);
  row[kMethod] = spec.method;
  if (known && method.isPcg) {
    row[kPreconditioner] = ToString(method.pcg.preconditioner);
    row[kRtol] = Cell(spec.rtol);
  }
  row[kNewtonTol] = Cell(spec.newtonTol);
  row[kConstraintHessian] = spec.constraintHessian;
  row[kNearRigid] = Cell(spec.nearRigid);
  row[kPatternPolicy] = spec.patternPolicy;
  row[kIntegrator] = spec.integrator;
  row[kDt] = Cell(dt, 9);
  row[kSteps] = Cell(0);
  row[kEndTime] = Cell(PlannedSteps(spec) * dt, 9);
  if (!spec.referenceIn.empty()) row[kReference] = spec.referenceDesc;
  return row;
}

// ------------------------------------------------------------ running

namespace {

// Reference files: "SDXREF1\n", the point count (int64), then x, y, z of
// every tracked point (doubles, native byte order: written and read on the
// same machine by the same suite).
constexpr char kReferenceMagic[8] = {'S', 'D', 'X', 'R', 'E', 'F', '1', '\n'};

bool WriteReference(std::string const& path, DynamicArray<Real3> const& points) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  std::int64_t const count = static_cast<std::int64_t>(points.size());
  file.write(kReferenceMagic, sizeof kReferenceMagic);
  file.write(reinterpret_cast<char const*>(&count), sizeof count);
  for (Real3 const& p : points)
    file.write(reinterpret_cast<char const*>(p.data()), 3 * sizeof(real));
  return static_cast<bool>(file.flush());
}

bool ReadReference(std::string const& path, DynamicArray<Real3>& points, std::string& message) {
  std::ifstream file(path, std::ios::binary);
  char magic[sizeof kReferenceMagic] = {};
  std::int64_t count = -1;
  file.read(magic, sizeof magic);
  file.read(reinterpret_cast<char*>(&count), sizeof count);
  if (!file || std::memcmp(magic, kReferenceMagic, sizeof magic) != 0 || count < 0 ||
      count > (1 << 28)) {
    message = "reference " + path + " missing or not a reference file";
    return false;
  }
  points.resize(static_cast<std::size_t>(count));
  for (Real3& p : points) file.read(reinterpret_cast<char*>(p.data()), 3 * sizeof(real));
  if (!file) message = "reference " + path + " is truncated";
  return static_cast<bool>(file);
}

/// sqrt(mean |x − x_ref|²) / L, or a message when the point sets differ.
bool RmsError(DynamicArray<Real3> const& x, DynamicArray<Real3> const& reference, real length,
              double& error, std::string& message) {
  if (x.size() != reference.size() || x.empty()) {
    message = "reference has " + std::to_string(reference.size()) + " points, the run " +
              std::to_string(x.size());
    return false;
  }
  double sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += (x[i] - reference[i]).squaredNorm();
  error = std::sqrt(sum / static_cast<double>(x.size())) / length;
  return true;
}

/// The figures summed over the steps of a run.
struct Totals {
  long long newton = 0, linearIterations = 0, linearSolves = 0, truncatedSolves = 0;
  long long factorizations = 0, reusedSolves = 0;
  int nearRigidCapped = 0;  ///< the most constraints the near-rigid cap lowered in a step
  double analysis = 0, assembly = 0, factorization = 0, solve = 0, lineSearch = 0, step = 0;
  double ordering = 0, pattern = 0, slotTables = 0, symbolic = 0;

  void Add(SceneStats const& s) {
    newton += s.newtonIterations;
    linearIterations += s.linearIterations;
    linearSolves += s.linearSolves;
    truncatedSolves += s.truncatedSolves;
    factorizations += s.factorizations;
    reusedSolves += s.reusedFactorSolves;
    nearRigidCapped = std::max(nearRigidCapped, s.nearRigidConstraints);
    analysis += s.analysisSeconds;
    ordering += s.orderingSeconds;
    pattern += s.patternSeconds;
    slotTables += s.slotTableSeconds;
    symbolic += s.symbolicSeconds;
    assembly += s.assemblySeconds;
    factorization += s.factorizationSeconds;
    solve += s.solveSeconds;
    lineSearch += s.lineSearchSeconds;
    step += s.stepSeconds;
  }
};

/// Fills the measured columns of `row` from the totals of `steps` steps and
/// the scene's statistics (cumulative counters; nnz and flops of the last step).
void FillMeasured(Row& row, Totals const& t, int steps, SceneStats const& s) {
  row[kSteps] = Cell(steps);
  row[kPatternBuilds] = Cell(s.patternBuilds);
  row[kSymbolicAnalyses] = Cell(s.symbolicAnalyses);
  row[kSolverObjectBuilds] = Cell(s.linearSolverObjectBuilds);
  if (steps == 0) return;
  row[kSolver] = s.linearSolver;
  row[kNewtonIterations] = Cell(t.newton);
  row[kLinearIterations] = Cell(t.linearIterations);
  row[kLinearSolves] = Cell(t.linearSolves);
  row[kTruncatedSolves] = Cell(t.truncatedSolves);
  row[kFactorizations] = Cell(t.factorizations);
  row[kReusedSolves] = Cell(t.reusedSolves);
  row[kNearRigidCapped] = Cell(t.nearRigidCapped);
  row[kNnzH] = Cell(s.hessianNonzeros);
  if (s.factorNonzeros > 0) row[kNnzL] = Cell(s.factorNonzeros, 9);
  if (s.factorFlops > 0) row[kFactorFlops] = Cell(s.factorFlops);
  row[kAnalysisS] = Cell(t.analysis);
  row[kOrderingS] = Cell(t.ordering);
  row[kPatternS] = Cell(t.pattern);
  row[kSlotTablesS] = Cell(t.slotTables);
  row[kSymbolicS] = Cell(t.symbolic);
  row[kAssemblyS] = Cell(t.assembly);
  row[kFactorizationS] = Cell(t.factorization);
  row[kSolveS] = Cell(t.solve);
  row[kLineSearchS] = Cell(t.lineSearch);
  row[kOtherS] = Cell(t.step - t.analysis - t.assembly - t.factorization - t.solve - t.lineSearch);
  row[kWallPerStepS] = Cell(t.step / steps);
  // without the one-time symbolic analysis (pattern, ordering, CHOLMOD's
  // analyze), which short runs of large scenes would otherwise spread over
  // few steps: the cost of a step once the scene runs
  row[kSteadyPerStepS] = Cell((t.step - t.analysis) / steps);
}

/// The mechanism columns: the largest joint drift and energy gain over the
/// steps (measured after each step, outside the timed step).
class MechanismWatch {
 public:
  explicit MechanismWatch(FamilyScene const& fs) : fs_(fs) {
    if (fs_.mechanicalEnergy) initialEnergy_ = fs_.mechanicalEnergy();
  }
  void Update() {
    if (!fs_.jointDrift) return;
    drift_ = std::max(drift_, fs_.jointDrift());
    gain_ = std::max(gain_, (fs_.mechanicalEnergy() - initialEnergy_) / fs_.energyScale);
    ++updates_;
  }
  void Fill(Row& row) const {
    if (updates_ == 0) return;
    row[kJointDrift] = Cell(drift_);
    row[kEnergyGain] = Cell(gain_);
  }

 private:
  FamilyScene const& fs_;
  real initialEnergy_ = 0, drift_ = 0, gain_ = -INFINITY;
  int updates_ = 0;
};

/// The contact columns (contact families only): the contact system's
/// figures of every step (the most candidates and active contacts, the
/// smallest barrier distance, the phase times summed), the exact
/// interpenetration test of scenes/interpenetration.h at step ends (outside
/// the timed step; brute force over primitive pairs, so on large scenes only
/// every few steps, and always at the last), and the creep: the largest
/// drift of the family's resting points over the run's second half.
class ContactWatch {
 public:
  ContactWatch(FamilyScene const& fs, std::string_view family, int steps, double dt)
      : fs_(fs), on_(IsContactFamily(family)), steps_(steps), dt_(dt),
        check_(fs.scene->GetParams().contact.activationDistance) {
    if (!on_) return;
    // one check costs ~P² primitive pairs (P: every collider's triangles,
    // edges and vertices); at most ~2e7 per step on average
    double primitives = 0;
    for (int id = 0, found = 0; found < fs.scene->GetNumColliders(); ++id)  // (ids may have gaps)
      if (Collider const* c = fs.scene->GetCollider(id)) {
        primitives += c->GetNumTriangles() + c->GetEdges().size() + c->GetNumVertices();
        ++found;
      }
    stride_ = std::max(1, static_cast<int>(std::ceil(primitives * primitives / 2e7)));
  }

  /// After step `done` (1-based).
  void Update(int done) {
    if (!on_) return;
    SceneStats const& s = fs_.scene->GetStats();
    candidates_ = std::max(candidates_, s.contactCandidates);
    active_ = std::max(active_, s.activeContacts);
    minDistance_ = std::min(minDistance_, s.minContactDistance);
    broad_ += s.contactBroadPhaseSeconds;
    narrow_ += s.contactNarrowPhaseSeconds;
    ccd_ += s.contactCcdSeconds;
    assembly_ += s.contactAssemblySeconds;
    if (done % stride_ == 0 || done == steps_) {
      ++checks_;
      std::string const found = check_.Find(*fs_.scene);
      minGap_ = std::min(minGap_, check_.GetMinGap());
      if (!found.empty() && interpenetrations_++ == 0)
        firstFound_ = "interpenetration after step " + std::to_string(done) + ": " + found;
    }
    if (fs_.restingPoints && done == steps_ / 2) {
      halfway_ = fs_.restingPoints();
      halfwayStep_ = done;
    }
    if (fs_.restingPoints && done == steps_ && halfwayStep_ > 0 && done > halfwayStep_) {
      DynamicArray<Real3> const now = fs_.restingPoints();
      real drift = 0;
      for (std::size_t i = 0; i < now.size() && i < halfway_.size(); ++i)
        drift = std::max(drift, (now[i] - halfway_[i]).norm());
      creep_ = drift / ((done - halfwayStep_) * dt_);
    }
  }

  /// The columns; an interpenetration makes the run fail (a wrong answer).
  void Fill(Row& row) const {
    if (!on_) return;
    row[kContactCandidates] = Cell(candidates_);
    row[kActiveContacts] = Cell(active_);
    if (std::isfinite(minDistance_)) row[kMinContactDistance] = Cell(minDistance_);
    row[kContactPatternBuilds] = Cell(fs_.scene->GetStats().contactPatternBuilds);
    row[kBroadPhaseS] = Cell(broad_);
    row[kNarrowPhaseS] = Cell(narrow_);
    row[kCcdS] = Cell(ccd_);
    row[kContactAssemblyS] = Cell(assembly_);
    row[kPenetrationChecks] = Cell(checks_);
    row[kInterpenetrations] = Cell(interpenetrations_);
    if (std::isfinite(minGap_)) row[kMinGap] = Cell(minGap_);
    if (creep_ >= 0) row[kCreepUmPerS] = Cell(creep_ * 1e6);
    if (interpenetrations_ > 0) {
      row[kStatus] = "failed";
      row[kReason] = OneLine(firstFound_);
    }
  }

 private:
  FamilyScene const& fs_;
  bool on_;
  int steps_;
  double dt_;
  scenes::InterpenetrationCheck check_;
  int stride_ = 1;
  int candidates_ = 0, active_ = 0, checks_ = 0, interpenetrations_ = 0, halfwayStep_ = 0;
  real minDistance_ = std::numeric_limits<real>::infinity(), minGap_ = std::numeric_limits<real>::infinity();
  double broad_ = 0, narrow_ = 0, ccd_ = 0, assembly_ = 0, creep_ = -1;
  DynamicArray<Real3> halfway_;
  std::string firstFound_;
};

/// Compares with (or writes) the reference; sets the error column, or a
/// note in `reason` when the reference is missing or does not match.
void HandleReference(RunSpec const& spec, FamilyScene const& fs, Row& row) {
  DynamicArray<Real3> const x = fs.trackedPositions();
  if (!spec.referenceOut.empty()) {
    if (!WriteReference(spec.referenceOut, x)) {
      row[kStatus] = "failed";
      row[kReason] = "cannot write " + spec.referenceOut;
    }
    return;
  }
  if (spec.referenceIn.empty()) return;
  DynamicArray<Real3> reference;
  double error = 0;
  std::string message;
  if (ReadReference(spec.referenceIn, reference, message) &&
      RmsError(x, reference, fs.length, error, message))
    row[kError] = Cell(error);
  else
    row[kReason] = OneLine(message);
}

/// The row's reason for a failed step: the code name, where, and the
/// library's message without the parts other columns hold (Scene::Step's
/// "Step(dt = ...) at t = ... failed in " prefix; the solver description in
/// "linear solver <description> failed (...)"), so that the cause survives the
/// cut to one short line.
std::string Reason(Error const& error, std::string const& where) {
  std::string message = error.GetMessage();
  std::size_t const cause = message.find(" failed in ");
  if (message.starts_with("Step(") && cause != message.npos)
    message.erase(0, cause + std::strlen(" failed in "));
  std::string_view const solver = "linear solver ";
  std::size_t const description = message.find(solver);
  std::size_t const failed = message.find(" failed (", description);
  if (description != message.npos && failed != message.npos)
    message.erase(description + solver.size() - 1, failed - (description + solver.size() - 1));
  return std::string(ToString(error.GetCode())) + " at " + where + ": " + message;
}

double PeakRssMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // KiB on Linux
}

/// Resident memory now [MB] (/proc/self/statm), or -1 where it cannot be read.
double ResidentMb() {
  std::FILE* file = std::fopen("/proc/self/statm", "r");
  if (!file) return -1;
  long size = 0, resident = 0;
  int const read = std::fscanf(file, "%ld %ld", &size, &resident);
  std::fclose(file);
  return read == 2 ? resident * (sysconf(_SC_PAGESIZE) / (1024.0 * 1024.0)) : -1;
}

/// FNV-1a over the bits of every actor's dynamic state (poses, velocities,
/// joint coordinates, twists), in creation order: equal hashes mean equal
/// final states bit for bit, so a change that must not alter behaviour can be
/// checked run by run (the `state_hash` column).
class StateHash {
 public:
  void Add(real value) {
    unsigned char bytes[sizeof value];
    std::memcpy(bytes, &value, sizeof value);
    for (unsigned char byte : bytes) hash_ = (hash_ ^ byte) * 0x100000001b3ull;
  }
  void Add(Real3 const& v) {
    for (int i = 0; i < 3; ++i) Add(v[i]);
  }
  std::string Hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

std::string HashState(Scene const& scene) {
  StateHash hash;
  scene.ForEachActor([&](Actor const& actor) {
    switch (actor.GetType()) {
      case ActorType::Rigid: {
        auto const& rigid = static_cast<RigidActor const&>(actor);
        hash.Add(rigid.GetPosition());
        for (int i = 0; i < 4; ++i) hash.Add(rigid.GetRotation().coeffs()[i]);
        hash.Add(rigid.GetLinearVelocity());
        hash.Add(rigid.GetAngularVelocity());
        break;
      }
      case ActorType::Deformable:
      case ActorType::Rod: {
        auto const& nodal = static_cast<NodalActor const&>(actor);
        for (int i = 0; i < nodal.GetNumNodes(); ++i) {
          hash.Add(nodal.GetNodePosition(i));
          hash.Add(nodal.GetNodeVelocity(i));
        }
        if (actor.GetType() == ActorType::Rod) {
          auto const& rod = static_cast<RodActor const&>(actor);
          for (int i = 0; i < rod.GetNumNodes(); ++i) {
            hash.Add(rod.GetTwist(i));
            hash.Add(rod.GetTwistVelocity(i));
          }
        }
        break;
      }
      case ActorType::Articulated: {
        auto const& articulated = static_cast<ArticulatedActor const&>(actor);
        for (real q : articulated.GetJointPositions()) hash.Add(q);
        for (real v : articulated.GetJointVelocities()) hash.Add(v);
        break;
      }
    }
  });
  return hash.Hex();
}

/// Set by a launcher: OpenMPI's, MPICH's/hydra's (PMI) and PMIx's rank
char const* LauncherRank() {
  for (char const* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (char const* value = std::getenv(name)) return value;
  return nullptr;
}

}  // namespace

int LaunchRank() {
  char const* rank = LauncherRank();
  return rank ? std::atoi(rank) : 0;
}

Row ExecuteRun(RunSpec const& spec) {
  auto const start = std::chrono::steady_clock::now();
  Row row = RowFromSpec(spec);
  Error error;
  SceneParams params;
  // under a launcher the scene runs on the job's ranks
  if (LauncherRank()) params.communicator = Communicator::World(error);

  auto finish = [&](std::string_view status, std::string_view reason) {
    row[kStatus] = status;
    if (!reason.empty()) row[kReason] = OneLine(reason);
    row[kTotalS] =
        Cell(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    // across ranks: the largest rank's memory (every rank holds the
    // replicated scene and its part of the rest)
    double peak = PeakRssMb();
    if (params.communicator.GetSize() > 1)
      MPI_Allreduce(MPI_IN_PLACE, &peak, 1, MPI_DOUBLE, MPI_MAX, ToMpiComm(params.communicator));
    row[kPeakRssMb] = Cell(peak, 4);
    row[kRanks] = Cell(params.communicator.GetSize());
    return row;
  };

  Method method;
  double dt = 0;
  std::string message;
  int const dofs = CountDofs(spec.family, spec.size, message);
  if (!MakeMethod(spec, method) || !ParseDt(spec.dt, dt) || dofs < 0)
    return finish("failed", message.empty() ? "invalid run spec" : message);
  if (method.solver == LinearSolverType::Dense && dofs > kDenseMaxDofs)
    return finish("skipped", "dense only up to " + std::to_string(kDenseMaxDofs) + " DoFs");

  if (error) return finish("failed", Reason(error, "set-up"));
  params.integrator =
      spec.integrator == "bdf2" ? IntegratorType::Bdf2 : IntegratorType::BackwardEuler;
  params.newton.velocityTolerance = spec.newtonTol;
  params.newton.maxIterations = spec.newtonMaxIterations > 0
                                    ? spec.newtonMaxIterations
                                    : DefaultNewtonMaxIterations(spec.family);
  params.newton.constraintHessian = spec.constraintHessian == "gn"    ? ConstraintHessian::GaussNewton
                                    : spec.constraintHessian == "gsd" ? ConstraintHessian::GeometricStiffnessDiagonal
                                                                      : ConstraintHessian::GeometricStiffness;
  params.newton.nearRigidBeta = spec.nearRigid;
  params.newton.reuseFactorization = method.reuseFactorization;
  params.newton.reuseForcingTerms = method.reuseForcingTerms;
  params.newton.singlePrecisionReusedFactor = method.singlePrecisionReusedFactor;
  params.numThreads = spec.threads;
  params.patternPolicy =
      spec.patternPolicy == "rebuild" ? PatternPolicy::RebuildWhenChanged : PatternPolicy::ReserveAndGrow;
  params.linearSolver = method.solver;
  params.pcg = method.pcg;
  params.ordering = method.ordering;

  // PETSc (and MPI) start once per process, on the first PETSc solver created:
  // ~0.3 s here, which the first Step would otherwise carry in no phase (it
  // would land in other_s). An application pays it once, not per step, so it
  // is paid here, before the timed steps (it still counts in total_s).
  if ((method.isPcg || method.solver == LinearSolverType::PetscMumps) &&
      !CreateLinearSolver(method.solver, method.pcg, error))
    return finish("failed", Reason(error, "set-up"));
  FamilyScene fs;
  if (!BuildFamilyScene(spec.family, spec.size, spec.stiffnessRatio, params, fs, error))
    return finish("failed", Reason(error, "set-up"));
  row[kDofs] = Cell(fs.scene->GetNumDofs());
  // the scene's description and state, before the first step builds the
  // pattern, the solver's objects and the factor
  if (double const resident = ResidentMb(); resident >= 0) row[kSceneRssMb] = Cell(resident, 4);

  Totals totals;
  MechanismWatch watch(fs);
  ContactWatch contact(fs, spec.family, spec.steps, dt);
  int done = 0;
  bool ok = true;
  for (; done < spec.steps; ++done) {
    if (fs.drive && !(ok = fs.drive(done * dt, (done + 1) * dt, error))) break;
    if (!(ok = fs.scene->Step(dt, error))) break;
    totals.Add(fs.scene->GetStats());
    watch.Update();
    contact.Update(done + 1);
  }
  FillMeasured(row, totals, done, fs.scene->GetStats());
  row[kOwnedDofs] = Cell(fs.scene->GetStats().ownedDofs);
  watch.Fill(row);
  contact.Fill(row);
  row[kStateHash] = HashState(*fs.scene);
  if (!ok) return finish("failed", Reason(error, "step " + std::to_string(done + 1)));
  HandleReference(spec, fs, row);
  std::string const status = row[kStatus].empty() ? "ok" : row[kStatus];
  std::string const reason = row[kReason];
  return finish(status, reason);
}

}  // namespace superdex::perf
