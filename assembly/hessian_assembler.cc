#include <superdex/assembly/hessian_assembler.h>

#include <algorithm>
#include <array>
#include <chrono>

#include <superdex/core/stopwatch.h>

namespace superdex::internal {

namespace {
using Clock = std::chrono::steady_clock;

// Global version counter, so that patterns of different assemblers (and
// successive builds of one) never share a version.
std::uint64_t NextPatternVersion() {
  static std::uint64_t version = 0;
  return ++version;
}
}  // namespace

bool HessianAssembler::Analyze(int numDofs, DynamicArray<int> const& blockSizes,
                               DynamicArray<DynamicArray<int>> const& contributorDofs,
                               OrderingMethod method, Error& error, int numParts, int part) {
  if (numParts < 1 || part < 0 || part >= numParts) {
    error.Set(ErrorCode::InvalidArgument, "part " + std::to_string(part) + " of " +
                                              std::to_string(numParts) + " parts does not exist");
    return false;
  }
  AnalysisTimes times;
  auto const orderingStart = Clock::now();
  // map DoFs to blocks and check the partition
  DynamicArray<int> dofToBlock(numDofs, -1);
  DynamicArray<int> blockStart(blockSizes.size() + 1, 0);
  for (std::size_t b = 0; b < blockSizes.size(); ++b) {
    blockStart[b + 1] = blockStart[b] + blockSizes[b];
    if (blockStart[b + 1] > numDofs) break;
    for (int d = blockStart[b]; d < blockStart[b + 1]; ++d) dofToBlock[d] = static_cast<int>(b);
  }
  if (blockStart.back() != numDofs) {
    error.Set(ErrorCode::InvalidState, "DoF blocks cover " + std::to_string(blockStart.back()) +
                                            " DoFs, expected " + std::to_string(numDofs));
    return false;
  }
  for (auto const& dofs : contributorDofs)
    if (!CheckDofList(dofs, numDofs, error)) return false;

  // order the blocks, expand to a scalar permutation
  BlockGraph graph = BuildBlockGraph(blockSizes, dofToBlock, contributorDofs);
  DynamicArray<int> blockOrder;
  if (!OrderBlocks(graph, method, blockOrder, error)) return false;
  DynamicArray<int> partBlockStart{0, static_cast<int>(blockOrder.size())};
  if (numParts > 1) {
    DynamicArray<int> partOfBlock, partitioned;
    if (!PartitionBlocks(graph, numParts, partOfBlock, error)) return false;
    PartitionMajorOrder(blockOrder, partOfBlock, numParts, partitioned, partBlockStart);
    blockOrder = std::move(partitioned);
  }
  DynamicArray<int> permutation(numDofs), partRowStart;
  int next = 0;
  for (std::size_t position = 0; position < blockOrder.size(); ++position) {
    while (static_cast<int>(partRowStart.size()) < numParts &&
           partBlockStart[partRowStart.size()] == static_cast<int>(position))
      partRowStart.push_back(next);
    int const block = blockOrder[position];
    for (int d = blockStart[block]; d < blockStart[block + 1]; ++d) permutation[d] = next++;
  }
  while (static_cast<int>(partRowStart.size()) <= numParts) partRowStart.push_back(next);
  times.orderingSeconds = SecondsSince(orderingStart);

  // the contributors this part evaluates (one of its DoFs owned) and owns
  // (its first DoF owned; part 0 owns those without DoFs). In one part every
  // contributor with DoFs is evaluated; one without (a term an own-block
  // solve took in) is not.
  bool const divided = numParts > 1;
  int const rowBegin = partRowStart[part], rowEnd = partRowStart[part + 1];
  DynamicArray<std::uint8_t> evaluated, owned;
  if (divided) {
    auto const isOwned = [&](int dof) {
      return permutation[dof] >= rowBegin && permutation[dof] < rowEnd;
    };
    evaluated.resize(contributorDofs.size());
    owned.resize(contributorDofs.size());
    for (std::size_t c = 0; c < contributorDofs.size(); ++c) {
      auto const& dofs = contributorDofs[c];
      evaluated[c] = std::any_of(dofs.begin(), dofs.end(), isOwned);
      owned[c] = dofs.empty() ? part == 0 : isOwned(dofs[0]);
    }
  } else if (std::any_of(contributorDofs.begin(), contributorDofs.end(), [](auto const& d) { return d.empty(); })) {
    evaluated.resize(contributorDofs.size());
    for (std::size_t c = 0; c < contributorDofs.size(); ++c) evaluated[c] = !contributorDofs[c].empty();
  }

  Pattern pattern;
  pattern.permutation = std::move(permutation);
  pattern.partRowStart = std::move(partRowStart);
  pattern.part = part;
  pattern.divided = divided;
  for (int block : blockOrder) pattern.orderedBlockSizes.push_back(blockSizes[block]);
  BuildPattern(contributorDofs, evaluated, {}, blockStart, pattern, times);

  // commit
  evaluated_ = std::move(evaluated);
  owned_ = std::move(owned);
  blockStart_ = std::move(blockStart);
  dofToBlock_ = std::move(dofToBlock);
  orderedBlockSizes_ = std::move(pattern.orderedBlockSizes);
  reserved_.clear();
  reservedSinceOrdering_ = 0;
  orderedBlockPairs_ = static_cast<std::int64_t>(graph.adjacency.size() / 2 + blockSizes.size());
  dynamicStage_ = 0;
  ClearDynamicContributors();
  Commit(pattern, times);
  ++numBuilds_;
  return true;
}

bool HessianAssembler::CheckDofList(DynamicArray<int> const& dofs, int numDofs, Error& error) {
  for (std::size_t i = 0; i < dofs.size(); ++i) {
    if (dofs[i] < 0 || dofs[i] >= numDofs || std::find(dofs.begin() + i + 1, dofs.end(), dofs[i]) != dofs.end()) {
      error.Set(ErrorCode::InvalidState,
                "contributor DoF list holds an out-of-range or repeated DoF " + std::to_string(dofs[i]));
      return false;
    }
  }
  return true;
}

void HessianAssembler::BuildPattern(DynamicArray<DynamicArray<int>> const& contributorDofs,
                                    DynamicArray<std::uint8_t> const& evaluated,
                                    DynamicArray<std::uint64_t> const& extraBlockPairs,
                                    DynamicArray<int> const& blockStart, Pattern& out, AnalysisTimes& times) const {
  auto const patternStart = Clock::now();
  int const numDofs = static_cast<int>(out.permutation.size());
  DynamicArray<int> const& permutation = out.permutation;
  bool const divided = out.divided;
  int const rowBegin = out.partRowStart[out.part], rowEnd = out.partRowStart[out.part + 1];
  // upper-triangle pattern of P H Pᵀ: rows per column, sorted and unique.
  // On one part of several only the entries with an owned row or column
  // (and every diagonal), from the contributors the part evaluates.
  auto const stored = [&](int row, int col) {
    return !divided || (row >= rowBegin && row < rowEnd) || (col >= rowBegin && col < rowEnd);
  };
  auto const assembled = [&](std::size_t c) { return evaluated.empty() || evaluated[c] != 0; };
  // Rows per column in one flat array (count, then fill; a column per DoF
  // as separate arrays costs several times the pattern's memory at its
  // peak), then each column sorted and deduplicated in place.
  auto const forEachEntry = [&](auto&& visit) {
    for (int d = 0; d < numDofs; ++d) visit(d, d);  // every diagonal
    for (std::size_t c = 0; c < contributorDofs.size(); ++c) {
      if (!assembled(c)) continue;
      for (int i : contributorDofs[c])
        for (int j : contributorDofs[c]) {
          int const pi = permutation[i], pj = permutation[j];
          if (pi <= pj && stored(pi, pj)) visit(pi, pj);
        }
    }
    // the reserved block pairs of the second family (one part only)
    for (std::uint64_t pair : extraBlockPairs) {
      int const a = static_cast<int>(pair >> 32), b = static_cast<int>(pair & 0xffffffffu);
      for (int i = blockStart[a]; i < blockStart[a + 1]; ++i)
        for (int j = blockStart[b]; j < blockStart[b + 1]; ++j) {
          int const pi = permutation[i], pj = permutation[j];
          visit(std::min(pi, pj), std::max(pi, pj));
        }
    }
  };
  DynamicArray<std::int64_t> entryStart(numDofs + 1, 0);
  forEachEntry([&](int, int col) { ++entryStart[col + 1]; });
  for (int c = 0; c < numDofs; ++c) entryStart[c + 1] += entryStart[c];
  DynamicArray<int> rows(static_cast<std::size_t>(entryStart[numDofs]));
  {
    DynamicArray<std::int64_t> next(entryStart.begin(), entryStart.end() - 1);
    forEachEntry([&](int row, int col) { rows[next[col]++] = row; });
  }
  SparseSymmetricMatrix& matrix = out.matrix;
  matrix.size = numDofs;
  matrix.colStart.assign(numDofs + 1, 0);
  std::int64_t kept = 0;
  for (int c = 0; c < numDofs; ++c) {
    auto const first = rows.begin() + entryStart[c], last = rows.begin() + entryStart[c + 1];
    std::sort(first, last);
    auto const end = std::unique(first, last);
    kept = std::copy(first, end, rows.begin() + kept) - rows.begin();
    matrix.colStart[c + 1] = static_cast<int>(kept);
  }
  matrix.rowIndex.assign(rows.begin(), rows.begin() + kept);
  DynamicArray<int>().swap(rows);
  matrix.values.assign(matrix.rowIndex.size(), 0);
  matrix.blockSizes = out.orderedBlockSizes;
  matrix.patternVersion = NextPatternVersion();
  times.patternSeconds += SecondsSince(patternStart);

  // DoF lists and slot table: local upper triangle (a <= b, row-major) →
  // value index, or −1 for an entry not stored; none for a contributor that
  // is not assembled here
  auto const slotStartTime = Clock::now();
  out.dofStart.reserve(contributorDofs.size() + 1);
  out.slotStart.reserve(contributorDofs.size() + 1);
  out.dropsEntries = false;
  for (std::size_t c = 0; c < contributorDofs.size(); ++c) {
    out.dofStart.push_back(static_cast<int>(out.dofs.size()));
    out.slotStart.push_back(static_cast<int>(out.slots.size()));
    if (!assembled(c)) continue;
    auto const& dofs = contributorDofs[c];
    out.dofs.insert(out.dofs.end(), dofs.begin(), dofs.end());
    AppendSlots(matrix, permutation, dofs, stored, out.slots, out.dropsEntries);
  }
  out.dofStart.push_back(static_cast<int>(out.dofs.size()));
  out.slotStart.push_back(static_cast<int>(out.slots.size()));
  times.slotTableSeconds += SecondsSince(slotStartTime);
}

int HessianAssembler::SlotOf(SparseSymmetricMatrix const& matrix, int row, int col) {
  auto const first = matrix.rowIndex.begin() + matrix.colStart[col];
  auto const last = matrix.rowIndex.begin() + matrix.colStart[col + 1];
  auto const found = std::lower_bound(first, last, row);
  return found != last && *found == row ? static_cast<int>(found - matrix.rowIndex.begin()) : -1;
}

template <class Stored>
void HessianAssembler::AppendSlots(SparseSymmetricMatrix const& matrix, DynamicArray<int> const& permutation,
                                   DynamicArray<int> const& dofs, Stored const& stored, DynamicArray<int>& slots,
                                   bool& dropsEntries) {
  int const n = static_cast<int>(dofs.size());
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b) {
      int const pa = permutation[dofs[a]], pb = permutation[dofs[b]];
      int const row = std::min(pa, pb), col = std::max(pa, pb);
      if (!stored(row, col)) {
        slots.push_back(-1);
        dropsEntries = true;
        continue;
      }
      slots.push_back(SlotOf(matrix, row, col));  // (−1: a missing entry, for the second family's growth)
    }
}

