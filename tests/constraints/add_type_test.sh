#!/usr/bin/env bash
# Adds the example constraint type of docs/extending.md (new_type/: the
# RigidCenterOnPlane type, its two files) to a copy of the tree by the
# checklist — the two files into constraints/, one line into
# constraints/constraint_types.h — checks that the change touches 3 files,
# builds the library and mochi from the copy, and checks with
# new_type/check_new_type.py that the factory and its validation, mochi's
# params class, factory, class and downcast, and the docs table came from the
# list.
#
# usage: add_type_test.sh SOURCE_DIR WORK_DIR PYTHON
set -euo pipefail
src=$1 work=$2 python=$3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

rm -rf "${work}"
mkdir -p "${work}/tree"
# the tracked files, as a clone has them, in a repository of their own
git -C "${src}" ls-files -z | (cd "${src}" && xargs -0 tar cf -) | tar xf - -C "${work}/tree"
cd "${work}/tree"
git init -q
git -c user.name=test -c user.email=test@localhost add -A
git -c user.name=test -c user.email=test@localhost commit -q -m "the tree"

# the checklist (docs/extending.md, "A new constraint type")
cp "${here}/new_type/rigid_center_on_plane.h" "${here}/new_type/rigid_center_on_plane.cc" constraints/
line='  X(RigidCenterOnPlane, RigidCenterOnPlaneConstraint, rigid_center_on_plane) \'
# the line goes before the blank line that ends the list
awk -v line="${line}" 'inlist && /^$/ { print line; inlist = 0 } /^#define SUPERDEX_CONSTRAINT_TYPES/ { inlist = 1 } { print }' \
  constraints/constraint_types.h > constraints/constraint_types.h.new
mv constraints/constraint_types.h.new constraints/constraint_types.h

touched=$(git status --porcelain | wc -l)
git status --porcelain
if [[ ${touched} -ne 3 ]]; then
  echo "add_type_test: adding a type touched ${touched} files, expected 3 (two new, the list)"
  exit 1
fi
added=$(git diff --numstat constraints/constraint_types.h | awk '{ print $1 " added, " $2 " removed" }')
echo "add_type_test: constraints/constraint_types.h: ${added}"
[[ ${added} == "1 added, 0 removed" ]] || { echo "add_type_test: expected one line added to the list"; exit 1; }

# the library and mochi from the copy: build type None, neither optimized
# nor with debug information (only the wiring is checked), in unity batches
# (SUPERDEX_UNITY_BUILD; mochi always is: 318 s -> 213 s on 2 cores); the library
# static and position independent, so that ctest install_static_and_consume
# can install this build as a static package (one compile serves both). With
# clang where it is installed (the sanitizer job's compiler, scripts/setup.sh):
# unoptimized, its front end takes the library's heaviest unity batch in 35 s
# where gcc 12 takes 91 s; the static library links into gcc-built programs
# (the same libstdc++).
source scripts/build_options.sh
compilers=()
if command -v clang++ >/dev/null 2>&1 && command -v clang >/dev/null 2>&1; then
  compilers=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++)
fi
superdex_configure build "${compilers[@]}" -DCMAKE_BUILD_TYPE=None -DSUPERDEX_NATIVE=OFF -DSUPERDEX_BUILD_TESTS=OFF \
  -DSUPERDEX_BUILD_EXAMPLES=OFF -DSUPERDEX_BUILD_PERF=OFF -DSUPERDEX_BUILD_PYTHON=ON \
  -DBUILD_SHARED_LIBS=OFF -DCMAKE_POSITION_INDEPENDENT_CODE=ON -DSUPERDEX_UNITY_BUILD=ON > configure.log
cmake --build build -j"${SUPERDEX_BUILD_JOBS:-2}" --target mochi > build.log 2>&1 || { tail -40 build.log; exit 1; }
PYTHONPATH=build/python PYTHONDONTWRITEBYTECODE=1 "${python}" "${here}/new_type/check_new_type.py" .
