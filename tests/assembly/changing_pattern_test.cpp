// HessianAssembler's second family: contributors whose DoF lists change
// between stages. Their block pairs are reserved in the pattern (kept while
// used, with hysteresis); a stage that needs an entry the pattern lacks
// grows it in the kept fill-reducing order; the assembled values are those
// of a fresh analysis of the same contributors, for any thread count.
#include "test_support.h"
#include "white_box.h"

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/parallel.h>

using namespace superdex;
using namespace superdex::test;

namespace {
// a chain of `numBlocks` 3-DoF blocks: each block's own contributor, then one
// per neighbouring pair
constexpr int kBlocks = 12;
DynamicArray<int> Block(int b) { return {3 * b, 3 * b + 1, 3 * b + 2}; }
DynamicArray<int> Pair(int a, int b) {
  DynamicArray<int> dofs = Block(a);
  DynamicArray<int> const other = Block(b);
  dofs.insert(dofs.end(), other.begin(), other.end());
  return dofs;
}
DynamicArray<DynamicArray<int>> Chain() {
  DynamicArray<DynamicArray<int>> contributors;
  for (int b = 0; b < kBlocks; ++b) contributors.push_back(Block(b));
  for (int b = 0; b + 1 < kBlocks; ++b) contributors.push_back(Pair(b, b + 1));
  return contributors;
}
DynamicArray<int> BlockSizes() { return DynamicArray<int>(kBlocks, 3); }

// a symmetric block and a gradient that depend on the contributor's index
// and the stage, so that a value in the wrong slot shows
MatrixX BlockValues(int n, int seed) {
  MatrixX h(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b) h(a, b) = h(b, a) = 1.0 / (1 + a + 2 * b + 3 * seed) + (a == b ? 10.0 : 0.0);
  return h;
}
VectorX GradientValues(int n, int seed) {
  VectorX g(n);
  for (int a = 0; a < n; ++a) g[a] = std::sin(1.0 + a + 0.37 * seed);
  return g;
}

struct Assembled {
  MatrixX hessian;
  VectorX gradient;
};

// assembles the static contributors, then `dynamicLists` through the second
// family (or, with `asStatic`, the same lists as static contributors after
// the chain's: what a fresh analysis of all of them adds, in the same order);
// with `skipEven`, the even-numbered ones add nothing in this assembly
Assembled Assemble(internal::HessianAssembler& assembler, int numStatic, int numDynamic, int stage, bool asStatic,
                   bool skipEven = false) {
  int const n = 3 * kBlocks;
  DynamicArray<real> gradient(n, 0);
  assembler.BeginAssembly(gradient);
  for (int c = 0; c < numStatic; ++c) {
    int const size = c < kBlocks ? 3 : 6;
    assembler.AddGradient(c, GradientValues(size, c));
    assembler.AddBlock(c, BlockValues(size, c));
  }
  for (int k = 0; k < numDynamic; ++k) {
    if (skipEven && k % 2 == 0) continue;
    int const seed = 1000 + 7 * k + stage;
    if (asStatic) {
      assembler.AddGradient(numStatic + k, GradientValues(6, seed));
      assembler.AddBlock(numStatic + k, BlockValues(6, seed));
    } else {
      assembler.AddDynamicGradient(k, GradientValues(6, seed));
      assembler.AddDynamicBlock(k, BlockValues(6, seed));
    }
  }
  assembler.FinishAssembly();
  return {DenseNaturalHessian(assembler), Eigen::Map<VectorX const>(gradient.data(), n)};
}

// a fresh analysis of the chain and `pairs` together, assembled at `stage`
Assembled Fresh(DynamicArray<DynamicArray<int>> const& pairs, int stage, internal::ParallelExecutor const* executor,
                bool skipEven = false) {
  DynamicArray<DynamicArray<int>> all = Chain();
  int const numStatic = static_cast<int>(all.size());
  all.insert(all.end(), pairs.begin(), pairs.end());
  internal::HessianAssembler fresh;
  fresh.SetExecutor(executor);
  Error error;
  REQUIRE(fresh.Analyze(3 * kBlocks, BlockSizes(), all, OrderingMethod::Metis, error));
  return Assemble(fresh, numStatic, static_cast<int>(pairs.size()), stage, true, skipEven);
}

// the natural-order permutation of the assembler (ordered position per DoF)
DynamicArray<real> Ordering(internal::HessianAssembler const& assembler) {
  int const n = 3 * kBlocks;
  DynamicArray<real> natural(n), ordered(n);
  for (int i = 0; i < n; ++i) natural[i] = i;
  assembler.PermuteToOrdered(natural, ordered);
  return ordered;
}

// the chain analysed, its contributors on `threads` threads
struct ChainAssembler {
  internal::ParallelExecutor executor;
  internal::HessianAssembler assembler;
  int numStatic = 0;
  explicit ChainAssembler(int threads) {
    executor.SetNumThreads(threads);
    assembler.SetExecutor(&executor);
    DynamicArray<DynamicArray<int>> const chain = Chain();
    numStatic = static_cast<int>(chain.size());
    Error error;
    REQUIRE(assembler.Analyze(3 * kBlocks, BlockSizes(), chain, OrderingMethod::Metis, error));
  }
};
}  // namespace

