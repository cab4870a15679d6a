// Independent reference solution of the large-deflection elastica of an end-loaded
// cantilever (Bisshopp & Drucker 1945), for checking rod / shell actors.
//
// Problem: inextensible, unshearable Euler–Bernoulli rod of length L and bending
// stiffness EI, clamped at s = 0 with tangent +x, dead load (0, −P) at the free end
// s = L, no self weight. θ(s) is the tangent angle from +x (counterclockwise
// positive); with σ = s/L and α = P L² / (E I) (′ = d/dσ):
//   bending moment  EI θ′(s) = −P (x(L) − x(s))   (the end load bends it down)
//   ⇒  θ″ = α cos θ,   θ(0) = 0,   θ′(1) = 0 (free end carries no moment),
//   x′ = cos θ, y′ = sin θ, x(0) = y(0) = 0 (positions in units of L).
// First integral: θ′²/2 − α sin θ = θ′(0)²/2, so with k = −θ′(0) > 0 the rod's
// curvature can vanish only where sin θ = −k²/(2α), and never if k² ≥ 2α.
//
// Method: shooting on k = −θ′(0). For each k the initial value problem is
// integrated with classical RK4 on a fixed grid of `steps` (default 20000), and
// f(k) = θ′(1) is driven to zero. Physical (first-mode) branch: θ decreases
// monotonically from 0 to the tip angle −φ₀ > −π/2 and θ′ < 0 on [0, 1). For k
// above the first-mode root θ′ stays negative up to σ = 1 (f < 0); just below it
// θ′ reaches zero before σ = 1 and turns positive (f > 0); much smaller k give
// pendulum-like oscillating shapes whose further roots are the buckled higher
// modes. Since θ′(0) = −α x(1) and x(1) ≤ 1, the root lies in (0, min(α, √(2α))],
// where f < 0. So the root taken is the LARGEST one: k is scanned downward from
// kHi = min(α, √(2α)) in kHi/256 steps to the first sign change, then bisected to
// |Δk| ≤ 1e-13 (relative to max(1, k)). This is the branch continuously
// connected to small α (δ/L ≈ α/3, θ(L) ≈ −α/2, x/L ≈ 1 − α²/15).
//
// Accuracy: RK4's global error is O(h⁴) with h = 5e-5; halving the step changes
// the results by ≤ 4e-14 for α ≤ 10 (≤ 2e-11 at α = 100), and they match the
// classical elliptic-integral solution (k² = (1 + sin φ₀)/2, sin φ₁ = 1/(k√2),
// √α = K(k) − F(k, φ₁), x/L = √(2 sin φ₀/α), δ/L = 1 − 2(E(k) − E(k, φ₁))/√α)
// to ≤ 1e-11 for 0.05 ≤ α ≤ 50. Reference values (x/L, δ/L, φ₀ = −θ(L) in rad):
//   α = 1: 0.94357, 0.30172, 0.46135      α = 3: 0.74558, 0.60325, 0.98602
//   α = 2: 0.83936, 0.49346, 0.78175      α = 5: 0.61237, 0.71379, 1.21537
// Valid for α > 0 (checked up to 100, where φ₀ → π/2); α ≤ 0 returns (1, 0, 0).
// Cost: ~40 ms per call at -O2 (about 60 integrations of 20000 steps).
#pragma once

#include <algorithm>
#include <cmath>

namespace superdex::test {

/// Tip of the end-loaded cantilever, in units of L.
struct ElasticaTip {
  double horizontal;  ///< x(L)/L, horizontal tip position
  double vertical;    ///< −y(L)/L, tip deflection (positive down)
  double tipAngle;    ///< −θ(L) in radians (positive: tip points below horizontal)
};

namespace elastica_detail {

struct State {
  double theta, dtheta, x, y;
};

// Integrates θ″ = α cos θ, x′ = cos θ, y′ = sin θ over σ ∈ [0, 1] from
// θ(0) = 0, θ′(0) = −k with `steps` RK4 steps.
inline State Integrate(double alpha, double k, int steps) {
  auto rhs = [alpha](const State& s) {
    const double c = std::cos(s.theta);
    return State{s.dtheta, alpha * c, c, std::sin(s.theta)};
  };
  auto axpy = [](const State& s, double a, const State& d) {
    return State{s.theta + a * d.theta, s.dtheta + a * d.dtheta, s.x + a * d.x, s.y + a * d.y};
  };
  const double h = 1.0 / steps;
  State s{0.0, -k, 0.0, 0.0};
  for (int i = 0; i < steps; ++i) {
    const State k1 = rhs(s);
    const State k2 = rhs(axpy(s, 0.5 * h, k1));
    const State k3 = rhs(axpy(s, 0.5 * h, k2));
    const State k4 = rhs(axpy(s, h, k3));
    s.theta += h / 6.0 * (k1.theta + 2.0 * k2.theta + 2.0 * k3.theta + k4.theta);
    s.dtheta += h / 6.0 * (k1.dtheta + 2.0 * k2.dtheta + 2.0 * k3.dtheta + k4.dtheta);
    s.x += h / 6.0 * (k1.x + 2.0 * k2.x + 2.0 * k3.x + k4.x);
    s.y += h / 6.0 * (k1.y + 2.0 * k2.y + 2.0 * k3.y + k4.y);
  }
  return s;
}

}  // namespace elastica_detail

/// Solves the end-loaded cantilever elastica for α = P L²/(EI) ≥ 0 (first mode).
/// `steps` is the number of RK4 steps (at least 20000 by default).
inline ElasticaTip SolveCantileverElastica(double alpha, int steps = 20000) {
  using elastica_detail::Integrate;
  if (alpha <= 0.0) return {1.0, 0.0, 0.0};
  auto f = [&](double k) { return Integrate(alpha, k, steps).dtheta; };
  double hi = std::min(alpha, std::sqrt(2.0 * alpha));  // f(hi) < 0
  const double dk = hi / 256.0;
  double lo = hi - dk;
  while (lo > 0.0 && f(lo) < 0.0) {  // scan down to the largest sign change
    hi = lo;
    lo -= dk;
  }
  lo = std::max(lo, 0.0);  // f(0⁺) = α > 0 for the straight rod
  while (hi - lo > 1e-13 * std::max(1.0, hi)) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (f(mid) < 0.0 ? hi : lo) = mid;
  }
  const elastica_detail::State s = Integrate(alpha, 0.5 * (lo + hi), steps);
  return {s.x, -s.y, -s.theta};
}

}  // namespace superdex::test
