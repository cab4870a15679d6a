#include <superdex/core/validate.h>

#include <cmath>
#include <sstream>

namespace superdex::internal {

std::string Format(real value) {
  std::ostringstream s;
  s.precision(17);
  s << value;
  return s.str();
}

std::string Format(Real3 const& v) {
  return "(" + Format(v.x()) + ", " + Format(v.y()) + ", " + Format(v.z()) + ")";
}

std::string Format(Quat const& q) {
  return "(w=" + Format(q.w()) + ", x=" + Format(q.x()) + ", y=" + Format(q.y()) +
         ", z=" + Format(q.z()) + ")";
}

namespace {
bool Fail(std::string_view field, std::string_view rule, std::string const& value, Error& error) {
  error.Set(ErrorCode::InvalidArgument,
            std::string(field) + " must be " + std::string(rule) + ", got " + value);
  return false;
}
}  // namespace

bool CheckFinite(real value, std::string_view field, Error& error) {
  return std::isfinite(value) || Fail(field, "finite", Format(value), error);
}

bool CheckFinite(Real3 const& value, std::string_view field, Error& error) {
  return value.allFinite() || Fail(field, "finite", Format(value), error);
}

bool CheckNonNegative(real value, std::string_view field, Error& error) {
  return (std::isfinite(value) && value >= 0) || Fail(field, "finite and >= 0", Format(value), error);
}

bool CheckPositive(real value, std::string_view field, Error& error) {
  return (std::isfinite(value) && value > 0) || Fail(field, "finite and > 0", Format(value), error);
}

bool CheckPositive(Real3 const& value, std::string_view field, Error& error) {
  return (value.allFinite() && (value.array() > 0).all()) ||
         Fail(field, "finite and > 0 in every component", Format(value), error);
}

bool CheckUnitQuat(Quat const& value, std::string_view field, Error& error) {
  bool ok = value.coeffs().allFinite() && std::abs(value.norm() - 1) <= 1e-6;
  return ok || Fail(field, "a unit quaternion (|q| = 1 within 1e-6)", Format(value), error);
}

}  // namespace superdex::internal
