// assembly/ordering.h: the fill-reducing ordering (SceneParams.ordering).
#include "defines.h"

namespace superdex::python {

void DefineOrdering(py::module_& m) {
  py::enum_<OrderingMethod>(m, "OrderingMethod", "Fill-reducing ordering of the global Hessian.")
      .value("Metis", OrderingMethod::Metis, "METIS nested dissection on the block graph (default)")
      .value("Natural", OrderingMethod::Natural, "DoFs in actor-creation order (for comparisons)")
      .value("SolverDefault", OrderingMethod::SolverDefault,
             "natural order; the linear solver orders (CHOLMOD: AMD/METIS)");
  py::enum_<PatternPolicy>(m, "PatternPolicy",
                           "How the pattern follows contributors whose DoF lists change between stages.")
      .value("ReserveAndGrow", PatternPolicy::ReserveAndGrow,
             "reserve their block pairs (kept while used), grow in the kept order (default)")
      .value("RebuildWhenChanged", PatternPolicy::RebuildWhenChanged,
             "rebuild and order the pattern anew whenever they change (for comparisons)");
}

}  // namespace superdex::python
