#!/usr/bin/env bash
# The main job: install dependencies, build SuperDex (Release) into build/,
# run the double-pendulum example and plot it. Results: results/double_pendulum/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
source scripts/env.sh

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
# the main job needs the library and its example only
cmake --build build -j"$(nproc)" --target superdex_double_pendulum

mkdir -p results/double_pendulum
build/examples/double_pendulum/superdex_double_pendulum --out results/double_pendulum
/usr/bin/python3 examples/double_pendulum/plot.py results/double_pendulum
echo "main.sh: results in results/double_pendulum/"
