// OwnedContributors: which of an actor's Hessian contributors this MPI rank
// counts in the energy (HessianAssembler::Owns, docs/distributed.md).
#pragma once

#include <cstdint>

#include <superdex/core/types.h>

namespace superdex::internal {

/// A run of contributors (an actor's, from its first), indexed from 0. Each
/// contributor is owned by exactly one rank, so the ranks' energies add up
/// to the whole. Empty flags: every contributor is owned (one process).
struct OwnedContributors {
  Span<std::uint8_t const> flags;
  bool operator()(int k) const { return flags.empty() || flags[k] != 0; }
};

}  // namespace superdex::internal
