#!/usr/bin/env bash
# curvature_bands.sh BUILD_DIR: curvature's first-order uncertainty bands (issue 21) on the
# synthetic run folder of `test_curv --make-run` (a shell whose anterior surface is an exact torus
# at every step; step 0 has zero displacement), with dudp_<p> fields appended to its step VTKs by
# an independent writer (tests/uq/add_dudp.py) whose effect on the readings is known:
#   dudp = u      every change since step 0 (flattening, steepening, SIA, its double-angle
#                 components, dK mean) is linear in u to first order, so dR/dp = R (to the
#                 surface's nonlinearity: K depends on u through curvature and slope, ~1% here);
#                 the coupling ratio and the SIA's axis are ratios / angles: dR/dp = 0;
#   dudp = 2 u    twice the above; dudp = z (a rigid move along the axis): every dR/dp = 0;
#   dudp = rot    a rigid rotation about the axis (per radian): the steep axis and the SIA's axis
#                 turn at 180/pi deg per radian, K, cylinder, SIA and (the incised meridian being a
#                 principal one) flattening and steepening do not change.
# Then: sd = sqrt(sum (dR/dp sd)^2) read back from curvature.tsv and --json by this script's own
# readers; the 90% interval is +-1.645 sd; sd 0 gives a zero band; doubling one sd doubles its
# contribution (and nothing else); a --sens file's fd rows enter as documented; without
# uncertainty.tsv (or with --no-uncertainty) every output is byte-identical to a run without
# the fields; bad uncertainty.tsv / --sens / a missing field: one line file:line, exit 2, nothing
# written; report.html carries the band and the tornado chart.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt_bands_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "curvature_bands: FAILED: $*" >&2; exit 1; }

d=$tmp/run
"$B/test_curv" --make-run "$d" --order2
# the reference: no fields, no uncertainty.tsv
"$B/curvature" -q --no-png "$d" > "$tmp/plain.txt"
"$B/curvature" -q --no-png --json "$d" > "$tmp/plain.json"
mkdir "$tmp/ref"
cp "$d"/curvature.tsv "$d"/meridians.tsv "$d"/report.html "$tmp/ref/"
sed -i 's/curvature [0-9.]* s\|[0-9.]* s of curvature//g' "$tmp/ref/report.html" || true

$PY tests/uq/add_dudp.py "$d" A=u B=u2 C=z D=rot Z=zero
# 1. fields present, no uncertainty.tsv: byte-identical outputs (the timing line of the page aside)
"$B/curvature" -q --no-png "$d" > "$tmp/plain2.txt"
cmp "$tmp/plain.txt" "$tmp/plain2.txt" || fail "summary changed by dudp fields without uncertainty.tsv"
cmp "$d/curvature.tsv" "$tmp/ref/curvature.tsv" || fail "curvature.tsv changed without uncertainty.tsv"
[ ! -e "$d/derivatives.tsv" ] || fail "derivatives.tsv written without uncertainty.tsv"

uq() { # write uncertainty.tsv: sd of A B C D Z E(fd) F(none)
    printf 'param\tunit\tvalue\tsd\tmethod\tsource\n' > "$d/uncertainty.tsv"
    printf 'A\tMPa\t2.0\t%s\tderivative\ttest\n' "$1" >> "$d/uncertainty.tsv"
    printf 'B\tkPa\t9.5\t%s\tderivative\ttest\n' "$2" >> "$d/uncertainty.tsv"
    printf 'C\tmm\t0\t%s\tderivative\ttest\n' "$3" >> "$d/uncertainty.tsv"
    printf 'D\trad\t0\t%s\tderivative\ttest\n' "$4" >> "$d/uncertainty.tsv"
    printf 'Z\tmmHg\t15\t%s\tderivative\ttest\n' "$5" >> "$d/uncertainty.tsv"
    printf 'E\tum\t0\t%s\tfd\ttest 2026\n' "$6" >> "$d/uncertainty.tsv"
    printf 'F\tum\t0\t0\tnone\ttest\n' >> "$d/uncertainty.tsv"
}
printf 'param\treading\tdR_dp\tstep\n' > "$tmp/sens.tsv"
for s in 1 2 3; do printf 'E\tsia_D\t%s\t%d\nE\tk_steep_D\t-0.01\t%d\n' "0.0$s" "$s" "$s" >> "$tmp/sens.tsv"; done

# --no-uncertainty: byte-identical too
uq 0.1 0.05 0.5 0.02 3 10
"$B/curvature" -q --no-png --no-uncertainty "$d" > "$tmp/plain3.txt"
cmp "$tmp/plain.txt" "$tmp/plain3.txt" && cmp "$d/curvature.tsv" "$tmp/ref/curvature.tsv" ||
    fail "--no-uncertainty changed an output"

