#!/usr/bin/env bash
# full.sh BUILD_DIR: the same input gives the same answer, to the last byte, on any thread count
# and any engine, at full size (ctest reproducible_full, label "reproducible"; issue 24):
#   1. the demo twice, as the README runs it (scripts/demo.sh: mesh-prep plans/eye.yaml, then
#      cutplan plans/lri-paired-60.yaml | augsolve, then curvature), once with
#      OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 and once with both 2, each in its own folder from
#      nothing: the two meshes are equal (cmp: mesh-prep with two thread settings), and so are
#      the two curvature.tsv and meridians.tsv; the cut did something (SIA above 1 D at the end);
#   2. the quick nomogram study (make -C plans/studies/nomogram quick: the default eye, paired
#      arcs of 15 to 90 deg) twice from nothing, each meshing its own eye: once with make
#      (ENGINE=local) and once with ENGINE=parallel (GNU parallel): the two eyes are equal and so
#      are the two nomogram.tsv, which hold the run's six arcs.
# It prints each part's wall-clock and CPU seconds. Measured on the shared 2-core machine at load
# 6-29: 47 min wall, 525 s of CPU (demo 97 + 87 s, make quick 162 + 179 s), peak 2.6 GB; on a
# quiet machine about 9 min. tests/reproducible.sh is the same check on a
# coarse eye and a reduced study (the quick look; label pipeline).
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/../.."
T=$(mktemp -d /tmp/kt-reproducible-full.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail() { echo "reproducible_full: FAILED: $*" >&2; exit 1; }
command -v parallel > /dev/null ||
    { echo "reproducible_full: GNU parallel missing (bash scripts/setup.sh --test): skipped" >&2; exit 77; }
now() { date +%s.%N; }
# timed LABEL LOG -- command...: runs it with its output in LOG, prints its wall-clock and CPU
# seconds (its children's user + system time, from bash's times).
# bash's times must run in this shell (a command substitution is a new process, with no children).
cpu() { awk 'NR == 2 { for (i = 1; i <= 2; i++) { split($i, p, /[ms]/); s += p[1] * 60 + p[2] } print s }' "$1"; }
timed() {
    local label=$1 log=$2 t0 t1 c0 c1
    shift 3
    times > "$T/times"
    c0=$(cpu "$T/times")
    t0=$(now)
    "$@" > "$log" 2>&1 || { tail -n 30 "$log" >&2; fail "$label"; }
    t1=$(now)
    times > "$T/times"
    c1=$(cpu "$T/times")
    awk -v l="$label" -v a="$t0" -v b="$t1" -v c="$c0" -v d="$c1" \
        'BEGIN { printf "reproducible_full: %-34s %6.1f s wall, %6.1f s CPU\n", l, b - a, d - c }'
}

# 1. The demo, twice, with two thread settings.
demo() { # DIR THREADS
    OMP_NUM_THREADS=$2 OPENBLAS_NUM_THREADS=$2 KT_NO_BUILD=1 KT_BUILD=$B bash scripts/demo.sh "$1"
}
timed "demo, 1 thread" "$T/demo1.log" -- demo "$T/demo1" 1
timed "demo, 2 threads" "$T/demo2.log" -- demo "$T/demo2" 2
cmp "$T/demo1/eye.msh" "$T/demo2/eye.msh" || fail "mesh-prep gave two different meshes of plans/eye.yaml"
for f in curvature.tsv meridians.tsv; do
    cmp "$T/demo1/$f" "$T/demo2/$f" || fail "the demo's two $f differ"
done
steps=$(($(wc -l < "$T/demo1/steps.tsv") - 1))
sia=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { n++; s = $c["sia_D"] }
    END { if (n == n0 && n >= 12) print s + 0 }' n0="$steps" "$T/demo1/curvature.tsv")
awk -v s="${sia:-nan}" 'BEGIN { exit !(s > 1) }' ||
    fail "curvature.tsv does not hold a row per step ($steps) ending with an SIA above 1 D (${sia:-none})"
echo "reproducible_full: demo: $(awk '$1 == "mesh" { print $2; exit }' "$T/demo1.log") nodes," \
     "the same mesh and curvature.tsv with 1 and 2 threads (SIA $sia D after $steps steps)"

# 2. The quick nomogram study, locally and through GNU parallel, each from nothing.
mk=(make --no-print-directory -C plans/studies/nomogram quick KT_BUILD="$B" KEEP_VTK=0)
timed "make quick (ENGINE=local)" "$T/local.log" -- "${mk[@]}" OUT="$T/local"
timed "make quick (ENGINE=parallel)" "$T/par.log" -- "${mk[@]}" OUT="$T/par" ENGINE=parallel
for f in eyes/default.msh nomogram.tsv; do
    [ -s "$T/local/$f" ] && [ -s "$T/par/$f" ] || fail "a study did not write $f"
done
cmp "$T/local/eyes/default.msh" "$T/par/eyes/default.msh" || fail "the two studies' eyes differ"
cmp "$T/local/nomogram.tsv" "$T/par/nomogram.tsv" || fail "the local and the parallel nomogram.tsv differ"
[ "$(wc -l < "$T/local/nomogram.tsv")" -eq 7 ] || fail "nomogram.tsv does not hold the quick run's six arcs"
echo "reproducible_full: nomogram study: the same nomogram.tsv locally and with ENGINE=parallel"
