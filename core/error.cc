#include <superdex/core/error.h>

namespace superdex {

std::string_view ToString(ErrorCode code) {
  switch (code) {
    case ErrorCode::kNone: return "None";
    case ErrorCode::kInvalidArgument: return "InvalidArgument";
    case ErrorCode::kInvalidHandle: return "InvalidHandle";
    case ErrorCode::kNotSupported: return "NotSupported";
    case ErrorCode::kInvalidState: return "InvalidState";
    case ErrorCode::kNewtonFailed: return "NewtonFailed";
    case ErrorCode::kLinearSolverFailed: return "LinearSolverFailed";
    case ErrorCode::kNonFiniteState: return "NonFiniteState";
    case ErrorCode::kBackendError: return "BackendError";
  }
  return "Unknown";
}

std::string Error::ToString() const {
  if (code_ == ErrorCode::kNone) return "no error";
  std::string text(superdex::ToString(code_));
  text.append(": ").append(message_);
  return text;
}

}  // namespace superdex