# 2. the bands
run() { # OUT [curvature options]
    local o=$1; shift
    "$B/curvature" -q --no-png -o "$tmp/$o" "$@" "$d" > "$tmp/$o.txt"
    "$B/curvature" -q --no-png --no-report --no-vtk -o "$tmp/$o.j" --json "$@" "$d" > "$tmp/$o.json"
}
run base --sens "$tmp/sens.tsv"
uq 0.2 0.05 0.5 0.02 3 10; run dbl --sens "$tmp/sens.tsv"   # A's sd doubled
uq 0 0 0 0 0 0;           run zero --sens "$tmp/sens.tsv"   # every sd 0
uq 0.1 0.05 0.5 0.02 3 10; run nosens                       # E left out (no --sens)
grep -q "^uncertainty, step 3 (first order, 6 independent quantities, 90% = +-1.645 sd): SIA [0-9.]* D (90%: [0-9.]*-[0-9.]*)" \
    "$tmp/base.txt" || fail "summary line: $(grep ^uncertainty "$tmp/base.txt")"
grep -q "^left out (method fd, no --sens rows): E" "$tmp/nosens.txt" || fail "nosens: E not said to be left out"
grep -q 'class="band"' "$tmp/base/report.html" && grep -q 'id="tornado"' "$tmp/base/report.html" ||
    fail "report.html: no band or tornado chart"
! grep -q 'id="tornado"' "$tmp/ref/report.html" || fail "tornado without bands"
cmp <(cut -f1-37 "$tmp/base/curvature.tsv") "$tmp/ref/curvature.tsv" || fail "bands changed the columns before them"

$PY - "$tmp" <<'PYEOF'
import csv, json, math, sys
t = sys.argv[1]
def table(p):
    with open(p) as f:
        return list(csv.DictReader(f, delimiter='\t'))
def num(s):
    return float('nan') if s in ('NaN', None) else float(s)
Z90 = 1.6448536269514722
R = ['k_steep_D', 'k_flat_D', 'axis_steep_deg', 'cyl_D', 'k_mean_D', 'dk_mean_D', 'flattening_D', 'steepening_D',
     'coupling_ratio', 'sia_D', 'sia_x_D', 'sia_y_D', 'sia_axis_deg', 'dv_D']
sd_of = {'A': 0.1, 'B': 0.05, 'C': 0.5, 'D': 0.02, 'Z': 3, 'E': 10, 'F': 0}
cur = {k: table(f'{t}/{k}/curvature.tsv') for k in ('base', 'dbl', 'zero', 'nosens')}
der = {k: table(f'{t}/{k}/derivatives.tsv') for k in ('base', 'dbl', 'zero', 'nosens')}
D = {}  # (step, param) -> row
for r in der['base']:
    D[int(r['step']), r['param']] = r
worst = {}
def close(label, a, b, rel, ab=1e-9):
    err = abs(a - b)
    worst[label] = max(worst.get(label, 0), err / max(abs(b), 1e-300) if rel else err)
    assert err <= rel * abs(b) + ab, f'{label}: {a} vs {b}'
