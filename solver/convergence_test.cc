#include <superdex/solver/convergence_test.h>

#include <limits>

namespace superdex::internal {

namespace {
/// Round-off resolution of the incremental potential, in units of its
/// magnitude Σ|terms|: a decrease smaller than this is not resolvable.
constexpr real kRoundOffUlps = 64;
}  // namespace

void ConvergenceTest::Reserve(int numDofs) { lengthScales_.setOnes(numDofs); }

void ConvergenceTest::BeginStage(real velocityTolerance, real h) {
  problem_.WriteDofLengthScales(Span<real>(lengthScales_.data(), lengthScales_.size()));
  tolerance_ = velocityTolerance;
  duration_ = h;
  lastChangeUnresolved_ = false;
}

real ConvergenceTest::Energy() {
  EnergySum const sum = problem_.Energy(assembler_, ranks_);
  energyScale_ = sum.scale;
  return sum.energy;
}

real ConvergenceTest::Resolution() const {
  return kRoundOffUlps * std::numeric_limits<real>::epsilon() * energyScale_;
}

ConvergenceTest::Verdict ConvergenceTest::Judge(VectorX const& gradient, VectorX const& delta,
                                                real resolution) const {
  Verdict verdict;
  verdict.stepNorm = (delta.cwiseAbs().cwiseProduct(lengthScales_)).maxCoeff() / duration_;
  verdict.slope = gradient.dot(delta);
  verdict.stepConverged = verdict.stepNorm <= tolerance_;
  verdict.stalled = lastChangeUnresolved_ && -verdict.slope <= resolution;
  return verdict;
}

}  // namespace superdex::internal
