// actors/rigid_actor.h: RigidActorParams and RigidActor.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineRigidActor(py::module_& m) {
  using P = RigidActorParams;
  ParamsClass<P>(m, "RigidActorParams",
                 "A rigid body (Scene.create_rigid_actor). Validated at creation.")
      .Field("mass", &P::mass, "[kg], > 0, default 1")
      .Field("inertia", &P::inertia,
             "principal moments in the body frame [kg·m²], > 0, default (1, 1, 1)")
      .Field("position", &P::position, "centre of mass, world [m]")
      .Field("rotation", &P::rotation, "body -> world, unit quaternion [w, x, y, z]")
      .Field("linear_velocity", &P::linearVelocity, "[m/s]")
      .Field("angular_velocity", &P::angularVelocity, "world frame [rad/s]");

  using Ref = RigidActorRef;
  using A = RigidActor;
  py::class_<Ref, ActorRef>(
      m, "RigidActor",
      "A rigid body: 6 DoFs, translation then a world-frame rotation increment (R <- Exp(δθ) R).")
      .def("get_mass", Forward<Ref>(&A::GetMass), "[kg]")
      .def("get_inertia", Forward<Ref>(&A::GetInertia), "Principal moments, body frame [kg·m²].")
      .def("get_position", Forward<Ref>(&A::GetPosition), "Centre of mass, world [m].")
      .def("get_rotation", Forward<Ref>(&A::GetRotation), "Body -> world rotation [w, x, y, z].")
      .def("get_linear_velocity", Forward<Ref>(&A::GetLinearVelocity), "[m/s]")
      .def("get_angular_velocity", Forward<Ref>(&A::GetAngularVelocity), "World frame [rad/s].")
      .def(
          "set_pose",
          [](Ref const& self, Real3 const& position, Quat const& rotation) {
            Checked([&](Error& e) { self.Get().SetPose(position, rotation, e); });
          },
          py::arg("position"), py::arg("rotation"),
          "Teleports the body (finite position, unit quaternion). Clears the integrator history.")
      .def(
          "set_velocity",
          [](Ref const& self, Real3 const& linear, Real3 const& angular) {
            Checked([&](Error& e) { self.Get().SetVelocity(linear, angular, e); });
          },
          py::arg("linear_velocity"), py::arg("angular_velocity"),
          "Sets the velocities (finite; angular in the world frame). Clears the integrator "
          "history.")
      .def("transform_point", Forward<Ref>(&A::TransformPoint), py::arg("local_point"),
           "World point of a body-frame point: t + R r.")
      .def("get_angular_momentum", Forward<Ref>(&A::GetAngularMomentum),
           "About the centre of mass, world frame: R I_b Rᵀ ω.")
      .def("get_kinetic_energy", Forward<Ref>(&A::GetKineticEnergy),
           "½ m v² + ½ ωᵀ R I_b Rᵀ ω [J].");
}

}  // namespace superdex::python
