#!/usr/bin/env bash
# lri_hostile.sh BUILD_DIR: a hostile case list for lri-plan's Pentacam import and patient
# checks and for lri-nomogram's tables (issue 36, item 8). Every case: the exit code, exactly
# one line on stderr naming file:line:col, nothing on stdout, no output folder left. Each row:
# name | what the case's folder gets (a shell snippet run there; $S is plans/patients) | the
# expected stderr (a grep -E pattern). Cases are refused before any meshing (seconds each).
set -uo pipefail
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
S=$PWD/plans/patients
T=$(mktemp -d /tmp/kt-hostile.XXXXXX)
trap 'rm -rf "$T"' EXIT
fails=0 n=0
export S

# every measured cell of a pachymetry map set to $1 um
pachy_all() { awk -F';' -v v="$1" 'BEGIN { OFS = ";" } NR > 3 { for (i = 2; i <= NF; i++) if ($i != "" && $i != "-1") $i = v } { print }' "$S/pentacam-pachy.csv"; }
export -f pachy_all
PAT='name: p\neye: %s\nage: 66\ncornea:\n  pentacam:\n    front: %s\n    back: %s\n    pachymetry: %s\n'
export PAT
plan_cases=(
"pachy-1500|printf \"\$PAT\" OD $S/pentacam-front.csv $S/pentacam-back.csv m.csv > p.yaml; pachy_all 1500 > m.csv|m\.csv:5:[0-9]+: expected a pachymetry in um within \[300, 1200\] \(the patient file's range for a pachymetry, .*p\.yaml:8:17\).*found 1500"
"od-export-os-patient|printf \"\$PAT\" OS $S/pentacam-front.csv $S/pentacam-back.csv $S/pentacam-pachy.csv > p.yaml|pentacam-front\.csv:2:5: expected an export of the patient's eye OS \(.*p\.yaml:2:6: eye\), the export's header says OD"
"left-header-od-patient|sed 's/^Eye;OD/Eye;left/' $S/pentacam-front.csv > f.csv; printf \"\$PAT\" OD f.csv $S/pentacam-back.csv $S/pentacam-pachy.csv > p.yaml|f\.csv:2:5: expected an export of the patient's eye OD .* says OS"
"front-back-swapped|printf \"\$PAT\" OD $S/pentacam-back.csv $S/pentacam-front.csv $S/pentacam-pachy.csv > p.yaml|pentacam-back\.csv:1:[0-9]+: expected an elevation map of the front \(.*p\.yaml:6:12: cornea\.pentacam\.front\), the export's header says an elevation of the back"
"swapped-no-header|tail -n +3 $S/pentacam-back.csv > b.csv; tail -n +3 $S/pentacam-front.csv > f.csv; printf \"\$PAT\" OD b.csv f.csv $S/pentacam-pachy.csv > p.yaml|p\.yaml:7:11: cornea\.pentacam\.back: the fit of .*f\.csv gives a mean radius .* \(swapped maps\?\)"
"pachymetry-as-front|printf \"\$PAT\" OD $S/pentacam-pachy.csv $S/pentacam-back.csv $S/pentacam-pachy.csv > p.yaml|pentacam-pachy\.csv:[0-9]+:[0-9]+: expected"
"elevation-in-um|sed '1s/\[mm\]/[um]/' $S/pentacam-front.csv > f.csv; printf \"\$PAT\" OD f.csv $S/pentacam-back.csv $S/pentacam-pachy.csv > p.yaml|f\.csv:1:[0-9]+: expected elevations in mm .* says um"
"thin-map|printf \"\$PAT\" OD $S/pentacam-front.csv $S/pentacam-back.csv m.csv > p.yaml; pachy_all 310 > m.csv|p\.yaml:8:17: cornea\.pentacam\.pachymetry: 310 um at the 10\.5 mm zone: expected a pachymetry the eye model can reach"
"extreme-keratometry|printf 'eye: OD\nage: 66\ncornea:\n  keratometry: {k_steep: 69 D, k_flat: 66 D, steep_axis: 90 deg}\n  thickness_at_zone: 640 um\n' > p.yaml|p\.yaml:5:22: cornea\.thickness_at_zone: 640 um .*K 69\.00 / 66\.00 D: cornea\.keratometry"
"blade-deeper-than-map|printf \"\$PAT\" OD $S/pentacam-front.csv $S/pentacam-back.csv m.csv > p.yaml; printf 'constraints: {depth: 560 um}\n' >> p.yaml; pachy_all 560 > m.csv|p\.yaml:9:22: constraints\.depth: expected at most 90% of the pachymetry at the zone"
)
for c in "${plan_cases[@]}"; do
    IFS='|' read -r name setup want <<< "$c"
    d=$T/plan-$name; mkdir -p "$d"
    (cd "$d" && eval "$setup") || { echo "FAIL $name: set-up"; fails=$((fails + 1)); continue; }
    rc=0; n=$((n + 1))
    (cd "$d" && timeout 120 "$B/lri-plan" -q --fast p.yaml -o out) >"$T/out" 2>"$T/err" || rc=$?
    left=$(cd "$d" && ls -A | grep -E '^out' | tr '\n' ' ')
    if [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qE -- "$want" "$T/err" && [ -z "$left" ] && [ ! -s "$T/out" ]; then
        echo "ok   lri-plan $name: $(cat "$T/err")"
    else
        echo "FAIL lri-plan $name: exit $rc, left '$left', stderr '$(cat "$T/err")', want /$want/"; fails=$((fails + 1))
    fi
done

# ---- lri-nomogram -------------------------------------------------------------------------
H='eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg'
{ printf "$H\n"; for age in 50 70; do for arc in 15 30 45 60 75 90; do
    printf 'e\t%s\t1.5\t90\t2\t%s\t0.9\t10.5\t%s\t0\n' $age $arc "$(awk "BEGIN { print $arc * ($age == 50 ? 0.02 : 0.03) }")"
done; done; } >"$T/t.tsv" # one eye name at two ages: two eyes
Q="--k-steep 44.5 --k-flat 43 --axis 90 --age 60"
nomo_cases=(
"duplicate-column|sed '1s/sia_D/arc_deg/' \$T/t.tsv > n.tsv|n\.tsv:1:66: expected each column once, 'arc_deg' is also column 6 \(at 1:40\)"
"duplicate-sd-column|awk 'BEGIN { OFS = \"\t\" } { print \$0, (NR == 1 ? \"sia_sd_D\" : \"0.1\"), (NR == 1 ? \"sia_sd_D\" : \"0.2\") }' \$T/t.tsv > n.tsv|n\.tsv:1:[0-9]+: expected each column once, 'sia_sd_D' is also column 11"
"duplicate-other-column|awk 'BEGIN { OFS = \"\t\" } { print \$0, (NR == 1 ? \"note\" : \"a\"), (NR == 1 ? \"note\" : \"b\") }' \$T/t.tsv > n.tsv|n\.tsv:1:[0-9]+: expected each column once, 'note' is also column 11"
"duplicated-case|(cat \$T/t.tsv; sed -n 4p \$T/t.tsv) > n.tsv|n\.tsv:14:1: expected each case once: this row repeats line 4 \(eye e, age 50 y"
"duplicated-case-other-sia|(cat \$T/t.tsv; sed -n '4s/0[.]9\t0\$/9\t0/p' \$T/t.tsv) > n.tsv|n\.tsv:14:1: expected each case once: this row repeats line 4"
)
export T
for c in "${nomo_cases[@]}"; do
    IFS='|' read -r name setup want <<< "$c"
    d=$T/nomo-$name; mkdir -p "$d"
    (cd "$d" && eval "$setup") || { echo "FAIL $name: set-up"; fails=$((fails + 1)); continue; }
    rc=0; n=$((n + 1))
    (cd "$d" && "$B/lri-nomogram" $Q n.tsv) >"$T/out" 2>"$T/err" || rc=$?
    if [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -qE -- "$want" "$T/err" && [ ! -s "$T/out" ]; then
        echo "ok   lri-nomogram $name: $(cat "$T/err")"
    else
        echo "FAIL lri-nomogram $name: exit $rc, stderr '$(cat "$T/err")', want /$want/"; fails=$((fails + 1))
    fi
done
# one eye name at two ages, the rows in either order: the same answer, and the lines it used
(head -1 "$T/t.tsv"; tail -n +2 "$T/t.tsv" | tac) >"$T/rev.tsv"
a=$("$B/lri-nomogram" $Q "$T/t.tsv" | tail -1 | cut -f1-12); b=$("$B/lri-nomogram" $Q "$T/rev.tsv" | tail -1 | cut -f1-12)
lines=$("$B/lri-nomogram" $Q "$T/t.tsv" | tail -1 | cut -f13)
n=$((n + 1))
if [ -n "$a" ] && [ "$a" = "$b" ] && [ "$(echo "$a" | cut -f2)" = "60.0" ] && [ "$lines" = "5;11" ]; then
    echo "ok   lri-nomogram: eye e at ages 50 and 70, either row order: arc 60.0 deg (lines $lines)"
else
    echo "FAIL lri-nomogram: row order: '$a' against '$b', lines '$lines' (expected 60.0 deg, lines 5;11)"; fails=$((fails + 1))
fi

echo "$((n - fails)) passed, $fails failed"
[ $fails -eq 0 ]
