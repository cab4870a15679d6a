// ParamsClass<T>: binds a plain parameter struct (RigidActorParams,
// RigidSphericalJointConstraintParams, SceneParams, ...) as a Python class
//
//   p = mochi.RigidSphericalJointConstraintParams(actor_a=a, local_pos_a=[0.5, 0, 0],
//                                                 stiffness=1e6)
//   p.damping = 10
//   p            # RigidSphericalJointConstraintParams(actor_a=..., ..., saturation=-1.0)
//
// with one line per field: .Field("local_pos_a", &T::localPosA, "doc"). The
// constructor takes every field as a keyword (unknown keywords are a
// TypeError), __repr__ lists the fields in declaration order, copy.copy()
// works. Reading a vector field gives a numpy view into the struct (so
// p.local_pos_a[1] = 2 changes p), reading a nested parameter struct (SceneParams.newton)
// gives a reference to it; everything else reads as a copy. Assigning a value
// that does not convert raises mochi.Error(InvalidArgument) naming the field
// ("RigidActorParams.position: ..."). Value checks (ranges, unit quaternions)
// are the library's, when the struct is used.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "support/arrays.h"
#include "support/objects.h"

namespace superdex::python {

/// True for parameter structs that are fields of another one (read by reference).
template <class F>
struct IsNestedParams : std::false_type {};
template <>
struct IsNestedParams<NewtonParams> : std::true_type {};
template <>
struct IsNestedParams<PcgParams> : std::true_type {};
template <>
struct IsNestedParams<SubstepParams> : std::true_type {};
template <>
struct IsNestedParams<ContactParams> : std::true_type {};

/// How a field of type F is read (Get) and assigned (Load).
template <class F, class Enable = void>
struct FieldTraits {
  static std::string Describe() {
    if constexpr (std::is_same_v<F, Real3>)
      return "a 3-sequence of numbers";
    else if constexpr (std::is_same_v<F, Quat>)
      return "a 4-sequence (w, x, y, z)";
    else if constexpr (std::is_same_v<F, bool>)
      return "a bool";
    else if constexpr (std::is_floating_point_v<F>)
      return "a number";
    else if constexpr (std::is_integral_v<F>)
      return "an integer";
    else if constexpr (std::is_same_v<F, std::string>)
      return "a str";
    else
      return "a " + std::string(py::str(py::type::of<F>().attr("__name__")));
  }
  static py::object Get(F& value, py::handle parent) {
    constexpr bool byReference =
        std::is_base_of_v<Eigen::MatrixBase<F>, F> || IsNestedParams<F>::value;
    return py::cast(
        value,
        byReference ? py::return_value_policy::reference_internal : py::return_value_policy::copy,
        parent);
  }
  static F Load(py::handle value, std::string const& field) {
    // None is no value of any field (pybind11 would read it as False for a
    // bool, flipping a default that is on)
    if (value.is_none()) Refuse(value, field, Describe());
    if constexpr (std::is_same_v<F, bool>) {
      // a bool (Python's or numpy's) only: not 0/1, not a str
      if (!py::isinstance<py::bool_>(value) && std::string(py::str(py::type::of(value).attr("__name__"))) != "bool_")
        Refuse(value, field, Describe());
    } else if constexpr (std::is_integral_v<F> && sizeof(F) <= 4) {
      // an integer out of range is one: say what the range is
      if (PyLong_Check(value.ptr())) {
        int overflow = 0;
        long long const v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
        if (overflow != 0 || v < static_cast<long long>(std::numeric_limits<F>::min()) ||
            v > static_cast<long long>(std::numeric_limits<F>::max()))
          Refuse(value, field, "an integer in [" + std::to_string(std::numeric_limits<F>::min()) + ", " +
                 std::to_string(std::numeric_limits<F>::max()) + "]");
      }
    }
    try {
      return value.cast<F>();
    } catch (py::cast_error const&) {
      Refuse(value, field, Describe());
    } catch (py::reference_cast_error const&) {
      Refuse(value, field, Describe());
    }
  }
  [[noreturn]] static void Refuse(py::handle value, std::string const& field, std::string const& expected) {
    Raise(ErrorCode::InvalidArgument, field + " must be " + expected + ", got " + std::string(py::repr(value)));
  }
};

template <>
struct FieldTraits<ActorHandle> {
  static py::object Get(ActorHandle& value, py::handle) { return py::cast(value); }
  /// None is the null handle: a static obstacle (ColliderParams.actor);
  /// a factory that needs an actor refuses it, naming the field.
  static ActorHandle Load(py::handle value, std::string const& field) {
    if (value.is_none()) return ActorHandle{};
    return LoadActorHandle(value, field);
  }
};

template <>
struct FieldTraits<DynamicArray<real>> {
  static py::object Get(DynamicArray<real>& value, py::handle) {
    return ToArray(Span<real const>(value));
  }
  static DynamicArray<real> Load(py::handle value, std::string const& field) {
    return LoadReals(value, field);
  }
};

template <>
struct FieldTraits<DynamicArray<int>> {
  static py::object Get(DynamicArray<int>& value, py::handle) {
    return ToArray(Span<int const>(value));
  }
  static DynamicArray<int> Load(py::handle value, std::string const& field) {
    return LoadInts(value, field);
  }
};

template <>
struct FieldTraits<DynamicArray<Real3>> {
  static py::object Get(DynamicArray<Real3>& value, py::handle) { return ToArray(value); }
  static DynamicArray<Real3> Load(py::handle value, std::string const& field) {
    return LoadPoints(value, field);
  }
};

template <std::size_t N>
struct FieldTraits<DynamicArray<std::array<int, N>>> {
  static py::object Get(DynamicArray<std::array<int, N>>& value, py::handle) {
    return ToArray(value);
  }
  static DynamicArray<std::array<int, N>> Load(py::handle value, std::string const& field) {
    return LoadIndexTuples<N>(value, field);
  }
};

template <class U>
struct IsStdArray : std::false_type {};
template <class U, std::size_t N>
struct IsStdArray<std::array<U, N>> : std::true_type {};

/// A list of parameter structs (ArticulatedActorParams.links): read as a list
/// of copies, assigned from any sequence.
template <class U>
struct FieldTraits<
    DynamicArray<U>,
    std::enable_if_t<std::is_class_v<U> && !std::is_same_v<U, Real3> && !IsStdArray<U>::value>> {
  static py::object Get(DynamicArray<U>& value, py::handle) {
    py::list out;
    for (U const& item : value) out.append(py::cast(item));
    return out;
  }
  static DynamicArray<U> Load(py::handle value, std::string const& field) {
    if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value))
      Raise(ErrorCode::InvalidArgument,
            field + " must be a sequence, got " + std::string(py::repr(value)));
    DynamicArray<U> out;
    std::size_t i = 0;
    for (py::handle item : value)
      out.push_back(FieldTraits<U>::Load(item, field + "[" + std::to_string(i++) + "]"));
    return out;
  }
};

