#include <superdex/constraints/constraint.h>

#include <algorithm>

#include <superdex/core/validate.h>

namespace superdex {

std::string_view ToString(QueryType type) {
  switch (type) {
    case QueryType::ConstraintForce: return "ConstraintForce";
  }
  return "Unknown";
}


namespace internal {
using Target = ConstraintKernel::Target;
namespace {
// out[i] = a[i] + s (b[i] − a[i]) for i in [first, first + count)
template <class Target>
void Lerp(Target const& a, Target const& b, real s, int first, int count, Target& out) {
  for (int i = first; i < first + count; ++i) out[i] = a[i] + s * (b[i] - a[i]);
}

// the unit quaternion (w, x, y, z) at `first`: slerp from a's to b's (shortest arc)
template <class Target>
void Slerp(Target const& a, Target const& b, real s, int first, Target& out) {
  Quat const qa(a[first], a[first + 1], a[first + 2], a[first + 3]);
  Quat const qb(b[first], b[first + 1], b[first + 2], b[first + 3]);
  Quat const q = qa.slerp(s, qb).normalized();
  out[first] = q.w(), out[first + 1] = q.x(), out[first + 2] = q.y(), out[first + 3] = q.z();
}
}  // namespace


Target InterpolateTarget(ConstraintKernel::TargetKind kind, Target const& from, Target const& to, real s) {
  if (s == 1 || from == to) return to;
  using TargetKind = ConstraintKernel::TargetKind;
  Target out = to;
  switch (kind) {
    case TargetKind::None: break;
    case TargetKind::Position: Lerp(from, to, s, 0, 3, out); break;
    case TargetKind::Dof: Lerp(from, to, s, 0, 1, out); break;
    case TargetKind::Rotation: Slerp(from, to, s, 0, out); break;
    case TargetKind::Transform:
      Lerp(from, to, s, 0, 3, out);
      Slerp(from, to, s, 3, out);
      break;
  }
  return out;
}
}  // namespace internal

Constraint::Constraint(Layout layout, internal::CompliantParams const& params)
    : internal::ConstraintKernel(std::move(layout)) {
  state_.params = params;
  state_.stageParams = params;
  state_.force.assign(GetNumDofs(), 0);
}

bool Constraint::SetStiffness(real stiffness, Error& error) {
  if (!internal::CheckNonNegative(stiffness, "stiffness", error)) return false;
  state_.params.stiffness = stiffness;
  state_.stageParams = state_.params;
  state_.nearRigidCapped = false;
  return true;
}

bool Constraint::SetDamping(real damping, Error& error) {
  if (!internal::CheckNonNegative(damping, "damping", error)) return false;
  state_.params.damping = damping;
  state_.stageParams = state_.params;
  state_.nearRigidCapped = false;
  return true;
}

bool Constraint::SetSaturation(real saturation, Error& error) {
  if (!internal::CheckFinite(saturation, "saturation", error)) return false;
  state_.params.saturation = saturation;
  state_.stageParams = state_.params;
  state_.nearRigidCapped = false;
  return true;
}

bool Constraint::SetHessianApproximation(ConstraintHessian hessian, Error& error) {
  if (!internal::CheckConstraintHessian(hessian, "hessianApproximation", true, error)) return false;
  state_.hessian = hessian;
  return true;
}

void Constraint::ReportNotSupported(std::string_view method, std::string_view why,
                                    Error& error) const {
  error.Set(ErrorCode::NotSupported, std::string(method) + " does not apply to a " +
                                         std::string(ToString(GetType())) + " constraint" +
                                         std::string(why));
}

bool Constraint::RequireTarget(TargetKind kind, std::string_view method, Error& error) const {
  if (GetTargetKind() == kind) return true;
  ReportNotSupported(method, "", error);
  return false;
}

bool Constraint::SetTargetPosition(Real3 const& position, Error& error) {
  if (!RequireTarget(TargetKind::Position, "SetTargetPosition", error) ||
      !internal::CheckFinite(position, "position", error))
    return false;
  for (int i = 0; i < 3; ++i) state_.target[i] = position[i];
  return true;
}

bool Constraint::SetTargetRotation(Quat const& rotation, Error& error) {
  if (!RequireTarget(TargetKind::Rotation, "SetTargetRotation", error) ||
      !internal::CheckUnitQuat(rotation, "rotation", error))
    return false;
  Quat const q = rotation.normalized();
  state_.target[0] = q.w(), state_.target[1] = q.x(), state_.target[2] = q.y(), state_.target[3] = q.z();
  return true;
}

bool Constraint::SetTargetTransform(Real3 const& position, Quat const& rotation, Error& error) {
  if (!RequireTarget(TargetKind::Transform, "SetTargetTransform", error) ||
      !internal::CheckFinite(position, "position", error) ||
      !internal::CheckUnitQuat(rotation, "rotation", error))
    return false;
  Quat const q = rotation.normalized();
  for (int i = 0; i < 3; ++i) state_.target[i] = position[i];
  state_.target[3] = q.w(), state_.target[4] = q.x(), state_.target[5] = q.y(), state_.target[6] = q.z();
  return true;
}

bool Constraint::SetTargetDof(real value, Error& error) {
  if (!RequireTarget(TargetKind::Dof, "SetTargetDof", error) ||
      !internal::CheckFinite(value, "value", error))
    return false;
  state_.target[0] = value;
  return true;
}

bool Constraint::UpdateOldTarget(Error& error) {
  if (GetTargetKind() == TargetKind::None) {
    ReportNotSupported("UpdateOldTarget", " (it has no target)", error);
    return false;
  }
  state_.oldTarget = state_.target;
  return true;
}

void Constraint::InitializeTarget(Target const& target) {
  state_.target = target;
  state_.oldTarget = target;
}


DynamicArray<real> Constraint::GetDeviation() const {
  VectorX const g = Value(state_.target);
  return DynamicArray<real>(g.begin(), g.end());
}

bool Constraint::IsQuerySupported(QueryType type) const { return type == QueryType::ConstraintForce; }

bool Constraint::RegisterQuery(QueryType type, Error& error) {
  if (!IsQuerySupported(type)) {
    ReportNotSupported("RegisterQuery(" + std::string(ToString(type)) + ")", "", error);
    return false;
  }
  state_.forceQueryRegistered = true;
  return true;
}

Span<real const> Constraint::GetForce(Error& error) const {
  if (!state_.forceQueryRegistered) {
    error.Set(ErrorCode::InvalidState,
              "GetForce needs RegisterQuery(QueryType::ConstraintForce) before stepping");
    return {};
  }
  if (!state_.forceValid) {
    error.Set(ErrorCode::InvalidState,
              "GetForce: no step has completed since the ConstraintForce query was registered");
    return {};
  }
  return state_.force;
}

DynamicArray<real> Constraint::LimitsFor(bool upper, std::string_view method, Error& error) const {
  if (!IsRange()) {
    ReportNotSupported(method, " (not a range type)", error);
    return {};
  }
  DynamicArray<real> lower, upperValues;
  GetLimits(lower, upperValues);
  return upper ? upperValues : lower;
}

DynamicArray<real> Constraint::GetLimitMinValues(Error& error) const {
  return LimitsFor(false, "GetLimitMinValues", error);
}

DynamicArray<real> Constraint::GetLimitMaxValues(Error& error) const {
  return LimitsFor(true, "GetLimitMaxValues", error);
}

}  // namespace superdex
