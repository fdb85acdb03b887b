#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test: the release build's unit and pipeline
# tests, then the unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer, the
# allocation-failure sweep in that build (no leak on any failure path), and 15 s of fuzzing per
# parser (scripts/fuzz.sh; KT_FUZZ_SECONDS overrides, 0 skips).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --test
bash scripts/build.sh build
(cd build && ctest --output-on-failure -j2)
# The sanitizer build leaves out CGAL (its one translation unit takes minutes and GBs to build).
bash scripts/build.sh build-asan -DKT_SANITIZE=ON -DKT_WITH_CGAL=OFF -DCMAKE_BUILD_TYPE=Debug
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$PWD/../tests/lsan.supp" \
    ctest --output-on-failure -j2 -L unit)
(ASAN_OPTIONS=detect_leaks=1 bash tests/alloc_fail.sh build-asan)
secs=${KT_FUZZ_SECONDS:-15}
if [ "$secs" -gt 0 ]; then bash scripts/fuzz.sh "$secs"; fi