for row in cur['base']:
    s = int(row['step'])
    # sia_x, sia_y: the SIA's double-angle components, consistent with sia_D / sia_axis_deg
    m, ax = num(row['sia_D']), num(row['sia_axis_deg'])
    close('sia_x', num(row['sia_x_D']), m * math.cos(2 * math.radians(ax)), 0, 1e-4)
    close('sia_y', num(row['sia_y_D']), m * math.sin(2 * math.radians(ax)), 0, 1e-4)
    a, b, c, dd, z = (D[s, p] for p in 'ABCDZ')
    for r in R:
        v = num(row[r])
        if math.isnan(v):
            assert row[r + '_sd'] == 'NaN', (s, r, row[r + '_sd'])
            continue
        da, db, dc, drot, dz = (num(x[r]) for x in (a, b, c, dd, z))
        # known derivatives
        if s > 0 and r in ('flattening_D', 'steepening_D', 'sia_D', 'sia_x_D', 'dk_mean_D'):
            close('dR/dA = R ' + r, da, v, 0.03, 2e-4)
        if s > 0 and r in ('coupling_ratio', 'sia_axis_deg', 'sia_y_D'):
            close('dR/dA = 0 ' + r, da, 0, 0, 0.03 * max(1, abs(v)))
        if s == 0:
            close('step 0: dR/dA', da, 0, 0, 1e-9)
        close('dR/dB = 2 dR/dA ' + r, db, 2 * da, 1e-5, 1e-6)
        close('dR/dC = 0 ' + r, dc, 0, 0, 1e-6)
        close('dR/dZ = 0 ' + r, dz, 0, 0, 0)
        if r in ('axis_steep_deg',) or (r == 'sia_axis_deg' and s > 0):
            close('rotation ' + r, drot, 180 / math.pi, 1e-4)
        elif r in ('k_steep_D', 'k_flat_D', 'cyl_D', 'k_mean_D', 'dk_mean_D', 'flattening_D', 'steepening_D', 'sia_D'):
            close('rotation ' + r, drot, 0, 0, 1e-4)
        # the sd is the root sum of squares of the contributions; --sens gives E's
        e = 0.0
        if s > 0 and r == 'sia_D': e = 0.01 * s
        if s > 0 and r == 'k_steep_D': e = -0.01
        want = math.sqrt((da * 0.1) ** 2 + (db * 0.05) ** 2 + (dc * 0.5) ** 2 + (drot * 0.02) ** 2 + (e * 10) ** 2)
        sd = num(row[r + '_sd'])
        close('sd ' + r, sd, want, 1e-4, 1e-6)
        lo, hi = num(row[r + '_lo90']), num(row[r + '_hi90'])
        if r in ('axis_steep_deg', 'sia_axis_deg'):
            close('lo90 ' + r, lo, (v - Z90 * sd) % 180, 0, 2e-4)
            close('hi90 ' + r, hi, (v + Z90 * sd) % 180, 0, 2e-4)
        elif r in ('cyl_D', 'sia_D', 'dv_D'):
            close('lo90 ' + r, lo, max(0, v - Z90 * sd), 0, 2e-4)
            close('hi90 ' + r, hi, v + Z90 * sd, 0, 2e-4)
        else:
            close('lo90 ' + r, lo, v - Z90 * sd, 0, 2e-4)
            close('hi90 ' + r, hi, v + Z90 * sd, 0, 2e-4)
        # doubling A's sd: A's contribution doubles, the others stay
        drow = cur['dbl'][s]
        want2 = math.sqrt((da * 0.2) ** 2 + (db * 0.05) ** 2 + (dc * 0.5) ** 2 + (drot * 0.02) ** 2 + (e * 10) ** 2)
        close('doubled sd ' + r, num(drow[r + '_sd']), want2, 1e-4, 1e-6)
        # every sd 0: a zero band
        zrow = cur['zero'][s]
        assert num(zrow[r + '_sd']) == 0, ('zero', s, r, zrow[r + '_sd'])
        assert zrow[r + '_lo90'] == zrow[r] == zrow[r + '_hi90'] or r.endswith('axis_deg'), ('zero band', s, r)
        # no --sens: E left out
        nrow = cur['nosens'][s]
        want3 = math.sqrt((da * 0.1) ** 2 + (db * 0.05) ** 2 + (dc * 0.5) ** 2 + (drot * 0.02) ** 2)
        close('no sens sd ' + r, num(nrow[r + '_sd']), want3, 1e-4, 1e-6)
# the derivatives do not depend on the sd
for k in ('dbl', 'zero', 'nosens'):
    for r0, r1 in zip(der['base'], der[k]):
        if r0['param'] == 'E' and k == 'nosens':
            continue
        for r in R:
            assert r0[r] == r1[r], (k, r0['step'], r0['param'], r, r0[r], r1[r])
# --json: a second reader of the same numbers
for k in ('base', 'nosens'):
    j = json.load(open(f'{t}/{k}.json'))
    ps = {p['param']: p for p in j['uncertainty']['params']}
    assert ps['E']['used'] is (k == 'base') and ps['F']['used'] is False and ps['A']['method'] == 'derivative'
    assert ps['E']['source'] == 'test 2026' and ps['A']['unit'] == 'MPa' and ps['A']['sd'] == 0.1
    for row, st in zip(cur[k], j['steps']):
        assert int(row['step']) == st['step']
        for r in R:
            for suf in ('_sd', '_lo90', '_hi90'):
                a, b = num(row[r + suf]), st[r + suf]
                if math.isnan(a):
                    assert b is None, (r + suf, b)
                else:
                    assert abs(a - b) <= 1e-4 * max(1, abs(a)), (k, row['step'], r + suf, a, b)
    # tornado figures: the SIA's contribution per quantity at the last step
    last = int(cur[k][-1]['step'])
    for p, q in ps.items():
        if q['used'] and p != 'E':
            close('json contrib ' + p, q['sia_sd_contrib_D'], abs(num(D[last, p]['sia_D'])) * sd_of[p], 1e-5, 1e-7)
