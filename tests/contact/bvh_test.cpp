// The broad phase (contact/bvh.h): every query against the brute-force
// O(N²) answer, compared as whole lists (same pairs, same order), on box sets
// of several sizes and shapes, before and after a refit; the self query's
// skip predicate; the two-set query, serial and on several threads; the
// swept and inflated boxes; and that repeated queries reuse their output
// vectors.
//
// The brute force judges overlap by its own rule (the intervals' largest
// lower end at most their smallest upper end, per axis), not by the
// header's Overlaps, so a wrong overlap rule in the header fails here too.
#include "test_support.h"

#include <superdex/contact/bvh.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace superdex;
using namespace superdex::test;
using namespace superdex::contact;

namespace {

bool BruteOverlap(Aabb const& a, Aabb const& b) {
  for (int axis = 0; axis < 3; ++axis) {
    if (std::max(a.lower[axis], b.lower[axis]) > std::min(a.upper[axis], b.upper[axis]))
      return false;
  }
  return true;
}

DynamicArray<IndexPair> BruteSelfPairs(DynamicArray<Aabb> const& boxes) {
  DynamicArray<IndexPair> pairs;
  int const n = static_cast<int>(boxes.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      if (BruteOverlap(boxes[i], boxes[j])) pairs.push_back({i, j});
  return pairs;
}

DynamicArray<IndexPair> BrutePairs(DynamicArray<Aabb> const& a, DynamicArray<Aabb> const& b) {
  DynamicArray<IndexPair> pairs;
  for (int i = 0; i < static_cast<int>(a.size()); ++i)
    for (int j = 0; j < static_cast<int>(b.size()); ++j)
      if (BruteOverlap(a[i], b[j])) pairs.push_back({i, j});
  return pairs;
}

DynamicArray<int> BruteOverlaps(DynamicArray<Aabb> const& boxes, Aabb const& query) {
  DynamicArray<int> indices;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i)
    if (BruteOverlap(boxes[i], query)) indices.push_back(i);
  return indices;
}

// Boxes with centres uniform in [0, extent]³ and half-sizes uniform in
// [0, halfSize] per axis.
DynamicArray<Aabb> RandomBoxes(int count, real extent, real halfSize, std::mt19937& rng) {
  std::uniform_real_distribution<real> position(0, extent), size(0, halfSize);
  DynamicArray<Aabb> boxes(count);
  for (Aabb& box : boxes) {
    Real3 const center(position(rng), position(rng), position(rng));
    Real3 const half(size(rng), size(rng), size(rng));
    box = {center - half, center + half};
  }
  return boxes;
}

// Flat boxes on an integer grid: corners in {0, …, 4}, one random axis of
// zero extent, so many boxes touch exactly on faces, edges and corners.
DynamicArray<Aabb> FlatGridBoxes(int count, std::mt19937& rng) {
  std::uniform_int_distribution<int> corner(0, 4), axis(0, 2);
  DynamicArray<Aabb> boxes(count);
  for (Aabb& box : boxes) {
    for (int a = 0; a < 3; ++a) {
      int const p = corner(rng), q = corner(rng);
      box.lower[a] = std::min(p, q);
      box.upper[a] = std::max(p, q);
    }
    int const flat = axis(rng);
    box.upper[flat] = box.lower[flat];
  }
  return boxes;
}

Bvh MakeBvh(DynamicArray<Aabb> const& boxes) {
  Bvh bvh;
  Error error;
  INFO(error.ToString());
  REQUIRE(bvh.Build(boxes, error));
  REQUIRE(bvh.GetNumBoxes() == static_cast<int>(boxes.size()));
  return bvh;
}

// Every query of the tree built (or refitted) over `boxes` against brute
// force: the self pairs, 50 random query boxes, and the two-set query with
// `others`.
void RequireQueriesMatchBruteForce(Bvh const& bvh, DynamicArray<Aabb> const& boxes,
                                   DynamicArray<Aabb> const& others, std::mt19937& rng) {
  DynamicArray<IndexPair> pairs;
  bvh.FindSelfPairs(pairs);
  REQUIRE(pairs == BruteSelfPairs(boxes));

  // query boxes around the set's own extent, some large
  Aabb bounds{Real3::Zero(), Real3::Zero()};
  for (Aabb const& box : boxes) {
    bounds.lower = bounds.lower.cwiseMin(box.lower);
    bounds.upper = bounds.upper.cwiseMax(box.upper);
  }
  real const extent = std::max((bounds.upper - bounds.lower).maxCoeff(), real(1));
  DynamicArray<Aabb> const queries = RandomBoxes(50, extent, extent / 8, rng);
  DynamicArray<int> indices;
  for (Aabb const& query : queries) {
    bvh.FindOverlaps(query, indices);
    REQUIRE(indices == BruteOverlaps(boxes, query));
  }

  bvh.FindPairsWith(others, pairs);
  REQUIRE(pairs == BrutePairs(boxes, others));
  // the two-set query on several threads, its queries in chunks: the same
  // list for any thread count (and the chunks' storage reused)
  DynamicArray<DynamicArray<IndexPair>> chunks;
  for (int threads : {1, 3, 4}) {
    internal::ParallelExecutor executor;
    executor.SetNumThreads(threads);
    DynamicArray<IndexPair> threaded;
    bvh.FindPairsWith(others, threaded, executor, chunks);
    REQUIRE(threaded == pairs);
  }
}

}  // namespace

