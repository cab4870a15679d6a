#include <superdex/core/error.h>

namespace superdex {

std::string_view ToString(ErrorCode code) {
  switch (code) {
    case ErrorCode::None: return "None";
    case ErrorCode::InvalidArgument: return "InvalidArgument";
    case ErrorCode::InvalidHandle: return "InvalidHandle";
    case ErrorCode::NotSupported: return "NotSupported";
    case ErrorCode::InvalidState: return "InvalidState";
    case ErrorCode::NewtonFailed: return "NewtonFailed";
    case ErrorCode::LinearSolverFailed: return "LinearSolverFailed";
    case ErrorCode::NonFiniteState: return "NonFiniteState";
    case ErrorCode::BackendError: return "BackendError";
  }
  return "Unknown";
}

std::string Error::ToString() const {
  if (code_ == ErrorCode::None) return "no error";
  std::string text(superdex::ToString(code_));
  text.append(": ").append(message_);
  return text;
}

}  // namespace superdex
