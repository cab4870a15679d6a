// The one Catch2 main of the test executables. A test case that checks
// nothing fails by default (Catch2's --warn NoAssertions), whether the
// executable runs under ctest or by hand.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

int main(int argc, char* argv[]) {
  Catch::Session session;
  session.configData().warnings = Catch::WarnAbout::NoAssertions;
  if (int const status = session.applyCommandLine(argc, argv); status != 0) return status;
  return session.run();
}
