// Broad phase of contact: a bounding-volume hierarchy (BVH) over
// axis-aligned boxes, and the boxes that bound a primitive over a step.
//
// Boxes are closed: two boxes overlap when their intervals intersect on all
// three axes, touching faces included (a ≤ b compared on the corners), so a
// flat box (lower = upper on an axis) overlaps what it touches.
//
// The tree is built top down: a node's boxes are split at the median of
// their centres along the longest axis of the centres' bounds (ties broken
// by box index), down to leaves of at most kBvhLeafSize boxes; the median
// split keeps the depth at most ⌈log₂(N / kBvhLeafSize)⌉ + 1 whatever the
// geometry (identical boxes included). Nodes are stored in depth-first
// order, each parent before its children.
//
// Every query returns its pairs sorted by (i, j) and without duplicates, so
// the result depends only on the boxes, never on the tree's shape or the
// traversal order. Queries clear their output vector and append to it, so a
// vector reused across calls keeps its capacity; Build and Refit likewise
// reuse the tree's storage. Queries run sequentially on the calling thread
// and allocate only through the output vector (the traversal stack is a
// fixed array on the call stack); they keep no state in the tree, so
// several threads may query one tree at once (each with its own output).
#pragma once

#include <compare>
#include <type_traits>

#include <superdex/core/error.h>
#include <superdex/core/parallel.h>
#include <superdex/core/types.h>

namespace superdex::contact {

/// A closed axis-aligned box [lower, upper] (m).
struct Aabb {
  Real3 lower = Real3::Zero();
  Real3 upper = Real3::Zero();
};

/// The boxes overlap (closed intervals on all three axes).
inline bool Overlaps(Aabb const& a, Aabb const& b) {
  return (a.lower.array() <= b.upper.array()).all() && (b.lower.array() <= a.upper.array()).all();
}

/// A pair of box indices found by a query.
struct IndexPair {
  int i = 0;
  int j = 0;
  friend auto operator<=>(IndexPair const&, IndexPair const&) = default;
};

/// The most boxes in one leaf.
inline constexpr int kBvhLeafSize = 4;

class Bvh {
 public:
  /// Builds the tree over `boxes` (box k has index k in every query). Each
  /// box must be finite with lower ≤ upper on every axis; otherwise returns
  /// false, sets an InvalidArgument error naming the box, and leaves an empty
  /// tree. Zero boxes give an empty tree (every query finds nothing).
  bool Build(Span<Aabb const> boxes, Error& error);

  /// Replaces the boxes of the built tree, keeping its structure (the split
  /// of boxes into nodes), and recomputes the node bounds bottom up: for
  /// boxes that moved but kept their number, e.g. a new step's positions.
  /// The queries stay exact however far the boxes moved; only their speed
  /// degrades as the tree drifts from a fresh build's. Returns false, sets
  /// an InvalidArgument error and changes nothing if the number of boxes
  /// differs from the built one's or a box is invalid (as in Build).
  bool Refit(Span<Aabb const> boxes, Error& error);

  int GetNumBoxes() const { return static_cast<int>(boxes_.size()); }
  int GetNumNodes() const { return static_cast<int>(nodes_.size()); }
  /// The longest root-to-leaf path, in nodes (0 for an empty tree).
  int GetDepth() const;

  /// Appends to `indices` (cleared first) the index of every box that
  /// overlaps `query`, in increasing order. Query boxes are not checked:
  /// infinite bounds work (−∞ to ∞ finds every box), a NaN finds nothing.
  void FindOverlaps(Aabb const& query, DynamicArray<int>& indices) const;

  /// Every pair (i, j), i < j, of overlapping boxes of the tree's own set for
  /// which skip(i, j) is false, sorted by (i, j) into `pairs` (cleared
  /// first). skip is called once per overlapping pair, with i < j; pass
  /// nullptr to keep every pair. For example, skip pairs of primitives that
  /// share a vertex.
  using SkipPair = bool (*)(void* context, int i, int j);
  void FindSelfPairs(DynamicArray<IndexPair>& pairs, SkipPair skip = nullptr,
                     void* context = nullptr) const;