/// The fields of T in declaration order, as assigned by keywords.
template <class T>
struct ParamsFields {
  struct Entry {
    std::string name;
    std::function<void(T&, py::handle)> assign;
  };
  static std::string& TypeName() {
    static std::string name;
    return name;
  }
  static std::vector<Entry>& Entries() {
    static std::vector<Entry> entries;
    return entries;
  }
};

/// Assigns `kwargs` to the fields of `value`; an unknown keyword is a TypeError.
template <class T>
void ApplyKeywords(T& value, py::kwargs const& kwargs) {
  auto const& entries = ParamsFields<T>::Entries();
  for (auto const& [key, item] : kwargs) {
    std::string const name = py::str(key);
    auto it =
        std::find_if(entries.begin(), entries.end(), [&](auto const& e) { return e.name == name; });
    if (it == entries.end()) {
      std::string known;
      for (auto const& e : entries) known += (known.empty() ? "" : ", ") + e.name;
      throw py::type_error(ParamsFields<T>::TypeName() + " has no field '" + name +
                           "' (fields: " + known + ")");
    }
    it->assign(value, item);
  }
}

/// The params argument of a factory: `params` (a T or None for defaults) with `kwargs` applied on
/// top.
template <class T>
T ParamsArgument(py::object const& params, py::kwargs const& kwargs) {
  if (!params.is_none() && !py::isinstance<T>(params))
    throw py::type_error("params must be a " + ParamsFields<T>::TypeName() + " or None, got " +
                         std::string(py::repr(params)));
  T value = params.is_none() ? T{} : params.cast<T>();
  ApplyKeywords(value, kwargs);
  return value;
}