TEST_CASE("Closed boxes overlap when they touch and not when apart", "[contact][bvh]") {
  Aabb const unit{{0, 0, 0}, {1, 1, 1}};
  REQUIRE(Overlaps(unit, unit));
  REQUIRE(Overlaps(unit, {{1, 0.5, 0.5}, {2, 2, 2}}));   // a shared face
  REQUIRE(Overlaps(unit, {{1, 1, 1}, {1, 1, 1}}));       // a corner point
  REQUIRE(Overlaps(unit, {{0.2, 0.2, 0.5}, {0.4, 0.4, 0.5}}));  // flat inside
  REQUIRE_FALSE(Overlaps(unit, {{1 + 1e-12, 0, 0}, {2, 1, 1}}));
  REQUIRE_FALSE(Overlaps(unit, {{0, -1, 0}, {1, -1e-12, 1}}));
  REQUIRE_FALSE(Overlaps(unit, {{0, 0, 2}, {1, 1, 3}}));
  // symmetric
  REQUIRE_FALSE(Overlaps({{0, 0, 2}, {1, 1, 3}}, unit));
  REQUIRE(Overlaps({{1, 0.5, 0.5}, {2, 2, 2}}, unit));
}

TEST_CASE("Self, single-box and two-set queries equal brute force on random box sets",
          "[contact][bvh]") {
  int const count = GENERATE(0, 1, 2, 3, 5, 37, 1000);
  CAPTURE(count);
  std::mt19937 rng(100 + count);
  // a density with a few overlaps per box: extent 10, half-sizes up to 0.6
  // for 1000 boxes; small sets packed tighter so that they overlap at all
  real const extent = count >= 1000 ? 10 : 1;
  DynamicArray<Aabb> const boxes = RandomBoxes(count, extent, 0.6, rng);
  // (1000 boxes: more queries than one chunk of the threaded query)
  DynamicArray<Aabb> const others = RandomBoxes(count / 2 + 3, extent, 0.6, rng);
  static_assert(Bvh::kQueryChunk < 1000 / 2);
  Bvh const bvh = MakeBvh(boxes);
  RequireQueriesMatchBruteForce(bvh, boxes, others, rng);
  if (count >= 5) {
    // the comparisons had pairs to compare
    REQUIRE(BruteSelfPairs(boxes).size() >= 1);
    REQUIRE(BrutePairs(boxes, others).size() >= 1);
  }
  if (count >= 1000) REQUIRE(BruteSelfPairs(boxes).size() >= 500);
}

