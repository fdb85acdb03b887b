#!/usr/bin/env bash
# lriplan_sweep.sh BUILD_DIR: the sweep's smoke subset (tests/sweep/sweep.sh cases smoke): the
# hardest eyes found, lri-plan --fast: issue 34's OS eye at white-to-white 11.8 mm (a tet of the
# tunnel's floor hung by one face: the factor was not positive definite), the right ATR eye whose
# pair runs into the temporal incision, a superior 2.8 mm incision on a with-the-rule eye, the
# narrowest cornea with the widest incision. Each must end in a plan or a one-line refusal naming
# the patient file before any solve, with no library message on stdout; and the two eyes of
# issue 34 must plan. About 40 CPU s a case.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
out=$(mktemp -d /tmp/kt-sweep.XXXXXX)
trap 'rm -rf "$out"' EXIT
bash tests/sweep/sweep.sh run "$B" "$out" smoke > "$out/table" 2> "$out/log"
cat "$out"/rows/*.tsv
cat "$out/table"
fails=0
n=$(cat "$out"/rows/*.tsv | wc -l)
[ "$n" -eq 4 ] || { echo "FAIL: expected 4 rows, got $n"; fails=1; }
if grep -q $'\tcrash\t' "$out"/rows/*.tsv; then echo "FAIL: a crash"; fails=1; fi
for k in OS-95-11.8-2.4-temporal-fast OD-180-11.7-2.2-temporal-fast; do
    grep -q $'\tplan\t' "$out/rows/$k.tsv" || { echo "FAIL: $k did not plan"; fails=1; }
done
awk -F'\t' '$7 == "plan" && $10 ~ /^single / {ok = 1} END {exit !ok}' "$out/rows/OD-180-11.7-2.2-temporal-fast.tsv" ||
    { echo "FAIL: the ATR eye's answer is not the single arc (its pair crosses the incision)"; fails=1; }
[ "$fails" -eq 0 ] && echo "lriplan_sweep: ok" || exit 1
