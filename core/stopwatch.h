#pragma once

#include <chrono>

namespace superdex::internal {

/// Seconds on the steady clock since `start` (the phase times in SceneStats).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace superdex::internal
