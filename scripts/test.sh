#!/usr/bin/env bash
# The test job: install dependencies, build SuperDex (Release) with its tests
# into build/, run every ctest test. Exits with ctest's status.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
source scripts/env.sh

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSUPERDEX_BUILD_TESTS=ON
cmake --build build -j"$(nproc)"

status=0
ctest --test-dir build --output-on-failure -j2 || status=$?
exit "${status}"
