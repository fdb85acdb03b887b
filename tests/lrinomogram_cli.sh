#!/usr/bin/env bash
# lrinomogram_cli.sh BUILD_DIR: lri-nomogram's conventions. --version; a missing or bad argument
# is one line on stderr naming it, exit 2, nothing on stdout; an age outside the table's ages
# and a cylinder outside what LRIs treat (0.5-3 D) answer with one warning line on stderr; the
# main incision's SIA vector shifts the answer exactly as the equivalent keratometry does
# (1.5 D @ 90 with 0.5 D @ 0 is 1.0 D @ 90); without a table it reads the shipped default
# (share/nomogram/nomogram.tsv) or says in one line how to make one.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt-lrinomo.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
N=$B/lri-nomogram
fails=0 n=0
ok() { n=$((n + 1)); echo "ok   $1"; }
no() { n=$((n + 1)); fails=$((fails + 1)); echo "FAIL $1"; }
# A table: SIA = 0.02 D/deg x arc for a pair, 0.01 for one, ages 50 and 70, arcs 15-90.
{
    printf 'eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\n'
    for age in 50 70; do for n2 in 1 2; do for arc in 15 30 45 60 75 90; do
        printf 'e%s\t%s\t1.5\t90\t%s\t%s\t0.9\t10.5\t%s\t0\n' "$age" "$age" "$n2" "$arc" "$(awk "BEGIN { print $arc * 0.01 * $n2 }")"
    done; done; done
} > "$tmp/t.tsv"
K="--k-steep 44.5 --k-flat 43 --axis 90"
"$N" --version > "$tmp/out" 2> "$tmp/err" && grep -q "^lri-nomogram (keratome) " "$tmp/out" && ok "--version: $(cat "$tmp/out")" || no "--version"
# expect NAME FRAGMENT ARGS...: exit 2, one line naming the argument, no stdout
expect() {
    local name="$1" want="$2"; shift 2
    local rc=0
    "$N" "$@" > "$tmp/out" 2> "$tmp/err" || rc=$?
    if [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -qF -- "$want" "$tmp/err" && [ ! -s "$tmp/out" ]; then
        ok "$name: $(cat "$tmp/err")"
    else
        no "$name: exit $rc, stderr '$(cat "$tmp/err")', want '$want'"
    fi
}
expect "missing --age" "lri-nomogram: --age: missing" $K "$tmp/t.tsv"
expect "missing --k-flat" "lri-nomogram: --k-flat: missing" --k-steep 44 --axis 90 --age 60 "$tmp/t.tsv"
expect "bad --axis" "lri-nomogram: --axis 190: expected an axis" --k-steep 44 --k-flat 43 --axis 190 --age 60 "$tmp/t.tsv"
expect "bad number" "lri-nomogram: --age abc: expected a number" $K --age abc "$tmp/t.tsv"
expect "bad --age=" "lri-nomogram: --age x: expected a number" $K --age=x "$tmp/t.tsv"
expect "unknown option" "lri-nomogram: --frobnicate: unknown option" $K --age 60 --frobnicate "$tmp/t.tsv"
expect "option without value" "lri-nomogram: --age: expected a value" $K --age
expect "--sia alone" "lri-nomogram: --sia-axis: missing" $K --age 60 --sia 0.5 "$tmp/t.tsv"
expect "bad --sia" "lri-nomogram: --sia 9: expected" $K --age 60 --sia 9 --sia-axis 0 "$tmp/t.tsv"
expect "two tables" "expected one NOMOGRAM.tsv" $K --age 60 "$tmp/t.tsv" "$tmp/t.tsv"
# Warnings: one line each, the answer still given.
"$N" $K --age 90 "$tmp/t.tsv" > "$tmp/out" 2> "$tmp/err"; rc=$?
[ $rc -eq 0 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "warning: --age 90 lies outside the table's simulated ages 50-70 y: clamped to 70 y" "$tmp/err" &&
    grep -q "^2	" "$tmp/out" && ok "age clamped: $(cat "$tmp/err")" || no "age warning: exit $rc, '$(cat "$tmp/err")'"
"$N" --k-steep 47 --k-flat 43 --axis 90 --age 60 "$tmp/t.tsv" > "$tmp/out" 2> "$tmp/err"; rc=$?
[ $rc -eq 0 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "warning: a cylinder of 4.00 D lies outside what LRIs treat" "$tmp/err" &&
    ok "cylinder warning: $(cat "$tmp/err")" || no "cylinder warning: exit $rc, '$(cat "$tmp/err")'"
"$N" $K --age 60 "$tmp/t.tsv" > "$tmp/out" 2> "$tmp/err"
[ ! -s "$tmp/err" ] && ok "no warning inside the ranges" || no "a warning inside the ranges: $(cat "$tmp/err")"
# The SIA vector: 1.5 @ 90 + 0.5 @ 0 answers as 1.0 @ 90 (the table lines equal, the comment aside).
"$N" --k-steep 44.5 --k-flat 43 --axis 90 --age 60 --sia 0.5 --sia-axis 0 "$tmp/t.tsv" 2>/dev/null | grep -v '^#' > "$tmp/a"
"$N" --k-steep 44 --k-flat 43 --axis 90 --age 60 "$tmp/t.tsv" 2>/dev/null | grep -v '^#' > "$tmp/b"
[ -s "$tmp/a" ] && cmp -s "$tmp/a" "$tmp/b" && ok "the SIA vector shifts the answer as 1.0 D @ 90 ($(sed -n 3p "$tmp/a" | cut -f1-4))" ||
    no "SIA vector: $(cat "$tmp/a") vs $(cat "$tmp/b")"
# A residual that comes out zero has no axis: 1.0 D @ 90 corrected in full by a pair (SIA at
# 0 deg, the table's; one arc under-corrects) prints 0.00 and "none" in residual_axis_deg; the
# under-correcting single arc keeps its axis.
awk -F'\t' '$1 == 1 && $5 != "none" && $4 != "0.00" { ok = 1 } END { exit !ok }' "$tmp/b" &&
    ok "a residual left keeps its axis: $(awk -F'\t' '$1 == 1' "$tmp/b" | cut -f1-5 | tr '\t' ' ')" ||
    no "the single arc's residual axis: $(cat "$tmp/b")"
awk -F'\t' '$1 == 2' "$tmp/b" > "$tmp/rows"
[ -s "$tmp/rows" ] && awk -F'\t' '$4 != "0.00" || $5 != "none" { bad = 1 } END { exit bad }' "$tmp/rows" &&
    ok "a zero residual has no axis: $(head -n 1 "$tmp/rows" | cut -f1-5 | tr '\t' ' ')" || no "zero residual's axis: $(cat "$tmp/rows")"
# An oblique SIA turns the incisions' axis: 1.5 @ 90 + 1.5 @ 45 = 2.12 @ 67.5 (printed 68).
"$N" $K --age 60 --sia 1.5 --sia-axis 45 "$tmp/t.tsv" 2>/dev/null | grep -q "^# pre-op 2.12 D @ 68 deg" &&
    ok "oblique SIA: centred on 68 deg" || no "oblique SIA: $("$N" $K --age 60 --sia 1.5 --sia-axis 45 "$tmp/t.tsv" 2>&1 | head -2)"
# The default table.
def="$(cd "$(dirname "$0")/.." && pwd)/share/nomogram/nomogram.tsv"
rc=0
"$N" $K --age 66 > "$tmp/out" 2> "$tmp/err" || rc=$?
if [ -s "$def" ]; then
    [ $rc -eq 0 ] && grep -q "^incisions" "$tmp/out" && ok "answers out of the box from $def" || no "default table: exit $rc, $(cat "$tmp/err")"
else
    [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "make -C plans/studies/nomogram quick" "$tmp/err" &&
        ok "no default table: one line says how to make it" || no "no default table: exit $rc, $(cat "$tmp/err")"
fi
echo "lrinomogram_cli: $((n - fails)) passed, $fails failed"
[ $fails -eq 0 ]
