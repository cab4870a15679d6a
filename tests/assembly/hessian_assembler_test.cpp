// HessianAssembler::ShiftDiagonal: the Levenberg shift Newton applies to a
// projected Hessian that failed its factorization by round-off.
#include "test_support.h"

#include <superdex/assembly/hessian_assembler.h>

using namespace superdex;
using namespace superdex::test;

TEST_CASE("a diagonal shift changes only the diagonal, by the given fraction of each entry",
          "[assembly][newton]") {
  // two 3-DoF blocks coupled by one contributor, in METIS order
  internal::HessianAssembler assembler;
  DynamicArray<int> const blockSizes{3, 3};
  DynamicArray<DynamicArray<int>> const contributors{{0, 1, 2}, {0, 1, 2, 3, 4, 5}};
  Error error;
  REQUIRE(assembler.Analyze(6, blockSizes, contributors, OrderingMethod::Metis, error));
  assembler.ZeroValues();
  MatrixX a = MatrixX::Zero(3, 3);
  a << 4, 1, 0, 1, -5, 2, 0, 2, 6;
  MatrixX b = MatrixX::Random(6, 6);
  b = (b + b.transpose()).eval();
  assembler.AddBlock(0, a);
  assembler.AddBlock(1, b);
  SparseSymmetricMatrix const before = assembler.GetMatrix();
  assembler.ShiftDiagonal(1e-3);
  SparseSymmetricMatrix const& after = assembler.GetMatrix();
  REQUIRE(after.values.size() == before.values.size());
  int diagonals = 0;
  for (int j = 0; j < after.size; ++j)
    for (int k = after.colStart[j]; k < after.colStart[j + 1]; ++k) {
      CAPTURE(j, k);
      if (after.rowIndex[k] == j) {
        ++diagonals;
        // |Hⱼⱼ| scales the shift: a negative entry moves up too
        CHECK(after.values[k] == before.values[k] + 1e-3 * std::abs(before.values[k]));
      } else {
        CHECK(after.values[k] == before.values[k]);
      }
    }
  CHECK(diagonals == 6);
}
