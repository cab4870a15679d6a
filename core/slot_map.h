// Internal: owning storage addressed by generation-checked handles.
#pragma once

#include <memory>
#include <vector>

#include <superdex/core/handle.h>

namespace superdex::internal {

template <class T, class Tag>
class SlotMap {
 public:
  using HandleT = Handle<Tag>;

  /// Storage of the scene numbered `owner`: its handles carry that number,
  /// and handles of any other owner are not found.
  explicit SlotMap(std::uint32_t owner) : owner_(owner) {}

  HandleT Insert(std::unique_ptr<T> object) {
    std::uint32_t index;
    if (!freeSlots_.empty()) {
      index = freeSlots_.back();
      freeSlots_.pop_back();
    } else {
      index = static_cast<std::uint32_t>(slots_.size());
      slots_.push_back({});
    }
    slots_[index].object = std::move(object);
    return {index, slots_[index].generation, owner_};
  }

  /// The object, or nullptr when the handle is null, out of range, stale or
  /// issued by another owner.
  T* Get(HandleT h) const {
    if (h.scene != owner_ || h.index >= slots_.size()) return nullptr;
    Slot const& s = slots_[h.index];
    return (s.generation == h.generation) ? s.object.get() : nullptr;
  }

  /// Removes and returns the object; bumps the slot's generation.
  std::unique_ptr<T> Remove(HandleT h) {
    if (Get(h) == nullptr) return nullptr;
    Slot& s = slots_[h.index];
    ++s.generation;
    freeSlots_.push_back(h.index);
    return std::move(s.object);
  }

  template <class Fn>
  void ForEach(Fn&& fn) const {
    for (Slot const& s : slots_)
      if (s.object) fn(*s.object);
  }

  std::size_t Size() const { return slots_.size() - freeSlots_.size(); }
  /// A non-null handle issued by another owner (another scene).
  bool IsForeign(HandleT h) const { return !h.IsNull() && h.scene != owner_; }

 private:
  struct Slot {
    std::unique_ptr<T> object;
    std::uint32_t generation = 1;
  };
  std::uint32_t owner_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> freeSlots_;
};

}  // namespace superdex::internal
