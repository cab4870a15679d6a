#!/usr/bin/env bash
# The test job (docs/testing.md): install dependencies; build SuperDex
# (Release) with its tests into build/ and run them with ctest; then the
# sanitizer job (scripts/test_sanitizers.sh: the C++ tests and the fuzz
# targets' corpora under ASan + UBSan in build-asan/) and 20 s of each fuzz
# target (scripts/fuzz.sh). Prints the time of each part and exits non-zero
# when any part failed.
#
#   bash scripts/test.sh          the whole job, as CI runs it (.ci/run)
#   bash scripts/test.sh --fast   the Release build and every test not labelled
#                                 slow; no sanitizer build, no fuzzing
#
# Environment:
#   SUPERDEX_SKIP_SANITIZERS=1   skip the sanitizer build, its tests and the fuzzing
#   SUPERDEX_FUZZ_SECONDS=N      seconds of fuzzing per target (default 20; 0 skips it)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

fast=0
case "${1:-}" in
  "") ;;
  --fast) fast=1 ;;
  *) echo "usage: bash scripts/test.sh [--fast]" >&2; exit 2 ;;
esac

times=()
status=0
# part NAME COMMAND...: runs a part of the job, records its time and status
part() {
  local name=$1 start=${SECONDS} rc=0
  shift
  "$@" || rc=$?
  times+=("$(printf '%-22s %5d s%s' "${name}" $((SECONDS - start)) "$( ((rc == 0)) || echo "  (failed: ${rc})")")")
  ((rc == 0)) || status=1
  return 0
}

part setup bash scripts/setup.sh
((status == 0)) || { echo "test.sh: setup failed"; exit 1; }
source scripts/env.sh
source scripts/build_options.sh

release_build() {
  superdex_configure build -DCMAKE_BUILD_TYPE=Release -DSUPERDEX_BUILD_TESTS=ON -DSUPERDEX_UNITY_BUILD=ON &&
    cmake --build build -j"${SUPERDEX_BUILD_JOBS}"
}
part "Release build" release_build
if ((status == 0)); then
  if ((fast)); then
    part "Release tests (fast)" ctest --test-dir build --output-on-failure -j2 -LE slow
  else
    part "Release tests" ctest --test-dir build --output-on-failure -j2
  fi
fi
if ((!fast)) && [[ -z ${SUPERDEX_SKIP_SANITIZERS:-} ]]; then
  part "sanitizer job" bash scripts/test_sanitizers.sh
  if ((${SUPERDEX_FUZZ_SECONDS:-20} > 0)); then
    part fuzzing bash scripts/fuzz.sh "${SUPERDEX_FUZZ_SECONDS:-20}"
  fi
fi

echo "test.sh: time per part"
printf '  %s\n' "${times[@]}"
echo "test.sh: $( ((status == 0)) && echo "every part passed" || echo "a part FAILED")"
exit "${status}"
