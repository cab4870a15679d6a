// Two-phase assembly of the global Hessian and gradient (docs/design.md §6).
//
// Analyze (topology changes only): from every contributor's DoF list build
// the block graph, order it (METIS), build the upper-triangle CSC pattern of
// P H Pᵀ, and precompute for every contributor the value slot of each entry
// of its local upper triangle. Bumps the pattern version.
//
// Assemble (every Newton iteration): BeginAssembly zeroes the values and the
// gradient; each contributor adds its local gradient (AddGradient) and its
// dense local block (AddBlock) through its DoF list and slot table: no
// search, no triplets, no sort, no allocation; FinishAssembly completes it.
//
// Threads. With one thread, contributions are added straight into the matrix
// and the gradient, contributor after contributor. With several
// (SetExecutor), contributors are evaluated concurrently (ParallelFor) and
// each writes only its own staging slots; FinishAssembly then sums, for every
// matrix entry and gradient entry, its contributions in contributor order,
// in parallel over entries. Both sum the same numbers in the same order from
// zero, so the assembled values are bit-identical for any thread count.
// Contract: each contributor adds at most one gradient and one block per
// assembly (a second call would be summed in another order when staged).
//
// A second family of contributors, whose DoF lists change between stages
// (contact pairs), is set at each stage start (SetDynamicContributors). The
// block pairs they use are reserved in the pattern and kept there while they
// are used (with hysteresis: a pair leaves only kReserveStages stages after
// its last use, at a rebuild). Where one needs an entry the pattern lacks,
// the pattern grows: rebuilt with the fill-reducing order kept (no METIS),
// or ordered again once the pairs added since the last ordering are many
// (kReorderFraction of the block graph). Their contributions are staged and
// added after every static contributor's, in their order, whatever the
// thread count.
//
// Gradients stay in natural DoF order; PermuteToOrdered/PermuteToNatural map
// vectors between the two orders around the linear solve.
#pragma once

#include <cstdint>
#include <unordered_map>

#include <superdex/assembly/ordering.h>
#include <superdex/assembly/owned_contributors.h>
#include <superdex/core/parallel.h>
#include <superdex/core/error.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex::internal {

/// Indices per chunk of the parallel assembly loops: elements and stencils
/// (~1–10 µs each), and node inertia blocks (~10 ns each)
inline constexpr int kElementGrain = 64;
inline constexpr int kNodeGrain = 2048;

/// Where a pattern build's time went [s]: the block graph and its
/// fill-reducing ordering (METIS), the CSC pattern, and the slot tables
/// (with the staging maps of a threaded assembly).
struct AnalysisTimes {
  double orderingSeconds = 0;
  double patternSeconds = 0;
  double slotTableSeconds = 0;
};

class HessianAssembler {
 public:
  /// Builds pattern, ordering and slot tables. Every DoF list must hold
  /// distinct indices in [0, numDofs); the block sizes must add to numDofs.
  /// Returns false (and changes nothing) on a METIS failure or bad input.
  ///
  /// Across MPI ranks (docs/distributed.md), with numParts > 1: the blocks
  /// are split into numParts parts (PartitionBlocks), the order is made
  /// partition-major (part p's rows contiguous, in p order, each part in the
  /// fill-reducing order), and this process is part `part`: it owns the rows
  /// GetOwnedRows(), evaluates only the contributors that touch one of them
  /// (Evaluates), and counts in its share of the energy the contributors
  /// whose first DoF it owns (Owns). It stores only the entries with an owned
  /// row or column (and every column's diagonal, the pattern's invariant,
  /// zero where not owned), and the DoF lists and slots of the contributors
  /// it evaluates: its memory is its part's. Those entries are assembled
  /// completely; the gradient only in owned DoFs.
  bool Analyze(int numDofs, DynamicArray<int> const& blockSizes,
               DynamicArray<DynamicArray<int>> const& contributorDofs, OrderingMethod method,
               Error& error, int numParts = 1, int part = 0);

  bool IsAnalyzed() const { return analyzed_; }
  /// The split of the last pattern build (Analyze, or a growth).
  AnalysisTimes const& GetLastAnalysisTimes() const { return lastTimes_; }

