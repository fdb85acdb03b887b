#!/usr/bin/env bash
# lriplan_errors.sh BUILD_DIR: bad patients and bad Pentacam maps exit 2 with one line
# "file:line:col: expected ..." on stderr, before anything is meshed: the plan folder is not
# even made (the main incision's bad width, kind, SIA and site among them). Usage errors exit 2 too.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt-lriplan-err.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0
K='keratometry: {k_steep: 44 D, k_flat: 43 D, steep_axis: 90 deg}'
# name|patient text|expected stderr fragment
cases=(
"kflat|eye: OD\nage: 68\ncornea:\n  keratometry: {k_steep: 43 D, k_flat: 44 D, steep_axis: 90 deg}|p.yaml:4:40: cornea.keratometry.k_flat: expected at most k_steep"
"axis200|eye: OD\nage: 68\ncornea:\n  keratometry: {k_steep: 44 D, k_flat: 43 D, steep_axis: 200 deg}|p.yaml:4:58: cornea.keratometry.steep_axis: expected"
"age-1|eye: OD\nage: -1\ncornea: {$K}|p.yaml:2:6: patient.age: expected"
"deep|eye: OD\nage: 68\ncornea: {$K, thickness_at_zone: 600 um}\nconstraints: {depth: 560 um}|p.yaml:4:22: constraints.depth: expected at most 90% of the pachymetry"
"zone|eye: OD\nage: 68\ncornea: {$K}\nconstraints: {zone: 6.5 mm}|p.yaml:4:21: constraints.zone: expected a diameter outside the optical zone"
"notpentacam|eye: OD\nage: 68\ncornea: {pentacam: {front: ../plans/eye.yaml}}|eye.yaml: expected a Pentacam map export"
"truncated|eye: OD\nage: 68\ncornea: {pentacam: {front: short.csv}}|short.csv:104:1: expected 141 rows of the grid, the file ends after 100"
"mainwidth|eye: OD\nage: 68\ncornea: {$K}\nmain_incision: {meridian: temporal, width: 0.5 mm}|p.yaml:4:44: main_incision.width: expected a length in [1, 6] mm"
"mainkind|eye: OD\nage: 68\ncornea: {$K}\nmain_incision: {meridian: temporal, width: 2.4 mm, kind: scleral}|p.yaml:4:58: main_incision.kind: expected one of: clear_corneal, limbal"
"mainsia|eye: OD\nage: 68\ncornea: {$K}\nmain_incision: {meridian: temporal, width: 2.4 mm, sia: {magnitude: -1 D, axis: 90 deg}}|p.yaml:4:69: main_incision.sia.magnitude: expected a power in [0, 5] D"
"mainsite|eye: OD\nage: 68\ncornea: {$K}\nmain_incision: {meridian: 400 deg, width: 2.4 mm}|p.yaml:4:27: main_incision.meridian"
# The conventions lri-nomogram(1) shares (keratome-patient(5)): an axis in [0, 180], 180 read as
# 0; an age in [18, 110]; the SIA {0-5 D, axis}. Beyond them, refused; at their ends, accepted:
# the error is then the later bad max_arc's (parsed after them), not theirs.
"axis180.5|eye: OD\nage: 68\ncornea:\n  keratometry: {k_steep: 44 D, k_flat: 43 D, steep_axis: 180.5 deg}|p.yaml:4:58: cornea.keratometry.steep_axis: expected"
"age17|eye: OD\nage: 17\ncornea: {$K}|p.yaml:2:6: patient.age: expected"
"age111|eye: OD\nage: 111\ncornea: {$K}|p.yaml:2:6: patient.age: expected"
"kflat19|eye: OD\nage: 68\ncornea:\n  keratometry: {k_steep: 44 D, k_flat: 19 D, steep_axis: 90 deg}|p.yaml:4:40: cornea.keratometry.k_flat: expected"
"siaaxis181|eye: OD\nage: 68\ncornea: {$K}\nmain_incision: {meridian: temporal, width: 2.4 mm, sia: {magnitude: 0.3 D, axis: 181 deg}}|main_incision.sia.axis: expected"
"ends-ok|eye: OD\nage: 18\ncornea:\n  keratometry: {k_steep: 70 D, k_flat: 20 D, steep_axis: 180 deg}\nmain_incision: {meridian: temporal, width: 2.4 mm, sia: {magnitude: 5 D, axis: 180 deg}}\nconstraints: {max_arc: 200 deg}|constraints.max_arc: expected"
"age110-ok|eye: OD\nage: 110\ncornea: {$K}\nmain_incision: {meridian: temporal, width: 2.4 mm, sia: {magnitude: 0 D, axis: 0 deg}}\nconstraints: {max_arc: 200 deg}|constraints.max_arc: expected"
)
head -n 103 plans/patients/pentacam-front.csv > "$tmp/short.csv"
for c in "${cases[@]}"; do
    IFS='|' read -r name text want <<< "$c"
    mkdir -p "$tmp/$name"
    printf "$text\n" > "$tmp/$name/p.yaml"
    cp "$tmp/short.csv" "$tmp/$name/"
    mkdir -p "$tmp/plans" && cp plans/eye.yaml "$tmp/plans/"
    rc=0
    "$B/lri-plan" -q "$tmp/$name/p.yaml" -o "$tmp/$name/out" > "$tmp/out" 2> "$tmp/err" || rc=$?
    if [ $rc -eq 2 ] && [ "$(wc -l < "$tmp/err")" -eq 1 ] && grep -qF -- "$want" "$tmp/err" && [ ! -e "$tmp/$name/out" ] \
        && [ ! -s "$tmp/out" ]; then
        echo "ok   $name: $(cat "$tmp/err")"
    else
        echo "FAIL $name: exit $rc, stderr '$(cat "$tmp/err")', want '$want'; out folder $([ -e "$tmp/$name/out" ] && echo made || echo absent)"
        fails=$((fails + 1))
    fi
done
for args in "" "-o $tmp/x" "$tmp/none.yaml" "--step 0 plans/patients/wtr-od.yaml -o $tmp/x" \
    "--base $tmp/none.yaml plans/patients/wtr-od.yaml -o $tmp/x"; do
    rc=0
    "$B/lri-plan" $args > /dev/null 2> "$tmp/err" || rc=$?
    if [ $rc -eq 2 ] && [ ! -e "$tmp/x" ]; then echo "ok   usage '$args': $(head -1 "$tmp/err")"
    else echo "FAIL usage '$args': exit $rc"; fails=$((fails + 1)); fi
done
echo "lriplan_errors: $((${#cases[@]} + 5 - fails)) passed, $fails failed"
[ $fails -eq 0 ]