void HessianAssembler::FindSlots(DynamicArray<int> const& dofs, int* slots) const {
  int const n = static_cast<int>(dofs.size());
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b) {
      int const pa = permutation_[dofs[a]], pb = permutation_[dofs[b]];
      *slots++ = SlotOf(matrix_, std::min(pa, pb), std::max(pa, pb));
    }
}

void HessianAssembler::Commit(Pattern& pattern, AnalysisTimes& times) {
  auto const start = Clock::now();
  matrix_ = std::move(pattern.matrix);
  permutation_ = std::move(pattern.permutation);
  partRowStart_ = std::move(pattern.partRowStart);
  part_ = pattern.part;
  dofStart_ = std::move(pattern.dofStart);
  dofs_ = std::move(pattern.dofs);
  slotStart_ = std::move(pattern.slotStart);
  slots_ = std::move(pattern.slots);
  dropsEntries_ = pattern.dropsEntries;
  analyzed_ = true;
  PrepareStaging();
  times.slotTableSeconds += SecondsSince(start);
  lastTimes_ = times;
}

// ---- the second family ----

void HessianAssembler::ClearDynamicContributors() {
  dynamicDofStart_.assign(1, 0);
  dynamicDofs_.clear();
  dynamicSlotStart_.assign(1, 0);
  dynamicSlots_.clear();
  dynamicValueStage_.clear();
  dynamicGradientStage_.clear();
  dynamicBlockStamp_.clear();
  dynamicGradientStamp_.clear();
}

