#include <superdex/linsolve/single_precision_factor.h>

#include <superdex/core/parallel.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#ifdef __AVX__
#include <immintrin.h>
#endif
#include <limits>

namespace superdex::internal {

namespace {

// GCC/Clang vector types: four lanes each, lowered to whatever vector width
// the target has (two 128-bit halves on SSE or a 128-bit-preferring tune)
typedef float Float4 __attribute__((vector_size(16)));
typedef double Double4 __attribute__((vector_size(32)));

// four floats widened to doubles: with AVX one vcvtps2pd from memory (the
// generic conversion compiles to a load, a shuffle and the conversion, 15 %
// slower on the solves here)
inline Double4 LoadWidened(float const* p) {
#ifdef __AVX__
  return reinterpret_cast<Double4>(_mm256_cvtps_pd(_mm_loadu_ps(p)));
#else
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return __builtin_convertvector(v, Double4);
#endif
}

inline Double4 Load(double const* p) {
  Double4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

typedef float Float8 __attribute__((vector_size(32)));

inline Float8 Load(float const* p) {
  Float8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// The vector type of the arithmetic T, and L's floats loaded into it: four
// doubles (widened), or eight floats
template <class T>
struct Lanes;
template <>
struct Lanes<double> {
  using Vector = Double4;
  static constexpr int kWidth = 4;
  static Vector LoadL(float const* p) { return LoadWidened(p); }
};
template <>
struct Lanes<float> {
  using Vector = Float8;
  static constexpr int kWidth = 8;
  static Vector LoadL(float const* p) { return Load(p); }
};

template <class Vector>
inline auto Sum(Vector const& v) {
  auto sum = v[0];
  for (std::size_t k = 1; k < sizeof(Vector) / sizeof(v[0]); ++k) sum += v[k];
  return sum;
}

template <class T>
inline void Store(T* p, typename Lanes<T>::Vector const& v) {
  std::memcpy(p, &v, sizeof v);
}

// Σ column[i] · w[i] over i < count in T: four independent vector sums, so
// that the multiply-adds do not wait on each other's latency
template <class T>
inline T Dot(float const* column, T const* w, int count) {
  using L = Lanes<T>;
  constexpr int kW = L::kWidth;
  typename L::Vector s0{}, s1{}, s2{}, s3{};
  int i = 0;
  for (; i + 4 * kW <= count; i += 4 * kW) {
    s0 += L::LoadL(column + i) * Load(w + i);
    s1 += L::LoadL(column + i + kW) * Load(w + i + kW);
    s2 += L::LoadL(column + i + 2 * kW) * Load(w + i + 2 * kW);
    s3 += L::LoadL(column + i + 3 * kW) * Load(w + i + 3 * kW);
  }
  for (; i + kW <= count; i += kW) s0 += L::LoadL(column + i) * Load(w + i);
  T sum = Sum((s0 + s1) + (s2 + s3));
  for (; i < count; ++i) sum += T(column[i]) * w[i];
  return sum;
}

// w[i] −= column[i] · a over i < count
template <class T>
inline void SubtractScaled(float const* column, T a, T* w, int count) {
  using L = Lanes<T>;
  int i = 0;
  for (; i + L::kWidth <= count; i += L::kWidth) Store(w + i, Load(w + i) - L::LoadL(column + i) * a);
  for (; i < count; ++i) w[i] -= T(column[i]) * a;
}

// t[i] −= Σₖ columnₖ[i] · aₖ over i < count, for the four columns at
// column, column + stride, ... (one pass over t for four columns of L)
template <class T>
inline void SubtractScaled4(float const* column, std::size_t stride, T const* a, T* t, int count) {
  using L = Lanes<T>;
  float const* c0 = column;
  float const* c1 = column + stride;
  float const* c2 = column + 2 * stride;
  float const* c3 = column + 3 * stride;
  int i = 0;
  for (; i + L::kWidth <= count; i += L::kWidth)
    Store(t + i, Load(t + i) - (L::LoadL(c0 + i) * a[0] + L::LoadL(c1 + i) * a[1]) -
                     (L::LoadL(c2 + i) * a[2] + L::LoadL(c3 + i) * a[3]));
  for (; i < count; ++i)
    t[i] -= (T(c0[i]) * a[0] + T(c1[i]) * a[1]) + (T(c2[i]) * a[2] + T(c3[i]) * a[3]);
}

// d[k] = Σᵢ columnₖ[i] · g[i] over i < count for the four columns at column,
// column + stride, ... (one pass over g for four columns of L)
template <class T>
inline void Dot4(float const* column, std::size_t stride, T const* g, int count, T* d) {
  using L = Lanes<T>;
  float const* c[4] = {column, column + stride, column + 2 * stride, column + 3 * stride};
  typename L::Vector s0{}, s1{}, s2{}, s3{};
  int i = 0;
  for (; i + L::kWidth <= count; i += L::kWidth) {
    auto const gi = Load(g + i);
    s0 += L::LoadL(c[0] + i) * gi;
    s1 += L::LoadL(c[1] + i) * gi;
    s2 += L::LoadL(c[2] + i) * gi;
    s3 += L::LoadL(c[3] + i) * gi;
  }
  d[0] = Sum(s0);
  d[1] = Sum(s1);
  d[2] = Sum(s2);
  d[3] = Sum(s3);
  for (; i < count; ++i)
    for (int k = 0; k < 4; ++k) d[k] += T(c[k][i]) * g[i];
}

}  // namespace

void SinglePrecisionFactor::Partition() {
  // the supernodal elimination tree: the parent of s is the supernode of its
  // first row below its own columns
  SupernodalLayout const& layout = layout_;
  int const numSupernodes = layout.numSupernodes;
  columnSupernode_.resize(static_cast<std::size_t>(layout.size));
  for (int s = 0; s < numSupernodes; ++s)
    for (int c = layout.super[s]; c < layout.super[s + 1]; ++c) columnSupernode_[c] = s;
  parent_.resize(static_cast<std::size_t>(numSupernodes));
  work_.assign(static_cast<std::size_t>(numSupernodes), 0.0);
  firstDescendant_.resize(static_cast<std::size_t>(numSupernodes));
  for (int s = 0; s < numSupernodes; ++s) firstDescendant_[s] = s;
  subtreeSize_.assign(static_cast<std::size_t>(numSupernodes), 1);
  bool postordered = true;
  for (int s = 0; s < numSupernodes; ++s) {
    int const numCols = layout.super[s + 1] - layout.super[s];
    int const numRows = layout.rowStart[s + 1] - layout.rowStart[s];
    work_[s] += double(numRows) * numCols;
    int const p = numRows > numCols ? columnSupernode_[layout.rows[layout.rowStart[s] + numCols]] : -1;
    parent_[s] = p;
    if (p >= 0 && p <= s) postordered = false;
    if (p > s) {
      work_[p] += work_[s];
      subtreeSize_[p] += subtreeSize_[s];
      firstDescendant_[p] = std::min(firstDescendant_[p], firstDescendant_[s]);
    }
    // postorder: a subtree's supernodes are the contiguous range up to its root
    if (s - firstDescendant_[s] + 1 != subtreeSize_[s]) postordered = false;
  }

  // split every subtree larger than 1 / kSubtreeTarget of the whole into
  // its children (a leaf stays whole); the split nodes form the top
  subtreeRoots_.clear();
  isTop_.assign(static_cast<std::size_t>(numSupernodes), 0);
  double total = 0;
  for (int s = 0; s < numSupernodes; ++s)
    if (parent_[s] < 0) total += work_[s];
  if (postordered && numSupernodes > 1) {
    double const limit = total / kSubtreeTarget;
    // children of each node, for the split (postorder: children before s)
    childStart_.assign(static_cast<std::size_t>(numSupernodes) + 1, 0);
    for (int s = 0; s < numSupernodes; ++s)
      if (parent_[s] >= 0) ++childStart_[parent_[s] + 1];
    for (int s = 0; s < numSupernodes; ++s) childStart_[s + 1] += childStart_[s];
    children_.resize(static_cast<std::size_t>(childStart_[numSupernodes]));
    nextChild_.assign(childStart_.begin(), childStart_.end() - 1);
    for (int s = 0; s < numSupernodes; ++s)
      if (parent_[s] >= 0) children_[nextChild_[parent_[s]]++] = s;
    pending_.clear();
    for (int s = 0; s < numSupernodes; ++s)
      if (parent_[s] < 0) pending_.push_back(s);
    while (!pending_.empty()) {
      int const s = pending_.back();
      pending_.pop_back();
      if (work_[s] <= limit || childStart_[s] == childStart_[s + 1]) {  // small, or a leaf
        subtreeRoots_.push_back(s);
        continue;
      }
      isTop_[s] = 1;
      for (int k = childStart_[s]; k < childStart_[s + 1]; ++k) pending_.push_back(children_[k]);
    }
    std::sort(subtreeRoots_.begin(), subtreeRoots_.end());
  } else {
    // one serial sweep: every supernode in the top
    std::fill(isTop_.begin(), isTop_.end(), 1);
  }

  // the subtrees, in postorder, into kGroups contiguous groups of about equal
  // work (a fixed split: the result does not depend on the thread count)
  int const numSubtrees = static_cast<int>(subtreeRoots_.size());
  double subtreeTotal = 0;
  for (int root : subtreeRoots_) subtreeTotal += work_[root];
  groupStart_.clear();
  groupStart_.push_back(0);
  double running = 0;
  for (int t = 0; t < numSubtrees; ++t) {
    running += work_[subtreeRoots_[t]];
    int const numStarted = static_cast<int>(groupStart_.size());
    if (t + 1 < numSubtrees && numStarted < kGroups && running >= subtreeTotal * numStarted / kGroups)
      groupStart_.push_back(t + 1);
  }
  if (numSubtrees > 0) groupStart_.push_back(numSubtrees);
  numGroups_ = static_cast<int>(groupStart_.size()) - 1;

  // the top's columns, numbered for the groups' buffers
  topIndex_.assign(static_cast<std::size_t>(layout.size), -1);
  topSupernodes_.clear();
  topColumns_.clear();
  for (int s = 0; s < numSupernodes; ++s) {
    if (!isTop_[s]) continue;
    topSupernodes_.push_back(s);
    for (int c = layout.super[s]; c < layout.super[s + 1]; ++c) {
      topIndex_[c] = static_cast<int>(topColumns_.size());
      topColumns_.push_back(c);
    }
  }
  std::size_t const bufferSize = static_cast<std::size_t>(numGroups_) * topColumns_.size();
  if (floatArithmetic_)
    floatWork_.groupBuffers.resize(bufferSize);
  else
    doubleWork_.groupBuffers.resize(bufferSize);
}

bool SinglePrecisionFactor::Assign(SupernodalLayout const& layout, double const* values) {
  assigned_ = false;
  reason_ = "";
  layout_ = layout;
  int maxRows = 0;
  for (int s = 0; s < layout.numSupernodes; ++s)
    maxRows = std::max(maxRows, layout.rowStart[s + 1] - layout.rowStart[s]);
  // sized once per layout: resize keeps the capacity when the size is the same
  values_.resize(layout.numValues);
  workspaceThreads_ = executor_ != nullptr ? executor_->GetNumThreads() : 1;
  maxRows_ = maxRows;
  auto const size = [&](auto& work) {
    work.inverseDiagonal.resize(static_cast<std::size_t>(layout.size));
    work.permuted.resize(static_cast<std::size_t>(layout.size));
    work.block.resize(static_cast<std::size_t>(maxRows) * workspaceThreads_);
  };
  if (floatArithmetic_)
    size(floatWork_);
  else
    size(doubleWork_);
  Partition();

  constexpr double kFloatMax = std::numeric_limits<float>::max();
  for (std::size_t e = 0; e < layout.numValues; ++e) {
    double const value = values[e];
    if (!(std::abs(value) <= kFloatMax)) {
      reason_ = "an entry of L does not fit a float";
      return false;
    }
    values_[e] = static_cast<float>(value);
  }
  double minDiagonal = std::numeric_limits<double>::infinity(), maxDiagonal = 0;
  for (int s = 0; s < layout.numSupernodes; ++s) {
    int const numCols = layout.super[s + 1] - layout.super[s];
    int const numRows = layout.rowStart[s + 1] - layout.rowStart[s];
    for (int j = 0; j < numCols; ++j) {
      double const diagonal = values_[layout.valueStart[s] + j + std::size_t(j) * numRows];
      if (!(diagonal > 0)) {
        reason_ = "a diagonal entry of L is not positive as a float";
        return false;
      }
      if (floatArithmetic_)
        floatWork_.inverseDiagonal[layout.super[s] + j] = 1 / float(diagonal);
      else
        doubleWork_.inverseDiagonal[layout.super[s] + j] = 1 / diagonal;
      minDiagonal = std::min(minDiagonal, diagonal);
      maxDiagonal = std::max(maxDiagonal, diagonal);
    }
  }
  diagonalSpread_ = layout.size > 0 ? maxDiagonal / minDiagonal : 1;
  if (diagonalSpread_ >= kMaxDiagonalSpread) {
    reason_ = "the spread of L's diagonal (GetDiagonalSpread) is >= kMaxDiagonalSpread";
    return false;
  }
  assigned_ = true;
  return true;
}

SinglePrecisionFactor::Supernode SinglePrecisionFactor::View(int s) const {
  SupernodalLayout const& layout = layout_;
  int const first = layout.super[s];
  return {first,
          layout.super[s + 1] - first,
          layout.rowStart[s + 1] - layout.rowStart[s],
          layout.rows + layout.rowStart[s],
          values_.data() + layout.valueStart[s]};
}

template <class T>
void SinglePrecisionFactor::ForwardSupernode(int s, T* w, T* topBuffer) {
  // L y = P b for supernode s: its rows of y into w (zero below its own
  // columns), then per block of up to four columns the block's small
  // triangle, and one pass over the rows under it (the rest of the
  // supernode's triangle and the rows below, contiguous in each column);
  // w scattered back, rows of the top to topBuffer when given (a group's
  // own sums)
  T* y = Work<T>().permuted.data();
  auto const [first, numCols, numRows, rows, block] = View(s);
  T const* inverse = Work<T>().inverseDiagonal.data() + first;
  for (int j = 0; j < numCols; ++j) w[j] = y[first + j];
  std::fill(w + numCols, w + numRows, T(0));
  for (int j = 0; j < numCols; j += 4) {
    int const width = std::min(4, numCols - j);
    float const* column = block + std::size_t(j) * numRows;  // column j, row 0
    for (int k = 0; k < width; ++k) {
      float const* columnK = column + std::size_t(k) * numRows;
      T const wk = w[j + k] * inverse[j + k];
      w[j + k] = wk;
      for (int m = k + 1; m < width; ++m) w[j + m] -= T(columnK[j + m]) * wk;
    }
    int const next = j + width;
    if (width == 4) {
      SubtractScaled4(column + next, numRows, w + j, w + next, numRows - next);
    } else {
      for (int k = 0; k < width; ++k)
        SubtractScaled(column + std::size_t(k) * numRows + next, w[j + k], w + next, numRows - next);
    }
  }
  for (int j = 0; j < numCols; ++j) y[first + j] = w[j];
  if (topBuffer == nullptr) {
    for (int i = numCols; i < numRows; ++i) y[rows[i]] += w[i];
  } else {
    for (int i = numCols; i < numRows; ++i) {
      int const top = topIndex_[rows[i]];
      if (top >= 0)
        topBuffer[top] += w[i];
      else
        y[rows[i]] += w[i];
    }
  }
}

template <class T>
void SinglePrecisionFactor::BackwardSupernode(int s, T* w) {
  // Lᵀ z = y for supernode s: w gathers its rows of y (those below its own
  // columns already solved), then per block of up to four columns from the
  // last, one pass over the rows under the block (dot products with the
  // solved values) and the block's small triangle
  T* y = Work<T>().permuted.data();
  auto const [first, numCols, numRows, rows, block] = View(s);
  T const* inverse = Work<T>().inverseDiagonal.data() + first;
  for (int i = 0; i < numRows; ++i) w[i] = y[rows[i]];
  for (int j = (numCols - 1) / 4 * 4; j >= 0; j -= 4) {
    int const width = std::min(4, numCols - j);
    float const* column = block + std::size_t(j) * numRows;
    int const next = j + width;
    T d[4];
    if (width == 4) {
      Dot4(column + next, numRows, w + next, numRows - next, d);
    } else {
      for (int k = 0; k < width; ++k)
        d[k] = Dot(column + std::size_t(k) * numRows + next, w + next, numRows - next);
    }
    for (int k = width - 1; k >= 0; --k) {
      float const* columnK = column + std::size_t(k) * numRows;
      T sum = w[j + k] - d[k];
      for (int m = k + 1; m < width; ++m) sum -= T(columnK[j + m]) * w[j + m];
      w[j + k] = sum * inverse[j + k];
    }
  }
  for (int j = 0; j < numCols; ++j) y[first + j] = w[j];
}

template <class F>
void SinglePrecisionFactor::RunGroups(F const& body) const {
  // (an executor given more threads since Assign sized the workspaces runs
  // the groups on this thread instead: the same result)
  if (executor_ != nullptr && executor_->GetNumThreads() <= workspaceThreads_)
    executor_->For(numGroups_, 1, body);
  else if (numGroups_ > 0)
    body(0, numGroups_, 0);
}

void SinglePrecisionFactor::Solve(double const* b, double* x) {
  if (floatArithmetic_)
    SolveIn<float>(b, x);
  else
    SolveIn<double>(b, x);
}

template <class T>
void SinglePrecisionFactor::SolveIn(double const* b, double* x) {
  SupernodalLayout const& layout = layout_;
  Workspace<T>& work = Work<T>();
  int const n = layout.size;
  int const* perm = layout.permutation;
  T* y = work.permuted.data();
  for (int k = 0; k < n; ++k) y[k] = T(b[perm != nullptr ? perm[k] : k]);

  // forward: the groups' subtrees concurrently (each writes only its own
  // columns, and its sums into the top to its own buffer), the buffers added
  // in group order, then the top in order
  int const numTop = static_cast<int>(topColumns_.size());
  std::fill(work.groupBuffers.begin(), work.groupBuffers.end(), T(0));
  auto const forwardGroups = [&](int begin, int end, int thread) {
    T* w = work.block.data() + std::size_t(thread) * maxRows_;
    for (int g = begin; g < end; ++g) {
      T* buffer = work.groupBuffers.data() + std::size_t(g) * numTop;
      for (int t = groupStart_[g]; t < groupStart_[g + 1]; ++t)
        for (int s = firstDescendant_[subtreeRoots_[t]]; s <= subtreeRoots_[t]; ++s)
          ForwardSupernode<T>(s, w, buffer);
    }
  };
  RunGroups(forwardGroups);
  for (int g = 0; g < numGroups_; ++g) {
    T const* buffer = work.groupBuffers.data() + std::size_t(g) * numTop;
    for (int i = 0; i < numTop; ++i) y[topColumns_[i]] += buffer[i];
  }
  for (int s : topSupernodes_) ForwardSupernode<T>(s, work.block.data(), nullptr);

  // backward: the top last to first, then the groups' subtrees concurrently
  // (each reads the top and writes only its own columns)
  for (auto s = topSupernodes_.rbegin(); s != topSupernodes_.rend(); ++s)
    BackwardSupernode<T>(*s, work.block.data());
  auto const backwardGroups = [&](int begin, int end, int thread) {
    T* w = work.block.data() + std::size_t(thread) * maxRows_;
    for (int g = begin; g < end; ++g)
      for (int t = groupStart_[g]; t < groupStart_[g + 1]; ++t)
        for (int s = subtreeRoots_[t]; s >= firstDescendant_[subtreeRoots_[t]]; --s) BackwardSupernode<T>(s, w);
  };
  RunGroups(backwardGroups);

  for (int k = 0; k < n; ++k) x[perm != nullptr ? perm[k] : k] = double(y[k]);
}

}  // namespace superdex::internal
