// Uses an installed SuperDex through find_package(SuperDex): the umbrella
// header, the generated config, Error, the SO(3) maps and the BLAS report.
// Exits non-zero when a result is wrong.
#include <superdex/superdex.h>
#include <superdex/core/blas_info.h>
#include <superdex/core/config.h>

#include <cstdio>

int main() {
  using namespace superdex;
  int failures = 0;

  std::printf("SuperDex %s\n", SUPERDEX_VERSION_STRING);

  // an Error converts to true once set, and names its code
  Error error;
  if (error) ++failures;
  error.Set(ErrorCode::kInvalidArgument, "stiffness must be >= 0, got -1");
  std::printf("error: %s\n", error.ToString().c_str());
  if (!error || error.GetCode() != ErrorCode::kInvalidArgument) ++failures;

  // Log inverts Exp
  Real3 const phi(0.3_r, -0.2_r, 0.5_r);
  Real3 const back = Log(Exp(phi));
  real const roundTrip = (back - phi).norm();
  std::printf("|Log(Exp(phi)) - phi| = %.3e\n", roundTrip);
  if (!(roundTrip <= 1e-12_r)) ++failures;

  BlasInfo const blas = GetBlasInfo();
  std::printf("BLAS: %s, core %s, %d threads\n", blas.library.c_str(),
              blas.coreName.empty() ? "-" : blas.coreName.c_str(), blas.numThreads);
  if (!blas.advice.empty()) std::printf("BLAS advice: %s\n", blas.advice.c_str());

  std::printf("%s\n", failures == 0 ? "consumer: ok" : "consumer: WRONG RESULTS");
  return failures == 0 ? 0 : 1;
}
