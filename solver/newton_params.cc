#include <superdex/solver/newton_params.h>

namespace superdex {

std::string_view ToString(HessianProjection projection) {
  switch (projection) {
    case HessianProjection::WhenIndefinite:
      return "WhenIndefinite";
    case HessianProjection::Always:
      return "Always";
  }
  return "Unknown";
}

}  // namespace superdex
