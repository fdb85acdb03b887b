#!/usr/bin/env bash
# uq_study.sh BUILD_DIR: the uncertainty study (plans/studies/uq) end to end on its ci set, cut
# to two sampled eyes of the coarse mesh plus the nominal eye, with tests/uq/ci.spec (the study's
# spec with arcs to 30 deg: single and paired, 15 deg a step; about 60 s of CPU): eyes.tsv,
# uq.tsv per family, arc and reading, tornado.tsv ranked per arc; then, on the nominal eye's
# real paired run:
#   - curvature's bands on a real eye: dudp_A = the displacement (tests/uq/add_dudp.py) makes
#     the flattening, steepening, SIA and its double-angle x component scale with A to first
#     order, so dR/dA = R (to 1%: K depends on u through curvature and slope), the coupling ratio
#     and the SIA's axis do not change (dR/dA = 0 to 1% of R); sd = |dR/dA| sd_A;
#   - sens.sh: two fake geometry runs whose curvature.tsv differ from the nominal's by +-0.05 D of
#     SIA give dsia_D/dthickness = 0.05 / H and zero for every other reading, and curvature
#     --sens with them adds (0.05 / H sd)^2 to the SIA's variance;
#   - summarize.sh with that band: uq.tsv's first-order columns are the band's and the sd ratio
#     is sampled sd / first-order sd.
# (The 64-eye comparison is a benchmark: make -C plans/studies/uq; see its README.)
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt_uqstudy_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
fail() { echo "uq_study: FAILED: $*" >&2; exit 1; }
O=$tmp/study

make -s -C plans/studies/uq SPEC="$PWD/tests/uq/ci.spec" SET=ci N=2 OUT="$O" KT_BUILD="$B" -j2 > "$tmp/make.log" 2>&1 ||
    { tail -n 30 "$tmp/make.log" >&2; fail "make SET=ci N=2"; }
# eyes.tsv: 2 eyes x 2 families x steps 0-2
[ "$(tail -n +2 "$O/eyes.tsv" | wc -l)" -eq 12 ] || fail "eyes.tsv: expected 12 rows (2 eyes, 2 families, 3 steps)"
awk -F'\t' 'NR == 1 { ok = $1 == "family" && $2 == "arc_deg" && $3 == "reading" && $7 == "sd" && $13 == "sd_ratio"; next }
    { n++; k[$1 " " $2]++; if ($4 != 2 || $6 + 0 != $6 || ($3 == "sia_D" && $1 == "paired" && $2 == 30 && !($5 > 0.3))) bad = 1 }
    END { exit !(ok && n == 32 && k["single 15"] == 8 && k["paired 30"] == 8 && !bad) }' "$O/uq.tsv" ||
    fail "uq.tsv: $(cat "$O/uq.tsv")"
grep -q "^| paired | 30 | " "$O/report.md" || fail "report.md has no paired 30 deg SIA row"
# tornado.tsv: the ranks of each arc 1, 2, ... by decreasing share
awk -F'\t' 'NR > 1 { k = $1 " " $2; n[k]++; if ($5 != n[k] || (n[k] > 1 && $4 > prev[k] + 1e-12)) bad = 1; prev[k] = $4 }
    END { exit !(length(n) == 4 && !bad) }' "$O/tornado.tsv" || fail "tornado.tsv: $(cat "$O/tornado.tsv")"
nom=$O/runs/nominal/run-paired
[ -f "$nom/step-0002.vtk" ] || fail "the nominal run keeps its step VTKs"

# curvature's bands on the real eye
$PY tests/uq/add_dudp.py "$nom" A=u
# the nominal eye is solved with augsolve --uncertainty at the study's sd (gen.sh's section)
cp "$nom/uncertainty.tsv" "$tmp/theirs.tsv" || fail "the nominal run has no uncertainty.tsv"
awk -F'\t' '$1 == "E_inplane" && $4 == 0.6 && $5 == "derivative" { a = 1 } $1 == "iop" && $4 == 3 { b = 1 }
    $1 == "thickness" && $4 == 10 && $5 == "fd" { c = 1 } END { exit !(a && b && c) }' "$tmp/theirs.tsv" ||
    fail "the nominal's uncertainty.tsv is not the study's: $(cat "$tmp/theirs.tsv")"
printf 'param\tunit\tvalue\tsd\tmethod\tsource\nA\tMPa\t2\t0.1\tderivative\ttest\nthickness\tum\t540\t10\tfd\ttest\n' \
    > "$nom/uncertainty.tsv"
