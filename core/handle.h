// Stable handles. A handle names an object by slot index and generation; the
// generation of a slot is bumped when its object is destroyed, so a handle
// kept past destruction is detected as stale instead of naming a new object.
#pragma once

#include <cstdint>
#include <functional>

namespace superdex {

template <class Tag>
struct Handle {
  static constexpr std::uint32_t kInvalidIndex = 0xffffffffu;
  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;

  bool IsNull() const { return index == kInvalidIndex; }
  friend bool operator==(Handle a, Handle b) = default;
};

struct ActorTag {};
struct ConstraintTag {};
using ActorHandle = Handle<ActorTag>;
using ConstraintHandle = Handle<ConstraintTag>;

}  // namespace superdex

template <class Tag>
struct std::hash<superdex::Handle<Tag>> {
  std::size_t operator()(superdex::Handle<Tag> h) const noexcept {
    return (std::size_t(h.generation) << 32) ^ h.index;
  }
};
