#!/usr/bin/env bash
# ctest setup_without_root: with every package installed and OpenBLAS the
# system BLAS, scripts/setup.sh only checks, and needs no root for it. Run as
# root (CI), the script runs as user nobody (setpriv), read from stdin so that
# a checkout only root can read does not matter; run as another user, it runs
# as that user.
#
# usage: setup_without_root.sh SETUP_SH
set -euo pipefail
setup=$(realpath "$1")
cd /
if [[ ${EUID} -eq 0 ]]; then
  command -v setpriv >/dev/null || { echo "setup_without_root: setpriv (util-linux) is missing"; exit 1; }
  output=$(setpriv --reuid=65534 --regid=65534 --clear-groups env -u SUDO_USER PATH=/usr/sbin:/usr/bin:/sbin:/bin \
    bash -s <"${setup}" 2>&1) || { echo "${output}"; echo "setup_without_root: setup.sh failed as nobody"; exit 1; }
else
  output=$(bash -s <"${setup}" 2>&1) || { echo "${output}"; echo "setup_without_root: setup.sh failed as $(id -un)"; exit 1; }
fi
echo "${output}"
[[ ${output} == *"already installed"* ]] || { echo "setup_without_root: expected nothing to install"; exit 1; }
