// SPD (and deliberately broken) test systems for the linear-solver tests, in
// the upper-triangle CSC layout of sparse_symmetric_matrix.h, and the
// residual that judges a solution. Test-only code: allocation is fine here.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex::test {

/// Upper-triangle entries (row <= col) keyed by (row, col), summed on insert.
class UpperEntries {
 public:
  explicit UpperEntries(int size) : size_(size) {}

  /// Adds v to A(i, j) of the symmetric matrix (either triangle).
  void Add(int i, int j, real v) {
    if (i > j) std::swap(i, j);
    entries_[{j, i}] += v;  // keyed (col, row) so that iteration is column-major
  }

  /// The CSC matrix with the given pattern version.
  SparseSymmetricMatrix ToMatrix(std::uint64_t patternVersion = 1) const {
    SparseSymmetricMatrix a;
    a.size = size_;
    a.patternVersion = patternVersion;
    a.colStart.assign(size_ + 1, 0);
    for (auto const& [key, value] : entries_) {
      a.colStart[key.first + 1] += 1;
      a.rowIndex.push_back(key.second);
      a.values.push_back(value);
    }
    for (int j = 0; j < size_; ++j) a.colStart[j + 1] += a.colStart[j];
    return a;
  }

 private:
  int size_;
  std::map<std::pair<int, int>, real> entries_;
};

/// 5-point Laplacian on an nx x ny grid (lexicographic order) plus shift * I.
inline SparseSymmetricMatrix Laplacian2d(int nx, int ny, real shift) {
  UpperEntries e(nx * ny);
  auto const id = [nx](int x, int y) { return x + nx * y; };
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) {
      e.Add(id(x, y), id(x, y), 4 + shift);
      if (x + 1 < nx) e.Add(id(x, y), id(x + 1, y), -1);
      if (y + 1 < ny) e.Add(id(x, y), id(x, y + 1), -1);
    }
  }
  return e.ToMatrix();
}

/// 7-point Laplacian on an n^3 grid (lexicographic order) plus shift * I.
inline SparseSymmetricMatrix Laplacian3d(int n, real shift) {
  UpperEntries e(n * n * n);
  auto const id = [n](int x, int y, int z) { return x + n * (y + n * z); };
  for (int z = 0; z < n; ++z) {
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        e.Add(id(x, y, z), id(x, y, z), 6 + shift);
        if (x + 1 < n) e.Add(id(x, y, z), id(x + 1, y, z), -1);
        if (y + 1 < n) e.Add(id(x, y, z), id(x, y + 1, z), -1);
        if (z + 1 < n) e.Add(id(x, y, z), id(x, y, z + 1), -1);
      }
    }
  }
  return e.ToMatrix();
}

/// numBlocks blocks of blockSize DoFs; each pair of blocks is coupled with
/// probability couplingProbability by an "element" G G' (G random, 2
/// blockSize x blockSize), every block gets a random mass diagonal in [1, 2].
/// SPD by construction: a positive diagonal plus a sum of PSD terms.
inline SparseSymmetricMatrix RandomBlockSpd(int numBlocks, int blockSize, real couplingProbability,
                                            unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<real> uniform(-1, 1);
  std::uniform_real_distribution<real> unit(0, 1);
  int const n = numBlocks * blockSize;
  UpperEntries e(n);
  for (int i = 0; i < n; ++i) e.Add(i, i, 1 + unit(rng));
  for (int bi = 0; bi < numBlocks; ++bi) {
    for (int bj = bi + 1; bj < numBlocks; ++bj) {
      if (unit(rng) >= couplingProbability) continue;
      MatrixX g(2 * blockSize, blockSize);
      for (Eigen::Index k = 0; k < g.size(); ++k) g.data()[k] = uniform(rng);
      MatrixX const local = g * g.transpose();
      auto const dof = [&](int localIndex) {
        return localIndex < blockSize ? bi * blockSize + localIndex
                                      : bj * blockSize + localIndex - blockSize;
      };
      for (int r = 0; r < 2 * blockSize; ++r) {
        for (int c = r; c < 2 * blockSize; ++c) e.Add(dof(r), dof(c), local(r, c));
      }
    }
  }
  return e.ToMatrix();
}

