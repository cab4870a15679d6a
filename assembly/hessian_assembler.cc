#include <superdex/assembly/hessian_assembler.h>

#include <algorithm>

namespace superdex::internal {

namespace {
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
  for (auto const& dofs : contributorDofs) {
    for (std::size_t i = 0; i < dofs.size(); ++i) {
      if (dofs[i] < 0 || dofs[i] >= numDofs ||
          std::find(dofs.begin() + i + 1, dofs.end(), dofs[i]) != dofs.end()) {
        error.Set(ErrorCode::InvalidState,
                  "contributor DoF list holds an out-of-range or repeated DoF " +
                      std::to_string(dofs[i]));
        return false;
      }
    }
  }

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

  // the contributors this part evaluates (one of its DoFs owned) and owns
  // (its first DoF owned; part 0 owns those without DoFs)
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
  }

  // upper-triangle pattern of P H Pᵀ: rows per column, sorted and unique.
  // On one part of several only the entries with an owned row or column
  // (and every diagonal), from the contributors the part evaluates.
  auto const stored = [&](int row, int col) {
    return !divided || (row >= rowBegin && row < rowEnd) || (col >= rowBegin && col < rowEnd);
  };
  auto const assembled = [&](std::size_t c) { return !divided || evaluated[c] != 0; };
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
  };
  DynamicArray<std::int64_t> entryStart(numDofs + 1, 0);
  forEachEntry([&](int, int col) { ++entryStart[col + 1]; });
  for (int c = 0; c < numDofs; ++c) entryStart[c + 1] += entryStart[c];
  DynamicArray<int> rows(static_cast<std::size_t>(entryStart[numDofs]));
  {
    DynamicArray<std::int64_t> next(entryStart.begin(), entryStart.end() - 1);
    forEachEntry([&](int row, int col) { rows[next[col]++] = row; });
  }
  SparseSymmetricMatrix matrix;
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
  matrix.blockSizes.reserve(blockOrder.size());
  for (int block : blockOrder) matrix.blockSizes.push_back(blockSizes[block]);
  matrix.patternVersion = NextPatternVersion();

  // DoF lists and slot table: local upper triangle (a <= b, row-major) →
  // value index, or −1 for an entry not stored; none for a contributor that
  // is not assembled here
  DynamicArray<int> dofStart, dofList, slotStart, slots;
  dofStart.reserve(contributorDofs.size() + 1);
  slotStart.reserve(contributorDofs.size() + 1);
  bool dropsEntries = false;
  for (std::size_t c = 0; c < contributorDofs.size(); ++c) {
    dofStart.push_back(static_cast<int>(dofList.size()));
    slotStart.push_back(static_cast<int>(slots.size()));
    if (!assembled(c)) continue;
    auto const& dofs = contributorDofs[c];
    int const n = static_cast<int>(dofs.size());
    dofList.insert(dofList.end(), dofs.begin(), dofs.end());
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) {
        int const pa = permutation[dofs[a]], pb = permutation[dofs[b]];
        int const row = std::min(pa, pb), col = std::max(pa, pb);
        if (!stored(row, col)) {
          slots.push_back(-1);
          dropsEntries = true;
          continue;
        }
        auto first = matrix.rowIndex.begin() + matrix.colStart[col];
        auto last = matrix.rowIndex.begin() + matrix.colStart[col + 1];
        slots.push_back(static_cast<int>(std::lower_bound(first, last, row) - matrix.rowIndex.begin()));
      }
  }
  dofStart.push_back(static_cast<int>(dofList.size()));
  slotStart.push_back(static_cast<int>(slots.size()));

  // commit
  matrix_ = std::move(matrix);
  permutation_ = std::move(permutation);
  partRowStart_ = std::move(partRowStart);
  part_ = part;
  evaluated_ = std::move(evaluated);
  owned_ = std::move(owned);
  dofStart_ = std::move(dofStart);
  dofs_ = std::move(dofList);
  slotStart_ = std::move(slotStart);
  slots_ = std::move(slots);
  dropsEntries_ = dropsEntries;
  analyzed_ = true;
  ++numBuilds_;
  PrepareStaging();
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
