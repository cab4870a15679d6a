// stage/integrator.h: the time integrators (stage generators).
#include "defines.h"

namespace superdex::python {

void DefineIntegrator(py::module_& m) {
  py::enum_<IntegratorType>(m, "IntegratorType", "Time integrator of Scene.step.")
      .value("BackwardEuler", IntegratorType::BackwardEuler, "one stage of dt, first order")
      .value("Bdf2", IntegratorType::Bdf2, "second order; its first step is backward Euler");
}

}  // namespace superdex::python