  // ---- the second family: contributors whose DoF lists change between stages ----
  /// A reserved block pair leaves the pattern only at a rebuild this many
  /// stages after its last use.
  static constexpr std::int64_t kReserveStages = 32;
  /// The pattern is ordered again (METIS) when the pairs of two blocks
  /// reserved since the last ordering exceed this fraction of the ordered
  /// block graph's pairs (its edges and blocks); until then it grows in the
  /// kept order.
  static constexpr double kReorderFraction = 0.25;
  struct DynamicUpdate {
    bool grew = false;       ///< the pattern was rebuilt (new pattern version)
    bool reordered = false;  ///< ... with a new fill-reducing order
  };
  /// Sets the second family for the coming stage (after Analyze):
  /// contributor k's DoF list dofLists[k] (distinct DoFs). Their
  /// block pairs are reserved; where an entry is missing, the pattern grows.
  /// False (nothing changed but the reserved stamps) on a bad DoF list.
  /// On one part of several the pattern does not grow: a list needing an
  /// entry it lacks (in an owned row or column) gives false, with no
  /// changing contributors set.
  /// With `rebuildWhenChanged` (the policy of re-analysing whenever the
  /// pairs change, for comparisons): no reserve; a set of DoF lists that
  /// differs from the last stage's rebuilds and orders the pattern anew for
  /// exactly these.
  bool SetDynamicContributors(Span<DynamicArray<int> const> dofLists, DynamicUpdate& update, Error& error,
                              bool rebuildWhenChanged = false);
  bool SetDynamicContributors(DynamicArray<DynamicArray<int>> const& dofLists, DynamicUpdate& update, Error& error,
                              bool rebuildWhenChanged = false) {
    return SetDynamicContributors(Span<DynamicArray<int> const>(dofLists.data(), dofLists.size()), update, error,
                                  rebuildWhenChanged);
  }
  int GetNumDynamicContributors() const { return static_cast<int>(dynamicDofStart_.size()) - 1; }
  /// Pattern rebuilds that kept the fill-reducing order (the second family's
  /// pairs grew), since construction.
  std::int64_t GetNumPatternGrowths() const { return numGrowths_; }
  /// Block pairs reserved for the second family.
  std::size_t GetNumReservedPairs() const { return reserved_.size(); }
  /// Adds the local gradient and the symmetric block of dynamic contributor
  /// k (as AddGradient and AddBlock); safe to call concurrently for
  /// different k; at most one of each per assembly. A contributor that adds
  /// nothing costs FinishAssembly nothing: only those stamped by these calls
  /// in this assembly are summed (most contact candidates are beyond reach).
  template <class Derived>
  void AddDynamicGradient(int k, Eigen::MatrixBase<Derived> const& g) {
    int const first = dynamicDofStart_[k], n = dynamicDofStart_[k + 1] - first;
    dynamicGradientStamp_[k] = dynamicStamp_;
    for (int a = 0; a < n; ++a) dynamicGradientStage_[first + a] = g[a];
  }
  template <class Derived>
  void AddDynamicBlock(int k, Eigen::MatrixBase<Derived> const& h) {
    int const n = dynamicDofStart_[k + 1] - dynamicDofStart_[k];
    dynamicBlockStamp_[k] = dynamicStamp_;
    real* out = dynamicValueStage_.data() + dynamicSlotStart_[k];
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) *out++ = h(a, b);
  }
  int GetNumDofs() const { return matrix_.size; }
  /// Stored entries in the owned columns: the whole pattern's count on one
  /// part; summed over the parts, the whole pattern's (each entry (i, j),
  /// i <= j, is in the columns of the part that owns j).
  std::int64_t CountOwnedColumnEntries() const {
    return matrix_.colStart[GetOwnedRowEnd()] - matrix_.colStart[GetOwnedRowBegin()];
  }
  int GetNumContributors() const { return static_cast<int>(slotStart_.size()) - 1; }
  /// How many times Analyze built a pattern since construction.
  std::int64_t GetNumPatternBuilds() const { return numBuilds_; }

  /// Parts of the partition (1: one process, every contributor evaluated).
  int GetNumParts() const { return static_cast<int>(partRowStart_.size()) - 1; }
  /// This process's part, in [0, GetNumParts()).
  int GetPart() const { return part_; }
  /// First ordered row of each part, then GetNumDofs() (GetNumParts() + 1).
  DynamicArray<int> const& GetPartRowStart() const { return partRowStart_; }
  int GetOwnedRowBegin() const { return partRowStart_[part_]; }
  int GetOwnedRowEnd() const { return partRowStart_[part_ + 1]; }
  /// Whether contributor `c` touches an owned row: actors and constraints
  /// skip the contributors this returns false for. Always true on one part.
  bool Evaluates(int c) const { return evaluated_.empty() || evaluated_[c] != 0; }
  /// Whether contributor `c`'s first DoF is owned (its energy is this part's
  /// to count). Always true on one part.
  bool Owns(int c) const { return owned_.empty() || owned_[c] != 0; }
  /// Owns for the `count` contributors from `first` (an actor's), indexed
  /// from 0: Actor::Energy's argument.
  OwnedContributors GetOwnedContributors(int first, int count) const {
    if (owned_.empty()) return {};
    return {Span<std::uint8_t const>(owned_.data() + first, static_cast<std::size_t>(count))};
  }

  /// The threads of ParallelFor and of the staged sums; nullptr (the
  /// default) or one thread: serial. Staging memory is sized here and at
  /// Analyze. The executor must outlive the assembler's use of it.
  void SetExecutor(ParallelExecutor const* executor);
  bool IsStaged() const { return staged_; }

  /// Starts an assembly into `gradient` (natural order, GetNumDofs()
  /// entries): zeroes it and the matrix values.
  void BeginAssembly(Span<real> gradient);
  /// Completes an assembly (staged: sums the contributions; serial: nothing
  /// more), then adds the second family's.
  void FinishAssembly();
  /// Zeroes the matrix values only (no gradient; tests of the pattern).
  void ZeroValues();
  /// Adds `relative` × |Hⱼⱼ| to every diagonal entry of the assembled values
  /// (a Levenberg shift, scaled per DoF).
  void ShiftDiagonal(real relative);

  /// Runs body(begin, end, thread) over [0, count) on the executor's threads
  /// (serially, in order, without one); `thread` indexes per-thread scratch.
  template <class F>
  void ParallelFor(int count, int grain, F&& body) const {
    if (executor_ && staged_)
      executor_->For(count, grain, std::forward<F>(body));
    else if (count > 0)
      body(0, count, 0);
  }
  int GetNumThreads() const { return executor_ && staged_ ? executor_->GetNumThreads() : 1; }

  /// Adds the local gradient `g` (n entries, in DoF-list order) of
  /// contributor `c`.
  template <class Derived>
  void AddGradient(int c, Eigen::MatrixBase<Derived> const& g) {
    int const first = dofStart_[c], n = dofStart_[c + 1] - first;
    if (staged_) {
      // the first write of this assembly assigns (the stage is not zeroed)
      real* out = gradientStage_.data() + first;
      if (gradientStamp_[c] != stamp_) {
        gradientStamp_[c] = stamp_;
        for (int a = 0; a < n; ++a) out[a] = g[a];
      } else {
        for (int a = 0; a < n; ++a) out[a] += g[a];
      }
    } else {
      int const* dofs = dofs_.data() + first;
      for (int a = 0; a < n; ++a) gradient_[dofs[a]] += g[a];
    }
  }

  /// Adds the symmetric local block `h` (n×n, n = the contributor's DoF
  /// count, in DoF-list order) of contributor `c`. Reads the upper triangle.
  template <class Derived>
  void AddBlock(int c, Eigen::MatrixBase<Derived> const& h) {
    int const n = dofStart_[c + 1] - dofStart_[c];
    int const* slot = slots_.data() + slotStart_[c];
    if (staged_) {
      real* out = valueStage_.data() + slotStart_[c];
      if (blockStamp_[c] != stamp_) {
        blockStamp_[c] = stamp_;
        for (int a = 0; a < n; ++a)
          for (int b = a; b < n; ++b) *out++ = h(a, b);
      } else {
        for (int a = 0; a < n; ++a)
          for (int b = a; b < n; ++b) *out++ += h(a, b);
      }
    } else if (!dropsEntries_) {
      real* values = matrix_.values.data();
      for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b) values[*slot++] += h(a, b);
    } else {
      // on one part of several: the entries of other parts' rows and
      // columns are not stored (slot −1)
      real* values = matrix_.values.data();
      for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b) {
          int const s = *slot++;
          if (s >= 0) values[s] += h(a, b);
        }
    }
  }

  /// After FinishAssembly, in one part: the assembled values at contributor
  /// c's entries (every contributor's terms there), as a symmetric n×n block
  /// in its DoF-list order; WriteBlock overwrites them with h's upper
  /// triangle (an actor that solves its own block, Actor::FactorizeOwnBlock).
  template <class Derived>
  void ReadBlock(int c, Eigen::MatrixBase<Derived>& h) const {
    int const n = dofStart_[c + 1] - dofStart_[c];
    int const* slot = slots_.data() + slotStart_[c];
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) h(a, b) = h(b, a) = matrix_.values[*slot++];
  }
  template <class Derived>
  void WriteBlock(int c, Eigen::MatrixBase<Derived> const& h) {
    int const n = dofStart_[c + 1] - dofStart_[c];
    int const* slot = slots_.data() + slotStart_[c];
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) matrix_.values[*slot++] = h(a, b);
  }

  /// After FinishAssembly, in one part: adds h's upper triangle to contributor
  /// c's entries (a term formed only after the assembly: an actor's Schur
  /// complement, Actor::FactorizeOwnBlock).
  template <class Derived>
  void AddToAssembledBlock(int c, Eigen::MatrixBase<Derived> const& h) {
    int const n = dofStart_[c + 1] - dofStart_[c];
    int const* slot = slots_.data() + slotStart_[c];
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) matrix_.values[*slot++] += h(a, b);
  }

  SparseSymmetricMatrix const& GetMatrix() const { return matrix_; }

  /// ordered[perm[i]] = natural[i]
  void PermuteToOrdered(Span<real const> natural, Span<real> ordered) const;
  /// natural[i] = ordered[perm[i]]
  void PermuteToNatural(Span<real const> ordered, Span<real> natural) const;

 private:
  /// Sizes the staging buffers and builds the entry → contributions maps.
  void PrepareStaging();
  /// A pattern in the making: the order, and what BuildPattern makes of it.
  struct Pattern {
    DynamicArray<int> permutation, partRowStart, orderedBlockSizes;
    int part = 0;
    bool divided = false;
    SparseSymmetricMatrix matrix;
    DynamicArray<int> dofStart, dofs, slotStart, slots;
    bool dropsEntries = false;
  };
  static bool CheckDofList(DynamicArray<int> const& dofs, int numDofs, Error& error);
  /// The CSC pattern of the contributors (those `evaluated` flags, all when
  /// empty) and of `extraBlockPairs` (a << 32 | b, a <= b: every DoF pair of
  /// the two blocks) in `out`'s order, and the contributors' slot tables.
  void BuildPattern(DynamicArray<DynamicArray<int>> const& contributorDofs,
                    DynamicArray<std::uint8_t> const& evaluated, DynamicArray<std::uint64_t> const& extraBlockPairs,
                    DynamicArray<int> const& blockStart, Pattern& out, AnalysisTimes& times) const;
  /// The slots of `dofs`' local upper triangle in `matrix` (−1 where not
  /// `stored`, or missing).
  template <class Stored>
  static void AppendSlots(SparseSymmetricMatrix const& matrix, DynamicArray<int> const& permutation,
                          DynamicArray<int> const& dofs, Stored const& stored, DynamicArray<int>& slots,
                          bool& dropsEntries);
  /// The value index of entry (row, col), row <= col, of `matrix` (−1: not in
  /// its pattern).
  static int SlotOf(SparseSymmetricMatrix const& matrix, int row, int col);
  /// The slots of `dofs`' local upper triangle in the current pattern, n(n +
  /// 1)/2 of them into `slots` (−1 where an entry is missing).
  void FindSlots(DynamicArray<int> const& dofs, int* slots) const;
  /// Second-family contributors per chunk of the parallel slot search
  static constexpr int kDynamicSlotGrain = 512;
  /// Makes `pattern` the assembler's (and its staging), recording `times`.
  void Commit(Pattern& pattern, AnalysisTimes& times);
  void ClearDynamicContributors();
  /// Rebuilds the pattern with the reserved pairs, in the kept order or (many
  /// pairs added since the last ordering) a new one.
  /// The second family's DoF lists and slot ranges (slots sized, unset).
  void SetDynamicLists(Span<DynamicArray<int> const> dofLists);
  /// Its staging sized and no contributor stamped for the coming assembly.
  void ClearDynamicStamps(std::size_t numLists);
  /// SetDynamicContributors on one part of several.
  bool SetDividedDynamicContributors(Span<DynamicArray<int> const> dofLists, Error& error);
  bool GrowPattern(DynamicUpdate& update, bool reorder, Error& error);
  void FinishStaticAssembly();

  bool analyzed_ = false;
  std::int64_t numBuilds_ = 0;
  SparseSymmetricMatrix matrix_;
  DynamicArray<int> permutation_;  ///< natural DoF → ordered position
  /// per contributor, into dofs_ (one past the end last); on one part of
  /// several, a contributor this part does not evaluate has no DoFs here
  DynamicArray<int> dofStart_;
  DynamicArray<int> dofs_;         ///< the contributors' DoF lists, concatenated
  DynamicArray<int> slotStart_;    ///< per contributor, into slots_ (one past the end last)
  /// value index of each local upper-triangle entry; −1 for an entry not
  /// stored (one part of several: neither its row nor its column is owned)
  DynamicArray<int> slots_;
  bool dropsEntries_ = false;      ///< some slot is −1
  Span<real> gradient_;            ///< of the assembly in progress
  DynamicArray<int> partRowStart_{0, 0};  ///< per part, its first ordered row; then numDofs
  int part_ = 0;                          ///< this process's part
  DynamicArray<std::uint8_t> evaluated_, owned_;  ///< per contributor; empty on one part

  // staged assembly (several threads)
  ParallelExecutor const* executor_ = nullptr;
  bool staged_ = false;
  DynamicArray<real> valueStage_;     ///< per slot (slots_ order)
  DynamicArray<real> gradientStage_;  ///< per contributor DoF (dofs_ order)
  /// The stages are not zeroed per assembly: a contributor's first AddBlock
  /// (AddGradient) of an assembly assigns its slots and stamps it; at
  /// FinishAssembly the slots of contributors without this assembly's stamp
  /// are zeroed (those that added nothing), before the sums
  DynamicArray<std::uint32_t> blockStamp_, gradientStamp_;
  std::uint32_t stamp_ = 0;
  DynamicArray<int> valueSourceStart_, valueSources_;        ///< value index → slot positions, ascending
  DynamicArray<int> gradientSourceStart_, gradientSources_;  ///< DoF → dofs_ positions, ascending

  AnalysisTimes lastTimes_;
  // the blocks of the DoFs (one part), for the second family's pairs
  DynamicArray<int> blockStart_, dofToBlock_, orderedBlockSizes_;
  // the second family: reserved block pairs (→ the last stage that used
  // them), this stage's contributors, their slots and staged contributions
  std::unordered_map<std::uint64_t, std::int64_t> reserved_;
  std::int64_t dynamicStage_ = 0;
  std::int64_t reservedSinceOrdering_ = 0;  ///< pairs of two blocks reserved by growths since the last ordering
  std::int64_t orderedBlockPairs_ = 0;      ///< edges + blocks of the block graph last ordered
  std::int64_t numGrowths_ = 0;
  DynamicArray<int> dynamicDofStart_{0}, dynamicDofs_, dynamicSlotStart_{0}, dynamicSlots_;
  DynamicArray<real> dynamicValueStage_, dynamicGradientStage_;
  /// per dynamic contributor: the assembly its block and gradient were last
  /// added in (dynamicStamp_ counts assemblies)
  DynamicArray<std::uint32_t> dynamicBlockStamp_, dynamicGradientStamp_;
  std::uint32_t dynamicStamp_ = 0;
};

}  // namespace superdex::internal
