#include "support/errors.h"

namespace superdex::python {

void Raise(ErrorCode code, std::string message) {
  throw PythonError(Error(code, std::move(message)));
}

void CheckIndex(int index, int count, std::string const& what) {
  CheckIndexRange(index, 0, count, what);
}

void CheckIndexRange(int index, int first, int end, std::string const& what) {
  if (index < first || index >= end)
    Raise(ErrorCode::InvalidArgument, what + " must be in [" + std::to_string(first) + ", " +
                                          std::to_string(end) + "), got " + std::to_string(index));
}

void RegisterErrorTranslator(py::object errorType) {
  // the type lives as long as the module (mochi.Error); keep one reference here
  static py::handle const type = errorType.release();
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (PythonError const& e) {
      Error const& error = e.GetError();
      py::object instance = type(py::str(error.ToString()));
      instance.attr("code") = py::cast(error.GetCode());
      instance.attr("message") = py::str(error.GetMessage());
      PyErr_SetObject(type.ptr(), instance.ptr());
    }
  });
}

}  // namespace superdex::python