"$B/curvature" -q --no-png --no-vtk --no-report -o "$tmp/band" "$nom" > "$tmp/band.txt"
# the fd quantity: fake geometry runs around the nominal's table
for sgn in plus minus; do for fam in single paired; do
    mkdir -p "$O/runs/thickness_$sgn/run-$fam"
    awk -F'\t' -v OFS='\t' -v d="$([ $sgn = plus ] && echo 0.05 || echo -0.05)" '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == "sia_D") c = i; print; next }
        { if ($1 > 0) $c = sprintf("%.4f", $c + d); print }' "$O/runs/nominal/run-$fam/curvature.tsv" \
        > "$O/runs/thickness_$sgn/run-$fam/curvature.tsv"
done; done
h=$(awk -F'\t' '$1 == "thickness" { print $4 }' "$O/params.tsv")
bash plans/studies/uq/sens.sh "$O" thickness_plus thickness_minus
"$B/curvature" -q --no-png --no-vtk --no-report --sens "$O/sens/paired.tsv" -o "$tmp/band2" "$nom" > "$tmp/band2.txt"
$PY - "$tmp" "$O" "$h" <<'PYEOF'
import csv, math, sys
t, o, h = sys.argv[1], sys.argv[2], float(sys.argv[3])
def table(p):
    with open(p) as f:
        return list(csv.DictReader(f, delimiter='\t'))
cur, der = table(t + '/band/curvature.tsv'), table(t + '/band/derivatives.tsv')
last = cur[-1]
d = {r['param']: r for r in der if r['step'] == last['step']}
worst = {}
for r in ('flattening_D', 'steepening_D', 'sia_D', 'sia_x_D', 'coupling_ratio', 'sia_axis_deg'):
    v, dv = float(last[r]), float(d['A'][r])
    if r in ('coupling_ratio', 'sia_axis_deg'):
        err = abs(dv) / max(1, abs(v))
    else:
        err = abs(dv - v) / abs(v)
    worst[r] = err
    assert err < 0.01, f'real eye: d{r}/dA = {dv} against {v}'
    assert abs(float(last[r + '_sd']) - abs(dv) * 0.1) <= 1e-5 + 1e-4 * abs(dv) * 0.1, (r, last[r + '_sd'])
print('uq_study: real eye, dR/dp for dudp = u: ' + ', '.join(f'{k} {v:.1e}' for k, v in worst.items()))
# the sens file and the band with it
sens = table(o + '/sens/paired.tsv')
for s in sens:
    want = 0.05 / h if (s['reading'] == 'sia_D' and s['step'] != '0') else 0
    if s['reading'] in ('sia_x_D', 'sia_y_D'):   # follow sia_D through its axis
        continue
    assert abs(float(s['dR_dp']) - want) < 2e-5 / h + 1e-12, (s, want)
b2 = table(t + '/band2/curvature.tsv')[-1]
sd1, sd2 = float(last['sia_D_sd']), float(b2['sia_D_sd'])
want = math.sqrt(sd1 ** 2 + (0.05 / h * 10) ** 2)
assert abs(sd2 - want) < 1e-4, (sd2, want)
print(f'uq_study: --sens adds the fd quantity: SIA sd {sd1:.4f} -> {sd2:.4f} D (expected {want:.4f})')
PYEOF
# the comparison with that band
KT_BUILD="$B" bash plans/studies/uq/summarize.sh "$O" > /dev/null
awk -F'\t' -v b="$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next } { v = $c["sia_D_sd"] } END { print v }' "$tmp/band2/curvature.tsv")" '
    $1 == "paired" && $2 == 30 && $3 == "sia_D" { ok = ($10 - b < 1e-5 && b - $10 < 1e-5) && ($13 == "NaN" || ($13 - $7 / $10 < 2e-3 && $7 / $10 - $13 < 2e-3)) }
    END { exit !ok }' "$O/uq.tsv" || fail "uq.tsv's first-order sd is not the band's: $(grep sia_D "$O/uq.tsv")"
grep -q "paired: first-order band: 2 quantities" "$O/report.md" || fail "report.md: $(grep first-order "$O/report.md")"
echo "uq_study: ok ($(grep -P '^paired\t30\tsia_D' "$O/uq.tsv" | cut -f1-12 | tr '\t' ' '))"