namespace {
std::uint64_t BlockPair(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}
}  // namespace

bool HessianAssembler::SetDynamicContributors(Span<DynamicArray<int> const> dofLists,
                                              DynamicUpdate& update, Error& error, bool rebuildWhenChanged) {
  update = DynamicUpdate{};
  if (!analyzed_) {
    error.Set(ErrorCode::InvalidState, "contributors whose DoF lists change between stages need an analysed pattern");
    return false;
  }
  for (auto const& dofs : dofLists)
    if (!CheckDofList(dofs, matrix_.size, error)) return false;
  if (GetNumParts() != 1) {
    if (rebuildWhenChanged) {
      error.Set(ErrorCode::InvalidState, "re-analysing the pattern whenever the changing contributors change is not "
                                         "supported on several parts");
      return false;
    }
    return SetDividedDynamicContributors(dofLists, error);
  }
  bool changed = false;
  if (rebuildWhenChanged) {
    // the same lists as the last stage's: nothing to do but zero stages
    changed = static_cast<int>(dofLists.size()) != GetNumDynamicContributors();
    for (std::size_t k = 0; !changed && k < dofLists.size(); ++k)
      changed = !std::equal(dofLists[k].begin(), dofLists[k].end(), dynamicDofs_.begin() + dynamicDofStart_[k],
                            dynamicDofs_.begin() + dynamicDofStart_[k + 1]);
    if (changed) reserved_.clear();
  }
  // every block pair they use is (kept) reserved, stamped with this stage:
  // the pairs of each list's distinct blocks (a node's 3 DoFs are one block)
  ++dynamicStage_;
  std::int64_t added = 0;
  for (auto const& dofs : dofLists) {
    std::array<int, 64> blocks;
    int numBlocks = 0;
    for (int dof : dofs) {
      int const block = dofToBlock_[dof];
      if (numBlocks > 0 && blocks[numBlocks - 1] == block) continue;  // (a block's DoFs come together)
      if (numBlocks == static_cast<int>(blocks.size())) break;        // (the rest below, pair by pair)
      blocks[numBlocks++] = block;
    }
    auto reserve = [&](int a, int b) {
      bool const inserted = reserved_.insert_or_assign(BlockPair(a, b), dynamicStage_).second;
      added += inserted && a != b;  // a new edge of the block graph (a block's own pair always is one)
    };
    for (int i = 0; i < numBlocks; ++i)
      for (int j = i; j < numBlocks; ++j) reserve(blocks[i], blocks[j]);
    if (numBlocks == static_cast<int>(blocks.size()))  // a list of more blocks than that: every DoF pair
      for (std::size_t i = 0; i < dofs.size(); ++i)
        for (std::size_t j = i; j < dofs.size(); ++j) reserve(dofToBlock_[dofs[i]], dofToBlock_[dofs[j]]);
  }
  // their slots, each list's into its own range on the assembler's threads
  // (storage kept: no allocation once grown); a missing entry makes the
  // pattern grow
  SetDynamicLists(dofLists);
  auto const fillSlots = [&] {
    ParallelFor(static_cast<int>(dofLists.size()), kDynamicSlotGrain, [&](int begin, int end, int) {
      for (int k = begin; k < end; ++k) {
        int* const slots = dynamicSlots_.data() + dynamicSlotStart_[k];
        // the pairs of two rigid bodies (or a body and the ground) come
        // together with one list: its slots are the last one's
        if (k > begin && dofLists[k] == dofLists[k - 1]) {
          std::copy(slots - (dynamicSlotStart_[k] - dynamicSlotStart_[k - 1]), slots, slots);
        } else {
          FindSlots(dofLists[k], slots);
        }
      }
    });
  };
  fillSlots();
  if (changed || std::find(dynamicSlots_.begin(), dynamicSlots_.end(), -1) != dynamicSlots_.end()) {
    reservedSinceOrdering_ += added;
    if (!GrowPattern(update, changed, error)) return false;
    fillSlots();
  }
  ClearDynamicStamps(dofLists.size());
  return true;
}

