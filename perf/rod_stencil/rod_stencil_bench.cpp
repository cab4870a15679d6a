// superdex_rod_stencil: single-thread cost of the discrete elastic rod's
// bending–twisting stencil (actors/rod_element.h), the per-interior-node work
// of every Newton iteration of a rod: gradient (11) and exact Hessian (11×11),
// with and without the 8×8 eigenvalue clamp, for the fast kernel
// (RodBendTwistGradientHessian) and its Jet<8> reference
// (RodBendTwistGradientHessianJet), and the energy alone.
//
// The stencils are random, like those of a rod in motion: edges 0.05–0.15 m in
// random directions, the second turned from the first by up to --turn degrees
// (default 60), twists in [−1, 1] rad, stage frames tilted by up to 0.05 rad
// off the current tangents (one step old) and spun at random, EI₁ = 2,
// EI₂ = 3.5, GJ = 1.5, rest strains in [−1, 1].
//
// Per variant it reports µs per stencil, each batch of 100 stencils timed
// as its best of --repeats runs (so that a machine shared with other work
// still gives the unpreempted figure), the ratio to the Jet<8> reference and,
// for the projected variants, the share of the time spent in the 8×8
// eigenvalue clamp, (t_projected − t_exact) / t_projected. It also reports the
// largest difference of the fast kernel's gradient and Hessian from the
// reference's over all stencils, relative to the reference's largest entry
// (gradient: at least 1).
//
// Usage: superdex_rod_stencil [--stencils N] [--repeats R] [--turn degrees]
#include <superdex/actors/rod_element.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

using superdex::real;
using superdex::Real3;
using superdex::internal::Matrix11;
using superdex::internal::RodReferenceFrame;
using superdex::internal::RodStencilRest;
using superdex::internal::RodStiffness;
using superdex::internal::Vector11;
using Clock = std::chrono::steady_clock;

struct Stencil {
  Real3 edgeA, edgeB;
  real thetaA, thetaB;
  RodReferenceFrame refA, refB;
  RodStencilRest rest;
  real refTwistStart;
};

RodStiffness const kStiffness{50.0, 2.0, 3.5, 1.5};

/// The stage frame of an edge: its tangent tilted by `tilt` about a random
/// axis, the director at a random angle about it.
RodReferenceFrame StageFrame(Real3 const& edge, real tilt, std::mt19937& rng) {
  std::normal_distribution<real> normal;
  std::uniform_real_distribution<real> angle(-std::numbers::pi_v<real>, std::numbers::pi_v<real>);
  Real3 const axis = Real3(normal(rng), normal(rng), normal(rng)).normalized();
  Real3 const t = (Eigen::AngleAxis<real>(tilt, axis) * edge.normalized()).normalized();
  Real3 const any = std::abs(t.x()) < 0.9 ? Real3::UnitX() : Real3::UnitY();
  Real3 const u = (any - any.dot(t) * t).normalized();
  return {t, Eigen::AngleAxis<real>(angle(rng), t) * u};
}

std::vector<Stencil> MakeStencils(int count, real maxTurn) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<real> unit(0, 1), symmetric(-1, 1);
  std::normal_distribution<real> normal;
  auto direction = [&] { return Real3(normal(rng), normal(rng), normal(rng)).normalized(); };
  std::vector<Stencil> stencils(count);
  for (Stencil& s : stencils) {
    Real3 const tA = direction();
    Real3 const tB =
        Eigen::AngleAxis<real>(maxTurn * unit(rng), tA.cross(direction()).normalized()) * tA;
    s.edgeA = (0.05 + 0.1 * unit(rng)) * tA;
    s.edgeB = (0.05 + 0.1 * unit(rng)) * tB;
    s.thetaA = symmetric(rng);
    s.thetaB = symmetric(rng);
    s.refA = StageFrame(s.edgeA, 0.05 * unit(rng), rng);
    s.refB = StageFrame(s.edgeB, 0.05 * unit(rng), rng);
    s.rest.voronoiLength = 0.5 * (s.edgeA.norm() + s.edgeB.norm());
    s.rest.strain = Real3(symmetric(rng), symmetric(rng), symmetric(rng));
    s.refTwistStart = superdex::internal::RodReferenceTwist(s.edgeA, s.edgeB, s.refA, s.refB, 0);
  }
  return stencils;
}

/// Wall time of each of `passes` (called as pass(begin, end)) over all n
/// stencils [s]: the stencils are timed in batches of kBatch, each batch's best
/// of `repeats` runs, summed; the passes take turns on each batch, so that all
/// of them see the same machine. On a machine shared with other work a batch
/// (0.1–2 ms) mostly runs without being preempted, where a whole pass would not.
constexpr int kBatch = 100;
template <class Pass>
std::vector<double> Best(int n, int repeats, std::vector<Pass> const& passes) {
  std::vector<double> total(passes.size(), 0);
  for (int begin = 0; begin < n; begin += kBatch) {
    int const end = std::min(n, begin + kBatch);
    std::vector<double> best(passes.size(), 1e300);
    for (int r = 0; r < repeats; ++r) {
      for (size_t p = 0; p < passes.size(); ++p) {
        auto const start = Clock::now();
        passes[p](begin, end);
        best[p] = std::min(best[p], std::chrono::duration<double>(Clock::now() - start).count());
      }
    }
    for (size_t p = 0; p < passes.size(); ++p) total[p] += best[p];
  }
  return total;
}

std::string CpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

volatile real gSink = 0;  // keeps every result observable

using Kernel = void (*)(RodStiffness const&, RodStencilRest const&, Real3 const&, Real3 const&,
                        real, real, RodReferenceFrame const&, RodReferenceFrame const&, real,
                        Vector11&, Matrix11&, bool);