print('curvature_bands: dR/dp = R for dudp = u, worst relative deviation:',
      ', '.join(f'{k[9:]} {v:.2g}' for k, v in sorted(worst.items()) if k.startswith('dR/dA = R')))
print('curvature_bands: rotation, worst |d axis/d theta - 180/pi| / (180/pi): %.2g' % worst['rotation axis_steep_deg'])
PYEOF

# 3. bad input: one line file:line, exit 2, nothing written
bad() { # WHAT EXPECTED-IN-MESSAGE [curvature options]
    local what=$1 want=$2; shift 2
    rm -rf "$tmp/bad"
    set +e
    "$B/curvature" -q --no-png -o "$tmp/bad" "$@" "$d" > "$tmp/bad.out" 2> "$tmp/bad.err"
    local st=$?
    set -e
    [ $st -eq 2 ] || fail "$what: exit $st, expected 2 ($(cat "$tmp/bad.err"))"
    [ "$(wc -l < "$tmp/bad.err")" -eq 1 ] || fail "$what: expected one line: $(cat "$tmp/bad.err")"
    grep -qF -- "$want" "$tmp/bad.err" || fail "$what: expected '$want' in: $(cat "$tmp/bad.err")"
    [ ! -e "$tmp/bad" ] || fail "$what: output written"
    [ ! -s "$tmp/bad.out" ] || fail "$what: summary printed"
}
uq 0.1 0.05 0.5 0.02 3 10
cp "$d/uncertainty.tsv" "$tmp/good.tsv"
sed -i '3s/derivative/exact/' "$d/uncertainty.tsv"; bad "method" "uncertainty.tsv:3:16: expected the method derivative, fd or none"
cp "$tmp/good.tsv" "$d/uncertainty.tsv"; sed -i '2s/\t0.1\t/\t-1\t/' "$d/uncertainty.tsv"
bad "negative sd" "uncertainty.tsv:2:11: expected the sd as a finite number >= 0"
cp "$tmp/good.tsv" "$d/uncertainty.tsv"; sed -i '1s/sd/sigma/' "$d/uncertainty.tsv"; bad "header" "uncertainty.tsv:1:1: expected the header"
cp "$tmp/good.tsv" "$d/uncertainty.tsv"; printf 'A\tMPa\t2\t0.1\tderivative\tx\n' >> "$d/uncertainty.tsv"; bad "twice" "uncertainty.tsv:9:1: param A given twice"
cp "$tmp/good.tsv" "$d/uncertainty.tsv"; printf 'G\tMPa\t2\t0.1\n' >> "$d/uncertainty.tsv"; bad "short row" "uncertainty.tsv:9:12: expected 6 tab-separated fields"
cp "$tmp/good.tsv" "$d/uncertainty.tsv"; printf 'G\tMPa\t2\t0.1\tderivative\tx\n' >> "$d/uncertainty.tsv"
bad "missing field" 'step-0000.vtk: expected POINT_DATA field "dudp_G"'
cp "$tmp/good.tsv" "$d/uncertainty.tsv"
printf 'param\treading\tdR_dp\nE\tsia_D\tfast\n' > "$tmp/s1.tsv"; bad "sens number" "s1.tsv:2:9: expected dR_dp as a finite number" --sens "$tmp/s1.tsv"
printf 'param\treading\tdR_dp\nA\tsia_D\t1\n' > "$tmp/s2.tsv"; bad "sens derivative" "s2.tsv:2:1: expected a quantity that" --sens "$tmp/s2.tsv"
printf 'param\treading\tdR_dp\nE\tsia\t1\n' > "$tmp/s3.tsv"; bad "sens reading" "s3.tsv:2:3: expected a reading with a band" --sens "$tmp/s3.tsv"
printf 'param\treading\tdR_dp\tstep\nE\tsia_D\t1\t9\n' > "$tmp/s4.tsv"; bad "sens step" "s4.tsv:2: expected a step of the run (0 to 3)" --sens "$tmp/s4.tsv"
printf 'param\treading\tdR\n' > "$tmp/s5.tsv"; bad "sens header" "s5.tsv:1:1: expected the header param\\treading\\tdR_dp" --sens "$tmp/s5.tsv"
bad "sens missing" "nope.tsv: cannot open" --sens "$tmp/nope.tsv"
rm "$d/uncertainty.tsv"; bad "sens without table" "--sens $tmp/sens.tsv: expected a run folder with uncertainty.tsv" --sens "$tmp/sens.tsv"
echo "curvature_bands: ok"