/// Two independent tridiagonal chains interleaved: even columns form one
/// chain, odd columns the other. Diagonal 4, couplings -1. Its elimination
/// tree is two paths whose columns alternate, so a postorder of it is not
/// the identity.
inline SparseSymmetricMatrix InterleavedChains(int size) {
  UpperEntries e(size);
  for (int i = 0; i < size; ++i) {
    e.Add(i, i, 4);
    if (i + 2 < size) e.Add(i, i + 2, -1);
  }
  return e.ToMatrix();
}

/// The matrix of a file of "row col value" lines of the upper triangle after
/// one comment line (tests/linsolve/data); size 0 when it cannot be read.
inline SparseSymmetricMatrix ReadUpperTriangle(std::string const& path) {
  std::ifstream in(path);
  std::string comment;
  if (!std::getline(in, comment)) return {};
  struct Entry {
    int row, col;
    real value;
  };
  std::vector<Entry> entries;
  int row = 0, col = 0, size = 0;
  real value = 0;
  while (in >> row >> col >> value) {
    entries.push_back({row, col, value});
    size = std::max(size, col + 1);
  }
  UpperEntries upper(size);
  for (Entry const& entry : entries) upper.Add(entry.row, entry.col, entry.value);
  return upper.ToMatrix();
}

/// Where a scrambled chain of 400 DoFs puts its i-th link (157 and 400 are
/// coprime: a permutation).
inline int ScrambledChainPosition(int i) { return (i * 157) % 400; }

/// A tridiagonal chain of 400 DoFs (a rod, in effect: diagonal 2.001,
/// couplings −1) with link i at column ScrambledChainPosition(i): no band in
/// the given order, a band after reverse Cuthill–McKee.
inline SparseSymmetricMatrix ScrambledChain() {
  int const n = 400;
  UpperEntries e(n);
  for (int i = 0; i < n; ++i) {
    e.Add(ScrambledChainPosition(i), ScrambledChainPosition(i), 2.001);
    if (i + 1 < n) e.Add(ScrambledChainPosition(i), ScrambledChainPosition(i + 1), -1);
  }
  return e.ToMatrix();
}

/// A copy of `a` whose diagonal entry at `column` is `value`.
inline SparseSymmetricMatrix WithDiagonal(SparseSymmetricMatrix a, int column, real value) {
  // the diagonal is the last stored entry of its column
  a.values[a.colStart[column + 1] - 1] = value;
  return a;
}

/// A deterministic right-hand side with entries in [-1, 1] and none zero.
inline VectorX TestRhs(int size, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<real> uniform(0.1, 1);
  VectorX b(size);
  for (int i = 0; i < size; ++i) b[i] = (i % 2 == 0 ? 1 : -1) * uniform(rng);
  return b;
}

/// Spans over a vector, for Solve's arguments.
inline Span<real const> View(VectorX const& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}
inline Span<real> View(VectorX& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}

/// y = A x for the symmetric A stored by its upper triangle.
inline VectorX Multiply(SparseSymmetricMatrix const& a, VectorX const& x) {
  VectorX y = VectorX::Zero(a.size);
  for (int j = 0; j < a.size; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
      int const i = a.rowIndex[k];
      y[i] += a.values[k] * x[j];
      if (i != j) y[j] += a.values[k] * x[i];
    }
  }
  return y;
}

/// ||A x - b|| / ||b||.
inline real RelativeResidual(SparseSymmetricMatrix const& a, VectorX const& x, VectorX const& b) {
  return (Multiply(a, x) - b).norm() / b.norm();
}

}  // namespace superdex::test
