#!/usr/bin/env bash
# Installs the three peer engines that perf/peers/ compares SuperDex with,
# from Debian bookworm's packages: Bullet 3.24, ODE 0.16.2, MuJoCo 2.2.2.
# Idempotent: when all three are installed it only says so. They are not
# dependencies of SuperDex (perf/peers builds each peer only when found).
#
# Run as root, or as a user with sudo.
set -euo pipefail

packages=(libbullet-dev libode-dev libmujoco-dev pkg-config)

as_root() {
  if [[ ${EUID} -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null 2>&1; then
    sudo "$@"
  else
    echo "setup_peers.sh: need root (or sudo) to run: $*" >&2
    exit 1
  fi
}

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "${p}" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("${p}")
  fi
done
if ((${#missing[@]} == 0)); then
  echo "setup_peers.sh: ${packages[*]} already installed"
  exit 0
fi

# the package lists may be stale or absent on a fresh image
as_root apt-get update
as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
echo "setup_peers.sh: installed ${missing[*]}"
