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

namespace {
// "(<prefix0><a>, <prefix1><b>, ...)", appended piece by piece
std::string FormatList(std::initializer_list<std::pair<char const*, real>> items) {
  std::string text("(");
  for (auto const& [label, value] : items) {
    if (text.size() > 1) text.append(", ");
    text.append(label).append(Format(value));
  }
  return text.append(")");
}
}  // namespace

std::string Format(Real3 const& v) { return FormatList({{"", v.x()}, {"", v.y()}, {"", v.z()}}); }

std::string Format(Quat const& q) {
  return FormatList({{"w=", q.w()}, {"x=", q.x()}, {"y=", q.y()}, {"z=", q.z()}});
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

bool CheckMagnitude(real value, real bound, std::string_view field, Error& error) {
  return std::abs(value) <= bound || Fail(field, "finite and within ±" + Format(bound), Format(value), error);
}

bool CheckMagnitude(Real3 const& value, real bound, std::string_view field, Error& error) {
  return (value.allFinite() && value.cwiseAbs().maxCoeff() <= bound) ||
         Fail(field, "finite and within ±" + Format(bound) + " in every component", Format(value), error);
}

bool CheckIntInRange(long long value, long long lowest, long long highest, std::string_view field, Error& error) {
  return (value >= lowest && value <= highest) ||
         Fail(field, "in [" + std::to_string(lowest) + ", " + std::to_string(highest) + "]", std::to_string(value),
              error);
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
