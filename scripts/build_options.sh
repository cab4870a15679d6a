# Build helpers shared by main.sh, test.sh and test_sanitizers.sh (bash;
# source it after env.sh).
#
# superdex_configure BUILD_DIR CMAKE_ARGS...: configures BUILD_DIR from the
# repository root. A new build directory uses Ninja when it is installed
# (Make otherwise); an existing one keeps the generator it was made with.
# ccache, when installed, is the compiler launcher (a build directory that
# already chose a launcher keeps it); it pays on rebuilds, not on a fresh
# machine, so it is not a dependency.
superdex_configure() {
  local dir=$1
  shift
  local args=()
  if [[ ! -f ${dir}/CMakeCache.txt ]] && command -v ninja >/dev/null 2>&1; then
    args+=(-G Ninja)
  fi
  if command -v ccache >/dev/null 2>&1 &&
    ! grep -q '^CMAKE_CXX_COMPILER_LAUNCHER:' "${dir}/CMakeCache.txt" 2>/dev/null; then
    args+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B "${dir}" "${args[@]}" "$@"
}
