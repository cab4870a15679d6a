#!/usr/bin/env bash
# Runs each libFuzzer target of build-asan/ (scripts/test_sanitizers.sh builds
# them with clang, ASan and UBSan) for SECONDS (default 60), starting from its
# seed corpus in tests/fuzz/corpus/<target> (read, never written). New inputs
# and any crash go to build-asan/fuzz-work/<target>/. Prints libFuzzer's
# final statistics per target; exits non-zero when a target found a crash.
# The targets run side by side, as many at a time as there are cores.
#
#   bash scripts/fuzz.sh [SECONDS [TARGET...]]    targets: obj gmsh tetgen scene_api contact
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh

seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(obj gmsh tetgen scene_api contact)

# as in test_sanitizers.sh: no LeakSanitizer (Open MPI's unloaded plugins)
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# fuzz TARGET: one target for SECONDS; returns non-zero when it found a crash
fuzz() {
  local target=$1
  local exe=build-asan/tests/fuzz/fuzz_${target} work=build-asan/fuzz-work/${target}
  mkdir -p "${work}/corpus"
  "${exe}" -max_total_time="${seconds}" -timeout=60 -rss_limit_mb=4096 -detect_leaks=0 \
    -print_final_stats=1 -artifact_prefix="${work}/" "${work}/corpus" "tests/fuzz/corpus/${target}" \
    > "${work}/log.txt" 2>&1
}

# the targets side by side, one per core (each one is single-threaded), each
# for SECONDS; then their results in the order given
echo "fuzz.sh: ${targets[*]}, ${seconds} s each, ${SUPERDEX_BUILD_JOBS} at a time"
for target in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= SUPERDEX_BUILD_JOBS)); do wait -n || true; done
  rm -f "build-asan/fuzz-work/${target}/status"
  { rc=0; fuzz "${target}" || rc=$?; echo "${rc}" > "build-asan/fuzz-work/${target}/status"; } &
done
wait
status=0
for target in "${targets[@]}"; do
  work=build-asan/fuzz-work/${target}
  if [[ $(cat "${work}/status" 2>/dev/null) != 0 ]]; then
    status=1
    echo "fuzz.sh: ${target} FAILED; the input is in ${work}/ (crash-*, timeout-*, oom-*):"
    tail -n 40 "${work}/log.txt"
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" "${work}/log.txt" |
    sed "s/^/  ${target} /" || true
done
exit "${status}"
