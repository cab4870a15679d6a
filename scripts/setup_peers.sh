#!/usr/bin/env bash
# Installs the three peer engines that perf/peers/ compares SuperDex with,
# from Debian bookworm's packages (Bullet 3.24, ODE 0.16.2, MuJoCo 2.2.2),
# with SuperDex's own dependencies: scripts/setup.sh --peers.
exec bash "$(dirname "${BASH_SOURCE[0]}")/setup.sh" --peers
