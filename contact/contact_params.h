// ContactParams: the scene's contact settings (docs/contact.md).
//
// Normal contact is a clamped log barrier on the gap d between two
// colliders' primitives (their unsigned distance less their thicknesses):
//
//   E = κ w d̂ b(d / d̂),   b(s) = −(s − 1)² ln s for 0 < s < 1, 0 beyond
//
// with κ the stiffness [Pa], w the area [m²] the contact stands for and d̂
// the activation distance [m]. Friction is the regularized Coulomb force of
// the reference page's ramp ρ over the tangential slip from a stick anchor
// (ρ's width ḡ = frictionRampWidth).
#pragma once

#include <superdex/core/error.h>
#include <superdex/core/types.h>

namespace superdex {

struct ContactParams {
  /// d̂ [m], > 0: primitives closer than this repel each other.
  real activationDistance = 1e-3;
  /// κ [Pa], > 0: the barrier's pressure scale.
  real stiffness = 1e6;
  /// ḡ [m], > 0: the tangential slip over which friction ramps up to μλ;
  /// a contact that slips less sticks to its anchor.
  real frictionRampWidth = 1e-4;
};

namespace internal {
/// InvalidArgument naming the field when a value is out of range.
bool ValidateContactParams(ContactParams const& params, Error& error);
}  // namespace internal

}  // namespace superdex