void Evaluate(Kernel kernel, Stencil const& s, Vector11& gradient, Matrix11& hessian,
              bool project) {
  kernel(kStiffness, s.rest, s.edgeA, s.edgeB, s.thetaA, s.thetaB, s.refA, s.refB, s.refTwistStart,
         gradient, hessian, project);
}

}  // namespace

int main(int argc, char** argv) {
  int numStencils = 20000, repeats = 20;
  real turnDegrees = 60;
  for (int i = 1; i < argc; ++i) {
    auto next = [&](char const* name) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--stencils"))
      numStencils = std::atoi(next("--stencils"));
    else if (!std::strcmp(argv[i], "--repeats"))
      repeats = std::atoi(next("--repeats"));
    else if (!std::strcmp(argv[i], "--turn"))
      turnDegrees = std::atof(next("--turn"));
    else {
      std::fprintf(stderr, "usage: %s [--stencils N] [--repeats R] [--turn degrees]\n", argv[0]);
      return 2;
    }
  }
  if (numStencils < 1 || repeats < 1 || !(turnDegrees >= 0 && turnDegrees <= 170)) {
    std::fprintf(stderr, "invalid arguments (--turn must be in [0, 170])\n");
    return 2;
  }

  std::vector<Stencil> const stencils =
      MakeStencils(numStencils, turnDegrees * std::numbers::pi_v<real> / 180);
  int const n = numStencils;
  Kernel const fast = superdex::internal::RodBendTwistGradientHessian;
  Kernel const reference = superdex::internal::RodBendTwistGradientHessianJet;

  std::printf(
      "superdex_rod_stencil: one thread, %d stencils, each batch of %d the best of %d runs\n", n,
      kBatch, repeats);
  std::printf("cpu: %s\n", CpuModel().c_str());
  std::printf("build: %s, compiler flags of the library: %s\n", SUPERDEX_PERF_BUILD_TYPE,
              SUPERDEX_PERF_CXX_FLAGS);
  std::printf(
      "stencils: edges 0.05-0.15 m turned by up to %.3g deg, twists in [-1, 1], stage frames "
      "tilted up to 0.05 rad\n",
      static_cast<double>(turnDegrees));

  // how far the fast kernel is from the reference (not timed)
  real gradientDeviation = 0, hessianDeviation = 0;
  for (bool project : {false, true}) {
    for (Stencil const& s : stencils) {
      Vector11 g, gRef;
      Matrix11 h, hRef;
      Evaluate(fast, s, g, h, project);
      Evaluate(reference, s, gRef, hRef, project);
      gradientDeviation =
          std::max(gradientDeviation, (g - gRef).lpNorm<Eigen::Infinity>() /
                                          std::max<real>(gRef.lpNorm<Eigen::Infinity>(), 1));
      hessianDeviation = std::max(
          hessianDeviation, (h - hRef).lpNorm<Eigen::Infinity>() / hRef.lpNorm<Eigen::Infinity>());
    }
  }
  std::printf(
      "fast vs Jet<8> reference, largest relative difference: gradient %.2e, Hessian %.2e\n",
      static_cast<double>(gradientDeviation), static_cast<double>(hessianDeviation));

  using Pass = std::function<void(int, int)>;
  Pass const energyPass = [&](int begin, int end) {
    real sum = 0;
    for (int i = begin; i < end; ++i) {
      Stencil const& s = stencils[i];
      sum += superdex::internal::RodBendTwistEnergy(kStiffness, s.rest, s.edgeA, s.edgeB, s.thetaA,
                                                    s.thetaB, s.refA, s.refB, s.refTwistStart);
    }
    gSink = gSink + sum;
  };
  auto kernelPass = [&](Kernel kernel, bool project) -> Pass {
    return [&stencils, kernel, project](int begin, int end) {
      Vector11 gradient;
      Matrix11 hessian;
      real sum = 0;
      for (int i = begin; i < end; ++i) {
        Evaluate(kernel, stencils[i], gradient, hessian, project);
        sum += gradient[4] + hessian(7, 2);
      }
      gSink = gSink + sum;
    };
  };
  std::vector<double> const seconds =
      Best(n, repeats,
           std::vector<Pass>{energyPass, kernelPass(reference, false), kernelPass(fast, false),
                             kernelPass(reference, true), kernelPass(fast, true)});
  double const energy = seconds[0], referenceExact = seconds[1], fastExact = seconds[2];
  double const referenceProjected = seconds[3], fastProjected = seconds[4];

  std::printf("\n%-32s %12s %14s %18s\n", "variant", "us/stencil", "vs reference",
              "projection share");
  std::printf("%-32s %12.3f\n", "energy", 1e6 * energy / n);
  auto report = [&](char const* variant, double seconds, double referenceSeconds,
                    double exactSeconds) {
    std::printf("%-32s %12.3f %13.2fx", variant, 1e6 * seconds / n, referenceSeconds / seconds);
    if (exactSeconds > 0) std::printf(" %17.1f%%", 100.0 * (seconds - exactSeconds) / seconds);
    std::printf("\n");
  };
  report("Jet<8> reference, exact", referenceExact, referenceExact, 0);
  report("fast, exact", fastExact, referenceExact, 0);
  report("Jet<8> reference, projected", referenceProjected, referenceProjected, referenceExact);
  report("fast, projected", fastProjected, referenceProjected, fastExact);
  std::printf(
      "\nprojection share = (t_projected - t_exact) / t_projected: the 8x8 eigenvalue clamp\n");
  std::printf("\n(sink %g)\n", static_cast<double>(gSink));
  return 0;
}