void HessianAssembler::SetDynamicLists(Span<DynamicArray<int> const> dofLists) {
  dynamicDofStart_.assign(1, 0);
  dynamicDofs_.clear();
  dynamicSlotStart_.assign(1, 0);
  for (auto const& dofs : dofLists) {
    dynamicDofs_.insert(dynamicDofs_.end(), dofs.begin(), dofs.end());
    dynamicDofStart_.push_back(static_cast<int>(dynamicDofs_.size()));
    int const n = static_cast<int>(dofs.size());
    dynamicSlotStart_.push_back(dynamicSlotStart_.back() + n * (n + 1) / 2);
  }
  dynamicSlots_.resize(static_cast<std::size_t>(dynamicSlotStart_.back()));
}

void HessianAssembler::ClearDynamicStamps(std::size_t numLists) {
  dynamicValueStage_.resize(dynamicSlots_.size());
  dynamicGradientStage_.resize(dynamicDofs_.size());
  // no contributor of this stage has added anything yet
  dynamicBlockStamp_.assign(numLists, 0);
  dynamicGradientStamp_.assign(numLists, 0);
  if (++dynamicStamp_ == 0) dynamicStamp_ = 1;
}

bool HessianAssembler::SetDividedDynamicContributors(Span<DynamicArray<int> const> dofLists, Error& error) {
  // One part of several (docs/distributed.md, "Contact across ranks"): the
  // pattern does not grow here, so every entry a list needs in this part
  // (an owned row or column) must be in it already, as it is for contact
  // with obstacles (a pair within one body's block). Entries of neither an
  // owned row nor an owned column are not this part's: slot −1, skipped.
  SetDynamicLists(dofLists);
  int const rowBegin = GetOwnedRowBegin(), rowEnd = GetOwnedRowEnd();
  auto const owned = [&](int ordered) { return ordered >= rowBegin && ordered < rowEnd; };
  constexpr int kMissing = -2;
  ParallelFor(static_cast<int>(dofLists.size()), kDynamicSlotGrain, [&](int begin, int end, int) {
    for (int k = begin; k < end; ++k) {
      int* slots = dynamicSlots_.data() + dynamicSlotStart_[k];
      auto const& dofs = dofLists[k];
      int const n = static_cast<int>(dofs.size());
      for (int a = 0; a < n; ++a)
        for (int b = a; b < n; ++b) {
          int const pa = permutation_[dofs[a]], pb = permutation_[dofs[b]];
          int const row = std::min(pa, pb), col = std::max(pa, pb);
          if (!owned(row) && !owned(col)) {
            *slots++ = -1;
          } else {
            int const slot = SlotOf(matrix_, row, col);
            *slots++ = slot >= 0 ? slot : kMissing;
          }
        }
    }
  });
  if (auto const missing = std::find(dynamicSlots_.begin(), dynamicSlots_.end(), kMissing);
      missing != dynamicSlots_.end()) {
    int const slot = static_cast<int>(missing - dynamicSlots_.begin());
    int const k = static_cast<int>(std::upper_bound(dynamicSlotStart_.begin(), dynamicSlotStart_.end(), slot) -
                                   dynamicSlotStart_.begin()) - 1;
    error.Set(ErrorCode::InvalidState, "changing contributor " + std::to_string(k) +
                                           " needs entries the pattern lacks, which cannot grow on several parts "
                                           "(contact between two bodies across MPI ranks)");
    SetDynamicLists(Span<DynamicArray<int> const>());
    ClearDynamicStamps(0);
    return false;
  }
  ClearDynamicStamps(dofLists.size());
  return true;
}

