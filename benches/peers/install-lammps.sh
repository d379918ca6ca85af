#!/usr/bin/env bash
# Install the LAMMPS peer (Debian bookworm: lammps 20220106 = stable 29 Sep 2021 update 2,
# built with the BODY package and Open MPI). Idempotent: installs only what is missing.
set -euo pipefail
need=()
command -v lmp >/dev/null || need+=(lammps)
[ -d /usr/share/lammps/examples/body ] || need+=(lammps-examples)
command -v mpirun >/dev/null || need+=(openmpi-bin)
command -v python3 >/dev/null || need+=(python3)
if [ ${#need[@]} -gt 0 ]; then
  sudo_cmd=()
  [ "$(id -u)" != 0 ] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${need[@]}"
fi
lmp -h | grep 'body/rounded/polygon' >/dev/null || { echo "this lmp lacks pair body/rounded/polygon" >&2; exit 1; }
echo "LAMMPS peer ready: $(lmp -h | sed -n "s/^Large-scale Atomic.Molecular Massively Parallel Simulator - //p")"
