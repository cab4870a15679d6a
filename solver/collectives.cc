#include <superdex/solver/collectives.h>

#include <superdex/core/mpi.h>

namespace superdex::internal {

void AllgatherRows(Communicator const& communicator, DynamicArray<int> const& partRowStart,
                   DynamicArray<int>& counts, DynamicArray<int>& displacements, Span<real> ordered) {
  int const ranks = static_cast<int>(partRowStart.size()) - 1;
  for (int r = 0; r < ranks; ++r) {
    displacements[r] = partRowStart[r];
    counts[r] = partRowStart[r + 1] - partRowStart[r];
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, ordered.data(), counts.data(), displacements.data(),
                 MPI_DOUBLE, ToMpiComm(communicator));
}

bool OnAllRanks(Communicator const& communicator, bool value) {
  int all = value ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &all, 1, MPI_INT, MPI_LAND, ToMpiComm(communicator));
  return all != 0;
}

int FirstDisagreement(Communicator const& communicator, Span<std::uint64_t const> values,
                      DynamicArray<std::uint64_t>& scratch) {
  std::size_t const n = values.size();
  scratch.resize(2 * n);
  for (std::size_t k = 0; k < n; ++k) {
    scratch[k] = values[k];
    scratch[n + k] = ~values[k];  // its minimum is the complement of the maximum
  }
  MPI_Allreduce(MPI_IN_PLACE, scratch.data(), static_cast<int>(2 * n), MPI_UINT64_T, MPI_MIN,
                ToMpiComm(communicator));
  for (std::size_t k = 0; k < n; ++k)
    if (scratch[k] != ~scratch[n + k]) return static_cast<int>(k);
  return -1;
}

void SumInRankOrder(Communicator const& communicator, Span<real> values, DynamicArray<real>& scratch) {
  int const count = static_cast<int>(values.size());
  MPI_Allgather(values.data(), count, MPI_DOUBLE, scratch.data(), count, MPI_DOUBLE, ToMpiComm(communicator));
  int const ranks = communicator.GetSize();
  for (int k = 0; k < count; ++k) {
    real sum = 0;
    for (int r = 0; r < ranks; ++r) sum += scratch[r * count + k];
    values[k] = sum;
  }
}

void OwnedRowsProduct::Set(Communicator const& communicator, DynamicArray<int> const* partRowStart) {
  communicator_ = communicator;
  partRowStart_ = partRowStart;
  counts_.assign(static_cast<std::size_t>(communicator.GetSize()), 0);
  displacements_.assign(counts_.size(), 0);
}

void OwnedRowsProduct::Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) {
  int const rank = communicator_.GetRank();
  MultiplySymmetricRows(a, (*partRowStart_)[rank], (*partRowStart_)[rank + 1], x, y);
  AllgatherRows(communicator_, *partRowStart_, counts_, displacements_, y);
}

void RankGroup::Set(Communicator const& communicator) {
  communicator_ = communicator;
  numRanks_ = communicator.GetSize();
  rank_ = communicator.GetRank();
}

void RankGroup::Reserve(int numDofs) {
  if (!IsDistributed()) return;
  orderedGradient_.setZero(numDofs);
  rankCounts_.assign(numRanks_, 0);
  rankDisplacements_.assign(numRanks_, 0);
  rankSums_.assign(2 * static_cast<std::size_t>(numRanks_), 0);
}

void RankGroup::GatherGradient(HessianAssembler const& assembler, Span<real> gradient) {
  int const n = static_cast<int>(gradient.size());
  assembler.PermuteToOrdered(Span<real const>(gradient.data(), n), Span<real>(orderedGradient_.data(), n));
  AllgatherRows(communicator_, assembler.GetPartRowStart(), rankCounts_, rankDisplacements_,
                Span<real>(orderedGradient_.data(), n));
  assembler.PermuteToNatural(Span<real const>(orderedGradient_.data(), n), gradient);
}

void RankGroup::SumInRankOrder(Span<real> values) { internal::SumInRankOrder(communicator_, values, rankSums_); }

bool RankGroup::OnAllRanks(bool value) const { return internal::OnAllRanks(communicator_, value); }

int RankGroup::FirstDisagreement(Span<std::uint64_t const> values) {
  return IsDistributed() ? internal::FirstDisagreement(communicator_, values, agreement_) : -1;
}

OwnedRowsProduct& RankGroup::GetProduct(HessianAssembler const& assembler) {
  ownedRowsProduct_.Set(communicator_, &assembler.GetPartRowStart());
  return ownedRowsProduct_;
}

}  // namespace superdex::internal