bool HessianAssembler::GrowPattern(DynamicUpdate& update, bool reorder, Error& error) {
  // the reserved pairs used in the last kReserveStages stages stay; older
  // ones leave now, with the rebuild (hysteresis: a pair that comes and goes
  // does not rebuild the pattern each time)
  for (auto it = reserved_.begin(); it != reserved_.end();)
    it = dynamicStage_ - it->second >= kReserveStages ? reserved_.erase(it) : std::next(it);
  DynamicArray<std::uint64_t> pairs;
  pairs.reserve(reserved_.size());
  for (auto const& [pair, stage] : reserved_) pairs.push_back(pair);
  std::sort(pairs.begin(), pairs.end());
  // the static contributors' lists, as analysed
  int const numContributors = GetNumContributors();
  DynamicArray<DynamicArray<int>> contributorDofs(numContributors);
  for (int c = 0; c < numContributors; ++c)
    contributorDofs[c].assign(dofs_.begin() + dofStart_[c], dofs_.begin() + dofStart_[c + 1]);
  AnalysisTimes times;
  Pattern pattern;
  pattern.part = 0;
  pattern.divided = false;
  pattern.partRowStart = partRowStart_;
  pattern.orderedBlockSizes = orderedBlockSizes_;
  if (reorder || reservedSinceOrdering_ > kReorderFraction * orderedBlockPairs_) {
    // the pairs added since the last ordering are many: order again, the
    // reserved pairs as edges of the block graph
    auto const orderingStart = Clock::now();
    DynamicArray<DynamicArray<int>> withPairs = contributorDofs;
    for (std::uint64_t pair : pairs)
      withPairs.push_back({blockStart_[static_cast<int>(pair >> 32)], blockStart_[static_cast<int>(pair & 0xffffffffu)]});
    DynamicArray<int> blockSizes(blockStart_.size() - 1);
    for (std::size_t b = 0; b + 1 < blockStart_.size(); ++b) blockSizes[b] = blockStart_[b + 1] - blockStart_[b];
    BlockGraph const graph = BuildBlockGraph(blockSizes, dofToBlock_, withPairs);
    DynamicArray<int> blockOrder;
    if (!OrderBlocks(graph, OrderingMethod::Metis, blockOrder, error)) return false;
    pattern.permutation.resize(matrix_.size);
    int next = 0;
    pattern.orderedBlockSizes.clear();
    for (int block : blockOrder) {
      pattern.orderedBlockSizes.push_back(blockSizes[block]);
      for (int d = blockStart_[block]; d < blockStart_[block + 1]; ++d) pattern.permutation[d] = next++;
    }
    orderedBlockPairs_ = static_cast<std::int64_t>(graph.adjacency.size() / 2 + blockSizes.size());
    reservedSinceOrdering_ = 0;
    times.orderingSeconds = SecondsSince(orderingStart);
    update.reordered = true;
    ++numBuilds_;
  } else {
    pattern.permutation = permutation_;  // the fill-reducing order is kept
    ++numGrowths_;
  }
  BuildPattern(contributorDofs, evaluated_, pairs, blockStart_, pattern, times);
  orderedBlockSizes_ = pattern.orderedBlockSizes;
  Commit(pattern, times);
  update.grew = true;
  return true;
}

