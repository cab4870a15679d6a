#include <superdex/linsolve/incomplete_cholesky.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cmath>
#include <numeric>

namespace superdex::internal {

namespace {

/// The shifts a group is factored with after α = 0, while below its
/// Gershgorin shift (which comes last).
constexpr real kShifts[] = {1e-3, 1e-2, 1e-1, 1};
/// Margin of strict diagonal dominance of the last shift.
constexpr real kDominanceMargin = 1e-3;

IncompleteCholesky::Result Failure(int column, std::string reason) {
  return {false, column, std::move(reason)};
}

/// Breadth-first level structure of the component of `root` within
/// [first, last): visits in `queue` (from its start), returns the number of
/// levels; `lastLevelBegin` is where the last level starts in `queue`.
int LevelStructure(Span<int const> adjacencyStart, Span<int const> adjacency, int first, int last,
                   int root, DynamicArray<int>& stamp, int stampValue, DynamicArray<int>& queue,
                   std::size_t& lastLevelBegin) {
  queue.clear();
  queue.push_back(root);
  stamp[root - first] = stampValue;
  std::size_t levelBegin = 0;
  int levels = 0;
  while (levelBegin < queue.size()) {
    ++levels;
    lastLevelBegin = levelBegin;
    std::size_t const levelEnd = queue.size();
    for (std::size_t q = levelBegin; q < levelEnd; ++q) {
      int const v = queue[q];
      for (int p = adjacencyStart[v]; p < adjacencyStart[v + 1]; ++p) {
        int const w = adjacency[p];
        if (w < first || w >= last || stamp[w - first] == stampValue) continue;
        stamp[w - first] = stampValue;
        queue.push_back(w);
      }
    }
    levelBegin = levelEnd;
  }
  return levels;
}

}  // namespace

void AppendReverseCuthillMcKee(Span<int const> adjacencyStart, Span<int const> adjacency,
                               int first, int last, DynamicArray<int>& order) {
  int const count = last - first;
  if (count <= 0) return;
  DynamicArray<int> degree(count, 0);
  for (int v = first; v < last; ++v)
    for (int p = adjacencyStart[v]; p < adjacencyStart[v + 1]; ++p)
      if (adjacency[p] >= first && adjacency[p] < last && adjacency[p] != v) ++degree[v - first];
  DynamicArray<int> stamp(count, -1), queue, neighbours;
  DynamicArray<char> numbered(count, 0);
  int stampValue = 0;
  auto byDegree = [&](int u, int w) {
    return degree[u - first] != degree[w - first] ? degree[u - first] < degree[w - first] : u < w;
  };
  for (int start = first; start < last; ++start) {
    if (numbered[start - first]) continue;
    // pseudo-peripheral root: from the start, the smallest-degree vertex of
    // the last level while the number of levels grows (George and Liu)
    int root = start;
    std::size_t lastLevelBegin = 0;
    int levels = LevelStructure(adjacencyStart, adjacency, first, last, root, stamp, stampValue++,
                                queue, lastLevelBegin);
    for (;;) {
      int const candidate = *std::min_element(queue.begin() + static_cast<std::ptrdiff_t>(lastLevelBegin),
                                              queue.end(), byDegree);
      std::size_t candidateLastLevel = 0;
      int const candidateLevels = LevelStructure(adjacencyStart, adjacency, first, last, candidate,
                                                 stamp, stampValue++, queue, candidateLastLevel);
      if (candidateLevels <= levels) break;
      root = candidate, levels = candidateLevels, lastLevelBegin = candidateLastLevel;
    }
    // Cuthill–McKee from the root, then reversed
    std::size_t const componentBegin = order.size();
    order.push_back(root);
    numbered[root - first] = 1;
    for (std::size_t head = componentBegin; head < order.size(); ++head) {
      int const v = order[head];
      neighbours.clear();
      for (int p = adjacencyStart[v]; p < adjacencyStart[v + 1]; ++p) {
        int const w = adjacency[p];
        if (w < first || w >= last || numbered[w - first]) continue;
        numbered[w - first] = 1;
        neighbours.push_back(w);
      }
      std::sort(neighbours.begin(), neighbours.end(), byDegree);
      order.insert(order.end(), neighbours.begin(), neighbours.end());
    }
    std::reverse(order.begin() + static_cast<std::ptrdiff_t>(componentBegin), order.end());
  }
}

IncompleteCholesky::Result IncompleteCholesky::Analyze(SparseSymmetricMatrix const& a, int levels,
                                                       Span<int const> groupSizes) {
  int const n = a.size;
  size_ = n;
  // groups, in A's order (the factor's order keeps them in place)
  groupStart_.assign(1, 0);
  for (int size : groupSizes) {
    if (size <= 0) return Failure(-1, "a group of DoFs is empty");
    groupStart_.push_back(groupStart_.back() + size);
  }
  if (groupSizes.empty()) groupStart_.push_back(n);
  if (groupStart_.back() != n)
    return Failure(-1, "the groups add to " + std::to_string(groupStart_.back()) +
                           " DoFs, the matrix has " + std::to_string(n));
  DynamicArray<int> groupOf(n);
  for (std::size_t g = 0; g + 1 < groupStart_.size(); ++g)
    std::fill(groupOf.begin() + groupStart_[g], groupOf.begin() + groupStart_[g + 1], static_cast<int>(g));

  // the graph of A within groups, both triangles, without the diagonal
  DynamicArray<int> adjacencyStart(static_cast<std::size_t>(n) + 1, 0);
  auto const kept = [&](int r, int c) { return r != c && groupOf[r] == groupOf[c]; };
  for (int c = 0; c < n; ++c)
    for (int e = a.colStart[c]; e < a.colStart[c + 1]; ++e)
      if (kept(a.rowIndex[e], c)) ++adjacencyStart[a.rowIndex[e] + 1], ++adjacencyStart[c + 1];
  std::partial_sum(adjacencyStart.begin(), adjacencyStart.end(), adjacencyStart.begin());
  DynamicArray<int> adjacency(static_cast<std::size_t>(adjacencyStart[n]));
  DynamicArray<int> cursor(adjacencyStart.begin(), adjacencyStart.end() - 1);
  for (int c = 0; c < n; ++c)
    for (int e = a.colStart[c]; e < a.colStart[c + 1]; ++e)
      if (int const r = a.rowIndex[e]; kept(r, c)) adjacency[cursor[r]++] = c, adjacency[cursor[c]++] = r;

  order_.clear();
  order_.reserve(n);
  for (std::size_t g = 0; g + 1 < groupStart_.size(); ++g)
    AppendReverseCuthillMcKee(adjacencyStart, adjacency, groupStart_[g], groupStart_[g + 1], order_);
  DynamicArray<int> position(n);  // old → new
  for (int i = 0; i < n; ++i) position[order_[i]] = i;

  // IC(levels) pattern row by row in the new order: row i's entries (i, k),
  // k < i, in a sorted linked list; each k, in increasing order, brings the
  // fill (i, j) for the entries (j, k) of the rows j < i already done
  DynamicArray<DynamicArray<int>> columnRows(n), columnLevels(n);  // L's column k: rows j > k
  DynamicArray<int> next(static_cast<std::size_t>(n) + 1), level(n), inRow(n, -1);
  int const head = n;
  int const end = INT_MAX;
  DynamicArray<int> initial;
  for (int i = 0; i < n; ++i) {
    initial.clear();
    int const old = order_[i];
    for (int p = adjacencyStart[old]; p < adjacencyStart[old + 1]; ++p)
      if (position[adjacency[p]] < i) initial.push_back(position[adjacency[p]]);
    std::sort(initial.begin(), initial.end());
    int previous = head;
    for (int k : initial) {
      next[previous] = k, level[k] = 0, inRow[k] = i;
      previous = k;
    }
    next[previous] = end;
    for (int k = next[head]; k != end; k = next[k]) {
      int cursorInList = k;
      for (std::size_t q = 0; q < columnRows[k].size(); ++q) {
        int const j = columnRows[k][q];
        int const fillLevel = level[k] + columnLevels[k][q] + 1;
        if (fillLevel > levels) continue;
        if (inRow[j] == i) {
          level[j] = std::min(level[j], fillLevel);
          continue;
        }
        // columnRows[k] is increasing: insert after the last insertion point
        while (next[cursorInList] < j) cursorInList = next[cursorInList];
        next[j] = next[cursorInList], next[cursorInList] = j;
        level[j] = fillLevel, inRow[j] = i;
      }
    }
    for (int k = next[head]; k != end; k = next[k]) {
      columnRows[k].push_back(i);
      columnLevels[k].push_back(level[k]);
    }
  }
  uStart_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int k = 0; k < n; ++k) uStart_[k + 1] = uStart_[k] + static_cast<int>(columnRows[k].size());
  uColumn_.resize(static_cast<std::size_t>(uStart_[n]));
  for (int k = 0; k < n; ++k) std::copy(columnRows[k].begin(), columnRows[k].end(), uColumn_.begin() + uStart_[k]);
  columnRows = {}, columnLevels = {};
  uValue_.assign(uColumn_.size(), 0);
  uInitial_.assign(uColumn_.size(), 0);
  // L by rows, each row's columns increasing (columns visited in order)
  lStart_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int row : uColumn_) ++lStart_[row + 1];
  std::partial_sum(lStart_.begin(), lStart_.end(), lStart_.begin());
  lColumn_.resize(uColumn_.size());
  lSlot_.resize(uColumn_.size());
  cursor.assign(lStart_.begin(), lStart_.end() - 1);
  for (int k = 0; k < n; ++k)
    for (int q = uStart_[k]; q < uStart_[k + 1]; ++q) {
      int const slot = cursor[uColumn_[q]]++;
      lColumn_[slot] = k, lSlot_[slot] = q;
    }

  // A's entries → slots of the factor
  entrySlot_.assign(a.rowIndex.size(), -1);
  diagonalEntry_.assign(n, -1);
  for (int c = 0; c < n; ++c)
    for (int e = a.colStart[c]; e < a.colStart[c + 1]; ++e) {
      int const r = a.rowIndex[e];
      if (r == c) diagonalEntry_[c] = e;
      if (!kept(r, c)) continue;
      int const low = std::min(position[r], position[c]), high = std::max(position[r], position[c]);
      auto const begin = uColumn_.begin() + uStart_[low], stop = uColumn_.begin() + uStart_[low + 1];
      entrySlot_[e] = static_cast<int>(std::lower_bound(begin, stop, high) - uColumn_.begin());
    }

  pivot_.assign(n, 0);
  inversePivot_.assign(n, 0);
  scale_.assign(n, 0);
  work_.assign(n, 0);
  mark_.assign(n, -1);
  largestShift_ = 0, numShiftedGroups_ = 0, numGroupFactorizations_ = 0;
  return {};
}

