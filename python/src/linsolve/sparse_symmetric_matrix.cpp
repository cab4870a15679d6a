// linsolve/sparse_symmetric_matrix.h: the upper triangle in CSC, for the
// linear solvers bound in linear_solver.cpp.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineSparseSymmetricMatrix(py::module_& m) {
  using M = SparseSymmetricMatrix;
  ParamsClass<M>(
      m, "SparseSymmetricMatrix",
      "A symmetric sparse matrix stored by its upper triangle in compressed sparse columns: for "
      "column j, rows row_index[col_start[j]:col_start[j+1]] in increasing order, every row <= "
      "j, the diagonal present. The pattern (size, col_start, row_index, block_sizes) is "
      "identified by pattern_version; only values change between factorizations. Array fields "
      "read as copies: assign whole arrays.")
      .Field("size", &M::size, "number of rows and columns")
      .Field("col_start", &M::colStart, "size + 1 column starts (int)")
      .Field("row_index", &M::rowIndex, "row of each stored entry (int)")
      .Field("values", &M::values, "value of each stored entry")
      .Field("block_sizes", &M::blockSizes,
             "sizes of the DoF blocks in matrix order, adding to size; empty = blocks of 1")
      .Field("pattern_version", &M::patternVersion,
             "identifies the pattern: change it whenever size, col_start, row_index or "
             "block_sizes change")
      .Class()
      .def("num_nonzeros", &M::NumNonzeros, "Stored (upper-triangle) entries: col_start[-1].");
}

}  // namespace superdex::python