void HessianAssembler::SetExecutor(ParallelExecutor const* executor) {
  executor_ = executor;
  PrepareStaging();
}

namespace {
/// For every target t in [0, numTargets): the positions p of `targets` with
/// targets[p] == t, ascending (a counting sort). Negative targets (entries
/// not stored) are nobody's source.
void InvertMap(DynamicArray<int> const& targets, int numTargets, DynamicArray<int>& start,
               DynamicArray<int>& sources) {
  start.assign(numTargets + 1, 0);
  for (int t : targets)
    if (t >= 0) ++start[t + 1];
  for (int t = 0; t < numTargets; ++t) start[t + 1] += start[t];
  sources.resize(static_cast<std::size_t>(start[numTargets]));
  DynamicArray<int> next(start.begin(), start.end() - 1);
  for (std::size_t p = 0; p < targets.size(); ++p)
    if (targets[p] >= 0) sources[next[targets[p]]++] = static_cast<int>(p);
}
/// Grain of the parallel loops over entries and staging slots
constexpr int kEntryGrain = 4096;
}  // namespace

void HessianAssembler::PrepareStaging() {
  staged_ = executor_ && executor_->GetNumThreads() > 1 && analyzed_;
  if (!staged_) {
    // release what a staged configuration held
    DynamicArray<real>().swap(valueStage_);
    DynamicArray<real>().swap(gradientStage_);
    DynamicArray<std::uint32_t>().swap(blockStamp_);
    DynamicArray<std::uint32_t>().swap(gradientStamp_);
    DynamicArray<int>().swap(valueSourceStart_);
    DynamicArray<int>().swap(valueSources_);
    DynamicArray<int>().swap(gradientSourceStart_);
    DynamicArray<int>().swap(gradientSources_);
    return;
  }
  valueStage_.assign(slots_.size(), 0);
  gradientStage_.assign(dofs_.size(), 0);
  blockStamp_.assign(static_cast<std::size_t>(GetNumContributors()), 0);
  gradientStamp_.assign(static_cast<std::size_t>(GetNumContributors()), 0);
  stamp_ = 0;
  InvertMap(slots_, static_cast<int>(matrix_.values.size()), valueSourceStart_, valueSources_);
  InvertMap(dofs_, matrix_.size, gradientSourceStart_, gradientSources_);
}