TEST_CASE("Queries equal brute force on flat boxes that touch exactly", "[contact][bvh]") {
  int const count = GENERATE(2, 7, 300);
  CAPTURE(count);
  std::mt19937 rng(7 + count);
  DynamicArray<Aabb> const boxes = FlatGridBoxes(count, rng);
  DynamicArray<Aabb> const others = FlatGridBoxes(count / 2 + 1, rng);
  Bvh const bvh = MakeBvh(boxes);
  RequireQueriesMatchBruteForce(bvh, boxes, others, rng);
  // points: boxes of zero size on all axes, many coincident
  DynamicArray<Aabb> points = FlatGridBoxes(count, rng);
  for (Aabb& box : points) box.upper = box.lower;
  RequireQueriesMatchBruteForce(MakeBvh(points), points, others, rng);
  if (count == 300) {
    // touching is the common case here: most pairs found touch only
    int touchingOnly = 0;
    for (IndexPair const& pair : BruteSelfPairs(boxes)) {
      Aabb const& a = boxes[pair.i];
      Aabb const& b = boxes[pair.j];
      bool const strict =
          ((a.lower.array() < b.upper.array()) && (b.lower.array() < a.upper.array())).all();
      if (!strict) ++touchingOnly;
    }
    REQUIRE(touchingOnly >= 100);
  }
}

TEST_CASE("Identical boxes: every pair, and the median split keeps the tree shallow",
          "[contact][bvh]") {
  int const count = GENERATE(4, 5, 200, 1025);
  CAPTURE(count);
  DynamicArray<Aabb> const boxes(count, Aabb{{1, 2, 3}, {1.5, 2, 4}});
  Bvh const bvh = MakeBvh(boxes);
  DynamicArray<IndexPair> pairs;
  bvh.FindSelfPairs(pairs);
  REQUIRE(pairs.size() == static_cast<std::size_t>(count) * (count - 1) / 2);
  REQUIRE(pairs == BruteSelfPairs(boxes));
  // depth ≤ ⌈log₂(N / leaf)⌉ + 1 (bvh.h)
  int const bound = static_cast<int>(std::ceil(std::log2(real(count) / kBvhLeafSize))) + 1;
  CAPTURE(bvh.GetDepth(), bound);
  REQUIRE(bvh.GetDepth() <= std::max(bound, 1));
  if (count == 1025) REQUIRE(bvh.GetDepth() == bound);
}

TEST_CASE("After a refit with moved boxes the queries equal brute force on the new boxes",
          "[contact][bvh]") {
  std::mt19937 rng(5);
  int const count = GENERATE(1, 2, 37, 1000);
  CAPTURE(count);
  real const extent = count >= 1000 ? 10 : 1;
  DynamicArray<Aabb> boxes = RandomBoxes(count, extent, 0.6, rng);
  DynamicArray<Aabb> const others = RandomBoxes(count / 2 + 3, extent, 0.6, rng);
  Bvh bvh = MakeBvh(boxes);
  auto refitAndCompare = [&] {
    Error error;
    REQUIRE(bvh.Refit(boxes, error));
    RequireQueriesMatchBruteForce(bvh, boxes, others, rng);
  };
  SECTION("small moves") {
    std::normal_distribution<real> jitter(0, 0.2);
    for (Aabb& box : boxes) {
      Real3 const shift(jitter(rng), jitter(rng), jitter(rng));
      box.lower += shift;
      box.upper += shift;
    }
    refitAndCompare();
  }
  SECTION("every box somewhere else") {
    boxes = RandomBoxes(count, extent, 0.6, rng);
    refitAndCompare();
  }
}

