#!/usr/bin/env bash
# lrinomogram_cli.sh BUILD_DIR: lri-nomogram's conventions. --version; a missing or bad argument
# is one line on stderr naming it, exit 2, nothing on stdout; an age outside the table's ages
# and a cylinder outside what LRIs treat (0.5-3 D) answer with one warning line on stderr; the
# main incision's SIA vector shifts the answer exactly as the equivalent keratometry does
# (1.5 D @ 90 with 0.5 D @ 0 is 1.0 D @ 90); without a table it reads the shipped default
# (share/nomogram/nomogram.tsv) or says in one line how to make one. The conventions shared with
# lri-plan (axis 180 read as 0 and printed 0, age 18-110, K 20-70 D, the SIA's range). The band: a table's
# sia_sd_D (curvature's sd) carried to the answer, the residual's sd and 90% interval; zero sd,
# zero band; a table without the column, none. --json: one object Python's json module reads,
# its figures the table's (the table rounds them).
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
# The conventions lri-plan shares (keratome-patient(5), CONVENTIONS): an axis in [0, 180], 180
# read as 0 and printed in [0, 180) (one that rounds to 180 as 0); an age in [18, 110] y; K in
# [20, 70] D; the SIA 0-5 D at the axis of its steepening. Beyond: name|args|the one line.
conv_bad=(
"axis 180.5|--k-steep 44.5 --k-flat 43 --axis 180.5 --age 60|--axis 180.5: expected an axis in [0, 180] deg"
"axis -1|--k-steep 44.5 --k-flat 43 --axis -1 --age 60|--axis -1: expected an axis in [0, 180] deg"
"age 17|$K --age 17|--age 17: expected an age in [18, 110] years"
"age 110.5|$K --age 110.5|--age 110.5: expected an age in [18, 110] years"
"sia-axis 181|$K --age 60 --sia 0.3 --sia-axis 181|--sia-axis 181: expected an axis in [0, 180] deg"
"sia 5.01|$K --age 60 --sia 5.01 --sia-axis 90|--sia 5.01: expected the main incision's SIA in [0, 5] D"
"k-flat 19|--k-steep 44 --k-flat 19 --axis 90 --age 60|--k-flat 19: expected a keratometry reading in [20, 70] D"
"k-steep 70.5|--k-steep 70.5 --k-flat 43 --axis 90 --age 60|--k-steep 70.5: expected a keratometry reading in [20, 70] D"
)
for c in "${conv_bad[@]}"; do
    IFS='|' read -r name args want <<< "$c"
    expect "$name" "lri-nomogram: $want" $args "$tmp/t.tsv"
done
# At the ends, accepted and the same answer: name|args|args (stdout compared whole; with "rows"
# first, the answer's rows only: the comment repeats the age given).
conv_same=(
"axis 180 is 0|--k-steep 44.5 --k-flat 43 --axis 180 --age 60|--k-steep 44.5 --k-flat 43 --axis 0 --age 60"
"sia-axis 180 is 0|$K --age 60 --sia 0.3 --sia-axis 180|$K --age 60 --sia 0.3 --sia-axis 0"
"--json: axis 180 is 0|--json --k-steep 44.5 --k-flat 43 --axis 180 --age 60 --sia 0.3 --sia-axis 180|--json --k-steep 44.5 --k-flat 43 --axis 0 --age 60 --sia 0.3 --sia-axis 0"
"rows age 18 answers as 50|$K --age 18|$K --age 50"
"rows age 110 answers as 70|$K --age 110|$K --age 70"
"rows K 20 D accepted|--k-steep 21.5 --k-flat 20 --axis 90 --age 60|$K --age 60"
"rows K 70 D accepted|--k-steep 70 --k-flat 68.5 --axis 90 --age 60|$K --age 60"
)
for c in "${conv_same[@]}"; do
    IFS='|' read -r name a b <<< "$c"
    filt=cat
    case $name in rows*) filt="grep -v ^#" ;; esac
    ra=0 rb=0
    "$N" $a "$tmp/t.tsv" 2> /dev/null | $filt > "$tmp/ca" || ra=$?
    "$N" $b "$tmp/t.tsv" 2> /dev/null | $filt > "$tmp/cb" || rb=$?
    [ $ra -eq 0 ] && [ $rb -eq 0 ] && [ -s "$tmp/ca" ] && cmp -s "$tmp/ca" "$tmp/cb" && ok "$name" ||
        no "$name: exit $ra/$rb, $(head -c 200 "$tmp/ca") vs $(head -c 200 "$tmp/cb")"
