// Colliders: the shapes through which bodies and obstacles touch
// (docs/contact.md).
//
// A collider belongs to an actor (a rigid actor, a link of an articulated
// actor, or the surface of a deformable or rod actor) or, without one, is a
// static obstacle. Every shape
// is a set of primitives with a thickness: points (a sphere is its centre
// with the radius as thickness), segments (a capsule, a rod's elements with
// its radius), triangles (a box, a triangle mesh, the boundary of a
// deformable actor) and, for a plane, its half-space.
#pragma once

#include <array>
#include <cstdint>

#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>

namespace superdex {

enum class ShapeType { Plane, Sphere, Box, Capsule, TriangleMesh, Surface };

std::string_view ToString(ShapeType type);

struct ColliderParams {
  /// The actor carrying the collider; null: a static obstacle (world frame).
  ActorHandle actor;
  /// The link of an articulated `actor` carrying the collider (0 <= link <
  /// its number of links; −1 for any other actor). The shape's pose is then
  /// local to the link frame.
  int link = -1;
  ShapeType shape = ShapeType::Surface;
  /// Pose of the shape: local to a rigid actor or a link, or world for an
  /// obstacle. Not used by Surface.
  Real3 position = Real3::Zero();
  Quat rotation = Quat::Identity();
  /// Plane: the outward normal in the shape's frame (normalized on creation);
  /// the plane passes through `position`.
  Real3 normal = Real3(0, 1, 0);
  /// Sphere, Capsule [m] > 0. Surface of a rod actor: 0 takes the rod's radius.
  real radius = 0;
  /// Box [m], each > 0.
  Real3 halfExtents = Real3::Zero();
  /// Capsule: half the length of its axis, the local z [m], > 0.
  real halfLength = 0;
  /// TriangleMesh: vertices in the shape's frame [m] and triangles (indices).
  DynamicArray<Real3> vertices;
  DynamicArray<std::array<int, 3>> triangles;
  /// Coulomb coefficient μ >= 0; two colliders touch with sqrt(μa μb).
  real friction = 0.5;
  /// Extra thickness of a Box, TriangleMesh or Surface (a shell's half
  /// thickness) [m], >= 0.
  real thickness = 0;
  /// Collision filtering: a and b touch when (a.group & b.mask) and
  /// (b.group & a.mask) are both non-zero.
  std::uint32_t group = 1;
  std::uint32_t mask = 0xffffffffu;
};

}  // namespace superdex
