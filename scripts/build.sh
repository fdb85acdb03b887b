#!/usr/bin/env bash
# Configures and builds keratome in build/ (or $1) with the given extra CMake options.
set -euo pipefail
dir=${1:-build}; shift || true
cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build "$dir" -j"$(nproc)"