done
# Printed as lri-plan prints an axis: 179.8 (and a sum at 179.97) shows 0, never 180.
"$N" --k-steep 44.5 --k-flat 43 --axis 179.8 --age 60 "$tmp/t.tsv" 2> /dev/null | grep -q "^# pre-op 1.50 D @ 0 deg.*centred on 0 deg" &&
    ok "axis 179.8 printed 0" || no "axis 179.8: $("$N" --k-steep 44.5 --k-flat 43 --axis 179.8 --age 60 "$tmp/t.tsv" 2>&1 | head -1)"
"$N" --json --k-steep 44.5 --k-flat 43 --axis 179.97 --age 60 "$tmp/t.tsv" 2> /dev/null |
    /usr/bin/python3 -c 'import json, sys; sys.exit(0 if json.load(sys.stdin)["pre_op_axis_deg"] == 0 else 1)' &&
    ok "--json: axis 179.97 printed 0.0" || no "--json: axis 179.97 not printed 0"
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
# The band (lri-nomogram(1), BAND). A table with sia_sd_D = 0.1 x SIA (0.001 x arc for one
# incision): an answer at a simulated arc carries that case's sd (the table's, i.e. curvature's
# sia_D_sd of the study's run), one between arcs the linear interpolation; the residual lies
# along the SIA (with the rule, SIA at 0 deg), so its sd is the SIA's; 90%: residual +- 1.645 sd,
# clipped at 0. A table of zero sd gives a zero band; the table without the column (above) NaN.
awk -F'\t' -v OFS='\t' 'NR == 1 { print $0, "sia_sd_D"; next } { print $0, 0.1 * $9 }' "$tmp/t.tsv" > "$tmp/sd.tsv"
awk -F'\t' -v OFS='\t' 'NR == 1 { print $0, "sia_sd_D"; next } { print $0, 0 }' "$tmp/t.tsv" > "$tmp/sd0.tsv"
band() { # ARGS...: the pair's row's columns 3-9 (sia, residual, axis, sia_sd, residual_sd, lo, hi)
    "$N" "$@" 2>/dev/null | awk -F'\t' '$1 == 2 { print $3, $4, $6, $7, $8, $9 }'
}
# --target 1.3 on 1.5 D at 60 y (between the ages 50 and 70: the same table): a pair of 65 deg,
# between the simulated 60 (SIA 1.2, sd 0.12) and 75 (1.5, 0.15): sd 0.13 interpolated; the
# residual 0.2 D lies along the SIA, so its sd is the SIA's; 90% 0.2 +- 0.214, clipped: 0-0.41.
read -r sia res ssd rsd lo hi < <(band --k-steep 44.5 --k-flat 43 --axis 90 --age 60 --target 1.3 "$tmp/sd.tsv")
awk -v a="$ssd" -v b="$rsd" -v l="$lo" -v h="$hi" 'BEGIN { exit !(a == 0.13 && b == 0.13 && l == 0 && h == 0.41) }' &&
    ok "band: sia sd 0.13 D interpolated between arcs, residual sd = the SIA's, 90% $lo-$hi D" || no "band: $sia $res $ssd $rsd $lo $hi"
# --target 1.2 on 1.5 D: SIA 1.2 (a simulated arc: 30 deg of the pair, 0.6 x 2), sd 0.12 (the
# case's own), residual 0.3 D along the SIA: sd 0.12, 90% 0.3 +- 0.197 = 0.10-0.50.
read -r sia res ssd rsd lo hi < <(band --k-steep 44.5 --k-flat 43 --axis 90 --age 60 --target 1.2 "$tmp/sd.tsv")
awk -v s="$sia" -v r="$res" -v a="$ssd" -v b="$rsd" -v l="$lo" -v h="$hi" \
    'BEGIN { exit !(s == 1.2 && r == 0.3 && a == 0.12 && b == 0.12 && l == 0.10 && h == 0.50) }' &&
    ok "band at a simulated arc: the case's sd 0.12 D, residual 0.30 D, 90% $lo-$hi D" || no "band at a simulated arc: $sia $res $ssd $rsd $lo $hi"
# The whole 1.5 D: a pair of 75 deg (sd 0.15), residual 0.00: its direction is round-off, the
# residual moves through 0 along the pre-op (here along the SIA): sd 0.15, 90% 0-0.25.
read -r sia res ssd rsd lo hi < <(band $K --age 60 "$tmp/sd.tsv")
[ "$res $ssd $rsd $lo $hi" = "0.00 0.15 0.15 0.00 0.25" ] && ok "a vanishing residual: its sd the SIA's ($rsd D)" ||
    no "vanishing residual: $res $ssd $rsd $lo $hi"
