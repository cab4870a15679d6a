// actors/actor.h: ActorType and the base class of every actor object.
#include "defines.h"
#include "support/objects.h"

namespace superdex::python {

void DefineActor(py::module_& m) {
  py::enum_<ActorType>(m, "ActorType", "Kind of actor.")
      .value("Rigid", ActorType::Rigid)
      .value("Deformable", ActorType::Deformable)
      .value("Rod", ActorType::Rod)
      .value("Articulated", ActorType::Articulated);

  py::class_<ActorRef> actor(
      m, "Actor",
      "An owner of a contiguous range of generalized DoFs in its scene. Made by the "
      "Scene.create_*_actor factories; the object holds the scene and the actor's stable "
      "handle, so once the actor is destroyed every method raises mochi.Error (InvalidHandle).");
  DefineIdentity<ActorRef>(actor);
  actor
      .def("get_num_dofs", Forward<ActorRef>(&Actor::GetNumDofs),
           "Number of generalized DoFs (6 for a rigid body).")
      .def("get_dof_offset", Forward<ActorRef>(&Actor::GetDofOffset),
           "First global DoF index; the actor's DoFs are [offset, offset + n). Changes when "
           "actors created before it are destroyed.");
}

}  // namespace superdex::python
