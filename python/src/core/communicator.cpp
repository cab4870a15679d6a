// core/communicator.h: the MPI processes (ranks) a scene runs on
// (SceneParams.communicator; docs/distributed.md).
#include "defines.h"
#include "support/errors.h"

#include <string>

namespace superdex::python {

void DefineCommunicator(py::module_& m) {
  py::class_<Communicator>(
      m, "Communicator",
      "The MPI processes (ranks) a scene runs on (SceneParams.communicator). Communicator() is "
      "one process, no MPI: the default. Under `mpirun -n R python3 script.py` every rank runs "
      "the same script and builds the same scene with Communicator.world(); each assembles its "
      "part of the rows and the linear solver (MUMPS or PCG) runs across the ranks, and every "
      "rank ends each step with the same state. docs/distributed.md.")
      .def(py::init<>(), "one process (no MPI), the default")
      .def_static(
          "world", [] { return Checked([](Error& error) { return Communicator::World(error); }); },
          "MPI_COMM_WORLD: the R ranks of `mpirun -n R`, or one rank without mpirun. Starts MPI "
          "(through PETSc) when nothing has; raises mochi.Error (BackendError) when MPI cannot "
          "start.")
      .def_static(
          "from_fortran_handle",
          [](int handle) {
            return Checked([&](Error& error) {
              Communicator const communicator = Communicator::FromFortranHandle(handle);
              communicator.Check("Communicator.from_fortran_handle(" + std::to_string(handle) + ")", error);
              return communicator;
            });
          },
          py::arg("handle"),
          "the communicator with this Fortran handle (MPI_Comm_c2f; with mpi4py, comm.py2f()). "
          "Raises mochi.Error where MPI is not running or the handle names no communicator. The "
          "program keeps the communicator valid while scenes use it.")
      .def("is_set", &Communicator::IsSet, "False for the one-process default")
      .def("get_fortran_handle", &Communicator::GetFortranHandle)
      .def("get_size", &Communicator::GetSize, "MPI_Comm_size (1 for the one-process default)")
      .def("get_rank", &Communicator::GetRank, "MPI_Comm_rank (0 for the one-process default)")
      .def("__repr__", [](Communicator const& c) {
        if (!c.IsSet()) return std::string("Communicator()");
        return "Communicator(fortran_handle=" + std::to_string(c.GetFortranHandle()) +
               ", size=" + std::to_string(c.GetSize()) + ", rank=" + std::to_string(c.GetRank()) + ")";
      });
}

}  // namespace superdex::python
