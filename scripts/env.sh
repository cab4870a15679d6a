# Environment for running SuperDex (bash). Source it: `source scripts/env.sh`.
#
# OpenBLAS 0.3.21 (Debian bookworm) picks its kernels from the CPU id, with
# tables that only know the CPUs of its release; a CPU it maps to an older
# core, or a stray OPENBLAS_CORETYPE, runs far below the hardware. Measured
# DGEMM per core on an AVX-512 AMD EPYC (docs/blas.md): Prescott (SSE3) ~23,
# Haswell (AVX2) ~62, SkylakeX (AVX-512) ~104 GFLOP/s. OPENBLAS_CORETYPE, read
# when OpenBLAS loads, overrides the detection; here it is chosen from the CPU
# flags:
#   avx512f avx512bw avx512dq avx512vl avx512cd  -> SkylakeX
#   avx2 fma                                      -> Haswell
#   otherwise                                     -> unset (OpenBLAS decides)
# A value already set by the caller is kept when it is at least as capable as
# this CPU's best; a weaker one is replaced (with a note on stderr) unless
# SUPERDEX_KEEP_OPENBLAS_CORETYPE is set.

_superdex_flags=""
if [[ -r /proc/cpuinfo ]]; then
  _superdex_flags=" $(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2) "
fi
_superdex_has() {
  local f
  for f in "$@"; do
    [[ ${_superdex_flags} == *" ${f} "* ]] || return 1
  done
}
_superdex_coretype=""
if _superdex_has avx512f avx512bw avx512dq avx512vl avx512cd; then
  _superdex_coretype=SkylakeX
elif _superdex_has avx2 fma; then
  _superdex_coretype=Haswell
fi

# instruction-set tier of an OpenBLAS core name: 3 AVX-512, 2 AVX2, 1 AVX, 0 older
_superdex_tier() {
  case "${1,,}" in
    skylakex | cooperlake | sapphirerapids) echo 3 ;;
    haswell | skylake | zen | atom_avx2) echo 2 ;;
    sandybridge) echo 1 ;;
    *) echo 0 ;;
  esac
}

if [[ -z ${OPENBLAS_CORETYPE:-} ]]; then
  if [[ -n ${_superdex_coretype} ]]; then
    export OPENBLAS_CORETYPE=${_superdex_coretype}
  fi
elif [[ -n ${_superdex_coretype} ]] &&
  (($(_superdex_tier "${OPENBLAS_CORETYPE}") < $(_superdex_tier "${_superdex_coretype}"))); then
  # a preset weaker than this CPU runs (seen: Haswell on an AVX-512 machine,
  # half the DGEMM rate) is replaced, unless the caller asks to keep it
  if [[ -n ${SUPERDEX_KEEP_OPENBLAS_CORETYPE:-} ]]; then
    echo "env.sh: keeping OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE} (SUPERDEX_KEEP_OPENBLAS_CORETYPE is set);" \
      "this CPU can run the ${_superdex_coretype} kernels" >&2
  else
    echo "env.sh: OPENBLAS_CORETYPE=${OPENBLAS_CORETYPE} from the environment is weaker than this CPU;" \
      "using ${_superdex_coretype} (set SUPERDEX_KEEP_OPENBLAS_CORETYPE=1 to keep it)" >&2
    export OPENBLAS_CORETYPE=${_superdex_coretype}
  fi
fi

# Build parallelism for the scripts: every CPU this process may use, counted
# without the OpenMP variables (set below), which GNU nproc honours: with
# OMP_THREAD_LIMIT=1, `nproc` says 1 and the builds ran on one core.
SUPERDEX_BUILD_JOBS=$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)
export SUPERDEX_BUILD_JOBS

# Debian's CHOLMOD opens an OpenMP team of 4 threads (fixed at its build) on
# every factorization, on top of OpenBLAS's own threads. On this 2-core
# machine that costs 40–60 µs per small factorization (docs/linear_solvers.md)
# and, measured on the pinned-cloth test (867 DoFs, ~30k factorizations):
# 21 s with the default, 3 min 50 s with OMP_THREAD_LIMIT=2, 15 s with
# OMP_THREAD_LIMIT=1. OpenBLAS (pthreads) still runs the dense kernels on every
# core, so CHOLMOD's OpenMP team is limited to one thread unless set already.
if [[ -z ${OMP_THREAD_LIMIT:-} ]]; then
  export OMP_THREAD_LIMIT=1
fi

unset -f _superdex_has _superdex_tier
unset _superdex_flags _superdex_coretype

# Open MPI's session directories. `ctest -j2` starts MPI in several
# processes at once (every PETSc test initializes it). Each creates the
# top-level session directory <base>/ompi.<host>.<uid> if it is missing, and
# removes it on exit if it is empty. Two processes creating it at the same
# moment make one of them fail in MPI_Init ("mkdir ... File exists", seen
# once in a fresh-clone run of scripts/test.sh). Here the base is a directory
# of our own whose top-level session directory holds a file named output-*
# (the files Open MPI's clean-up leaves in place), so it always exists and
# is never removed. A base the caller chose is kept.
if [[ -z ${OMPI_MCA_orte_tmpdir_base:-} ]]; then
  export OMPI_MCA_orte_tmpdir_base="${TMPDIR:-/tmp}/superdex-ompi-$(id -u)"
  _superdex_session="${OMPI_MCA_orte_tmpdir_base}/ompi.$(hostname -s 2>/dev/null || hostname).$(id -u)"
  if mkdir -p "${_superdex_session}" 2>/dev/null; then
    : >"${_superdex_session}/output-superdex-keep"
  fi
  unset _superdex_session
fi