read -r sia res ssd rsd lo hi < <(band $K --age 60 --target 1.2 "$tmp/sd0.tsv")
[ "$ssd $rsd $lo $hi" = "0.00 0.00 0.30 0.30" ] && ok "zero sd in the table: zero band" || no "zero sd: $ssd $rsd $lo $hi"
read -r sia res ssd rsd lo hi < <(band $K --age 60 "$tmp/t.tsv")
[ "$ssd $rsd $lo $hi" = "NaN NaN NaN NaN" ] && "$N" $K --age 60 "$tmp/t.tsv" 2>/dev/null | grep -q "^# no band" &&
    ok "a table without sia_sd_D: no band (NaN), said in a comment" || no "old table: $ssd $rsd $lo $hi"
printf 'eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\tsia_sd_D\ne\t60\t1.5\t90\t2\t30\t0.9\t10.5\t1\t0\t-1\n' > "$tmp/bad.tsv"
expect "negative sia_sd_D" "bad.tsv:2:" $K --age 60 "$tmp/bad.tsv"
# --json: the same answer as the table, through the JSON writer.
if "$N" $K --age 60 --target 1.2 "$tmp/t.tsv" > "$tmp/tab" 2> /dev/null &&
    "$N" $K --age 60 --target 1.2 --json "$tmp/t.tsv" > "$tmp/json" 2> /dev/null &&
    /usr/bin/python3 - "$tmp/tab" "$tmp/json" <<'PY'
import json, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if not l.startswith("#")]
h, d = rows[0], json.load(open(sys.argv[2]))
a = d["answers"]
ok = len(a) == len(rows) - 1 == 2 and d["tool"] == "lri-nomogram"
for r, q in zip(rows[1:], a):
    ok = ok and int(r[h.index("incisions")]) == q["incisions"] and abs(float(r[h.index("arc_deg")]) - q["arc_deg"]) <= 0.051
    ok = ok and abs(float(r[h.index("residual_D")]) - q["residual_D"]) <= 0.0051 and r[h.index("note")] == q["note"]
    ok = ok and r[h.index("table_lines")] == q["table_lines"]
sys.exit(0 if ok else 1)
PY
then ok "--json: the table's answer as one JSON object"; else no "--json: $(head -c 300 "$tmp/json")"; fi
# The default table.
def="$(cd "$(dirname "$0")/.." && pwd)/share/nomogram/nomogram.tsv"
rc=0
"$N" $K --age 66 > "$tmp/out" 2> "$tmp/err" || rc=$?
if [ -s "$def" ]; then
    [ $rc -eq 0 ] && grep -q "^incisions" "$tmp/out" && ok "answers out of the box from $def" || no "default table: exit $rc, $(cat "$tmp/err")"
    # the shipped table has the band (remade with augsolve --uncertainty): a pair's answer has a
    # positive SIA sd, and at a simulated arc it is the table's (curvature's) sia_sd_D
    if head -n 1 "$def" | tr '\t' '\n' | grep -qx sia_sd_D; then
        read -r tsia tsd < <(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $c["incisions"] == 2 && $c["arc_deg"] == 45 { print $c["sia_D"], $c["sia_sd_D"]; exit }' "$def")
        read -r sia res ssd rsd lo hi < <(band $K --age 60 --target "$tsia")
        awk -v a="$ssd" -v t="$tsd" 'BEGIN { exit !(a > 0 && a - t < 0.006 && t - a < 0.006) }' &&
            ok "the shipped table's band: sia sd $ssd D at 2 x 45 deg = its sia_sd_D $tsd" || no "shipped band: $ssd vs $tsd"
    else # a table shipped before issue 21's band: read as before, with no band
        "$N" $K --age 66 2>/dev/null | grep -q "^# no band" &&
            ok "the shipped table has no sia_sd_D yet (remake: make -C plans/studies/nomogram quick): answered without a band" ||
            no "the shipped table without sia_sd_D: no '# no band' comment"
    fi
else
    [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -q "make -C plans/studies/nomogram quick" "$tmp/err" &&
        ok "no default table: one line says how to make it" || no "no default table: exit $rc, $(cat "$tmp/err")"
fi
echo "lrinomogram_cli: $((n - fails)) passed, $fails failed"
[ $fails -eq 0 ]
