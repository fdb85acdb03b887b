#!/usr/bin/env bash
# setup.sh [--test]: installs the Debian 12 packages keratome needs, when any is missing.
# Idempotent. --test adds what only the tests use: Chromium (headless rendering of
# report.html), python3-pil (reading its screenshot) and a font for it, python3-vtk9 and
# python3-yaml (tests/physics_vtk.sh reads the step files with VTK 9 and the scene with yaml).
set -euo pipefail
pkgs=(build-essential cmake pkg-config libsuitesparse-dev libmetis-dev libopenblas-dev
      libgmsh-dev gmsh libcgal-dev libcgal-demo libyaml-dev libpng-dev
      python3-meshio python3-numpy gnuplot-nox
      # planning studies (plans/studies): GNU parallel and a Slurm cluster (tests/study_slurm.sh
      # starts a single-node one: munge, slurmctld, slurmd, the sbatch client)
      parallel slurm-wlm munge)
if [ "${1:-}" = --test ]; then
  # test only: chromium for the report checks; clang and its runtime (libFuzzer) for
  # scripts/fuzz.sh; valgrind (memcheck of the small unit programs); VTK 9 and yaml for python
  pkgs+=(chromium python3-pil fonts-dejavu-core clang libclang-rt-14-dev valgrind python3-vtk9
         python3-yaml)
elif [ $# -gt 0 ]; then
  echo "setup: unknown option $1 (usage: setup.sh [--test])" >&2; exit 2
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  SUDO=; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
else
  echo "setup: all packages present" >&2
fi
# Real third-party inputs for the CGAL models: extracted from libcgal-demo, never committed.
data=share/data
if [ ! -f "$data/bunny00.off" ] || [ ! -f "$data/liver.inr.gz" ]; then
  mkdir -p "$data"
  tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$data" --strip-components=2 \
      data/meshes/bunny00.off data/images/liver.inr.gz
fi