void HessianAssembler::BeginAssembly(Span<real> gradient) {
  gradient_ = gradient;
  // the second family's stages are assigned by each contributor's add,
  // stamped with this assembly's number (FinishAssembly sums only those)
  if (++dynamicStamp_ == 0) {  // wrapped: no stamp of an earlier assembly may match
    std::fill(dynamicBlockStamp_.begin(), dynamicBlockStamp_.end(), 0u);
    std::fill(dynamicGradientStamp_.begin(), dynamicGradientStamp_.end(), 0u);
    dynamicStamp_ = 1;
  }
  if (!staged_) {
    std::fill(gradient.begin(), gradient.end(), real(0));
    ZeroValues();
    return;
  }
  // FinishAssembly overwrites values and gradient; the stages are assigned
  // by each contributor's first write (AddBlock, AddGradient): a new stamp
  if (++stamp_ == 0) {  // wrapped: no stamp of an earlier assembly may match
    std::fill(blockStamp_.begin(), blockStamp_.end(), 0u);
    std::fill(gradientStamp_.begin(), gradientStamp_.end(), 0u);
    stamp_ = 1;
  }
}

void HessianAssembler::FinishAssembly() {
  FinishStaticAssembly();
  // the second family after every static contributor, in its order (both
  // paths: the same sums for any thread count), those that added something
  // in this assembly
  // (on one part of several: the entries it stores, slot >= 0, and the
  // gradient in its own rows, as the static contributors')
  int const numDynamic = GetNumDynamicContributors();
  bool const divided = GetNumParts() > 1;
  int const rowBegin = GetOwnedRowBegin(), rowEnd = GetOwnedRowEnd();
  for (int k = 0; k < numDynamic; ++k) {
    if (dynamicBlockStamp_[k] == dynamicStamp_)
      for (int s = dynamicSlotStart_[k]; s < dynamicSlotStart_[k + 1]; ++s)
        if (int const slot = dynamicSlots_[s]; slot >= 0) matrix_.values[slot] += dynamicValueStage_[s];
    if (dynamicGradientStamp_[k] == dynamicStamp_)
      for (int d = dynamicDofStart_[k]; d < dynamicDofStart_[k + 1]; ++d) {
        int const dof = dynamicDofs_[d];
        if (!divided || (permutation_[dof] >= rowBegin && permutation_[dof] < rowEnd))
          gradient_[dof] += dynamicGradientStage_[d];
      }
  }
}

