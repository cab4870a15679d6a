#!/usr/bin/env bash
# Runs each libFuzzer target of build-asan/ (scripts/test_sanitizers.sh builds
# them with clang, ASan and UBSan) for SECONDS (default 60), starting from its
# seed corpus in tests/fuzz/corpus/<target> (read, never written). New inputs
# and any crash go to build-asan/fuzz-work/<target>/. Prints libFuzzer's
# final statistics per target; exits non-zero when a target found a crash.
#
#   bash scripts/fuzz.sh [SECONDS [TARGET...]]    targets: obj gmsh tetgen scene_api
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh

seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(obj gmsh tetgen scene_api)

# as in test_sanitizers.sh: no LeakSanitizer (Open MPI's unloaded plugins)
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
status=0
for target in "${targets[@]}"; do
  exe=build-asan/tests/fuzz/fuzz_${target}
  work=build-asan/fuzz-work/${target}
  mkdir -p "${work}/corpus"
  echo "fuzz.sh: ${target} for ${seconds} s"
  if ! "${exe}" -max_total_time="${seconds}" -timeout=60 -rss_limit_mb=4096 -detect_leaks=0 \
      -print_final_stats=1 -artifact_prefix="${work}/" "${work}/corpus" "tests/fuzz/corpus/${target}" \
      > "${work}/log.txt" 2>&1; then
    status=1
    echo "fuzz.sh: ${target} FAILED; the input is in ${work}/ (crash-*, timeout-*, oom-*):"
    tail -n 40 "${work}/log.txt"
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" "${work}/log.txt" |
    sed "s/^/  ${target} /" || true
done
exit "${status}"
