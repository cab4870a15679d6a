#!/usr/bin/env bash
# Runs every perf/peers program that was built, side by side:
#   perf/peers/run.sh OUT_DIR [BUILD_DIR]
# writes OUT_DIR/peers.csv (every row of every program, one header) and
# OUT_DIR/peers.md (a table per scene: rows engine × dt, columns the
# metrics). BUILD_DIR defaults to build/ (the directory scripts/main.sh
# configures); the time steps are PEERS_RATES (default 60,120,240: dt =
# 1/60, 1/120, 1/240). A program that is not built is skipped with a note;
# one that fails still leaves its rows (its failed runs marked) and makes
# the script exit 1 after the tables are written.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

if [[ $# -lt 1 ]]; then
  echo "usage: perf/peers/run.sh OUT_DIR [BUILD_DIR]" >&2
  exit 2
fi
out=$1
build=${2:-build}
rates=${PEERS_RATES:-60,120,240}
mkdir -p "${out}"

# SuperDex's environment (OpenBLAS kernels, CHOLMOD's thread team) as the
# other scripts run it
if [[ -f scripts/env.sh ]]; then
  # shellcheck source=/dev/null
  source scripts/env.sh
fi

csv=${out}/peers.csv
echo "engine,scene,dt,wall_per_sim_s,metric,value,unit,note" >"${csv}"
status=0
for program in superdex_peer bullet_peer bullet_f64_peer ode_peer mujoco_peer; do
  binary=${build}/perf/peers/${program}
  if [[ ! -x ${binary} ]]; then
    echo "run.sh: ${binary} not built, skipped" >&2
    continue
  fi
  echo "run.sh: ${program} (rates ${rates})" >&2
  "${binary}" --rates "${rates}" --no-header >>"${csv}" || {
    echo "run.sh: ${program} exited $?" >&2
    status=1
  }
done

/usr/bin/python3 perf/peers/table.py "${csv}" >"${out}/peers.md"
echo "run.sh: ${csv} and ${out}/peers.md" >&2
exit "${status}"
