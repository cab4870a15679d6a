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

}  // namespace internal
}  // namespace superdex
