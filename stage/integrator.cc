#include <superdex/stage/integrator.h>

#include <cmath>

namespace superdex {

std::string_view ToString(IntegratorType type) {
  switch (type) {
    case IntegratorType::BackwardEuler: return "BackwardEuler";
    case IntegratorType::Bdf2: return "BDF2";
  }
  return "Unknown";
}

namespace internal {

StageCoefficients MakeStage(IntegratorType type, real dt, bool hasHistory) {
  StageCoefficients s;
  s.duration = dt;
  if (type == IntegratorType::Bdf2 && hasHistory) {
    s.beta = 2.0 / 3.0;
    s.cPrevious = -1.0 / 3.0;
    s.aVelocity = 4.0 / 3.0;
    s.bVelocity = -1.0 / 3.0;
    s.usesHistory = true;
  }
  return s;
}

StageCoefficients StageCoefficients::ForBody(bool hasHistory) const {
  return usesHistory && !hasHistory ? MakeStage(IntegratorType::BackwardEuler, duration, false) : *this;
}

bool IsHistoryUsable(real historyStep, real dt) {
  return historyStep > 0 && std::abs(historyStep - dt) <= kHistoryStepTolerance * dt;
}

}  // namespace internal
}  // namespace superdex
