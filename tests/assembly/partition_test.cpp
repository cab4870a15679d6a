// The partition of the DoF blocks among ranks (PartitionBlocks, METIS
// k-way) and the partition-major order built from it (PartitionMajorOrder):
// every block in one part, parts balanced in DoFs, few couplings cut,
// the same parts on every call, and each part's blocks kept in the
// fill-reducing order.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>

#include <superdex/assembly/ordering.h>

#include "assembly/lattice.h"

namespace superdex::internal {
namespace {

using test::Lattice;


int Nodes(int) { return 3; }
int Mixed(int b) { return b % 5 == 0 ? 6 : 3; }  // bodies among nodes

/// DoFs per part, and the graph's edges whose ends lie in different parts
struct Cut {
  DynamicArray<long> dofs;
  long edges = 0;
};
Cut Measure(BlockGraph const& graph, DynamicArray<int> const& part, int numParts) {
  Cut cut;
  cut.dofs.assign(numParts, 0);
  for (std::size_t b = 0; b < part.size(); ++b) {
    REQUIRE(part[b] >= 0);
    REQUIRE(part[b] < numParts);
    cut.dofs[part[b]] += graph.blockSizes[b];
    for (int k = graph.adjacencyStart[b]; k < graph.adjacencyStart[b + 1]; ++k)
      if (static_cast<int>(b) < graph.adjacency[k] && part[b] != part[graph.adjacency[k]]) ++cut.edges;
  }
  return cut;
}

TEST_CASE("blocks are split into balanced parts with few couplings cut", "[assembly][partition]") {
  auto const [name, size] = GENERATE(table<std::string, int (*)(int)>({{"nodes", Nodes}, {"nodes and bodies", Mixed}}));
  int const numParts = GENERATE(2, 3, 4, 7, 16);
  CAPTURE(name, numParts);
  // a 40 x 10 x 10 beam of blocks
  BlockGraph const graph = Lattice(40, 10, 10, size);
  Error error;
  DynamicArray<int> part;
  REQUIRE(PartitionBlocks(graph, numParts, part, error));
  REQUIRE(part.size() == graph.blockSizes.size());
  Cut const cut = Measure(graph, part, numParts);
  long const total = std::accumulate(cut.dofs.begin(), cut.dofs.end(), 0L);
  for (long dofs : cut.dofs) {
    CAPTURE(dofs, total);
    // METIS's 3 % imbalance on weights, and a block's DoFs of slack
    REQUIRE(dofs <= 1.03 * total / numParts + 6);
    REQUIRE(dofs > 0);
  }
  // cutting the 40-long beam into slabs cuts 100 couplings per slab face:
  // k-way finds about that (a random split would cut ~(1 − 1/k) of 11,500)
  CAPTURE(cut.edges);
  REQUIRE(cut.edges <= 2 * 100 * (numParts - 1));
  // the same parts on every call (every rank computes them)
  DynamicArray<int> again;
  REQUIRE(PartitionBlocks(graph, numParts, again, error));
  REQUIRE(again == part);
}

TEST_CASE("one part, too few blocks and no couplings split into contiguous runs", "[assembly][partition]") {
  Error error;
  DynamicArray<int> part;
  BlockGraph graph = Lattice(10, 1, 1, Mixed);
  REQUIRE(PartitionBlocks(graph, 1, part, error));
  REQUIRE(std::all_of(part.begin(), part.end(), [](int p) { return p == 0; }));

  // more parts than blocks: each block in its own part, in order
  REQUIRE(PartitionBlocks(graph, 12, part, error));
  REQUIRE(std::is_sorted(part.begin(), part.end()));
  REQUIRE(std::adjacent_find(part.begin(), part.end()) == part.end());
  REQUIRE(part.back() < 12);

  // independent blocks (no contributor couples two): runs of about equal DoFs
  graph.adjacencyStart.assign(graph.blockSizes.size() + 1, 0);
  graph.adjacency.clear();
  REQUIRE(PartitionBlocks(graph, 3, part, error));
  REQUIRE(std::is_sorted(part.begin(), part.end()));
  Cut const cut = Measure(graph, part, 3);
  for (long dofs : cut.dofs) REQUIRE(std::abs(dofs - 36 / 3.0) <= 6);
}

TEST_CASE("a part count below one is refused, naming it", "[assembly][partition][input]") {
  Error error;
  DynamicArray<int> part;
  REQUIRE_FALSE(PartitionBlocks(Lattice(4, 4, 4, Nodes), 0, part, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(error.GetMessage().find("numParts") != std::string::npos);
  REQUIRE(error.GetMessage().find("0") != std::string::npos);
}

TEST_CASE("the partition-major order keeps each part's blocks in the fill-reducing order",
          "[assembly][partition]") {
  BlockGraph const graph = Lattice(12, 6, 6, Nodes);
  Error error;
  DynamicArray<int> blockOrder, part, order, partStart;
  REQUIRE(OrderBlocks(graph, OrderingMethod::Metis, blockOrder, error));
  REQUIRE(PartitionBlocks(graph, 4, part, error));
  PartitionMajorOrder(blockOrder, part, 4, order, partStart);
  REQUIRE(partStart.size() == 5);
  REQUIRE(partStart.front() == 0);
  REQUIRE(partStart.back() == static_cast<int>(blockOrder.size()));
  // a permutation of the blocks
  DynamicArray<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t b = 0; b < sorted.size(); ++b) REQUIRE(sorted[b] == static_cast<int>(b));
  // position of each block in the fill-reducing order
  DynamicArray<int> rank(blockOrder.size());
  for (std::size_t i = 0; i < blockOrder.size(); ++i) rank[blockOrder[i]] = static_cast<int>(i);
  for (int p = 0; p < 4; ++p)
    for (int i = partStart[p]; i < partStart[p + 1]; ++i) {
      REQUIRE(part[order[i]] == p);
      if (i > partStart[p]) REQUIRE(rank[order[i - 1]] < rank[order[i]]);
    }
}

}  // namespace
}  // namespace superdex::internal
