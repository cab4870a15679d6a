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
  /// κ [Pa], > 0: the barrier's pressure scale. A pressure p rests at
  /// s ≈ 1 − √(p/3κ) of d̂ (1 kPa at 0.82 d̂); a stiffer κ against a light
  /// body's inertia costs Newton iterations where contacts form
  /// (docs/contact.md, "Why 1e4 Pa").
  real stiffness = 1e4;
  /// ḡ [m], > 0: the tangential slip over which friction ramps up to μλ;
  /// a contact that slips less sticks to its anchor.
  real frictionRampWidth = 1e-4;
  /// The cap on distance evaluations of one pair's continuous collision
  /// detection in one Newton iteration, in [1, 1e8]. Every time CCD returns
  /// is safe, whatever the cap: a pair that slides fast at a gap far below
  /// its motion (the case that needs many) gets a shorter step when the cap
  /// is reached, never one into contact. The cap bounds the time one step
  /// can spend there (one distance, and a rotation for a rigid side, per
  /// evaluation, per pair and Newton iteration).
  int ccdMaxIterations = 10000;
};

/// [m] The range of contact geometry: every coordinate of a collider's
/// vertices (world frame, at creation and at each obstacle pose given), and
/// every radius, half length, half extent and thickness, is at most this in
/// magnitude. There a double still resolves 1.2e-7 m and squared distances
/// stay far from overflow (a capsule 1e300 m long would make every distance
/// to it NaN).
inline constexpr real kMaxContactCoordinate = 1e9;

namespace internal {
/// InvalidArgument naming the field when a value is out of range.
bool ValidateContactParams(ContactParams const& params, Error& error);
}  // namespace internal

}  // namespace superdex
