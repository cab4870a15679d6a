#include <superdex/stage/constraint_hessian.h>

namespace superdex {

std::string_view ToString(ConstraintHessian hessian) {
  switch (hessian) {
    case ConstraintHessian::SceneDefault: return "SceneDefault";
    case ConstraintHessian::GaussNewton: return "GaussNewton";
    case ConstraintHessian::GeometricStiffness: return "GeometricStiffness";
    case ConstraintHessian::GeometricStiffnessDiagonal: return "GeometricStiffnessDiagonal";
  }
  return "Unknown";
}

namespace internal {
bool CheckConstraintHessian(ConstraintHessian hessian, std::string_view field, bool allowSceneDefault,
                            Error& error) {
  switch (hessian) {
    case ConstraintHessian::SceneDefault:
      if (allowSceneDefault) return true;
      error.Set(ErrorCode::InvalidArgument,
                std::string(field) + " must name a Hessian (SceneDefault is for constraints only)");
      return false;
    case ConstraintHessian::GaussNewton:
    case ConstraintHessian::GeometricStiffness:
    case ConstraintHessian::GeometricStiffnessDiagonal: return true;
  }
  error.Set(ErrorCode::InvalidArgument, std::string(field) + " must be a ConstraintHessian, got the value " +
                                            std::to_string(static_cast<int>(hessian)));
  return false;
}

}  // namespace internal

}  // namespace superdex
