#!/usr/bin/env bash
# The C++ test suite under AddressSanitizer + UndefinedBehaviorSanitizer, and
# the fuzz targets: builds the library, its Catch2 tests and tests/fuzz with
# clang (-fsanitize=address,undefined and libFuzzer's coverage, -O1, linked
# by lld: a third less link time than ld; no
# examples, perf harness or Python module) into build-asan/, and runs ctest
# there (without the install test). Any sanitizer report fails the test that
# produced it. Expects scripts/setup.sh to have run. scripts/fuzz.sh then runs
# the fuzz targets of this build.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh

source scripts/build_options.sh

start=${SECONDS}
CC=clang CXX=clang++ superdex_configure build-asan -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1" -DCMAKE_C_FLAGS_SANITIZE="-O1 -g1" \
  -DSUPERDEX_SANITIZE=address,undefined -DSUPERDEX_FUZZ=ON -DSUPERDEX_BUILD_TESTS=ON -DSUPERDEX_UNITY_BUILD=ON \
  -DSUPERDEX_BUILD_EXAMPLES=OFF -DSUPERDEX_BUILD_PERF=OFF -DSUPERDEX_BUILD_PYTHON=OFF \
  -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=lld
cmake --build build-asan -j"${SUPERDEX_BUILD_JOBS}"
echo "test_sanitizers.sh: build $((SECONDS - start)) s"

# LeakSanitizer is off: Open MPI (initialized by PETSc) leaks from plugins it
# has unloaded by exit, whose stacks cannot be symbolized or suppressed
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
start=${SECONDS}
status=0
ctest --test-dir build-asan --output-on-failure -j2 -LE install || status=$?
echo "test_sanitizers.sh: tests $((SECONDS - start)) s"
exit "${status}"
