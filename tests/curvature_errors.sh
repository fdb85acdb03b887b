#!/usr/bin/env bash
# curvature_errors.sh BUILD_DIR: the documented bad inputs of curvature(1) exit 2 with one line
# on stderr naming the culprit, and leave no output (no table, map, surface or temporary folder)
# in the run folder or the -o folder. Inputs are synthetic run folders from test_curv --make-run.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt_curverr_XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fails=0

listing() { ls -lA --time-style=+%s.%N "$1" "$tmp/out" 2>/dev/null || true; }

# expect_fail NAME PATTERN DIR -- curvature args: exit 2, one stderr line matching PATTERN,
# and DIR (and -o folder $tmp/out) unchanged.
expect_fail() {
    local name=$1 pattern=$2 dir=$3
    shift 4
    local before after rc=0
    before=$(listing "$dir")
    "$B/curvature" -q "$@" > "$tmp/stdout" 2> "$tmp/stderr" || rc=$?
    after=$(listing "$dir")
    local why=""
    [ $rc -eq 2 ] || why="exit $rc, expected 2"
    [ "$(wc -l < "$tmp/stderr")" -eq 1 ] || why="$why; stderr has $(wc -l < "$tmp/stderr") lines"
    grep -q -- "$pattern" "$tmp/stderr" || why="$why; stderr lacks '$pattern'"
    [ ! -s "$tmp/stdout" ] || why="$why; stdout not empty"
    [ "$before" = "$after" ] || why="$why; files changed: $(diff <(echo "$before") <(echo "$after") | tr '\n' ' ' || true)"
    if [ -n "$why" ]; then
        echo "FAIL $name: $why"; cat "$tmp/stderr"; fails=$((fails + 1))
    else
        echo "ok   $name: $(cat "$tmp/stderr")"
    fi
}

mk() { rm -rf "$tmp/$1"; "$B/test_curv" --make-run "$tmp/$1" "${@:2}"; }

mk gap; rm "$tmp/gap/step-0002.vtk"
expect_fail "gap in the step numbering" "step-0002.vtk: missing" "$tmp/gap" -- "$tmp/gap"

mk listed; printf '4\t123\n' >> "$tmp/listed/steps.tsv"
expect_fail "steps.tsv lists a step without its VTK" "steps.tsv:6:1: step 4" "$tmp/listed" -- "$tmp/listed"

mk short; sed -i 's/^steps: 3$/steps: 4/' "$tmp/short/run.yaml"
expect_fail "run.yaml declares more steps" "step-0004.vtk: missing" "$tmp/short" -- "$tmp/short"

# A run folder holds one run (issue 26, item 2): a step file beyond run.yaml's steps is another
# run's; a mesh or a plan other than the run's is refused.
mk extra; cp "$tmp/extra/step-0003.vtk" "$tmp/extra/step-0004.vtk"
expect_fail "a step file beyond run.yaml's steps" "step-0004.vtk: not a step of this run (run.yaml says steps: 3)" "$tmp/extra" -- "$tmp/extra"
mk rehash; sed -i 's/^mesh_hash: "\(.\)/mesh_hash: "f/; s/^mesh_hash: "ff/mesh_hash: "0f/' "$tmp/rehash/run.yaml"
expect_fail "a mesh other than the run's" "eye.msh: not the mesh this run was solved on" "$tmp/rehash" -- "$tmp/rehash"
mk nohash; sed -i '/^mesh_hash:/d' "$tmp/nohash/run.yaml"
expect_fail "run.yaml without mesh_hash" "mesh_hash" "$tmp/nohash" -- "$tmp/nohash"
mk nosteps; sed -i '/^steps:/d' "$tmp/nosteps/run.yaml"
expect_fail "run.yaml without steps" "steps" "$tmp/nosteps" -- "$tmp/nosteps"
mk otherplan; cp plans/lri-paired-60.yaml "$tmp/otherplan/plan.yaml"; cp plans/eye.yaml "$tmp/otherplan/"
printf 'plan: "plan.yaml"\nplan_hash: "0123456789abcdef"\n' >> "$tmp/otherplan/run.yaml"
expect_fail "a plan other than the run's" "plan.yaml: not the plan this run was made from" "$tmp/otherplan" -- "$tmp/otherplan"

mk nodisp --drop displacement
expect_fail "VTK without displacement" "step-0001.vtk: expected POINT_DATA field \"displacement\"" "$tmp/nodisp" -- "$tmp/nodisp"
expect_fail "same, -o elsewhere" "displacement" "$tmp/nodisp" -- -o "$tmp/out" "$tmp/nodisp"

mk noorig --drop origin
expect_fail "VTK without origin" "step-0001.vtk: expected POINT_DATA field \"origin\"" "$tmp/noorig" -- "$tmp/noorig"

mk noant --no-anterior
expect_fail "mesh without the anterior group" "eye.msh: no surface group \"anterior\"" "$tmp/noant" -- "$tmp/noant"
expect_fail "same, --mesh mode" "no surface group \"anterior\"" "$tmp/noant" -- -o "$tmp/out" \
    --mesh "$tmp/noant/eye.msh" "$tmp/noant/step-0000.vtk"

