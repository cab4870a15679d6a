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
                               OrderingMethod method, Error& error) {
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
  DynamicArray<int> permutation(numDofs);
  int next = 0;
  for (int block : blockOrder)
    for (int d = blockStart[block]; d < blockStart[block + 1]; ++d) permutation[d] = next++;

  // upper-triangle pattern of P H Pᵀ: rows per column, sorted and unique
  DynamicArray<DynamicArray<int>> columns(numDofs);
  for (int d = 0; d < numDofs; ++d) columns[d].push_back(d);
  for (auto const& dofs : contributorDofs)
    for (int i : dofs)
      for (int j : dofs) {
        int const pi = permutation[i], pj = permutation[j];
        if (pi <= pj) columns[pj].push_back(pi);
      }
  SparseSymmetricMatrix matrix;
  matrix.size = numDofs;
  matrix.colStart.assign(numDofs + 1, 0);
  for (int c = 0; c < numDofs; ++c) {
    auto& rows = columns[c];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    matrix.colStart[c + 1] = matrix.colStart[c] + static_cast<int>(rows.size());
  }
  matrix.rowIndex.reserve(matrix.colStart.back());
  for (auto const& rows : columns) matrix.rowIndex.insert(matrix.rowIndex.end(), rows.begin(), rows.end());
  matrix.values.assign(matrix.rowIndex.size(), 0);
  matrix.blockSizes.reserve(blockOrder.size());
  for (int block : blockOrder) matrix.blockSizes.push_back(blockSizes[block]);
  matrix.patternVersion = NextPatternVersion();

  // slot table: local upper triangle (a <= b, row-major) → value index
  DynamicArray<int> contributorSize, slotStart, slots;
  contributorSize.reserve(contributorDofs.size());
  slotStart.reserve(contributorDofs.size());
  for (auto const& dofs : contributorDofs) {
    int const n = static_cast<int>(dofs.size());
    contributorSize.push_back(n);
    slotStart.push_back(static_cast<int>(slots.size()));
    for (int a = 0; a < n; ++a)
      for (int b = a; b < n; ++b) {
        int const pa = permutation[dofs[a]], pb = permutation[dofs[b]];
        int const row = std::min(pa, pb), col = std::max(pa, pb);
        auto first = matrix.rowIndex.begin() + matrix.colStart[col];
        auto last = matrix.rowIndex.begin() + matrix.colStart[col + 1];
        slots.push_back(static_cast<int>(std::lower_bound(first, last, row) - matrix.rowIndex.begin()));
      }
  }

  // commit
  matrix_ = std::move(matrix);
  permutation_ = std::move(permutation);
  contributorSize_ = std::move(contributorSize);
  slotStart_ = std::move(slotStart);
  slots_ = std::move(slots);
  analyzed_ = true;
  ++numBuilds_;
  return true;
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
