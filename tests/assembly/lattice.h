// A lattice of DoF blocks coupled to their lattice neighbours: the block
// graph of a structured mesh's nodes, for the partition tests.
#pragma once

#include <superdex/assembly/ordering.h>

namespace superdex::test {

/// nx × ny × nz blocks, block b of size(b) DoFs, each coupled to its six
/// lattice neighbours by a two-block contributor
inline internal::BlockGraph Lattice(int nx, int ny, int nz, int (*size)(int)) {
  int const n = nx * ny * nz;
  DynamicArray<int> blockSizes(n), dofToBlock;
  for (int b = 0; b < n; ++b) {
    blockSizes[b] = size(b);
    dofToBlock.insert(dofToBlock.end(), blockSizes[b], b);
  }
  DynamicArray<int> blockStart(n + 1, 0);
  for (int b = 0; b < n; ++b) blockStart[b + 1] = blockStart[b] + blockSizes[b];
  auto id = [&](int x, int y, int z) { return x + nx * (y + ny * z); };
  DynamicArray<DynamicArray<int>> contributors;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        for (int axis = 0; axis < 3; ++axis) {
          int const x2 = x + (axis == 0), y2 = y + (axis == 1), z2 = z + (axis == 2);
          if (x2 >= nx || y2 >= ny || z2 >= nz) continue;
          DynamicArray<int> dofs;
          for (int b : {id(x, y, z), id(x2, y2, z2)})
            for (int d = blockStart[b]; d < blockStart[b + 1]; ++d) dofs.push_back(d);
          contributors.push_back(dofs);
        }
  return internal::BuildBlockGraph(blockSizes, dofToBlock, contributors);
}

}  // namespace superdex::test
