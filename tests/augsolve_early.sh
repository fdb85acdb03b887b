#!/usr/bin/env bash
# augsolve_early.sh BUILD_DIR: augsolve checks everything it can before the first solve
# (augsolve(1): "before anything is factored"): on a coarse prestressed eye, a typo on the last
# step's line of the edits stream, an --output set the mesh lacks (every method), a --steps
# list beyond the plan, an option conflict, a -o that is a file and a run folder another
# augsolve holds each exit 2 before the prestress solve (its "prestress" line never appears on
# stderr) and leave no steps.tsv. Good runs of the same inputs do print that line, and their
# steps (planned, augmented, refactor) agree with a fresh factorization to 1e-10.
set -uo pipefail
B=${1:?build dir}
T=$(mktemp -d /tmp/augsolve_early.XXXXXX)
trap 'rm -rf "$T"' EXIT
printf 'leak:libgmsh.so\n' >"$T/lsan.supp"
export LSAN_OPTIONS="suppressions=$T/lsan.supp:print_suppressions=0"
fail=0
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$T/eye.yaml" || { echo "FAIL could not coarsen the eye"; exit 1; }
grep -q "reference: prestressed" "$T/eye.yaml" || { echo "FAIL eye.yaml is not prestressed"; exit 1; }
sed -e "s|^scene:.*|scene: $T/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 10 deg|' \
    plans/lri-single-30.yaml >"$T/plan.yaml"
"$B/mesh-prep" -q "$T/eye.yaml" -o "$T/eye.msh" >/dev/null || { echo "FAIL mesh-prep"; exit 1; }
"$B/cutplan" -q "$T/plan.yaml" "$T/eye.msh" -o "$T/lri.edits" || { echo "FAIL cutplan"; exit 1; }

# check NAME PATTERN RUN_DIR -- command...: exit 2 with PATTERN on stderr, before the prestress.
check() {
    local name=$1 pat=$2 run=$3
    shift 4
    "$@" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ "$rc" != 2 ]; then
        echo "FAIL $name: exit $rc, expected 2"; cat "$T/err"; fail=1; return
    fi
    if ! grep -q -- "$pat" "$T/err"; then
        echo "FAIL $name: stderr lacks '$pat':"; cat "$T/err"; fail=1; return
    fi
    if grep -q prestress "$T/err"; then
        echo "FAIL $name: refused only after the prestress solve:"; cat "$T/err"; fail=1; return
    fi
    if [ -e "$run/steps.tsv" ] || [ -e "$run/run.yaml" ]; then
        echo "FAIL $name: steps.tsv or run.yaml left behind"; fail=1; return
    fi
    echo "ok   $name"
}

# the last edit line of the stream, its keyword misspelt
last=$(grep -n '^dup ' "$T/lri.edits" | tail -1 | cut -d: -f1)
sed "${last}s/^dup /dpu /" "$T/lri.edits" >"$T/typo.edits"
check "typo on the last step's line $last" "typo.edits:$last:1: expected" "$T/r1" -- \
    "$B/augsolve" "$T/eye.msh" "$T/typo.edits" -o "$T/r1"
for m in planned augmented refactor cg pcg-jacobi newton; do
    check "--output nosuchset, --method $m" "output nosuchset" "$T/r2" -- \
        "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/r2" --method "$m" --output nosuchset
done
check "--steps beyond the plan" "expected steps in 0.." "$T/r3" -- \
    "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/r3" --steps 1,99
check "augmented with a simplicial factor" "factor simplicial" "$T/r4" -- \
    "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/r4" --method augmented --factor simplicial
: >"$T/afile"
check "-o names a file" "afile" "$T/afile.d" -- "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/afile"
mkdir -p "$T/r5"
exec 9>"$T/r5/.augsolve.lock" # this shell holds the lock, as a running augsolve would
flock -n 9 || { echo "FAIL cannot take the lock"; exit 1; }
check "a locked run folder" "another augsolve" "$T/r5" -- \
    "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/r5"
exec 9>&-

# the control: the same inputs run, and the prestress line the checks look for is printed;
# every direct method's steps (step 0 and the last, the cut's three steps applied) agree with a
# fresh factorization (--verify) to 1e-10
last=$(grep -c '^step ' "$T/lri.edits")
for m in planned augmented refactor; do
    if "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/ok-$m" --method "$m" --no-vtk --verify \
        --verify-tol 1e-10 --steps "$last" 2>"$T/err" >/dev/null && grep -q prestress "$T/err" &&
        [ -s "$T/ok-$m/run.yaml" ] &&
        awk -F'\t' -v last="$last" 'NR > 1 { n++; ok += $13 ~ /^[0-9.]+(e[-+][0-9]+)?$/ && $13 + 0 <= 1e-10 && $1 == (n == 1 ? 0 : last) }
            END { exit !(n == 2 && ok == 2) }' "$T/ok-$m/steps.tsv"; then
        echo "ok   control run, --method $m: prints its prestress line, --verify-tol 1e-10 holds"
    else
        echo "FAIL control run, --method $m:"; cat "$T/err"; fail=1
    fi
done
exit $fail
