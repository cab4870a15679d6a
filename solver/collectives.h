// Internal: the few collective operations the Newton solver needs across MPI
// ranks (docs/distributed.md, "Stage 1"), and RankGroup, the distributed
// pieces of a stage solve with their scratch. Every rank holds the whole scene;
// these keep what each rank computes for its own part, and every decision
// taken from it, the same on all ranks. (A linear solver's result is made
// the same on every rank by AgreeOnResult, petsc_distributed_matrix.h.)
#pragma once

#include <cstdint>

#include <superdex/core/communicator.h>
#include <superdex/core/types.h>
#include <superdex/assembly/hessian_assembler.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>

namespace superdex::internal {

/// `ordered` holds this rank's rows [partRowStart[rank], partRowStart[rank+1])
/// of a vector in the partition-major order; afterwards every rank holds all
/// of it (MPI_Allgatherv in place). `counts` and `displacements` are scratch
/// of one entry per rank, sized once by the caller.
void AllgatherRows(Communicator const& communicator, DynamicArray<int> const& partRowStart,
                   DynamicArray<int>& counts, DynamicArray<int>& displacements, Span<real> ordered);

/// True on every rank when `value` is true on every rank (MPI_LAND).
bool OnAllRanks(Communicator const& communicator, bool value);

/// The index of the first of `values` that differs between the ranks, the
/// same on every rank, or -1 where all agree: one MPI_Allreduce (MPI_MIN over
/// the values and their complements, giving the minimum and the maximum).
/// `scratch` is resized to twice the values.
int FirstDisagreement(Communicator const& communicator, Span<std::uint64_t const> values,
                      DynamicArray<std::uint64_t>& scratch);

/// Each of `values` replaced by its sum over the ranks, added in rank order
/// so that every rank gets the same bits (MPI_Allgather, then the sums).
/// `scratch` holds at least values.size() entries per rank, sized by the
/// caller.
void SumInRankOrder(Communicator const& communicator, Span<real> values, DynamicArray<real>& scratch);

/// ReusedFactorCg's product across ranks: each rank multiplies its own rows
/// [partRowStart[rank], partRowStart[rank+1]) of the partition-major order
/// (MultiplySymmetricRows reads only the entries the rank has complete),
/// then AllgatherRows gives every rank all of y, the same bits everywhere.
class OwnedRowsProduct final : public MatrixProduct {
 public:
  /// `partRowStart` (one entry per rank and one more) must outlive the
  /// product; it is read at every Multiply, so a new partition needs no call.
  void Set(Communicator const& communicator, DynamicArray<int> const* partRowStart);
  void Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) override;

 private:
  Communicator communicator_;
  DynamicArray<int> const* partRowStart_ = nullptr;
  DynamicArray<int> counts_, displacements_;  ///< MPI_Allgatherv scratch
};

/// The ranks a stage runs on (SceneParams::communicator) and what the Newton
/// solver does across them: each rank assembles its part of the rows; these
/// make every rank hold the same gradient, energy and decisions.
class RankGroup {
 public:
  void Set(Communicator const& communicator);
  Communicator const& GetCommunicator() const { return communicator_; }
  int GetSize() const { return numRanks_; }
  int GetRank() const { return rank_; }
  bool IsDistributed() const { return numRanks_ > 1; }

  /// Sizes the scratch for a pattern of `numDofs` (at each pattern build).
  void Reserve(int numDofs);
  /// Every rank's owned entries of `gradient` (natural order) to every rank.
  void GatherGradient(HessianAssembler const& assembler, Span<real> gradient);
  /// Each value summed over the ranks, in rank order (at most 2 values).
  void SumInRankOrder(Span<real> values);
  bool OnAllRanks(bool value) const;
  /// FirstDisagreement across the group's ranks (-1 in one process).
  int FirstDisagreement(Span<std::uint64_t const> values);
  /// The product of a reused-factor CG across the ranks.
  OwnedRowsProduct& GetProduct(HessianAssembler const& assembler);

 private:
  Communicator communicator_;
  int numRanks_ = 1, rank_ = 0;
  VectorX orderedGradient_;  ///< the gradient in the partition-major order
  OwnedRowsProduct ownedRowsProduct_;
  DynamicArray<int> rankCounts_, rankDisplacements_;  ///< MPI_Allgatherv scratch
  DynamicArray<real> rankSums_;  ///< SumInRankOrder scratch: 2 per rank
  DynamicArray<std::uint64_t> agreement_;  ///< FirstDisagreement scratch
};

}  // namespace superdex::internal