TEST_CASE("Refit and Build refuse mismatched or invalid boxes and keep the tree",
          "[contact][bvh]") {
  std::mt19937 rng(9);
  DynamicArray<Aabb> const boxes = RandomBoxes(50, 1, 0.3, rng);
  Bvh bvh = MakeBvh(boxes);
  DynamicArray<IndexPair> before;
  bvh.FindSelfPairs(before);
  REQUIRE_FALSE(before.empty());

  Error error;
  DynamicArray<Aabb> const fewer(boxes.begin(), boxes.end() - 1);
  REQUIRE_FALSE(bvh.Refit(fewer, error));
  CAPTURE(error.ToString());
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "50"));
  REQUIRE(Mentions(error, "49"));

  DynamicArray<Aabb> inverted = RandomBoxes(50, 1, 0.3, rng);
  std::swap(inverted[7].lower.y(), inverted[7].upper.y());
  inverted[7].upper.y() -= 1e-3;  // strictly inverted even if the box was flat
  error.Clear();
  REQUIRE_FALSE(bvh.Refit(inverted, error));
  CAPTURE(error.ToString());
  REQUIRE(Mentions(error, "boxes[7]"));
  REQUIRE(Mentions(error, "lower.y"));

  DynamicArray<Aabb> nonFinite = RandomBoxes(50, 1, 0.3, rng);
  nonFinite[3].upper.z() = std::numeric_limits<real>::quiet_NaN();
  error.Clear();
  REQUIRE_FALSE(bvh.Refit(nonFinite, error));
  REQUIRE(Mentions(error, "boxes[3]"));

  // the refused refits left the tree as it was
  DynamicArray<IndexPair> after;
  bvh.FindSelfPairs(after);
  REQUIRE(after == before);

  // a refused build leaves an empty tree
  error.Clear();
  REQUIRE_FALSE(bvh.Build(nonFinite, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(bvh.GetNumBoxes() == 0);
  bvh.FindSelfPairs(after);
  REQUIRE(after.empty());
}

TEST_CASE("The self query's skip predicate sees each overlapping pair once and is honoured",
          "[contact][bvh]") {
  // 1000 boxes standing for triangles of random vertex ids in [0, 400):
  // pairs sharing a vertex are skipped, as a contact set would
  std::mt19937 rng(21);
  int const count = 1000;
  DynamicArray<Aabb> const boxes = RandomBoxes(count, 10, 0.6, rng);
  std::uniform_int_distribution<int> vertexId(0, 399);
  DynamicArray<std::array<int, 3>> triangles(count);
  for (auto& triangle : triangles)
    for (int& v : triangle) v = vertexId(rng);
  auto const shareVertex = [&](int i, int j) {
    for (int a : triangles[i])
      for (int b : triangles[j])
        if (a == b) return true;
    return false;
  };
  Bvh const bvh = MakeBvh(boxes);
  DynamicArray<IndexPair> const all = BruteSelfPairs(boxes);
  DynamicArray<IndexPair> expected;
  for (IndexPair const& pair : all)
    if (!shareVertex(pair.i, pair.j)) expected.push_back(pair);
  // the predicate must matter here, and leave something
  REQUIRE(expected.size() < all.size());
  REQUIRE(!expected.empty());

  DynamicArray<IndexPair> calls;
  DynamicArray<IndexPair> pairs;
  bvh.FindSelfPairs(pairs, [&](int i, int j) {
    calls.push_back({i, j});
    return shareVertex(i, j);
  });
  REQUIRE(pairs == expected);
  std::sort(calls.begin(), calls.end());
  REQUIRE(calls == all);  // once per overlapping pair, always with i < j

  // the function-pointer form with a context
  struct Context {
    decltype(shareVertex) const* skip;
  } context{&shareVertex};
  bvh.FindSelfPairs(
      pairs, [](void* c, int i, int j) { return (*static_cast<Context*>(c)->skip)(i, j); },
      &context);
  REQUIRE(pairs == expected);
}

TEST_CASE("The two-set query pairs the tree's boxes with another set's, also when one is empty",
          "[contact][bvh]") {
  std::mt19937 rng(33);
  DynamicArray<Aabb> const a = RandomBoxes(1000, 10, 0.6, rng);
  DynamicArray<Aabb> const b = RandomBoxes(700, 10, 0.6, rng);
  DynamicArray<IndexPair> pairs;
  MakeBvh(a).FindPairsWith(b, pairs);
  DynamicArray<IndexPair> const expected = BrutePairs(a, b);
  REQUIRE(expected.size() >= 300);
  REQUIRE(pairs == expected);
  // the other way round: the same pairs, swapped, in their own order
  MakeBvh(b).FindPairsWith(a, pairs);
  REQUIRE(pairs == BrutePairs(b, a));
  MakeBvh(a).FindPairsWith({}, pairs);
  REQUIRE(pairs.empty());
  MakeBvh({}).FindPairsWith(b, pairs);
  REQUIRE(pairs.empty());
}

TEST_CASE("Queries reuse their output vectors' storage across rebuilds and refits",
          "[contact][bvh]") {
  // (the tree's own storage is reused the same way, bvh.cc, but is not
  // visible from here)
  std::mt19937 rng(44);
  DynamicArray<Aabb> const first = RandomBoxes(1000, 10, 0.6, rng);
  DynamicArray<Aabb> const second = RandomBoxes(1000, 10, 0.6, rng);
  Bvh bvh = MakeBvh(first);
  DynamicArray<IndexPair> pairs, twoSet;
  DynamicArray<int> indices;
  Aabb const query{{2, 2, 2}, {6, 6, 6}};
  // the first calls size every buffer
  bvh.FindSelfPairs(pairs);
  bvh.FindPairsWith(second, twoSet);
  bvh.FindOverlaps(query, indices);
  REQUIRE(!pairs.empty());
  REQUIRE(!twoSet.empty());
  REQUIRE(!indices.empty());
  IndexPair const* const pairsData = pairs.data();
  IndexPair const* const twoSetData = twoSet.data();
  int const* const indicesData = indices.data();

  // a refit and a rebuild with the same boxes, then the same queries: the
  // same answers in the same buffers
  Error error;
  REQUIRE(bvh.Refit(first, error));
  REQUIRE(bvh.Build(first, error));
  bvh.FindSelfPairs(pairs);
  bvh.FindPairsWith(second, twoSet);
  bvh.FindOverlaps(query, indices);
  REQUIRE(pairs.data() == pairsData);
  REQUIRE(twoSet.data() == twoSetData);
  REQUIRE(indices.data() == indicesData);
  REQUIRE(pairs == BruteSelfPairs(first));
  REQUIRE(twoSet == BrutePairs(first, second));
  REQUIRE(indices == BruteOverlaps(first, query));
}

TEST_CASE("Swept and inflated boxes hold the primitive over the step, inflated by the margin",
          "[contact][bvh]") {
  DynamicArray<Real3> const positions = {{0, 0, 0}, {1, 2, 0}, {-1, 0.5, 3}, {9, 9, 9}};
  DynamicArray<Real3> const displacements = {{0.5, -1, 0}, {0, 0, 0}, {2, 0, -4}, {1, 1, 1}};
  std::array<int, 3> const triangle = {0, 1, 2};
  Aabb const swept = SweptBox(positions, displacements, triangle, 0.1);
  // start and end corners: x from −1 to 1, y from −1 to 2, z from −1 to 3
  REQUIRE((swept.lower - Real3(-1.1, -1.1, -1.1)).norm() <= 1e-15);
  REQUIRE((swept.upper - Real3(1.1, 2.1, 3.1)).norm() <= 1e-15);
  Aabb const inflated = InflatedBox(positions, triangle, 0.5, 0.1);
  REQUIRE((inflated.lower - Real3(-1.6, -0.6, -0.6)).norm() <= 1e-15);
  REQUIRE((inflated.upper - Real3(1.6, 2.6, 3.6)).norm() <= 1e-15);

  // random segments moving through each other: whenever two come within
  // the margin at a sampled time, their swept boxes overlap
  std::mt19937 rng(3);
  std::uniform_real_distribution<real> u(-1, 1);
  real const margin = 0.05;
  int close = 0, apartAndDisjoint = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    DynamicArray<Real3> x(4), dx(4);
    for (int i = 0; i < 4; ++i) {
      x[i] = Real3(u(rng), u(rng), u(rng));
      dx[i] = Real3(u(rng), u(rng), u(rng));
    }
    std::array<int, 2> const a = {0, 1}, b = {2, 3};
    bool const overlap = Overlaps(SweptBox(x, dx, a, margin), SweptBox(x, dx, b, margin));
    bool near = false;
    // (sampled points within the margin: the segments certainly come that close)
    for (int k = 0; k <= 20 && !near; ++k) {
      real const t = k / 20.0;
      for (int s = 0; s <= 10 && !near; ++s) {
        Real3 const p = x[0] + t * dx[0] + s / 10.0 * (x[1] + t * dx[1] - x[0] - t * dx[0]);
        for (int r = 0; r <= 10 && !near; ++r) {
          Real3 const q = x[2] + t * dx[2] + r / 10.0 * (x[3] + t * dx[3] - x[2] - t * dx[2]);
          near = (p - q).norm() <= margin;
        }
      }
    }
    CAPTURE(trial);
    if (near) {
      ++close;
      REQUIRE(overlap);
    } else if (!overlap) {
      ++apartAndDisjoint;
    }
  }
  REQUIRE(close >= 100);
  REQUIRE(apartAndDisjoint >= 100);
}
