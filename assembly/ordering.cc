#include <superdex/assembly/ordering.h>

#include <algorithm>
#include <numeric>

#include <metis.h>

namespace superdex {

std::string_view ToString(OrderingMethod method) {
  switch (method) {
    case OrderingMethod::Metis: return "METIS";
    case OrderingMethod::Natural: return "natural";
    case OrderingMethod::SolverDefault: return "solver default";
  }
  return "Unknown";
}

std::string_view ToString(PatternPolicy policy) {
  switch (policy) {
    case PatternPolicy::ReserveAndGrow: return "ReserveAndGrow";
    case PatternPolicy::RebuildWhenChanged: return "RebuildWhenChanged";
  }
  return "Unknown";
}

namespace internal {

BlockGraph BuildBlockGraph(DynamicArray<int> const& blockSizes, DynamicArray<int> const& dofToBlock,
                           DynamicArray<DynamicArray<int>> const& contributorDofs) {
  int const numBlocks = static_cast<int>(blockSizes.size());
  // collect neighbour lists, then sort and deduplicate
  DynamicArray<DynamicArray<int>> neighbours(numBlocks);
  DynamicArray<int> blocks;
  for (auto const& dofs : contributorDofs) {
    blocks.clear();
    for (int dof : dofs) blocks.push_back(dofToBlock[dof]);
    std::sort(blocks.begin(), blocks.end());
    blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
    for (int a : blocks)
      for (int b : blocks)
        if (a != b) neighbours[a].push_back(b);
  }
  BlockGraph graph;
  graph.blockSizes = blockSizes;
  graph.adjacencyStart.assign(numBlocks + 1, 0);
  for (int v = 0; v < numBlocks; ++v) {
    auto& n = neighbours[v];
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    graph.adjacencyStart[v + 1] = graph.adjacencyStart[v] + static_cast<int>(n.size());
  }
  graph.adjacency.reserve(graph.adjacencyStart.back());
  for (auto const& n : neighbours) graph.adjacency.insert(graph.adjacency.end(), n.begin(), n.end());
  return graph;
}

bool OrderBlocks(BlockGraph const& graph, OrderingMethod method, DynamicArray<int>& blockOrder,
                 Error& error) {
  idx_t numBlocks = static_cast<idx_t>(graph.blockSizes.size());
  blockOrder.resize(numBlocks);
  std::iota(blockOrder.begin(), blockOrder.end(), 0);
  // METIS needs a graph with at least one edge to dissect; tiny or edgeless
  // graphs keep the natural order (nothing to gain)
  if (method != OrderingMethod::Metis || numBlocks < 3 || graph.adjacency.empty()) return true;

  DynamicArray<idx_t> xadj(graph.adjacencyStart.begin(), graph.adjacencyStart.end());
  DynamicArray<idx_t> adjncy(graph.adjacency.begin(), graph.adjacency.end());
  DynamicArray<idx_t> vwgt(graph.blockSizes.begin(), graph.blockSizes.end());
  DynamicArray<idx_t> perm(numBlocks), iperm(numBlocks);
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  int status = METIS_NodeND(&numBlocks, xadj.data(), adjncy.data(), vwgt.data(), options,
                            perm.data(), iperm.data());
  if (status != METIS_OK) {
    error.Set(ErrorCode::BackendError,
              "METIS_NodeND failed with status " + std::to_string(status) + " on a block graph of " +
                  std::to_string(numBlocks) + " vertices");
    return false;
  }
  // METIS: row i of the permuted matrix is row perm[i] of the original
  for (idx_t i = 0; i < numBlocks; ++i) blockOrder[i] = static_cast<int>(perm[i]);
  return true;
}

bool PartitionBlocks(BlockGraph const& graph, int numParts, DynamicArray<int>& partOfBlock, Error& error) {
  if (numParts < 1) {
    error.Set(ErrorCode::InvalidArgument, "numParts must be >= 1, got " + std::to_string(numParts));
    return false;
  }
  idx_t numBlocks = static_cast<idx_t>(graph.blockSizes.size());
  partOfBlock.assign(numBlocks, 0);
  if (numParts == 1 || numBlocks == 0) return true;
  if (numBlocks < numParts || graph.adjacency.empty()) {
    // contiguous runs: block b goes to the part its DoF midpoint falls in
    long total = 0;
    for (int size : graph.blockSizes) total += size;
    long before = 0;
    for (idx_t b = 0; b < numBlocks; ++b) {
      long const middle = 2 * before + graph.blockSizes[b];  // twice the midpoint
      partOfBlock[b] = static_cast<int>(std::min<long>(numParts - 1, middle * numParts / (2 * total)));
      before += graph.blockSizes[b];
    }
    return true;
  }
  DynamicArray<idx_t> xadj(graph.adjacencyStart.begin(), graph.adjacencyStart.end());
  DynamicArray<idx_t> adjncy(graph.adjacency.begin(), graph.adjacency.end());
  DynamicArray<idx_t> vwgt(graph.blockSizes.begin(), graph.blockSizes.end());
  DynamicArray<idx_t> part(numBlocks);
  idx_t numConstraints = 1, parts = numParts, edgeCut = 0;
  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  int const status = METIS_PartGraphKway(&numBlocks, &numConstraints, xadj.data(), adjncy.data(), vwgt.data(),
                                         nullptr, nullptr, &parts, nullptr, nullptr, options, &edgeCut,
                                         part.data());
  if (status != METIS_OK) {
    error.Set(ErrorCode::BackendError, "METIS_PartGraphKway failed with status " + std::to_string(status) +
                                           " on a block graph of " + std::to_string(numBlocks) +
                                           " vertices into " + std::to_string(numParts) + " parts");
    return false;
  }
  for (idx_t b = 0; b < numBlocks; ++b) partOfBlock[b] = static_cast<int>(part[b]);
  return true;
}

void PartitionMajorOrder(DynamicArray<int> const& blockOrder, DynamicArray<int> const& partOfBlock,
                         int numParts, DynamicArray<int>& order, DynamicArray<int>& partStart) {
  partStart.assign(numParts + 1, 0);
  for (int block : blockOrder) ++partStart[partOfBlock[block] + 1];
  for (int p = 0; p < numParts; ++p) partStart[p + 1] += partStart[p];
  DynamicArray<int> next(partStart.begin(), partStart.end() - 1);
  order.resize(blockOrder.size());
  for (int block : blockOrder) order[next[partOfBlock[block]]++] = block;
}

}  // namespace internal
}  // namespace superdex
