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

TEST_CASE("staged assembly: a contributor that adds nothing contributes zeros, a second add sums",
          "[assembly][parallel]") {
  // the stages are not zeroed between assemblies (each contributor's first
  // write assigns): what a contributor wrote in an earlier assembly must not
  // come back when it adds nothing, and a second AddBlock in one assembly adds
  DynamicArray<int> const blockSizes{3, 3, 3};
  DynamicArray<DynamicArray<int>> const contributors{{0, 1, 2}, {3, 4, 5, 0, 1, 2}, {6, 7, 8, 3, 4, 5}};
  internal::ParallelExecutor executor;
  executor.SetNumThreads(2);
  auto assemble = [&](internal::HessianAssembler& assembler, bool second, bool twice,
                      DynamicArray<real>& gradient) {
    gradient.assign(9, 0);
    assembler.BeginAssembly(gradient);
    for (int c = 0; c < 3; ++c) {
      if (c == 1 && !second) continue;
      int const n = static_cast<int>(contributors[c].size());
      MatrixX block = MatrixX::Constant(n, n, 1.0 + c);
      VectorX g = VectorX::Constant(n, 10.0 + c);
      assembler.AddBlock(c, block);
      assembler.AddGradient(c, g);
      if (c == 2 && twice) {
        assembler.AddBlock(c, block);
        assembler.AddGradient(c, g);
      }
    }
    assembler.FinishAssembly();
    return assembler.GetMatrix().values;
  };
  Error error;
  internal::HessianAssembler serial, staged;
  REQUIRE(serial.Analyze(9, blockSizes, contributors, OrderingMethod::Metis, error));
  REQUIRE(staged.Analyze(9, blockSizes, contributors, OrderingMethod::Metis, error));
  staged.SetExecutor(&executor);
  REQUIRE(staged.IsStaged());
  DynamicArray<real> gradientSerial, gradientStaged;
  for (auto [second, twice] : {std::pair{true, false}, {false, false}, {true, true}, {false, true}}) {
    CAPTURE(second, twice);
    DynamicArray<real> const expected = assemble(serial, second, twice, gradientSerial);
    DynamicArray<real> const values = assemble(staged, second, twice, gradientStaged);
    CHECK(values == expected);
    CHECK(gradientStaged == gradientSerial);
  }
  // contributor 1 left out last: DoF 0's gradient is contributor 0's 10
  // alone, without contributor 1's 11 of the assemblies before
  CHECK(gradientStaged[0] == 10);
}
