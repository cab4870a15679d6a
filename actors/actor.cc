#include <superdex/actors/actor.h>

namespace superdex {

std::string_view ToString(ActorType type) {
  switch (type) {
    case ActorType::kRigid: return "Rigid";
  }
  return "Unknown";
}

}  // namespace superdex
