#!/usr/bin/env bash
# The main job: install dependencies, build SuperDex (Release) into build/,
# run the perf harness's quick suite (scene families × sizes × solvers ×
# time steps × integrators) and draw its charts and summary table.
# Results: results/perf/ (results.csv, results.json, *.png, summary.md).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
source scripts/env.sh
source scripts/build_options.sh

# (the library in unity batches, as test.sh builds it: the two commands share
# build/ without recompiling it)
superdex_configure build -DCMAKE_BUILD_TYPE=Release -DSUPERDEX_UNITY_BUILD=ON
# the main job needs the library and the harness only
cmake --build build -j"${SUPERDEX_BUILD_JOBS}" --target superdex_perf

rm -rf results/perf
status=0
build/perf/harness/superdex_perf --suite quick --out results/perf || status=$?
/usr/bin/python3 perf/harness/plot.py results/perf
echo "main.sh: results in results/perf/ (summary.md, charts *.png)"
exit "${status}"