void HessianAssembler::FinishStaticAssembly() {
  if (!staged_) return;
  // contributors that added nothing in this assembly contribute zeros
  int const numContributors = GetNumContributors();
  executor_->For(numContributors, kEntryGrain, [this](int begin, int end, int) {
    for (int c = begin; c < end; ++c) {
      if (blockStamp_[c] != stamp_)
        std::fill(valueStage_.begin() + slotStart_[c], valueStage_.begin() + slotStart_[c + 1], real(0));
      if (gradientStamp_[c] != stamp_)
        std::fill(gradientStage_.begin() + dofStart_[c], gradientStage_.begin() + dofStart_[c + 1], real(0));
    }
  });
  // every entry: 0 + its contributions in contributor order, as the serial
  // assembly adds them
  auto sum = [](DynamicArray<int> const& start, DynamicArray<int> const& sources, DynamicArray<real> const& stage,
                real* out) {
    return [&start, &sources, &stage, out](int begin, int end, int) {
      for (int t = begin; t < end; ++t) {
        real total = 0;
        for (int k = start[t]; k < start[t + 1]; ++k) total += stage[sources[k]];
        out[t] = total;
      }
    };
  };
  executor_->For(static_cast<int>(matrix_.values.size()), kEntryGrain,
                 sum(valueSourceStart_, valueSources_, valueStage_, matrix_.values.data()));
  executor_->For(matrix_.size, kEntryGrain,
                 sum(gradientSourceStart_, gradientSources_, gradientStage_, gradient_.data()));
}

void HessianAssembler::ZeroValues() { std::fill(matrix_.values.begin(), matrix_.values.end(), 0); }

void HessianAssembler::ShiftDiagonal(real relative) {
  // upper CSC with sorted rows: a column's diagonal entry is its last
  for (int j = 0; j < matrix_.size; ++j) {
    int const last = matrix_.colStart[j + 1] - 1;
    if (last >= matrix_.colStart[j] && matrix_.rowIndex[last] == j)
      matrix_.values[last] += relative * std::abs(matrix_.values[last]);
  }
}

void HessianAssembler::PermuteToOrdered(Span<real const> natural, Span<real> ordered) const {
  for (std::size_t i = 0; i < permutation_.size(); ++i) ordered[permutation_[i]] = natural[i];
}

void HessianAssembler::PermuteToNatural(Span<real const> ordered, Span<real> natural) const {
  for (std::size_t i = 0; i < permutation_.size(); ++i) natural[i] = ordered[permutation_[i]];
}

}  // namespace superdex::internal