TEST_CASE("contributors whose pairs come and go: the pattern grows in the kept order, fits, and assembles as a "
          "fresh analysis",
          "[assembly][pattern]") {
  int const threads = GENERATE(1, 2);
  CAPTURE(threads);
  ChainAssembler chain(threads);
  internal::HessianAssembler& assembler = chain.assembler;
  internal::ParallelExecutor const& executor = chain.executor;
  int const numStatic = chain.numStatic;
  Error error;
  REQUIRE(assembler.GetNumPatternBuilds() == 1);
  DynamicArray<real> const order = Ordering(assembler);
  std::int64_t const chainEntries = assembler.CountOwnedColumnEntries();

  // the stages' pairs: (0, 5) and (2, 9) come, (0, 5) goes, (0, 5) comes back
  // with (4, 11), then a pair of neighbours the chain already couples
  DynamicArray<DynamicArray<DynamicArray<int>>> const stages{
      {Pair(0, 5), Pair(2, 9)}, {Pair(2, 9)}, {Pair(0, 5), Pair(4, 11)}, {Pair(3, 4)}, {}};
  // growth where a pair is new to the pattern, a fit where every entry is there
  DynamicArray<bool> const grows{true, false, true, false, false};
  std::uint64_t version = assembler.GetMatrix().patternVersion;
  for (std::size_t s = 0; s < stages.size(); ++s) {
    CAPTURE(s);
    internal::HessianAssembler::DynamicUpdate update;
    REQUIRE(assembler.SetDynamicContributors(stages[s], update, error));
    CHECK(update.grew == grows[s]);
    CHECK_FALSE(update.reordered);
    CHECK(assembler.GetNumDynamicContributors() == static_cast<int>(stages[s].size()));
    // a growth is a new pattern version (the linear solver analyses again),
    // in the fill-reducing order the chain was given
    CHECK((assembler.GetMatrix().patternVersion != version) == grows[s]);
    version = assembler.GetMatrix().patternVersion;
    CHECK(Ordering(assembler) == order);
    // the values: the same sums as a fresh analysis of all contributors,
    // bit for bit; the pairs that went keep their entries, at zero
    Assembled const got = Assemble(assembler, numStatic, static_cast<int>(stages[s].size()), int(s), false);
    Assembled const fresh = Fresh(stages[s], int(s), &executor);
    REQUIRE(got.hessian.cwiseAbs().maxCoeff() > 0);
    CHECK(got.hessian == fresh.hessian);
    CHECK(got.gradient == fresh.gradient);
  }
  CHECK(assembler.GetNumPatternBuilds() == 1);
  CHECK(assembler.GetNumPatternGrowths() == 2);
  // the reserve: each pair's block pairs (a, a), (a, b), (b, b), once each:
  // three pairs' 9, and (3, 3), (3, 4) ((4, 4) is (4, 11)'s too)
  CHECK(assembler.GetNumReservedPairs() == 3 * 3 + 2);
  CHECK(assembler.CountOwnedColumnEntries() > chainEntries);
}

TEST_CASE("reserved pairs leave at a rebuild only after kReserveStages stages unused", "[assembly][pattern]") {
  internal::HessianAssembler assembler;
  Error error;
  REQUIRE(assembler.Analyze(3 * kBlocks, BlockSizes(), Chain(), OrderingMethod::Metis, error));
  internal::HessianAssembler::DynamicUpdate update;
  REQUIRE(assembler.SetDynamicContributors({Pair(0, 7)}, update, error));
  REQUIRE(update.grew);
  std::size_t const reserved = assembler.GetNumReservedPairs();
  // unused, (0, 7) stays reserved (no rebuild only to shrink the pattern),
  // and a new pair's growth within the hysteresis keeps it
  for (int s = 0; s < 5; ++s) REQUIRE(assembler.SetDynamicContributors(DynamicArray<DynamicArray<int>>{}, update, error));
  REQUIRE(assembler.SetDynamicContributors({Pair(1, 8)}, update, error));
  REQUIRE(update.grew);
  CHECK(assembler.GetNumReservedPairs() == reserved + 3);  // (1, 1), (1, 8), (8, 8)
  // after kReserveStages stages unused, the next growth drops it
  for (std::int64_t s = 0; s < internal::HessianAssembler::kReserveStages; ++s)
    REQUIRE(assembler.SetDynamicContributors({Pair(1, 8)}, update, error));
  REQUIRE(assembler.SetDynamicContributors({Pair(1, 8), Pair(2, 10)}, update, error));
  REQUIRE(update.grew);
  // (0, 0), (0, 7), (7, 7) left; (2, 2), (2, 10), (10, 10) came
  CHECK(assembler.GetNumReservedPairs() == reserved + 3 - 3 + 3);
}

