#!/usr/bin/env bash
# fuzz.sh SECONDS [HARNESS...]: builds the libFuzzer harnesses of tests/fuzz (clang, ASan +
# UBSan, in build-fuzz/ or $KT_FUZZ_BUILD) and runs each for SECONDS on its seed corpus
# tests/fuzz/corpus/<harness> (every seed is run first: the committed crashes are regression
# cases). New inputs the fuzzer keeps go to <build>/corpus/<harness>, so runs accumulate; a
# crash, leak, timeout (-timeout, 10 s per input) or out-of-memory input goes to
# <build>/artifacts/. Prints executions, coverage and time per harness; exits 1 when any
# harness found a problem. KT_FUZZ_NOBUILD=1 skips the build (parallel runs of one build).
set -uo pipefail
cd "$(dirname "$0")/.."
secs=${1:?usage: fuzz.sh SECONDS [HARNESS...]}
shift
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(scene plan msh_ascii msh_binary edits vtk)
build=${KT_FUZZ_BUILD:-build-fuzz}
if [ "${KT_FUZZ_NOBUILD:-0}" != 1 ]; then
    cmake -S . -B "$build" -DKT_FUZZ=ON -DKT_WITH_CGAL=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ >/dev/null || exit 1
    targets=()
    for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
    cmake --build "$build" -j"$(nproc)" --target "${targets[@]}" >/dev/null || exit 1
fi
mkdir -p "$build/artifacts"
# The harnesses write each input to a file: in memory (tmpfs) when there is one, 15x faster.
[ -z "${TMPDIR:-}" ] && [ -d /dev/shm ] && [ -w /dev/shm ] && export TMPDIR=/dev/shm
fail=0
printf '%-11s %12s %8s %8s %8s  %s\n' harness executions cov ft seconds result
for h in "${harnesses[@]}"; do
    work="$build/corpus/$h"
    log="$build/fuzz-$h.log"
    mkdir -p "$work"
    t0=$(date +%s)
    # Leaks are checked at the end of each input (ASan's LeakSanitizer, libFuzzer's default).
    OPENBLAS_NUM_THREADS=1 nice -n 19 "$build/fuzz_$h" -max_total_time="$secs" -timeout=10 \
        -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix="$build/artifacts/$h-" \
        "$work" "tests/fuzz/corpus/$h" >"$log" 2>&1
    rc=$?
    t1=$(date +%s)
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    last=$(grep -E '^#[0-9]+' "$log" | grep -o 'cov: [0-9]* ft: [0-9]*' | tail -1)
    cov=$(echo "$last" | awk '{print $2}')
    ft=$(echo "$last" | awk '{print $4}')
    result=ok
    if [ $rc -ne 0 ]; then
        result="FAILED (exit $rc; see $log and $build/artifacts/)"
        grep -m3 -E 'ERROR|SUMMARY|runtime error' "$log" | sed 's/^/    /'
        fail=1
    fi
    printf '%-11s %12s %8s %8s %8s  %s\n' "$h" "${execs:-?}" "${cov:-?}" "${ft:-?}" $((t1 - t0)) "$result"
done
exit $fail