mk ok
expect_fail "--mesh with a missing step file" "step-0009.vtk" "$tmp/ok" -- -o "$tmp/out" \
    --mesh "$tmp/ok/eye.msh" "$tmp/ok/step-0000.vtk" "$tmp/ok/step-0009.vtk"
expect_fail "no run.yaml" "run.yaml" "$tmp/ok" -- "$tmp/ok/nothing-here"
expect_fail "--zone 0" "--zone 0" "$tmp/ok" -- --zone 0 "$tmp/ok"
expect_fail "--fit unknown" "--fit spline" "$tmp/ok" -- --fit spline "$tmp/ok"
expect_fail "--order 1" "--order 1" "$tmp/ok" -- --order 1 "$tmp/ok"
rm -f "$tmp/ok/run.yaml"
expect_fail "run folder without run.yaml" "run.yaml" "$tmp/ok" -- "$tmp/ok"

# and the good folder still works after all that
mk good
"$B/curvature" -q "$tmp/good" > /dev/null
[ -s "$tmp/good/curvature.tsv" ] && [ -s "$tmp/good/axial-0003.png" ] && [ -s "$tmp/good/surface-0003.vtk" ] \
    || { echo "FAIL good run: outputs missing"; fails=$((fails + 1)); }
! ls -A "$tmp/good" | grep -q '\.tmp' || { echo "FAIL good run: temporary left"; fails=$((fails + 1)); }

# The tables read back (io/tsv.h): a field that is not a number, a short row, a missing column
# are exit 2 with one line naming file:line:col, never a value read as 0; CRLF ends read as LF.
mk badstep; sed -i '3s/^[0-9]*/x1/' "$tmp/badstep/steps.tsv"
expect_fail "steps.tsv: a step that is not a number" \
    "steps.tsv:3:1: expected an integer from 0 to 1000000 in column step, found 'x1'" "$tmp/badstep" -- "$tmp/badstep"
cp -r "$tmp/good" "$tmp/good2"
"$B/curvature" --compare "$tmp/good" "$tmp/good2" -o "$tmp/cmp1" 2> "$tmp/stderr" && [ -s "$tmp/cmp1/compare.html" ] ||
    { echo "FAIL --compare of two good runs: $(cat "$tmp/stderr")"; fails=$((fails + 1)); }
# corrupt(DIR LINE COLUMN TEXT): the field of that column on that line of DIR/curvature.tsv set to
# TEXT; prints the field's first byte in its line
corrupt() {
    cp -r "$tmp/good" "$tmp/$1"
    awk -F'\t' -v OFS='\t' -v ln="$2" -v name="$3" -v txt="$4" -v out="$tmp/col" '
        NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i }
        NR == ln { b = 1; for (i = 1; i < c; i++) b += length($i) + 1; $c = txt; print b > out }
        { print }' "$tmp/good/curvature.tsv" > "$tmp/$1/curvature.tsv"
    cat "$tmp/col"
}
col=$(corrupt cyl 4 cyl_D 1.2.3)
expect_fail "--compare: cyl_D not a number" "cyl/curvature.tsv:4:$col: expected a number in column cyl_D, found '1.2.3'" \
    "$tmp/cyl" -- --compare "$tmp/good" "$tmp/cyl" -o "$tmp/out"
col=$(corrupt emptysia 3 sia_D "")
expect_fail "--compare: sia_D empty" "emptysia/curvature.tsv:3:$col: expected a number in column sia_D, found an empty field" \
    "$tmp/emptysia" -- --compare "$tmp/emptysia" "$tmp/good" -o "$tmp/out"
cp -r "$tmp/good" "$tmp/shortrow"; sed -i '3s/\t.*//' "$tmp/shortrow/curvature.tsv"
len=$(sed -n 3p "$tmp/shortrow/curvature.tsv" | tr -d '\n' | wc -c)
expect_fail "--compare: a short row" "shortrow/curvature.tsv:3:$((len + 1)): expected a field in column" \
    "$tmp/shortrow" -- --compare "$tmp/good" "$tmp/shortrow" -o "$tmp/out"
cp -r "$tmp/good" "$tmp/nocol"
awk -F'\t' -v OFS='\t' 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "sia_D") c = i } { $c = "x"; print }' \
    "$tmp/good/curvature.tsv" > "$tmp/nocol/curvature.tsv"
expect_fail "--compare: no sia_D column" "nocol/curvature.tsv:1:1: expected a column sia_D (a table of curvature(1))" \
    "$tmp/nocol" -- --compare "$tmp/good" "$tmp/nocol" -o "$tmp/out"
sed -i 's/$/\r/' "$tmp/good2/curvature.tsv"
"$B/curvature" --compare "$tmp/good" "$tmp/good2" -o "$tmp/cmp2" 2> "$tmp/stderr" &&
    cmp -s "$tmp/cmp1/compare.html" "$tmp/cmp2/compare.html" ||
    { echo "FAIL --compare of a CRLF table: not the same page $(cat "$tmp/stderr")"; fails=$((fails + 1)); }

[ $fails -eq 0 ] && echo "curvature_errors: ok" || { echo "curvature_errors: $fails failed"; exit 1; }
