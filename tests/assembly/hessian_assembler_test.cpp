// HessianAssembler: the Levenberg shift Newton applies to a projected
// Hessian that failed its factorization by round-off, staged (threaded)
// assembly, and the part of the pattern one MPI rank stores.
#include "test_support.h"

#include <cmath>
#include <limits>

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

TEST_CASE("on one part of several, the assembler stores only its rows' and columns' entries, as one part assembles them",
          "[assembly][partition]") {
  // a 6×5×4 lattice of 3-DoF blocks: one contributor per block and one per
  // lattice edge, with blocks that differ from contributor to contributor
  int const nx = 6, ny = 5, nz = 4, numBlocks = nx * ny * nz, n = 3 * numBlocks;
  DynamicArray<int> const blockSizes(numBlocks, 3);
  DynamicArray<DynamicArray<int>> contributors;
  auto dofsOf = [](std::initializer_list<int> blocks) {
    DynamicArray<int> dofs;
    for (int b : blocks)
      for (int c = 0; c < 3; ++c) dofs.push_back(3 * b + c);
    return dofs;
  };
  auto id = [&](int x, int y, int z) { return x + nx * (y + ny * z); };
  for (int b = 0; b < numBlocks; ++b) contributors.push_back(dofsOf({b}));
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (x + 1 < nx) contributors.push_back(dofsOf({id(x, y, z), id(x + 1, y, z)}));
        if (y + 1 < ny) contributors.push_back(dofsOf({id(x, y, z), id(x, y + 1, z)}));
        if (z + 1 < nz) contributors.push_back(dofsOf({id(x, y, z), id(x, y, z + 1)}));
      }
  int const numContributors = static_cast<int>(contributors.size());
  internal::ParallelExecutor executor;
  executor.SetNumThreads(2);
  // assembles every contributor the assembler evaluates; returns H (natural
  // order, dense) from the stored entries and the gradient
  auto assemble = [&](internal::HessianAssembler& assembler, MatrixX& dense, DynamicArray<real>& gradient,
                      DynamicArray<int>& orderedOf) {
    gradient.assign(n, 0);
    assembler.BeginAssembly(gradient);
    for (int c = 0; c < numContributors; ++c) {
      if (!assembler.Evaluates(c)) continue;
      int const m = static_cast<int>(contributors[c].size());
      MatrixX block(m, m);
      for (int a = 0; a < m; ++a)
        for (int b = 0; b < m; ++b) block(a, b) = std::sin(1.0 + c + 0.37 * (a + b)) + (a == b ? 4.0 : 0.0);
      assembler.AddBlock(c, block);
      assembler.AddGradient(c, VectorX::Constant(m, 0.5 + std::cos(real(c))));
    }
    assembler.FinishAssembly();
    // the natural DoF at each ordered position (ordered[perm[i]] = i), and back
    VectorX natural(n), ordered(n);
    for (int i = 0; i < n; ++i) natural[i] = i;
    assembler.PermuteToOrdered(Span<real const>(natural.data(), n), Span<real>(ordered.data(), n));
    DynamicArray<int> naturalOf(n);
    orderedOf.assign(n, 0);
    for (int p = 0; p < n; ++p) {
      naturalOf[p] = static_cast<int>(ordered[p]);
      orderedOf[naturalOf[p]] = p;
    }
    SparseSymmetricMatrix const& h = assembler.GetMatrix();
    dense = MatrixX::Constant(n, n, std::numeric_limits<real>::quiet_NaN());  // NaN: not stored
    for (int j = 0; j < n; ++j)
      for (int k = h.colStart[j]; k < h.colStart[j + 1]; ++k) {
        int const i = h.rowIndex[k];
        dense(naturalOf[i], naturalOf[j]) = dense(naturalOf[j], naturalOf[i]) = h.values[k];
      }
  };

  Error error;
  internal::HessianAssembler whole;
  REQUIRE(whole.Analyze(n, blockSizes, contributors, OrderingMethod::Metis, error));
  MatrixX expected;
  DynamicArray<real> expectedGradient;
  DynamicArray<int> wholeOrder;
  assemble(whole, expected, expectedGradient, wholeOrder);
  std::int64_t const wholeEntries = whole.GetMatrix().NumNonzeros();

  int const numParts = GENERATE(2, 3);
  bool const staged = GENERATE(false, true);
  CAPTURE(numParts, staged);
  std::int64_t ownedColumnEntries = 0;
  for (int part = 0; part < numParts; ++part) {
    CAPTURE(part);
    internal::HessianAssembler assembler;
    REQUIRE(assembler.Analyze(n, blockSizes, contributors, OrderingMethod::Metis, error, numParts, part));
    if (staged) assembler.SetExecutor(&executor);
    REQUIRE(assembler.IsStaged() == staged);
    MatrixX actual;
    DynamicArray<real> gradient;
    DynamicArray<int> order;
    assemble(assembler, actual, gradient, order);
    int const rowBegin = assembler.GetOwnedRowBegin(), rowEnd = assembler.GetOwnedRowEnd();
    auto const owned = [&](int natural) { return order[natural] >= rowBegin && order[natural] < rowEnd; };
    int mismatches = 0, missing = 0, extra = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        bool const stored = !std::isnan(actual(i, j));
        bool const mine = owned(i) || owned(j);
        bool const inWhole = !std::isnan(expected(i, j));
        if (mine && inWhole && !stored) ++missing;
        if (!mine && stored && i != j) ++extra;  // only the diagonals of other rows are kept
        if (!mine && stored && i == j && actual(i, j) != 0) ++mismatches;
        // the same contributions added in the same order: the same bits
        if (mine && stored && actual(i, j) != expected(i, j)) ++mismatches;
      }
    CHECK(missing == 0);
    CHECK(extra == 0);
    CHECK(mismatches == 0);
    for (int i = 0; i < n; ++i)
      if (owned(i)) CHECK(gradient[i] == expectedGradient[i]);
    // its part of the memory: fewer entries than the whole pattern
    CHECK(assembler.GetMatrix().NumNonzeros() < wholeEntries);
    ownedColumnEntries += assembler.CountOwnedColumnEntries();
  }
  // each entry of the whole pattern is in the owned columns of one part
  CHECK(ownedColumnEntries == wholeEntries);
}