IncompleteCholesky::Result IncompleteCholesky::Factorize(SparseSymmetricMatrix const& a) {
  int const n = size_;
  for (int c = 0; c < n; ++c) {
    real const diagonal = a.values[diagonalEntry_[c]];
    if (!(diagonal > 0) || !std::isfinite(diagonal))
      return Failure(c, "the diagonal entry of column " + std::to_string(c) +
                            " is not positive (the matrix is not positive definite)");
    scale_[c] = 1 / std::sqrt(diagonal);
  }
  std::fill(uInitial_.begin(), uInitial_.end(), real(0));
  for (int c = 0; c < n; ++c)
    for (int e = a.colStart[c]; e < a.colStart[c + 1]; ++e)
      if (int const slot = entrySlot_[e]; slot >= 0)
        uInitial_[slot] = a.values[e] * scale_[a.rowIndex[e]] * scale_[c];

  largestShift_ = 0, numShiftedGroups_ = 0, numGroupFactorizations_ = 0;
  for (std::size_t g = 0; g + 1 < groupStart_.size(); ++g) {
    int const first = groupStart_[g], last = groupStart_[g + 1];
    ++numGroupFactorizations_;
    int failed = FactorRows(first, last, 0);
    if (failed < 0) continue;
    // Gershgorin: the largest off-diagonal row sum of the group's Â
    real largestSum = 0;
    for (int i = first; i < last; ++i) {
      real sum = 0;
      for (int p = lStart_[i]; p < lStart_[i + 1]; ++p) sum += std::abs(uInitial_[lSlot_[p]]);
      for (int q = uStart_[i]; q < uStart_[i + 1]; ++q) sum += std::abs(uInitial_[q]);
      largestSum = std::max(largestSum, sum);
    }
    real const dominantShift = (1 + kDominanceMargin) * largestSum - 1;
    real shift = 0;
    for (real candidate : kShifts) {
      if (failed < 0 || !(candidate < dominantShift)) break;
      shift = candidate;
      ++numGroupFactorizations_;
      failed = FactorRows(first, last, shift);
    }
    if (failed >= 0 && dominantShift > shift && std::isfinite(dominantShift)) {
      shift = dominantShift;
      ++numGroupFactorizations_;
      failed = FactorRows(first, last, shift);
    }
    if (failed >= 0) {
      int const column = order_[failed];
      char detail[160];
      std::snprintf(detail, sizeof(detail), " (Jacobi-scaled, shifted by %.3g: pivot %.3g)", shift,
                    pivot_[failed]);
      return Failure(column, "incomplete Cholesky broke down at column " + std::to_string(column) +
                                 detail + ": the matrix is not positive definite, or singular "
                                          "to working precision");
    }
    ++numShiftedGroups_;
    largestShift_ = std::max(largestShift_, shift);
  }
  return {};
}

