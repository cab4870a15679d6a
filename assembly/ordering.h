// Fill-reducing ordering of the global Hessian, computed on the compressed
// block graph: one vertex per DoF block (a rigid body, a deformable node),
// weighted by its size, an edge wherever some contributor couples two blocks.
// The scalar permutation keeps every block's DoFs contiguous.
#pragma once

#include <string_view>

#include <superdex/core/error.h>
#include <superdex/core/types.h>

namespace superdex {

enum class OrderingMethod {
  Metis,    ///< METIS_NodeND nested dissection on the block graph (default)
  Natural,  ///< DoFs in actor-creation order (for comparisons)
  /// The assembler keeps the natural order and the linear solver orders:
  /// CHOLMOD its own choice (AMD, then METIS if AMD's fill is poor); PCG and
  /// dense keep the natural order. For comparing against the cached METIS
  /// ordering.
  SolverDefault,
};

std::string_view ToString(OrderingMethod method);

/// How the pattern follows contributors whose DoF lists change between
/// stages (contact pairs; docs/architecture.md, "A pattern that may change").
enum class PatternPolicy {
  /// Their block pairs are reserved in the pattern and kept while used (with
  /// hysteresis); the pattern grows in the kept fill-reducing order where
  /// they need more, and is ordered again only after many pairs (default).
  ReserveAndGrow,
  /// The pattern is rebuilt and ordered anew for exactly this stage's pairs
  /// whenever they differ from the last stage's (for comparisons).
  RebuildWhenChanged,
};

std::string_view ToString(PatternPolicy policy);

namespace internal {

/// Block graph in CSR form (no self loops, symmetric).
struct BlockGraph {
  DynamicArray<int> blockSizes;
  DynamicArray<int> adjacencyStart;  ///< numBlocks + 1
  DynamicArray<int> adjacency;
};

/// Builds the block graph of contributors given by their global DoF lists.
/// `dofToBlock` maps each DoF to its block.
BlockGraph BuildBlockGraph(DynamicArray<int> const& blockSizes, DynamicArray<int> const& dofToBlock,
                           DynamicArray<DynamicArray<int>> const& contributorDofs);

/// Ordered position of every block: blockOrder[newPosition] = block.
/// Returns false and sets `error` if METIS fails.
bool OrderBlocks(BlockGraph const& graph, OrderingMethod method, DynamicArray<int>& blockOrder,
                 Error& error);

/// Splits the blocks into `numParts` parts of about equal DoF counts with
/// few coupled pairs across parts: METIS k-way (METIS_PartGraphKway, METIS's
/// default 3 % imbalance, its fixed seed: the same parts on every call and
/// every rank), each block weighted by its DoFs. With one part, fewer
/// blocks than parts or a graph without edges, the blocks are cut into
/// contiguous runs of about equal DoFs instead. partOfBlock[b] is in
/// [0, numParts). Returns false and sets `error` (InvalidArgument when
/// numParts < 1, BackendError when METIS fails).
/// The partition of the DoFs among MPI ranks (docs/distributed.md).
bool PartitionBlocks(BlockGraph const& graph, int numParts, DynamicArray<int>& partOfBlock, Error& error);

/// Partition-major order of the blocks: part 0's blocks first, then part
/// 1's, ..., each part's in their relative order in `blockOrder` (a
/// fill-reducing order within every part). order[newPosition] = block;
/// partStart[p] is part p's first position (numParts + 1 entries).
void PartitionMajorOrder(DynamicArray<int> const& blockOrder, DynamicArray<int> const& partOfBlock,
                         int numParts, DynamicArray<int>& order, DynamicArray<int>& partStart);

}  // namespace internal
}  // namespace superdex
