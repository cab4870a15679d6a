#include <superdex/actors/actor.h>

namespace superdex {

std::string_view ToString(ActorType type) {
  switch (type) {
    case ActorType::Rigid: return "Rigid";
    case ActorType::Deformable: return "Deformable";
    case ActorType::Rod: return "Rod";
    case ActorType::Articulated: return "Articulated";
  }
  return "Unknown";
}

}  // namespace superdex
