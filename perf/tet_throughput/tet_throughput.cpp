// superdex_tet_throughput: single-thread throughput of the linear-tetrahedron
// kernels (actors/tet_element.h), the per-element work of every Newton
// iteration of a volumetric deformable: energy, gradient (12) and Hessian
// (12×12), with and without the PSD projection of ∂²Ψ/∂F².
//
// The elements are random and mildly deformed, like those of a soft body
// in motion: a rest tetrahedron with edges ~0.1 m (a regular one with each
// node jittered by up to ±20 % of the edge, randomly oriented), deformed by
// x = R (I + δ) X + t with R a random rotation and δ uniform in [−s, s]
// per entry (s = --strain, default 0.15). E = 1e5 Pa, ν = --poisson (0.3).
//
// Per model and variant it reports the best of --repeats passes over all
// elements: ns per element and elements per second (one thread), and for the
// projected variants the share of the time spent projecting,
// (t_projected − t_exact) / t_projected. It also times the 9×9 projection
// alone (the exact ∂²Ψ/∂F², then each projection), and counts the elements
// whose ∂²Ψ/∂F² really was indefinite (smallest eigenvalue < −1e-12·largest).
//
// Usage: superdex_tet_throughput [--elements N] [--repeats R] [--strain s] [--poisson nu]
#include <superdex/core/symmetric_eigen.h>
#include <superdex/actors/tet_element.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace {

using superdex::real;
using superdex::Real3;
using superdex::Real33;
using superdex::TetMaterialModel;
using superdex::internal::LameParameters;
using superdex::internal::Matrix12;
using superdex::internal::Matrix9;
using superdex::internal::TetPsdProjection;
using superdex::internal::TetRestData;
using superdex::internal::Vector12;
using Clock = std::chrono::steady_clock;

struct Elements {
  std::vector<TetRestData> rest;
  std::vector<Vector12> x;
  std::vector<Real33> f;  // F of each element (for the projection-only timings)
};

Real33 RandomRotation(std::mt19937& rng) {
  std::normal_distribution<real> normal;
  Eigen::Quaternion<real> q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

Elements MakeElements(int count, real strain) {
  std::mt19937 rng(2024);
  std::uniform_real_distribution<real> uniform(-1, 1);
  real const edge = 0.1;
  // a regular tetrahedron of edge `edge`, positively oriented
  std::array<Real3, 4> const regular = {Real3(1, 1, 1), Real3(1, -1, -1), Real3(-1, 1, -1),
                                        Real3(-1, -1, 1)};
  Elements elements;
  elements.rest.reserve(count);
  elements.x.reserve(count);
  elements.f.reserve(count);
  while (static_cast<int>(elements.rest.size()) < count) {
    Real33 const orientation = RandomRotation(rng);
    std::array<Real3, 4> rest;
    for (int a = 0; a < 4; ++a) {
      Real3 const jitter(uniform(rng), uniform(rng), uniform(rng));
      rest[a] = orientation * (edge / std::sqrt(real(8)) * regular[a]) + 0.2 * edge * jitter;
    }
    if (Real33((Real33() << rest[1] - rest[0], rest[2] - rest[0], rest[3] - rest[0]).finished())
            .determinant() < 0)
      std::swap(rest[1], rest[2]);
    TetRestData data;
    if (!superdex::internal::MakeTetRestData(rest[0], rest[1], rest[2], rest[3], data)) continue;
    Real33 delta;
    for (int k = 0; k < 9; ++k) delta.data()[k] = strain * uniform(rng);
    Real33 const deformation = RandomRotation(rng) * (Real33::Identity() + delta);
    Real3 const translation(uniform(rng), uniform(rng), uniform(rng));
    Vector12 x;
    for (int a = 0; a < 4; ++a) x.segment<3>(3 * a) = deformation * rest[a] + translation;
    elements.rest.push_back(data);
    elements.x.push_back(x);
    elements.f.push_back(superdex::internal::TetDeformationGradient(data, x));
  }
  return elements;
}

/// Best wall time of `repeats` calls of `pass` [s].
template <class Pass>
double Best(int repeats, Pass&& pass) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    auto const start = Clock::now();
    pass();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - start).count());
  }
  return best;
}

std::string CpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

volatile real gSink = 0;  // keeps every result observable

}  // namespace

