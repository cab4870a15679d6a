// contact/collider.h, contact/contact_params.h: mochi.ShapeType, ContactParams,
// ColliderParams, Collider and Contact (docs/contact.md).
//
//   scene = mochi.Scene.create(contact=mochi.ContactParams(activation_distance=1e-3))
//   scene.create_collider(shape=mochi.ShapeType.Plane)               # static ground
//   scene.create_collider(actor=box, shape=mochi.ShapeType.Box, half_extents=[.1, .1, .1])
//   for c in scene.get_contacts(): print(c.point, c.normal_force)
#include "defines.h"
#include "support/factory.h"

namespace superdex::python {

void DefineContact(py::module_& m) {
  py::enum_<ShapeType>(m, "ShapeType", "The shape of a collider (docs/contact.md).")
      .value("Plane", ShapeType::Plane, "a static half-space through position, outward normal")
      .value("Sphere", ShapeType::Sphere, "radius")
      .value("Box", ShapeType::Box, "half_extents")
      .value("Capsule", ShapeType::Capsule, "radius, half_length along the local z axis")
      .value("TriangleMesh", ShapeType::TriangleMesh, "vertices and triangles")
      .value("Surface", ShapeType::Surface, "a deformable or rod actor's own surface (default)");

  using P = ContactParams;
  ParamsClass<P>(m, "ContactParams",
                 "Contact between colliders: the barrier's activation distance and stiffness, the "
                 "friction ramp's width (docs/contact.md).")
      .Field("activation_distance", &P::activationDistance, "d̂ [m] > 0, default 1e-3")
      .Field("stiffness", &P::stiffness, "κ [Pa] > 0: the barrier's pressure scale, default 1e4")
      .Field("friction_ramp_width", &P::frictionRampWidth,
             "ḡ [m] > 0: the slip over which friction ramps up to μλ, default 1e-4")
      .Field("ccd_max_iterations", &P::ccdMaxIterations,
             "the cap on one pair's CCD distance evaluations per Newton iteration, in [1, 1e8], "
             "default 10000 (a lower cap: shorter safe steps, never unsafe ones)");

  using C = ColliderParams;
  ParamsClass<C>(m, "ColliderParams",
                 "A collider (Scene.create_collider): on an actor, or a static obstacle with actor "
                 "None.")
      .Field("actor", &C::actor, "the carrying actor (rigid, deformable or rod); None: a static obstacle")
      .Field("link", &C::link, "the link of an articulated actor carrying the collider (-1 for any other actor); the pose is then local to the link frame")
      .Field("shape", &C::shape, "ShapeType, default Surface")
      .Field("position", &C::position, "the shape's pose: local to a rigid actor, world for an obstacle [m]")
      .Field("rotation", &C::rotation, "(w, x, y, z), unit")
      .Field("normal", &C::normal, "Plane: outward normal in the shape's frame")
      .Field("radius", &C::radius, "Sphere, Capsule [m] > 0; a rod's Surface: 0 takes the rod's radius")
      .Field("half_extents", &C::halfExtents, "Box [m], each > 0")
      .Field("half_length", &C::halfLength, "Capsule: half its axis (local z) [m] > 0")
      .Field("vertices", &C::vertices, "TriangleMesh: vertices in the shape's frame [m]")
      .Field("triangles", &C::triangles, "TriangleMesh: vertex indices")
      .Field("friction", &C::friction, "Coulomb μ >= 0, default 0.5; two colliders touch with sqrt(μa μb)")
      .Field("thickness", &C::thickness, "extra thickness of a Box, TriangleMesh or Surface [m] >= 0")
      .Field("group", &C::group, "collision group bits")
      .Field("mask", &C::mask, "a and b touch when a.group & b.mask and b.group & a.mask");

  py::class_<ColliderRef>(m, "Collider", "A collider of a scene (Scene.create_collider).")
      .def("get_id", [](ColliderRef const& c) { return c.Get().GetId(); })
      .def("get_shape", [](ColliderRef const& c) { return c.Get().GetShape(); })
      .def("get_actor", [](ColliderRef const& c) { return c.Get().GetActor(); },
           "the carrying actor's handle (a null handle for a static obstacle)")
      .def("get_link", [](ColliderRef const& c) { return c.Get().GetLink(); },
           "the articulated actor's link carrying it (-1: none)")
      .def("get_friction", [](ColliderRef const& c) { return c.Get().GetFriction(); })
      .def("may_touch", [](ColliderRef const& c, ColliderRef const& other) { return c.Get().MayTouch(other.Get()); },
           py::arg("other"),
           "whether the two may touch: their groups and masks; not two colliders of one actor, except links of "
           "one articulated actor that are neither one link nor parent and child")
      .def("get_thickness", [](ColliderRef const& c) { return c.Get().GetThickness(); },
           "the thickness around every primitive [m] (a Sphere's, Capsule's or rod's radius)")
      .def("get_position", [](ColliderRef const& c) { return c.Get().GetPosition(); },
           "the shape's position now: local to its actor, world for an obstacle [m]")
      .def("get_rotation", [](ColliderRef const& c) { return c.Get().GetRotation(); }, "[w, x, y, z]")
      .def(
          "get_world_vertices",
          [](ColliderRef const& c) {
            DynamicArray<Real3> vertices;
            c.Get().GetWorldVertices(vertices);
            return vertices;
          },
          "the shape's vertices in the world now (n x 3; a deformable or rod actor's: its nodes)")
      .def("get_edges", [](ColliderRef const& c) { return c.Get().GetEdges(); }, "vertex index pairs")
      .def("get_triangles", [](ColliderRef const& c) { return c.Get().GetTriangles(); }, "vertex index triples")
      .def(
          "set_transform",
          [](ColliderRef const& c, Real3 const& position, Quat const& rotation) {
            Checked([&](Error& e) { c.Get().SetTransform(position, rotation, e); });
          },
          py::arg("position"), py::arg("rotation"),
          "Moves a static obstacle there at once (refused where it would intersect a body).")
      .def(
          "set_target_transform",
          [](ColliderRef const& c, Real3 const& position, Quat const& rotation) {
            Checked([&](Error& e) { c.Get().SetTargetTransform(position, rotation, e); });
          },
          py::arg("position"), py::arg("rotation"),
          "Moves a static obstacle kinematically over the next step, pushing the bodies in its way.")
      .def("__repr__", [](ColliderRef const& c) {
        return "Collider(id=" + std::to_string(c.Get().GetId()) + ", shape=" + std::string(ToString(c.Get().GetShape())) +
               ")";
      });

  py::class_<ContactInfo>(m, "Contact", "An active contact of the last step (Scene.get_contacts).")
      .def_readonly("collider_a", &ContactInfo::colliderA, "the body's collider id")
      .def_readonly("collider_b", &ContactInfo::colliderB, "the obstacle's collider id")
      .def_readonly("point", &ContactInfo::point, "closest point on collider B [m]")
      .def_readonly("normal", &ContactInfo::normal, "unit normal from B towards A")
      .def_readonly("distance", &ContactInfo::distance, "the gap [m]")
      .def_readonly("normal_force", &ContactInfo::normalForce, "on A along normal [N]")
      .def_readonly("friction_force", &ContactInfo::frictionForce, "on A [N]");
}

}  // namespace superdex::python
