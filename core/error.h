// Error reporting: every public call that can fail takes an `Error&`
// out-parameter. A call that fails returns false/nullptr, sets the error's
// code and a message naming the bad field and value, and changes nothing.
#pragma once

#include <string>
#include <string_view>

namespace superdex {

enum class ErrorCode {
  None = 0,
  InvalidArgument,    ///< a parameter is out of its valid range or non-finite
  InvalidHandle,      ///< a handle is stale, null or of the wrong kind
  NotSupported,       ///< the method does not apply to this object's type
  InvalidState,       ///< the call is valid but not in the object's current state
  NewtonFailed,       ///< a stage's Newton iteration did not converge
  LinearSolverFailed, ///< the linear solver failed (not positive definite, not converged)
  NonFiniteState,     ///< a stage produced a non-finite energy or configuration
  BackendError,       ///< an external library (CHOLMOD, METIS, PETSc) reported an error
};

/// Short name of an error code ("InvalidArgument", ...).
std::string_view ToString(ErrorCode code);

class Error {
 public:
  Error() = default;
  Error(ErrorCode code, std::string message) : code_(code), message_(std::move(message)) {}

  /// True when an error is set.
  explicit operator bool() const { return code_ != ErrorCode::None; }

  ErrorCode GetCode() const { return code_; }
  std::string const& GetMessage() const { return message_; }

  /// Sets the error (overwrites any previous one).
  void Set(ErrorCode code, std::string message) {
    code_ = code;
    message_ = std::move(message);
  }
  void Clear() {
    code_ = ErrorCode::None;
    message_.clear();
  }

  /// "InvalidArgument: stiffness must be finite and >= 0, got -1".
  std::string ToString() const;

 private:
  ErrorCode code_ = ErrorCode::None;
  std::string message_;
};

}  // namespace superdex