int main(int argc, char** argv) {
  int numElements = 1000000, repeats = 3;
  real strain = 0.15, poisson = 0.3;
  for (int i = 1; i < argc; ++i) {
    auto next = [&](char const* name) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", name);
        std::exit(2);
      }
      return argv[++i];
    };
    if (!std::strcmp(argv[i], "--elements"))
      numElements = std::atoi(next("--elements"));
    else if (!std::strcmp(argv[i], "--repeats"))
      repeats = std::atoi(next("--repeats"));
    else if (!std::strcmp(argv[i], "--strain"))
      strain = std::atof(next("--strain"));
    else if (!std::strcmp(argv[i], "--poisson"))
      poisson = std::atof(next("--poisson"));
    else {
      std::fprintf(stderr, "usage: %s [--elements N] [--repeats R] [--strain s] [--poisson nu]\n",
                   argv[0]);
      return 2;
    }
  }
  if (numElements < 1 || repeats < 1 || !(strain >= 0) || !(poisson > -1 && poisson < 0.5)) {
    std::fprintf(stderr, "invalid arguments\n");
    return 2;
  }

  LameParameters const lame = superdex::internal::LameFromYoungPoisson(1e5, poisson);
  Elements const elements = MakeElements(numElements, strain);
  int const n = numElements;

  std::printf("superdex_tet_throughput: one thread, %d elements, best of %d passes\n", n, repeats);
  std::printf("cpu: %s\n", CpuModel().c_str());
  std::printf("build: %s, compiler flags of the library: %s\n", SUPERDEX_PERF_BUILD_TYPE,
              SUPERDEX_PERF_CXX_FLAGS);
  char const* coretype = std::getenv("OPENBLAS_CORETYPE");
  std::printf("OPENBLAS_CORETYPE=%s (the kernels are Eigen fixed-size code; no BLAS call)\n",
              coretype ? coretype : "(unset)");
  std::printf("elements: edge ~0.1 m, F = R (I + delta), |delta_ij| <= %.3g, E = 1e5, nu = %.3g\n",
              strain, poisson);

  // how many elements really need a projection (not timed)
  for (TetMaterialModel model :
       {TetMaterialModel::StableNeoHookean, TetMaterialModel::LinearElastic}) {
    int indefinite = 0, inverted = 0;
    for (int e = 0; e < n; ++e) {
      Matrix9 const a = superdex::internal::TetStressDerivative(model, lame, elements.f[e]);
      auto const eigenvalues = superdex::SymmetricEigenvalues(a);
      // negative beyond round-off (LinearElastic's exact zeros come out ±1e-16)
      if (eigenvalues[0] < -1e-12 * eigenvalues[8]) ++indefinite;
      if (elements.f[e].determinant() <= 0) ++inverted;
    }
    std::printf("%s: d2Psi/dF2 indefinite for %.1f %% of the elements (%d inverted)\n",
                std::string(superdex::ToString(model)).c_str(), 100.0 * indefinite / n, inverted);
  }

  std::printf("\n%-17s %-44s %12s %14s %16s\n", "model", "variant", "ns/element", "elements/s",
              "projection share");
  for (TetMaterialModel model :
       {TetMaterialModel::StableNeoHookean, TetMaterialModel::LinearElastic}) {
    std::string const name(superdex::ToString(model));
    auto report = [&](char const* variant, double seconds, double exactSeconds) {
      double const ns = 1e9 * seconds / n;
      std::printf("%-17s %-44s %12.1f %14.3e", name.c_str(), variant, ns, n / seconds);
      if (exactSeconds > 0) std::printf(" %15.1f%%", 100.0 * (seconds - exactSeconds) / seconds);
      std::printf("\n");
    };

    double const energy = Best(repeats, [&] {
      real sum = 0;
      for (int e = 0; e < n; ++e)
        sum += superdex::internal::TetEnergy(model, lame, elements.rest[e], elements.x[e]);
      gSink = gSink + sum;
    });
    report("energy", energy, 0);

    auto egh = [&](TetPsdProjection projection) {
      return Best(repeats, [&] {
        Vector12 gradient;
        Matrix12 hessian;
        real sum = 0;
        for (int e = 0; e < n; ++e) {
          sum += superdex::internal::TetEnergyGradientHessian(
              model, lame, elements.rest[e], elements.x[e], gradient, hessian, projection);
          sum += gradient[4] + hessian(7, 2);
        }
        gSink = gSink + sum;
      });
    };
    double const exact = egh(TetPsdProjection::None);
    report("energy+gradient+Hessian, exact", exact, 0);
    double const analytic = egh(TetPsdProjection::Analytic);
    report("energy+gradient+Hessian, projected analytic", analytic, exact);
    double const solver = egh(TetPsdProjection::EigenSolver);
    report("energy+gradient+Hessian, projected 9x9 solver", solver, exact);

    // the 9×9 part alone
    auto ninebynine = [&](auto&& kernel) {
      return Best(repeats, [&] {
        real sum = 0;
        for (int e = 0; e < n; ++e) sum += kernel(elements.f[e])(4, 5);
        gSink = gSink + sum;
      });
    };
    double const derivative = ninebynine(
        [&](Real33 const& f) { return superdex::internal::TetStressDerivative(model, lame, f); });
    report("  d2Psi/dF2 exact (9x9)", derivative, 0);
    double const analyticOnly = ninebynine([&](Real33 const& f) {
      return superdex::internal::TetProjectedStressDerivative(model, lame, f,
                                                              TetPsdProjection::Analytic);
    });
    report("  d2Psi/dF2 projected analytic (9x9)", analyticOnly, 0);
    double const solverOnly = ninebynine([&](Real33 const& f) {
      return superdex::internal::ProjectToPsdEigenSolver(
          superdex::internal::TetStressDerivative(model, lame, f));
    });
    report("  d2Psi/dF2 projected 9x9 solver (9x9)", solverOnly, 0);
  }
  std::printf("\nprojection share = (t_projected - t_exact) / t_projected of the full kernel\n");
  std::printf("(sink %g)\n", static_cast<double>(gSink));
  return 0;
}
