#pragma once

#include <chrono>

namespace superdex::internal {

/// Seconds on the steady clock since `start` (the phase times in SceneStats).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// Adds the seconds of its scope to `sink` (a phase time measured where the
/// phase has several exits).
class ScopedSeconds {
 public:
  explicit ScopedSeconds(double& sink) : sink_(sink), start_(std::chrono::steady_clock::now()) {}
  ~ScopedSeconds() { sink_ += SecondsSince(start_); }
  ScopedSeconds(ScopedSeconds const&) = delete;
  ScopedSeconds& operator=(ScopedSeconds const&) = delete;

 private:
  double& sink_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace superdex::internal
