// core/config.h: version and the backends compiled into this build.
#include "defines.h"

namespace superdex::python {

void DefineConfig(py::module_& m) {
  m.attr("__version__") = SUPERDEX_VERSION_STRING;
  m.attr("VERSION_MAJOR") = SUPERDEX_VERSION_MAJOR;
  m.attr("VERSION_MINOR") = SUPERDEX_VERSION_MINOR;
  m.attr("VERSION_PATCH") = SUPERDEX_VERSION_PATCH;
  m.attr("HAS_CHOLMOD") = bool(SUPERDEX_HAS_CHOLMOD);
  m.attr("HAS_METIS") = bool(SUPERDEX_HAS_METIS);
  m.attr("HAS_PETSC") = bool(SUPERDEX_HAS_PETSC);
}

}  // namespace superdex::python
