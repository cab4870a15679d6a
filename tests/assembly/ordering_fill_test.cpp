// The METIS nested-dissection ordering of the block graph gives less fill
// than the natural ordering on a 3-D lattice of bodies: the block graph of
// n×n×n rigid bodies (6 DoFs each) joined to their axis neighbours is ordered
// by OrderBlocks, expanded to the scalar pattern in that order, and CHOLMOD
// analyses it in exactly that order (CholmodOrdering::Given: no AMD
// fallback that could hide a broken METIS order).
#include "test_support.h"

#include <superdex/assembly/ordering.h>
#include <superdex/linsolve/cholmod_solver.h>

#include <algorithm>
#include <iostream>

using namespace superdex;
using namespace superdex::internal;

namespace {
constexpr int kBlock = 6;  // a rigid body's DoFs

// the lattice's block graph: block (i, j, k) coupled with its neighbours
BlockGraph LatticeGraph(int n) {
  auto index = [n](int i, int j, int k) { return (i * n + j) * n + k; };
  DynamicArray<int> blockSizes(n * n * n, kBlock), dofToBlock(kBlock * n * n * n);
  for (int d = 0; d < int(dofToBlock.size()); ++d) dofToBlock[d] = d / kBlock;
  DynamicArray<DynamicArray<int>> pairs;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        for (int axis = 0; axis < 3; ++axis) {
          int const i2 = i + (axis == 0), j2 = j + (axis == 1), k2 = k + (axis == 2);
          if (i2 >= n || j2 >= n || k2 >= n) continue;
          DynamicArray<int> dofs;
          for (int block : {index(i, j, k), index(i2, j2, k2)})
            for (int d = 0; d < kBlock; ++d) dofs.push_back(kBlock * block + d);
          pairs.push_back(dofs);
        }
  return BuildBlockGraph(blockSizes, dofToBlock, pairs);
}

// nnz(L) of the lattice's matrix in the given block order (upper-triangle
// CSC of dense blocks on the diagonal and on every coupled pair)
double FactorNonzeros(BlockGraph const& graph, OrderingMethod method) {
  Error error;
  DynamicArray<int> order;
  REQUIRE(OrderBlocks(graph, method, order, error));
  int const blocks = int(order.size());
  DynamicArray<int> position(blocks);
  for (int p = 0; p < blocks; ++p) position[order[p]] = p;
  SparseSymmetricMatrix a;
  a.size = kBlock * blocks;
  a.blockSizes.assign(blocks, kBlock);
  a.patternVersion = 1;
  a.colStart.push_back(0);
  for (int p = 0; p < blocks; ++p) {
    DynamicArray<int> rows{p};  // block positions coupled with p, up to p
    for (int e = graph.adjacencyStart[order[p]]; e < graph.adjacencyStart[order[p] + 1]; ++e)
      if (position[graph.adjacency[e]] < p) rows.push_back(position[graph.adjacency[e]]);
    std::sort(rows.begin(), rows.end());
    for (int c = 0; c < kBlock; ++c) {
      for (int q : rows)
        for (int r = 0; r < kBlock && kBlock * q + r <= kBlock * p + c; ++r) {
          a.rowIndex.push_back(kBlock * q + r);
          a.values.push_back(kBlock * q + r == kBlock * p + c ? 100 : -1);
        }
      a.colStart.push_back(int(a.rowIndex.size()));
    }
  }
  CholmodSolver solver(CholmodOrdering::Given);
  REQUIRE(solver.Analyze(a).status == LinearSolveStatus::Ok);
  return solver.GetFactorNonzeros();
}
}  // namespace

TEST_CASE("METIS ordering beats the natural ordering on a 1000-body lattice", "[assembly][ordering]") {
  BlockGraph const graph = LatticeGraph(10);
  double const metis = FactorNonzeros(graph, OrderingMethod::Metis);
  double const natural = FactorNonzeros(graph, OrderingMethod::Natural);
  std::cout << "lattice 10^3 bodies, CHOLMOD on the given order: nnz(L) METIS = " << metis
            << ", natural = " << natural << " (ratio " << natural / metis << ")\n";
  REQUIRE(metis > 0);
  // nested dissection of a 3-D lattice against its lexicographic order (the
  // scene with this lattice measured 2.90x for METIS's order, 2.94x for
  // AMD's); a METIS order no better than 2x is a broken ordering, not a
  // slightly worse one
  REQUIRE(natural >= 2 * metis);
}