int IncompleteCholesky::FactorRows(int first, int last, real shift) {
  real const minPivot = kMinPivot * (1 + shift);
  for (int i = first; i < last; ++i) {
    int const rowBegin = lStart_[i], rowEnd = lStart_[i + 1];
    for (int p = rowBegin; p < rowEnd; ++p) {
      work_[lColumn_[p]] = uInitial_[lSlot_[p]];
      mark_[lColumn_[p]] = i;
    }
    real pivot = 1 + shift;
    for (int p = rowBegin; p < rowEnd; ++p) {
      // work_[k] = Âᵢₖ − Σ_{m<k} L(i,m) d_m L(k,m) = L(i,k) d_k
      int const k = lColumn_[p];
      real const reduced = work_[k];
      real const entry = reduced * inversePivot_[k];
      uValue_[lSlot_[p]] = entry;
      pivot -= reduced * entry;
      for (int q = uStart_[k]; q < uStart_[k + 1]; ++q) {
        int const j = uColumn_[q];
        if (j >= i) break;
        if (mark_[j] == i) work_[j] -= reduced * uValue_[q];
      }
    }
    pivot_[i] = pivot;
    if (!(pivot > minPivot) || !std::isfinite(pivot)) return i;
    inversePivot_[i] = 1 / pivot;
  }
  return -1;
}

void IncompleteCholesky::Apply(real const* r, real* z) {
  int const n = size_;
  real* y = work_.data();
  for (int i = 0; i < n; ++i) y[i] = r[order_[i]] * scale_[order_[i]];
  for (int k = 0; k < n; ++k) {  // L y' = y, by columns
    real const value = y[k];
    if (value == 0) continue;
    for (int q = uStart_[k]; q < uStart_[k + 1]; ++q) y[uColumn_[q]] -= uValue_[q] * value;
  }
  for (int k = 0; k < n; ++k) y[k] *= inversePivot_[k];
  for (int k = n - 1; k >= 0; --k) {  // Lᵀ z = y, by rows of Lᵀ
    real value = y[k];
    for (int q = uStart_[k]; q < uStart_[k + 1]; ++q) value -= uValue_[q] * y[uColumn_[q]];
    y[k] = value;
  }
  for (int i = 0; i < n; ++i) z[order_[i]] = y[i] * scale_[order_[i]];
}

}  // namespace superdex::internal
