#!/usr/bin/env bash
# smoke.sh BUILD_DIR: the benchmark suite's own check (ctest label "bench"). Runs every part of
# scripts/bench.sh (bandwidth, paper, ordering, tradeoff, stability, planned, uncertainty, and the report) in
# its --smoke mode, on the smallest cases: beams 5x5x4 and 5x5x8, the 4-cell brick, and for the
# tradeoff part the smallest eye that still cuts (scripts/bench/common.sh, prep_eye). Checks
# that the suite exits 0; that no tool run was refused as bad usage (exit 2: a removed option,
# as --refactor 'm>3000' once was) other than cutplan's refusal of the stability part's tilted
# sliver plans, which is that case's expected answer; that every part wrote its table with rows
# and the report names every part; that the tables hold no GMRES column (augsolve has no GMRES
# since issue 11); that the augmented steps agree with a fresh factorization (tradeoff's
# verify_rel_diff_max <= 1e-8) and that no stability case is silently wrong.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/../.."
T=$(mktemp -d /tmp/kt-bench-smoke.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail() { echo "bench smoke: FAILED: $*" >&2; exit 1; }
R=$T/results
if ! bash scripts/bench.sh "$B" --smoke --results "$R" > "$T/bench.log" 2>&1; then
    tail -n 30 "$T/bench.log" >&2
    fail "scripts/bench.sh --smoke exited non-zero"
fi

# no run refused as bad usage, but for cutplan on the tilted sliver plans
awk -F'\t' 'NR > 1 && $3 == 2 && !($7 ~ /\/cutplan / && $2 ~ /^cut-brick-8-tilt/) { print; bad = 1 }
    END { exit bad }' "$R/ledger.tsv" || fail "a run exited 2 (bad usage), above"
[ "$(awk 'END { print NR }' "$R/ledger.tsv")" -gt 20 ] || fail "the ledger holds too few runs"

# every part's table, with rows
rows() { [ -s "$1" ] && [ "$(wc -l < "$1")" -ge "$2" ] || fail "$1: fewer than $2 lines"; }
rows "$R/bandwidth/stream.tsv" 2
rows "$R/bandwidth/summary.tsv" 2
rows "$R/paper/steps.tsv" 10
rows "$R/paper/headline.tsv" 2
rows "$R/paper/crossover.tsv" 2
rows "$R/ordering/ordering.tsv" 3
rows "$R/tradeoff/tradeoff.tsv" 3
rows "$R/stability/stability.tsv" 5
rows "$R/planned/planned.md" 3
rows "$R/uncertainty/runs.tsv" 5
rows "$R/uncertainty/uncertainty.tsv" 3
awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { n++; if (!($(c["cpu_ratio"]) + 0 > 0)) bad = 1 } END { exit !(n == 2 && !bad) }' \
    "$R/uncertainty/uncertainty.tsv" || fail "uncertainty: no CPU ratio for both output variants"
awk -F'\t' '$2 ~ /^unc-/ && $3 != 0 { bad = 1 } END { exit bad }' "$R/ledger.tsv" ||
    fail "uncertainty: an augsolve run failed"
for h in Bandwidth Paper Ordering "Speed against accuracy" Stability "The planned method" \
    "augsolve --uncertainty"; do
    grep -q "^## $h" "$R/report.md" || fail "report.md has no section '$h'"
done

# no rotted column; real outcomes
if grep -il gmres "$R"/*/*.tsv; then fail "a table still has a GMRES column (files above)"; fi
awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $1 ~ /^aug-/ { n++; v = $(c["verify_rel_diff_max"]); if (!(v + 0 <= 1e-8) || $(c["exit"]) != 0) bad = 1 }
    END { exit !(n >= 1 && !bad) }' "$R/tradeoff/tradeoff.tsv" ||
    fail "tradeoff: an augmented run missing, failed or off a fresh factorization by more than 1e-8"
awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { n++; if ($(c["verdict"]) ~ /^(SILENT|error$)/) bad = 1 } END { exit !(n >= 5 && !bad) }' "$R/stability/stability.tsv" ||
    fail "stability: a case is silently wrong"
echo "bench smoke: every part ran on its smallest cases ($(($(wc -l < "$R/ledger.tsv") - 1)) runs)"
