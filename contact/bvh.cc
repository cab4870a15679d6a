#include <superdex/contact/bvh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace superdex::contact {

namespace {

// The median split halves every node, so the tree over at most 2³¹ boxes is
// at most 32 nodes deep; a traversal keeps at most one pending right child
// per level.
constexpr int kMaxStack = 64;

std::string FormatReal(real value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

// Empty when every box is finite with lower ≤ upper, else what is wrong.
std::string CheckBoxes(Span<Aabb const> boxes) {
  static char const* const kAxis[] = {"x", "y", "z"};
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    Aabb const& box = boxes[k];
    for (int a = 0; a < 3; ++a) {
      std::string const name = "boxes[" + std::to_string(k) + "]";
      if (!std::isfinite(box.lower[a]) || !std::isfinite(box.upper[a])) {
        return name + " must be finite, got lower." + kAxis[a] + " = " + FormatReal(box.lower[a]) +
               ", upper." + kAxis[a] + " = " + FormatReal(box.upper[a]);
      }
      if (box.lower[a] > box.upper[a]) {
        return name + " must have lower <= upper, got lower." + kAxis[a] + " = " +
               FormatReal(box.lower[a]) + " > upper." + kAxis[a] + " = " + FormatReal(box.upper[a]);
      }
    }
  }
  return {};
}

void Extend(Aabb& box, Aabb const& other) {
  box.lower = box.lower.cwiseMin(other.lower);
  box.upper = box.upper.cwiseMax(other.upper);
}

Aabb Inflated(Aabb box, real amount) {
  box.lower.array() -= amount;
  box.upper.array() += amount;
  return box;
}

}  // namespace

bool Bvh::Build(Span<Aabb const> boxes, Error& error) {
  nodes_.clear();
  boxes_.clear();
  boxIndex_.clear();
  position_.clear();
  if (boxes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 2)) {
    error.Set(ErrorCode::InvalidArgument,
              "boxes must number at most " + std::to_string(std::numeric_limits<int>::max() / 2) +
                  ", got " + std::to_string(boxes.size()));
    return false;
  }
  if (std::string problem = CheckBoxes(boxes); !problem.empty()) {
    error.Set(ErrorCode::InvalidArgument, std::move(problem));
    return false;
  }
  int const numBoxes = static_cast<int>(boxes.size());
  if (numBoxes == 0) return true;

  // split the boxes into nodes by their centres
  centers_.resize(numBoxes);
  boxIndex_.resize(numBoxes);
  for (int i = 0; i < numBoxes; ++i) {
    centers_[i] = boxes[i].lower / 2 + boxes[i].upper / 2;
    boxIndex_[i] = i;
  }
  BuildNode(0, numBoxes);

  // the boxes in tree order, and where each caller's box went
  boxes_.resize(numBoxes);
  position_.resize(numBoxes);
  for (int k = 0; k < numBoxes; ++k) position_[boxIndex_[k]] = k;
  return Refit(boxes, error);
}

int Bvh::BuildNode(int begin, int end) {
  int const node = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kBvhLeafSize) {
    nodes_[node].first = begin;
    nodes_[node].count = end - begin;
    return node;
  }
  // the longest axis of the centres' bounds
  Real3 lower = Real3::Constant(std::numeric_limits<real>::infinity());
  Real3 upper = -lower;
  for (int k = begin; k < end; ++k) {
    lower = lower.cwiseMin(centers_[boxIndex_[k]]);
    upper = upper.cwiseMax(centers_[boxIndex_[k]]);
  }
  int axis = 0;
  (upper - lower).maxCoeff(&axis);
  // the median along it, equal centres ordered by index, so that the split
  // is defined (and halves the node) even for identical boxes
  int const middle = begin + (end - begin) / 2;
  auto const before = [&](int a, int b) {
    real const ca = centers_[a][axis], cb = centers_[b][axis];
    return ca < cb || (ca == cb && a < b);
  };
  std::nth_element(boxIndex_.begin() + begin, boxIndex_.begin() + middle, boxIndex_.begin() + end,
                   before);
  BuildNode(begin, middle);  // the left child, node + 1
  int const right = BuildNode(middle, end);
  nodes_[node].right = right;
  return node;
}

bool Bvh::Refit(Span<Aabb const> boxes, Error& error) {
  if (boxes.size() != boxes_.size()) {
    error.Set(ErrorCode::InvalidArgument, "boxes must number " + std::to_string(boxes_.size()) +
                                              " as when the tree was built, got " +
                                              std::to_string(boxes.size()));
    return false;
  }
  if (std::string problem = CheckBoxes(boxes); !problem.empty()) {
    error.Set(ErrorCode::InvalidArgument, std::move(problem));
    return false;
  }
  for (std::size_t k = 0; k < boxes_.size(); ++k) boxes_[k] = boxes[boxIndex_[k]];
  // children follow their parent, so a backward sweep sees them first
  for (int node = static_cast<int>(nodes_.size()) - 1; node >= 0; --node) {
    Node& n = nodes_[node];
    if (n.count > 0) {
      n.bounds = boxes_[n.first];
      for (int k = n.first + 1; k < n.first + n.count; ++k) Extend(n.bounds, boxes_[k]);
    } else {
      n.bounds = nodes_[node + 1].bounds;
      Extend(n.bounds, nodes_[n.right].bounds);
    }
  }
  return true;
}

