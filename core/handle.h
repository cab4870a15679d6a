// Stable handles. A handle names an object by slot index, generation and
// scene; the generation of a slot is bumped when its object is destroyed, so a
// handle kept past destruction is detected as stale instead of naming a new
// object, and a handle of one scene is refused by every other scene
// (docs/lifetime.md).
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace superdex {

template <class Tag>
struct Handle {
  static constexpr std::uint32_t kInvalidIndex = 0xffffffffu;
  std::uint32_t index = kInvalidIndex;
  std::uint32_t generation = 0;
  /// The scene that issued the handle (a number unique in the process,
  /// from 1); 0 for a null handle or one built from numbers.
  std::uint32_t scene = 0;

  bool IsNull() const { return index == kInvalidIndex; }
  friend bool operator==(Handle a, Handle b) = default;
};

struct ActorTag {};
struct ConstraintTag {};
using ActorHandle = Handle<ActorTag>;
using ConstraintHandle = Handle<ConstraintTag>;

/// "{index i, generation g, scene s}", for error messages.
template <class Tag>
std::string HandleText(Handle<Tag> h) {
  return "{index " + std::to_string(h.index) + ", generation " + std::to_string(h.generation) + ", scene " +
         std::to_string(h.scene) + "}";
}

}  // namespace superdex

template <class Tag>
struct std::hash<superdex::Handle<Tag>> {
  std::size_t operator()(superdex::Handle<Tag> h) const noexcept {
    return ((std::size_t(h.generation) << 32) ^ h.index) * 0x9e3779b97f4a7c15ull ^ h.scene;
  }
};
