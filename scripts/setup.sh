#!/usr/bin/env bash
# Installs SuperDex's build and run dependencies from Debian packages and
# makes OpenBLAS the system BLAS/LAPACK. Idempotent: when everything is
# already in place it only checks (about a second) and prints one line.
#
# Run as root, or as a user with sudo. `--peers` adds the engines that
# perf/peers compares SuperDex with (Bullet 3.24, ODE 0.16.2, MuJoCo 2.2.2:
# not dependencies of SuperDex; perf/peers builds each one only when found).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libmetis-dev petsc-dev libtbb-dev
  catch2 pybind11-dev
  python3-dev python3-numpy python3-matplotlib python3-pytest
  libopenblas-dev libopenblas0-pthread
  clang libclang-rt-14-dev lld
)
if [[ ${1:-} == --peers ]]; then
  packages+=(libbullet-dev libode-dev libmujoco-dev)
fi

# run as root, or through sudo when we are not root
as_root() {
  if [[ ${EUID} -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo "$@"
  else
    echo "setup.sh: need root (or sudo) to run: $*" >&2
    exit 1
  fi
}

# which packages are missing (dpkg status is the source of truth)
missing=()
for pkg in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "${pkg}" 2>/dev/null || true)
  [[ ${status} == installed ]] || missing+=("${pkg}")
done

if ((${#missing[@]} > 0)); then
  echo "setup.sh: installing ${missing[*]}"
  as_root apt-get update
  as_root env DEBIAN_FRONTEND=noninteractive \
    apt-get install -y --no-install-recommends "${missing[@]}"
fi

# make libblas.so.3 / liblapack.so.3 resolve to the multithreaded OpenBLAS
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)
libdir=/usr/lib/${multiarch}
switched=()
for lib in libblas.so.3 liblapack.so.3; do
  target=${libdir}/openblas-pthread/${lib}
  current=$(readlink -f "${libdir}/${lib}" 2>/dev/null || true)
  if [[ ${current} != "$(readlink -f "${target}")" ]]; then
    as_root update-alternatives --set "${lib}-${multiarch}" "${target}" >/dev/null
    switched+=("${lib}")
  fi
done

summary="setup.sh: ${#packages[@]} packages"
if ((${#missing[@]} > 0)); then
  summary+=" (installed ${#missing[@]})"
else
  summary+=" already installed"
fi
if ((${#switched[@]} > 0)); then
  summary+="; switched ${switched[*]} to OpenBLAS"
else
  summary+="; BLAS/LAPACK = OpenBLAS (pthread)"
fi
echo "${summary}"
