#!/usr/bin/env bash
# fuzz.sh SECONDS [HARNESS...]: builds the libFuzzer harnesses of tests/fuzz (clang, ASan +
# UBSan, in build-fuzz/ or $KT_FUZZ_BUILD) and runs each for SECONDS on its seed corpus
# tests/fuzz/corpus/<harness> (every seed is run first: committed crashing inputs are
# regression cases). New inputs the fuzzer keeps go to <build>/corpus/<harness>, so runs
# accumulate; a crash, leak, hang (-timeout: KT_FUZZ_TIMEOUT seconds per input, default 10) or
# out-of-memory input (-rss_limit_mb 2048) goes to <build>/artifacts/. Prints executions,
# coverage (libFuzzer's cov and ft) and seconds per harness; exits 1 when any harness found a
# problem. KT_FUZZ_NOBUILD=1 skips the build (parallel runs of one build).
set -uo pipefail
cd "$(dirname "$0")/.."
secs=${1:?usage: fuzz.sh SECONDS [HARNESS...]}
shift
harnesses=("$@")
[ ${#harnesses[@]} -eq 0 ] && harnesses=(scene plan msh_ascii msh_binary edits vtk patient pentacam)
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
timeout=${KT_FUZZ_TIMEOUT:-10}
for h in "${harnesses[@]}"; do
    work="$build/corpus/$h"
    log="$build/fuzz-$h.log"
    mkdir -p "$work"
    : >"$log"
    t0=$(date +%s)
    execs=0 rc=0 notes=""
    # A timeout is confirmed by running its input alone: on a loaded machine a starved process
    # can miss the wall-clock limit; one that passes alone is noted and fuzzing goes on.
    while :; do
        left=$((secs - ($(date +%s) - t0)))
        [ $left -le 0 ] && break
        # Leaks are checked after each input (LeakSanitizer, libFuzzer's default with ASan).
        OPENBLAS_NUM_THREADS=1 nice -n 19 "$build/fuzz_$h" -max_total_time="$left" \
            -timeout="$timeout" -rss_limit_mb=2048 -print_final_stats=1 \
            -artifact_prefix="$build/artifacts/$h-" "$work" "tests/fuzz/corpus/$h" >"$log.part" 2>&1
        rc=$?
        cat "$log.part" >>"$log"
        n=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log.part" | tail -1)
        execs=$((execs + ${n:-0}))
        [ $rc -eq 0 ] && break
        art=$(sed -n 's/.*Test unit written to \(.*timeout-[0-9a-f]*\)$/\1/p' "$log.part" | tail -1)
        if [ -n "$art" ] && "$build/fuzz_$h" -timeout="$timeout" -runs=1 "$art" >/dev/null 2>&1; then
            notes="$notes; a timeout did not recur alone (load): $art"
            mv "$art" "$art.unconfirmed"
            rc=0
            continue
        fi
        break
    done
    rm -f "$log.part"
    t1=$(date +%s)
    last=$(grep -E '^#[0-9]+' "$log" | grep -o 'cov: [0-9]* ft: [0-9]*' | tail -1)
    cov=$(echo "$last" | awk '{print $2}')
    ft=$(echo "$last" | awk '{print $4}')
    result="ok$notes"
    if [ $rc -ne 0 ]; then
        result="FAILED (exit $rc; see $log and $build/artifacts/)"
        grep -m3 -E 'ERROR|SUMMARY|runtime error' "$log" | sed 's/^/    /'
        fail=1
    fi
    printf '%-11s %12s %8s %8s %8s  %s\n' "$h" "$execs" "${cov:-?}" "${ft:-?}" $((t1 - t0)) "$result"
done
exit $fail