int Bvh::GetDepth() const {
  if (nodes_.empty()) return 0;
  // depth-first with each pending node's depth
  std::array<std::pair<int, int>, kMaxStack> stack;
  int top = 0;
  int deepest = 0;
  stack[top++] = {0, 1};
  while (top > 0) {
    auto const [node, depth] = stack[--top];
    deepest = std::max(deepest, depth);
    if (nodes_[node].count == 0) {
      stack[top++] = {node + 1, depth + 1};
      stack[top++] = {nodes_[node].right, depth + 1};
    }
  }
  return deepest;
}

template <class Visit>
void Bvh::Traverse(Aabb const& query, Visit&& visit) const {
  if (nodes_.empty()) return;
  std::array<int, kMaxStack> pending;
  int top = 0;
  int node = 0;
  while (true) {
    Node const& n = nodes_[node];
    if (Overlaps(n.bounds, query)) {
      if (n.count == 0) {
        // descend left, the right child waits
        pending[top++] = n.right;
        node = node + 1;
        continue;
      }
      for (int k = n.first; k < n.first + n.count; ++k) {
        if (Overlaps(boxes_[k], query)) visit(k);
      }
    }
    if (top == 0) return;
    node = pending[--top];
  }
}

void Bvh::FindOverlaps(Aabb const& query, DynamicArray<int>& indices) const {
  indices.clear();
  Traverse(query, [&](int k) { indices.push_back(boxIndex_[k]); });
  std::sort(indices.begin(), indices.end());
}

void Bvh::FindSelfPairs(DynamicArray<IndexPair>& pairs, SkipPair skip, void* context) const {
  pairs.clear();
  // each box against the tree, keeping the partners of larger index: every
  // pair is found once, from its smaller index, and the pairs come grouped
  // by i in increasing order
  for (int i = 0; i < GetNumBoxes(); ++i) {
    std::size_t const start = pairs.size();
    Traverse(boxes_[position_[i]], [&](int k) {
      int const j = boxIndex_[k];
      if (j > i && (skip == nullptr || !skip(context, i, j))) pairs.push_back({i, j});
    });
    std::sort(pairs.begin() + start, pairs.end());
  }
}

void Bvh::FindPairsWith(Span<Aabb const> others, DynamicArray<IndexPair>& pairs) const {
  pairs.clear();
  for (std::size_t j = 0; j < others.size(); ++j) {
    Traverse(others[j], [&](int k) { pairs.push_back({boxIndex_[k], static_cast<int>(j)}); });
  }
  std::sort(pairs.begin(), pairs.end());
}

void Bvh::FindPairsWith(Span<Aabb const> others, DynamicArray<IndexPair>& pairs,
                        internal::ParallelExecutor const& executor,
                        DynamicArray<DynamicArray<IndexPair>>& chunks) const {
  int const count = static_cast<int>(others.size());
  int const numChunks = (count + kQueryChunk - 1) / kQueryChunk;
  if (static_cast<int>(chunks.size()) < numChunks) chunks.resize(numChunks);
  executor.For(numChunks, 1, [&](int begin, int end, int) {
    for (int chunk = begin; chunk < end; ++chunk) {
      DynamicArray<IndexPair>& out = chunks[chunk];
      out.clear();
      int const last = std::min(count, (chunk + 1) * kQueryChunk);
      for (int j = chunk * kQueryChunk; j < last; ++j)
        Traverse(others[j], [&](int k) { out.push_back({boxIndex_[k], j}); });
    }
  });
  pairs.clear();
  for (int chunk = 0; chunk < numChunks; ++chunk) pairs.insert(pairs.end(), chunks[chunk].begin(), chunks[chunk].end());
  std::sort(pairs.begin(), pairs.end());
}

Aabb SweptBox(Span<Real3 const> positions, Span<Real3 const> displacements,
              Span<int const> vertices, real margin) {
  Aabb box{Real3::Constant(std::numeric_limits<real>::infinity()),
           Real3::Constant(-std::numeric_limits<real>::infinity())};
  for (int v : vertices) {
    Real3 const end = positions[v] + displacements[v];
    box.lower = box.lower.cwiseMin(positions[v]).cwiseMin(end);
    box.upper = box.upper.cwiseMax(positions[v]).cwiseMax(end);
  }
  return Inflated(box, margin);
}

Aabb InflatedBox(Span<Real3 const> positions, Span<int const> vertices, real displacementBound,
                 real margin) {
  Aabb box{Real3::Constant(std::numeric_limits<real>::infinity()),
           Real3::Constant(-std::numeric_limits<real>::infinity())};
  for (int v : vertices) {
    box.lower = box.lower.cwiseMin(positions[v]);
    box.upper = box.upper.cwiseMax(positions[v]);
  }
  return Inflated(box, displacementBound + margin);
}

}  // namespace superdex::contact