template <class T>
class ParamsClass {
 public:
  ParamsClass(py::handle scope, char const* name, char const* doc) : class_(scope, name, doc) {
    ParamsFields<T>::TypeName() = name;
    class_
        .def(py::init([](py::kwargs const& kwargs) {
               T value{};
               ApplyKeywords(value, kwargs);
               return value;
             }),
             (std::string("Every field is a keyword argument; omitted fields keep their defaults. "
                          "Fields of ") +
              name + ": see help(mochi." + name + ").")
                 .c_str())
        .def("__repr__", &Repr)
        .def("__copy__", [](T const& self) { return T(self); })
        .def(
            "__deepcopy__", [](T const& self, py::dict const&) { return T(self); },
            py::arg("memo"));
  }

  /// Binds field `name` (snake_case of the C++ field) to `member`.
  template <class F>
  ParamsClass& Field(char const* name, F T::*member, char const* doc) {
    std::string const qualified = ParamsFields<T>::TypeName() + "." + name;
    ParamsFields<T>::Entries().push_back({name, [member, qualified](T& self, py::handle value) {
                                            self.*member = FieldTraits<F>::Load(value, qualified);
                                          }});
    class_.def_property(
        name,
        [member](py::object self) { return FieldTraits<F>::Get(self.cast<T&>().*member, self); },
        [member, qualified](T& self, py::handle value) {
          self.*member = FieldTraits<F>::Load(value, qualified);
        },
        doc);
    return *this;
  }

  /// The compliant-potential fields every constraint's params share.
  /// (pybind11 copies docstrings, so temporaries are fine.)
  ParamsClass& CompliantFields(char const* stiffnessUnit, char const* dampingUnit,
                               char const* saturationUnit) {
    std::string const stiffness = std::string("stiffness k >= 0 ") + stiffnessUnit + ", default 0";
    std::string const damping = std::string("damping d >= 0 ") + dampingUnit + ", default 0";
    std::string const saturation =
        std::string("saturation ḡ ") + saturationUnit +
        ": the elastic force is capped at k·ḡ; <= 0 (default -1) disables it";
    return Field("stiffness", &T::stiffness, stiffness.c_str())
        .Field("damping", &T::damping, damping.c_str())
        .Field("saturation", &T::saturation, saturation.c_str());
  }

  py::class_<T>& Class() { return class_; }

 private:
  /// "Name(field=value, ...)"; small arrays as lists, large ones by shape, enums by name.
  static std::string Repr(py::object const& self) {
    std::string text = ParamsFields<T>::TypeName() + "(";
    bool first = true;
    for (auto const& entry : ParamsFields<T>::Entries()) {
      py::object value = self.attr(entry.name.c_str());
      std::string shown;
      if (py::isinstance<py::array>(value)) {
        py::array const a = value.cast<py::array>();
        shown = a.size() <= 16
                    ? std::string(py::repr(value.attr("tolist")()))
                    : "<array of shape " + std::string(py::str(value.attr("shape"))) + ">";
      } else if (py::hasattr(value.get_type(), "__members__")) {
        shown = py::str(value);  // a mochi enum: "IntegratorType.Bdf2"
      } else {
        shown = py::repr(value);
      }
      text += (first ? "" : ", ") + entry.name + "=" + shown;
      first = false;
    }
    return text + ")";
  }

  py::class_<T> class_;
};

}  // namespace superdex::python
