// A symmetric sparse matrix stored by its upper triangle in compressed
// sparse columns (CSC): for column j, rows rowIndex[colStart[j] ..
// colStart[j+1]) in increasing order, every row <= j, the diagonal present.
//
// The pattern (size, colStart, rowIndex) is constant between pattern builds;
// only `values` change per Newton iteration. `patternVersion` identifies the
// pattern: the assembler bumps it whenever it rebuilds, and the linear
// solvers key their symbolic analysis on it.
#pragma once

#include <cstdint>

#include <superdex/core/types.h>

namespace superdex {

struct SparseSymmetricMatrix {
  int size = 0;
  DynamicArray<int> colStart;  ///< size + 1 entries
  DynamicArray<int> rowIndex;  ///< NumNonzeros() entries
  DynamicArray<real> values;   ///< NumNonzeros() entries
  /// Sizes of the DoF blocks in matrix order (a node's 3 DoFs, a rigid
  /// body's 6), contiguous and adding to `size`; part of the pattern. Empty
  /// means unknown (treated as blocks of 1).
  DynamicArray<int> blockSizes;
  std::uint64_t patternVersion = 0;

  std::int64_t NumNonzeros() const { return colStart.empty() ? 0 : colStart.back(); }
};

}  // namespace superdex
