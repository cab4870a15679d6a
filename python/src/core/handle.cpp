// core/handle.h: ActorHandle and ConstraintHandle.
#include "defines.h"
#include "support/errors.h"

namespace superdex::python {

namespace {

template <class Tag>
void DefineHandleClass(py::module_& m, char const* name, char const* doc) {
  using H = Handle<Tag>;
  std::string const typeName = name;
  py::class_<H>(m, name, doc)
      .def(py::init<>(), "A null handle.")
      .def(py::init([](std::uint32_t index, std::uint32_t generation, std::uint32_t scene) {
             return H{index, generation, scene};
           }),
           py::arg("index"), py::arg("generation") = 0, py::arg("scene") = 0,
           "The handle of slot `index`, `generation` of the scene numbered `scene` "
           "(Scene.get_id()); another scene refuses it.")
      .def_readonly("index", &H::index, "Slot index (0xffffffff for a null handle).")
      .def_readonly("generation", &H::generation,
                    "Generation of the slot, bumped when its object is destroyed.")
      .def_readonly("scene", &H::scene,
                    "The number of the scene that issued the handle (0 for a null handle).")
      .def("is_null", &H::IsNull, "True for a default-constructed handle.")
      .def(
          "__eq__",
          [](H const& a, py::object const& b) { return py::isinstance<H>(b) && a == b.cast<H>(); },
          py::arg("other"))
      .def("__hash__", [](H const& h) { return std::hash<H>()(h); })
      .def("__repr__", [typeName](H const& h) {
        return h.IsNull() ? typeName + "()"
                          : typeName + "(index=" + std::to_string(h.index) +
                                ", generation=" + std::to_string(h.generation) +
                                ", scene=" + std::to_string(h.scene) + ")";
      });
}

}  // namespace

void DefineHandle(py::module_& m) {
  DefineHandleClass<ActorTag>(
      m, "ActorHandle",
      "Stable handle of an actor: slot index + generation + scene. A handle kept past the "
      "actor's destruction is detected as stale (Scene.get_actor returns None), and one of "
      "another scene is refused (InvalidHandle).");
  DefineHandleClass<ConstraintTag>(
      m, "ConstraintHandle",
      "Stable handle of a constraint: slot index + generation + scene. A handle kept past "
      "the constraint's destruction is detected as stale, and one of another scene is refused.");
}

}  // namespace superdex::python
