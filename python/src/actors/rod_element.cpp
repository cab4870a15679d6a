// actors/rod_element.h: the section stiffnesses a rod reports
// (RodActor.get_stiffness). The element kernels themselves are internal.
#include "defines.h"

namespace superdex::python {

void DefineRodElement(py::module_& m) {
  using S = internal::RodStiffness;
  py::class_<S>(m, "RodStiffness", "Section stiffnesses of a rod [N, N·m², N·m², N·m²].")
      .def_readonly("stretch", &S::stretch, "EA")
      .def_readonly("bend1", &S::bend1, "EI₁, about d₁")
      .def_readonly("bend2", &S::bend2, "EI₂, about d₂")
      .def_readonly("twist", &S::twist, "GJ")
      .def("__repr__", [](S const& s) {
        auto f = [](real v) { return std::string(py::repr(py::float_(v))); };
        return "RodStiffness(stretch=" + f(s.stretch) + ", bend1=" + f(s.bend1) +
               ", bend2=" + f(s.bend2) + ", twist=" + f(s.twist) + ")";
      });
}

}  // namespace superdex::python
