// constraints/constraint_types.h: every constraint type's binding, from the
// one list — its params class (from the params struct's Fields() and
// kSummary), its class (mochi.<Class>, derived from mochi.Constraint; a class
// serving two types is bound once), Scene.create_<name>_constraint, and the
// downcast of a Constraint to its class. The per-type files
// (rigid_spherical_joint.cpp, ...) only add a type's own accessors to its class.
#include "defines.h"
#include "support/factory.h"

namespace superdex::python {

namespace {
/// RigidSphericalJoint → rigid_spherical_joint, Articulated3dRotationTarget →
/// articulated_3d_rotation_target (the snake_case of mochi's names).
std::string SnakeCase(std::string_view camel) {
  std::string snake;
  for (std::size_t i = 0; i < camel.size(); ++i) {
    char const c = camel[i];
    bool const upper = std::isupper(static_cast<unsigned char>(c)) != 0;
    bool const digitAfterLetter =
        std::isdigit(static_cast<unsigned char>(c)) && i > 0 && std::isalpha(static_cast<unsigned char>(camel[i - 1]));
    if (i > 0 && (upper || digitAfterLetter)) snake += '_';
    snake += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return snake;
}

template <class Params>
void DefineParams(py::module_& m, std::string const& name) {
  ParamsClass<Params> params(m, name.c_str(), std::string(Params::kSummary).c_str());
  for (auto const& field : Params::Fields())
    std::visit([&](auto member) { params.Field(SnakeCase(field.name).c_str(), member, std::string(field.doc).c_str()); },
               field.member);
}

template <class Class, class Params>
void DefineClass(py::module_& m, char const* name) {
  if (py::hasattr(m, name)) return;  // a class serving two types (target and range)
  py::class_<ConstraintRefOf<Class>, ConstraintRef>(m, name, std::string(Params::kSummary).c_str());
}
}  // namespace

void DefineConstraintTypes(py::module_& m) {
#define SUPERDEX_BIND_TYPE(Name, Class, file)                                  \
  DefineParams<Name##ConstraintParams>(m, #Name "ConstraintParams");           \
  DefineClass<Class, Name##ConstraintParams>(m, #Class);
  SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_BIND_TYPE)
#undef SUPERDEX_BIND_TYPE
}

void DefineConstraintFactories(SceneClass& cls) {
#define SUPERDEX_BIND_FACTORY(Name, Class, file)                                                              \
  DefineFactory(cls, ("create_" + SnakeCase(#Name) + "_constraint").c_str(), &Scene::Create##Name##Constraint, \
                "a " #Class " (ConstraintType." #Name ")");
  SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_BIND_FACTORY)
#undef SUPERDEX_BIND_FACTORY
}

py::object WrapConstraint(SceneRef const& scene, Constraint& c) {
  switch (c.GetType()) {
#define SUPERDEX_WRAP_TYPE(Name, Class, file) \
  case ConstraintType::Name: return Cast<ConstraintRefOf<Class>>(scene, static_cast<Class&>(c));
    SUPERDEX_CONSTRAINT_TYPES(SUPERDEX_WRAP_TYPE)
#undef SUPERDEX_WRAP_TYPE
  }
  return py::cast(ConstraintRef(scene, c));
}

}  // namespace superdex::python
