#!/usr/bin/env bash
# The test job: install dependencies; build SuperDex (Release) with its tests
# into build/ and run every ctest test; then the sanitizer job
# (scripts/test_sanitizers.sh: the C++ tests and the fuzz targets' corpora
# under ASan + UBSan in build-asan/) and 60 s of each fuzz target
# (scripts/fuzz.sh). Exits non-zero when any of the three failed. On the
# 2-core CI machine the whole job takes about 35 minutes (docs/architecture.md).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
source scripts/env.sh

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DSUPERDEX_BUILD_TESTS=ON
cmake --build build -j"${SUPERDEX_BUILD_JOBS}"

status=0
ctest --test-dir build --output-on-failure -j2 || status=$?
bash scripts/test_sanitizers.sh || status=1
bash scripts/fuzz.sh "${SUPERDEX_FUZZ_SECONDS:-60}" || status=1
exit "${status}"
