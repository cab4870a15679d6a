// Shared helpers of the contact kernels' tests: fixed-size central
// differences and well-conditioned random primitive pairs.
#pragma once

#include <array>
#include <map>
#include <random>

#include <superdex/contact/distance.h>

namespace superdex::test {

template <int n>
using Vec = contact::LocalVector<n>;
template <int n>
using Mat = contact::LocalMatrix<n>;

/// Node i (coordinates 3i … 3i + 2) of a stacked vector.
template <int n>
Real3 Node(Vec<n> const& x, int i) {
  return x.template segment<3>(3 * i);
}

inline Real3 RandomPoint(std::mt19937& rng, real scale = 1) {
  std::uniform_real_distribution<real> uniform(-scale, scale);
  return Real3(uniform(rng), uniform(rng), uniform(rng));
}

inline real Uniform(std::mt19937& rng, real lo, real hi) {
  return std::uniform_real_distribution<real>(lo, hi)(rng);
}

inline real MaxAbs(MatrixX const& a) {
  return a.cwiseAbs().maxCoeff();
}

/// max |a − b| relative to the largest entry of the analytic `a`.
inline real RelativeError(MatrixX const& a, MatrixX const& b) {
  return MaxAbs(a - b) / MaxAbs(a);
}

/// Central differences of the scalar f at x, step `step` per coordinate.
template <int n, class F>
Vec<n> CentralGradient(F const& f, Vec<n> const& x, real step) {
  Vec<n> g;
  for (int i = 0; i < n; ++i) {
    Vec<n> xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    g[i] = (f(xp) - f(xm)) / (2 * step);
  }
  return g;
}

/// Central differences of the vector function grad at x (its Jacobian).
template <int n, class G>
Mat<n> CentralJacobian(G const& grad, Vec<n> const& x, real step) {
  Mat<n> j;
  for (int i = 0; i < n; ++i) {
    Vec<n> xp = x, xm = x;
    xp[i] += step;
    xm[i] -= step;
    j.col(i) = (grad(xp) - grad(xm)) / (2 * step);
  }
  return j;
}

/// The sine² of the angle between a and b.
inline real Sin2(Real3 const& a, Real3 const& b) {
  return a.cross(b).squaredNorm() / (a.squaredNorm() * b.squaredNorm());
}

/// A triangle with edges >= 0.3 and sine² of every angle >= 0.05, so that
/// every feature's distance is well conditioned for central differences.
inline std::array<Real3, 3> RandomTriangle(std::mt19937& rng) {
  for (;;) {
    std::array<Real3, 3> const t = {RandomPoint(rng), RandomPoint(rng), RandomPoint(rng)};
    bool ok = true;
    for (int i = 0; i < 3; ++i) {
      Real3 const a = t[(i + 1) % 3] - t[i], b = t[(i + 2) % 3] - t[i];
      ok = ok && a.norm() >= 0.3 && Sin2(a, b) >= 0.05;
    }
    if (ok) return t;
  }
}

/// A point around the triangle: barycentric coordinates in [−1, 2] (so every
/// feature is closest for some) and an offset along the normal in [−1, 1].
inline Real3 RandomPointNear(std::mt19937& rng, std::array<Real3, 3> const& t) {
  Real3 const u = t[1] - t[0], v = t[2] - t[0];
  Real3 const n = u.cross(v).normalized();
  return t[0] + Uniform(rng, -1, 2) * u + Uniform(rng, -1, 2) * v + Uniform(rng, -1, 1) * n;
}

/// Two segments with lengths >= 0.3 and sine² of the angle >= 0.05.
inline std::array<Real3, 4> RandomEdgePair(std::mt19937& rng) {
  for (;;) {
    std::array<Real3, 4> const e = {RandomPoint(rng), RandomPoint(rng), RandomPoint(rng), RandomPoint(rng)};
    Real3 const a = e[1] - e[0], b = e[3] - e[2];
    if (a.norm() >= 0.3 && b.norm() >= 0.3 && Sin2(a, b) >= 0.05) return e;
  }
}

inline Vec<12> Pack(Real3 const& a, Real3 const& b, Real3 const& c, Real3 const& d) {
  Vec<12> x;
  x << a, b, c, d;
  return x;
}

/// Every one of the `types` enumerators has `count` entries in `seen`.
inline bool AllReached(std::map<int, int> const& seen, int types, int count) {
  for (int t = 0; t < types; ++t)
    if (!seen.contains(t) || seen.at(t) < count) return false;
  return true;
}

}  // namespace superdex::test
