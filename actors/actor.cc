#include <superdex/actors/actor.h>

#include <algorithm>

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

void Actor::WriteDofLengthScales(Span<real> scales) const {
  std::fill(scales.begin() + dofOffset_, scales.begin() + dofOffset_ + numDofs_, real(1));
}

void Actor::AddEnergy(internal::HessianAssembler const& assembler, int firstContributor,
                      internal::EnergySum& sum) const {
  // (the owned flags from this actor's first contributor on)
  real const energy =
      Energy(assembler.GetOwnedContributors(firstContributor, assembler.GetNumContributors() - firstContributor));
  sum.Add(energy, EnergyRoundOffScale());
}

}  // namespace superdex
