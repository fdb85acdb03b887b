#!/usr/bin/env bash
# curvature_subset.sh BUILD_DIR: a run folder records exactly the steps it holds (issue 36,
# item 5). augsolve --steps 0,2 on the coarse eye writes run.yaml's step_files: [0, 2] and those
# two step files; curvature reads exactly them (exit 0, two rows numbered 0 and 2), and still
# refuses a folder whose files disagree with the record: a step file it does not list, a listed
# one missing, a list that is not increasing from 0.
set -u
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt_curvsub.XXXXXX)
trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$T/eye.yaml" || { echo "FAIL could not coarsen the eye"; exit 1; }
sed -e "s|^scene:.*|scene: $T/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 10 deg|' \
    plans/lri-single-30.yaml >"$T/plan.yaml"
"$B/mesh-prep" -q "$T/eye.yaml" -o "$T/eye.msh" >/dev/null || { echo "FAIL mesh-prep"; exit 1; }
"$B/cutplan" -q "$T/plan.yaml" "$T/eye.msh" -o "$T/lri.edits" || { echo "FAIL cutplan"; exit 1; }
"$B/augsolve" -q --steps 0,2 "$T/eye.msh" "$T/lri.edits" -o "$T/run" || { echo "FAIL augsolve --steps 0,2"; exit 1; }

grep -qx "step_files: \[0, 2\]" "$T/run/run.yaml" || fail "run.yaml does not record step_files: [0, 2]: $(grep step "$T/run/run.yaml")"
[ "$(cd "$T/run" && ls step-*.vtk | tr '\n' ' ')" = "step-0000.vtk step-0002.vtk " ] || fail "step files: $(ls "$T/run")"
if "$B/curvature" -q --no-png "$T/run" >/dev/null 2>"$T/err"; then
    rows=$(cut -f1 "$T/run/curvature.tsv" | tail -n +2 | tr '\n' ' ')
    [ "$rows" = "0 2 " ] && echo "ok   curvature on a --steps 0,2 run: exit 0, rows $rows" || fail "curvature rows: $rows"
    [ -e "$T/run/surface-0002.vtk" ] || fail "surface-0002.vtk not written (the step's own number)"
else
    fail "curvature on a --steps 0,2 run: $(cat "$T/err")"
fi

# refused NAME PATTERN: curvature on $T/bad exits 2 with PATTERN on stderr
refused() {
    local rc=0
    "$B/curvature" -q --no-png "$T/bad" >/dev/null 2>"$T/err" || rc=$?
    if [ $rc -ne 2 ]; then fail "$1: exit $rc, expected 2: $(cat "$T/err")"
    elif ! grep -q -- "$2" "$T/err"; then fail "$1: stderr lacks '$2': $(cat "$T/err")"
    else echo "ok   $1: $(cat "$T/err")"; fi
}
fresh() { rm -rf "$T/bad"; cp -r "$T/run" "$T/bad"; rm -f "$T/bad"/curvature.tsv "$T/bad"/surface-*; }
fresh; cp "$T/bad/step-0000.vtk" "$T/bad/step-0001.vtk"
refused "a step file the record does not list" "step-0001.vtk: not a step of this run (run.yaml's step_files do not list it)"
fresh; rm "$T/bad/step-0002.vtk"
refused "a listed step file missing" "step-0002.vtk: missing (run.yaml's step_files list it)"
fresh; sed -i 's/^step_files: .*/step_files: [0, 2, 1]/' "$T/bad/run.yaml"
refused "step_files not increasing" "run.yaml:.*step_files"
fresh; sed -i 's/^step_files: .*/step_files: [0, 7]/' "$T/bad/run.yaml"
refused "step_files beyond steps:" "run.yaml:.*step_files"

if [ $fails -ne 0 ]; then echo "$fails failure(s)"; exit 1; fi
echo "the run folder's record and curvature agree"
