// core/error.h: ErrorCode and mochi.Error.
#include "defines.h"
#include "support/errors.h"

namespace superdex::python {

void DefineError(py::module_& m) {
  py::enum_<ErrorCode>(m, "ErrorCode", "What went wrong (mochi.Error.code).")
      .value("None_", ErrorCode::None, "no error (C++ ErrorCode::None)")
      .value("InvalidArgument", ErrorCode::InvalidArgument,
             "a parameter is out of its valid range or non-finite")
      .value("InvalidHandle", ErrorCode::InvalidHandle,
             "a handle is stale, null or of the wrong kind (also: a destroyed actor or constraint)")
      .value("NotSupported", ErrorCode::NotSupported,
             "the method does not apply to this object's type")
      .value("InvalidState", ErrorCode::InvalidState,
             "the call is valid but not in the object's current state (also: a destroyed scene)")
      .value("NewtonFailed", ErrorCode::NewtonFailed, "a stage's Newton iteration did not converge")
      .value("LinearSolverFailed", ErrorCode::LinearSolverFailed,
             "the linear solver failed (not positive definite, not converged)")
      .value("NonFiniteState", ErrorCode::NonFiniteState,
             "a stage produced a non-finite energy or configuration")
      .value("BackendError", ErrorCode::BackendError,
             "an external library (CHOLMOD, METIS, PETSc) reported an error");

  py::object error = py::reinterpret_steal<py::object>(PyErr_NewExceptionWithDoc(
      "mochi.Error",
      "Raised for every superdex::Error. Attributes: code (a mochi.ErrorCode; code.name is its "
      "name) and message (the library's message, naming the bad field and value). str(e) is "
      "'<code name>: <message>'. A failed call changes nothing.",
      PyExc_Exception, nullptr));
  if (!error) throw py::error_already_set();
  error.attr("code") = py::cast(ErrorCode::None);
  error.attr("message") = py::str("");
  m.attr("Error") = error;
  RegisterErrorTranslator(error);
}

}  // namespace superdex::python
