// superdex::Error -> mochi.Error. Binding code reports every failure by
// throwing PythonError; the translator registered by DefineError
// (core/error.cpp) turns it into a mochi.Error instance carrying `code` (a
// mochi.ErrorCode) and `message`, with str() = "<Code>: <message>".
#pragma once

#include <exception>
#include <string>
#include <type_traits>

#include "support/casters.h"

namespace superdex::python {

/// A superdex::Error on its way to Python as mochi.Error.
class PythonError : public std::exception {
 public:
  explicit PythonError(Error error) : error_(std::move(error)), text_(error_.ToString()) {}
  Error const& GetError() const { return error_; }
  char const* what() const noexcept override { return text_.c_str(); }

 private:
  Error error_;
  std::string text_;
};

/// Raises mochi.Error(code, message).
[[noreturn]] void Raise(ErrorCode code, std::string message);

/// Raises mochi.Error when `error` is set.
inline void ThrowIfError(Error const& error) {
  if (error) throw PythonError(error);
}

/// Calls fn(error) and raises mochi.Error if it set one; returns fn's result.
template <class F>
auto Checked(F&& fn) {
  Error error;
  if constexpr (std::is_void_v<decltype(fn(error))>) {
    fn(error);
    ThrowIfError(error);
  } else {
    auto result = fn(error);
    ThrowIfError(error);
    return result;
  }
}

/// Raises mochi.Error(InvalidArgument) unless 0 <= index < count; `what`
/// names the index ("node index", "link").
void CheckIndex(int index, int count, std::string const& what);
/// As CheckIndex, for first <= index < end.
void CheckIndexRange(int index, int first, int end, std::string const& what);

/// Registers the translator of PythonError to `errorType` (mochi.Error).
void RegisterErrorTranslator(py::object errorType);

}  // namespace superdex::python