TEST_CASE("many new pairs order the pattern again; RebuildWhenChanged orders it for exactly the stage's pairs",
          "[assembly][pattern]") {
  Error error;
  internal::HessianAssembler::DynamicUpdate update;
  // every block with every block three apart: more than kReorderFraction of
  // the chain's block graph
  DynamicArray<DynamicArray<int>> many;
  for (int b = 0; b + 3 < kBlocks; ++b) many.push_back(Pair(b, b + 3));
  {
    internal::HessianAssembler assembler;
    REQUIRE(assembler.Analyze(3 * kBlocks, BlockSizes(), Chain(), OrderingMethod::Metis, error));
    REQUIRE(assembler.SetDynamicContributors(many, update, error));
    CHECK(update.grew);
    CHECK(update.reordered);
    CHECK(assembler.GetNumPatternBuilds() == 2);
    CHECK(assembler.GetNumPatternGrowths() == 0);
    Assembled const got = Assemble(assembler, static_cast<int>(Chain().size()), static_cast<int>(many.size()), 0, false);
    CHECK(got.hessian == Fresh(many, 0, nullptr).hessian);
  }
  {
    internal::HessianAssembler assembler;
    REQUIRE(assembler.Analyze(3 * kBlocks, BlockSizes(), Chain(), OrderingMethod::Metis, error));
    DynamicArray<DynamicArray<int>> const one{Pair(0, 5)};
    REQUIRE(assembler.SetDynamicContributors(one, update, error, /*rebuildWhenChanged=*/true));
    CHECK(update.reordered);
    // the same pairs again: nothing rebuilt
    REQUIRE(assembler.SetDynamicContributors(one, update, error, true));
    CHECK_FALSE(update.grew);
    // a pair that goes leaves the pattern at once
    std::int64_t const withPair = assembler.CountOwnedColumnEntries();
    REQUIRE(assembler.SetDynamicContributors(DynamicArray<DynamicArray<int>>{}, update, error, true));
    CHECK(update.reordered);
    CHECK(assembler.CountOwnedColumnEntries() < withPair);
    CHECK(assembler.GetNumPatternBuilds() == 3);
    CHECK(assembler.GetNumReservedPairs() == 0);
  }
}

TEST_CASE("a changing contributor with a bad DoF list is refused and changes nothing", "[assembly][pattern]") {
  internal::HessianAssembler assembler;
  Error error;
  REQUIRE(assembler.Analyze(3 * kBlocks, BlockSizes(), Chain(), OrderingMethod::Metis, error));
  internal::HessianAssembler::DynamicUpdate update;
  REQUIRE(assembler.SetDynamicContributors({Pair(0, 5)}, update, error));
  std::uint64_t const version = assembler.GetMatrix().patternVersion;
  for (DynamicArray<int> const& bad : {DynamicArray<int>{0, 1, 1}, DynamicArray<int>{-1, 2}, DynamicArray<int>{36}}) {
    Error badError;
    CHECK_FALSE(assembler.SetDynamicContributors({bad}, update, badError));
    CHECK(badError.GetCode() == ErrorCode::InvalidState);
    CHECK(assembler.GetMatrix().patternVersion == version);
    CHECK(assembler.GetNumDynamicContributors() == 1);
  }
}

TEST_CASE("a contributor of the second family that adds nothing in an assembly contributes nothing to it",
          "[assembly][pattern]") {
  // contact candidates beyond reach skip their add: what they added in the
  // assembly before must not stay in the sums (their stages are not zeroed:
  // only those stamped in this assembly are summed)
  ChainAssembler chain(GENERATE(1, 2));
  auto& [executor, assembler, numStatic] = chain;
  Error error;
  DynamicArray<DynamicArray<int>> const pairs{Pair(0, 5), Pair(2, 9), Pair(4, 11), Pair(1, 7)};
  internal::HessianAssembler::DynamicUpdate update;
  REQUIRE(assembler.SetDynamicContributors(pairs, update, error));
  int const numDynamic = static_cast<int>(pairs.size());
  Assembled const all = Assemble(assembler, numStatic, numDynamic, 0, false);
  REQUIRE((all.hessian - Fresh(pairs, 0, &executor).hessian).norm() == 0);
  // every other one skips the next assembly
  Assembled const some = Assemble(assembler, numStatic, numDynamic, 1, false, true);
  Assembled const fresh = Fresh(pairs, 1, &executor, true);
  REQUIRE((some.hessian - fresh.hessian).norm() == 0);
  REQUIRE((some.gradient - fresh.gradient).norm() == 0);
  REQUIRE((some.hessian - all.hessian).norm() > 0);
  // and a new stage: nothing of the last one's
  REQUIRE(assembler.SetDynamicContributors(pairs, update, error));
  Assembled const again = Assemble(assembler, numStatic, numDynamic, 1, false, true);
  REQUIRE((again.hessian - fresh.hessian).norm() == 0);
  REQUIRE((again.gradient - fresh.gradient).norm() == 0);
}
