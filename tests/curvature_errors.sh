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

[ $fails -eq 0 ] && echo "curvature_errors: ok" || { echo "curvature_errors: $fails failed"; exit 1; }
