// Input validation used by every public call. Each check sets `error` with a
// message naming the field and the offending value and returns false.
#pragma once

#include <string_view>

#include <superdex/core/error.h>
#include <superdex/core/types.h>

namespace superdex::internal {

bool CheckFinite(real value, std::string_view field, Error& error);
bool CheckFinite(Real3 const& value, std::string_view field, Error& error);
bool CheckNonNegative(real value, std::string_view field, Error& error);
bool CheckPositive(real value, std::string_view field, Error& error);
bool CheckPositive(Real3 const& value, std::string_view field, Error& error);
/// Finite with |value| <= bound (every component of a vector).
bool CheckMagnitude(real value, real bound, std::string_view field, Error& error);
bool CheckMagnitude(Real3 const& value, real bound, std::string_view field, Error& error);
/// An integer in [lowest, highest].
bool CheckIntInRange(long long value, long long lowest, long long highest, std::string_view field, Error& error);
/// A unit quaternion: finite and | |q| - 1 | <= 1e-6.
bool CheckUnitQuat(Quat const& value, std::string_view field, Error& error);

std::string Format(real value);
std::string Format(Real3 const& value);
std::string Format(Quat const& value);

}  // namespace superdex::internal