  /// As above with any callable skip(i, j) -> bool.
  template <class F>
  void FindSelfPairs(DynamicArray<IndexPair>& pairs, F&& skip) const {
    using Body = std::remove_reference_t<F>;
    FindSelfPairs(
        pairs,
        [](void* context, int i, int j) -> bool { return (*static_cast<Body*>(context))(i, j); },
        const_cast<std::remove_const_t<Body>*>(&skip));
  }

  /// Every pair (i, j) with box i of the tree's set and box j of `others`
  /// overlapping, sorted by (i, j) into `pairs` (cleared first): the two-set
  /// query, with the tree built over one set and the other set's boxes
  /// queried against it.
  void FindPairsWith(Span<Aabb const> others, DynamicArray<IndexPair>& pairs) const;
  /// As above, the queries divided among `executor`'s threads in fixed
  /// chunks of kQueryChunk boxes, each chunk's pairs into its own vector of
  /// `chunks` (grown as needed and kept between calls, so that a reused
  /// `chunks` allocates nothing once large enough), then concatenated and
  /// sorted: the same pairs in the same order for any thread count.
  static constexpr int kQueryChunk = 256;
  void FindPairsWith(Span<Aabb const> others, DynamicArray<IndexPair>& pairs,
                     internal::ParallelExecutor const& executor, DynamicArray<DynamicArray<IndexPair>>& chunks) const;

 private:
  // A node's bounds, and either its two children (internal: the left child
  // follows the node, `right` is the other) or its boxes (leaf: `count` > 0
  // boxes from `first` in the tree's box order).
  struct Node {
    Aabb bounds;
    int first = 0;  ///< leaf: the first box in tree order
    int count = 0;  ///< leaf: the number of boxes; 0 for an internal node
    int right = 0;  ///< internal: the right child's node index
  };

  /// Builds the subtree over the tree-order boxes [begin, end); returns its node.
  int BuildNode(int begin, int end);
  /// Calls visit(k) for every tree-order box k overlapping `query`.
  template <class Visit>
  void Traverse(Aabb const& query, Visit&& visit) const;

  DynamicArray<Node> nodes_;
  DynamicArray<Aabb> boxes_;     ///< the boxes in tree order
  DynamicArray<int> boxIndex_;   ///< boxIndex_[k]: the caller's index of tree-order box k
  DynamicArray<int> position_;   ///< position_[i]: the tree-order place of the caller's box i
  DynamicArray<Real3> centers_;  ///< build scratch: the box centres, by the caller's index
};

/// The box of a primitive over a step: of its vertices' start positions
/// x_v and end positions x_v + Δx_v (v in `vertices`, indices into both
/// arrays), inflated on every side by `margin` (≥ 0; the barrier's reach
/// d̂ plus the thickness). Every vertex moving linearly, the primitive at any
/// t ∈ [0, 1] lies in the box of start and end, so two primitives whose
/// boxes are both made with `margin` have overlapping boxes whenever they
/// come within 2·margin of each other (so certainly within `margin`) at some
/// time of the step. At least one vertex; indices must be valid (not
/// checked).
Aabb SweptBox(Span<Real3 const> positions, Span<Real3 const> displacements,
              Span<int const> vertices, real margin);

/// The box of a primitive's start positions x_v (v in `vertices`) inflated
/// by displacementBound + margin: it holds the primitive wherever each of
/// its vertices moves by at most displacementBound (m), e.g. a bound on the
/// step length known before the step is. At least one vertex; indices must
/// be valid (not checked).
Aabb InflatedBox(Span<Real3 const> positions, Span<int const> vertices, real displacementBound,
                 real margin);

}  // namespace superdex::contact
