// The one Catch2 main of the MPI test programs, compiled once: MPI_Init, the
// test cases named on the command line, MPI_Finalize. A rank whose checks
// fail exits non-zero, and mpiexec fails the test. A test case that checks
// nothing fails (Catch2's --warn NoAssertions), as in tests/test_main.cpp.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <mpi.h>

int main(int argc, char* argv[]) {
  MPI_Init(&argc, &argv);
  Catch::Session session;
  session.configData().warnings = Catch::WarnAbout::NoAssertions;
  int status = session.applyCommandLine(argc, argv);
  if (status == 0) status = session.run();
  MPI_Finalize();
  return status == 0 ? 0 : 1;  // a count of failures could wrap to 0 as an exit code
}
