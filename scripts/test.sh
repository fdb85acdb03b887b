#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the release build's unit and pipeline
# tests, then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
bash scripts/build.sh build
(cd build && ctest --output-on-failure -j2)
# The sanitizer build leaves out CGAL (its one translation unit takes minutes and GBs to build).
bash scripts/build.sh build-asan -DKT_SANITIZE=ON -DKT_WITH_CGAL=OFF -DCMAKE_BUILD_TYPE=Debug
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$PWD/../tests/lsan.supp" \
    ctest --output-on-failure -j2 -L unit)
