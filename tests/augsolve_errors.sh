#!/usr/bin/env bash
# augsolve_errors.sh BUILD_DIR: augsolve's documented failures. Bad edits streams exit 2 with
# one "file:line:col: expected ..." line (or a step-level message) and leave no steps.tsv;
# a backward error above --tol exits 1, the removed GMRES options exit 2; a good stream piped from cutplan runs to the end,
# agrees with a fresh factorization (--verify) and its VTKs read back with meshio.
set -uo pipefail
B=${1:?build dir}
T=$(mktemp -d /tmp/augsolve_errors.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail=0
check() { # check NAME EXPECTED_RC GREP_PATTERN RUN_DIR -- command...
    local name=$1 want=$2 pat=$3 run=$4
    shift 5
    "$@" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ "$rc" != "$want" ]; then
        echo "FAIL $name: exit $rc, expected $want"; cat "$T/err"; fail=1; return
    fi
    if [ -n "$pat" ] && ! grep -q -- "$pat" "$T/err"; then
        echo "FAIL $name: stderr lacks '$pat':"; cat "$T/err"; fail=1; return
    fi
    if [ "$want" != 0 ] && [ -e "$run/steps.tsv" ]; then
        echo "FAIL $name: steps.tsv left behind"; fail=1; return
    fi
    if [ "$want" != 0 ] && ls "$run" 2>/dev/null | grep -q '\.tmp\.'; then
        echo "FAIL $name: temporary file left behind"; fail=1; return
    fi
    echo "ok   $name"
}

"$B/mesh-prep" plans/bench/beam-16.yaml -o "$T/beam.msh" -q >/dev/null || { echo "mesh-prep failed"; exit 1; }
"$B/cutplan" plans/bench/cut-beam-16.yaml "$T/beam.msh" -o "$T/cut.edits" -q || { echo "cutplan failed"; exit 1; }
read -r _ _ _ NN NE < <(grep -m1 '^mesh ' "$T/cut.edits" | awk '{print $1, $2, $2, $3, $4}')
S=$(grep -m1 '^scene ' "$T/cut.edits" | cut -d' ' -f2-)
hdr() { printf 'keratome-edits 1\nscene %s\nmesh %s %s %s\n' "$S" "$T/beam.msh" "$NN" "$NE"; }

# A good run from a pipe, verified against fresh factorizations each step.
check "stream from cutplan, --verify" 0 "" "$T/ok" -- bash -c \
    "'$B/cutplan' plans/bench/cut-beam-16.yaml '$T/beam.msh' -o - -q | '$B/augsolve' '$T/beam.msh' - -o '$T/ok' --verify -q"
steps=$(grep -c '^step ' "$T/cut.edits")
rows=$(($(wc -l <"$T/ok/steps.tsv") - 1))
[ "$rows" = $((steps + 1)) ] || { echo "FAIL steps.tsv has $rows rows for $steps steps + step 0"; fail=1; }
awk -F'\t' 'NR > 1 && !($13 ~ /^[0-9.]+(e[-+][0-9]+)?$/ && $13 + 0 <= 1e-8) { bad = 1 } END { exit bad }' "$T/ok/steps.tsv" ||
    { echo "FAIL verify_rel_diff above 1e-8"; fail=1; }
grep -q "^steps: $steps$" "$T/ok/run.yaml" || { echo "FAIL run.yaml steps"; fail=1; }
if /usr/bin/python3 -c 'import meshio' 2>/dev/null; then
    last=$(printf '%s/ok/step-%04d.vtk' "$T" "$steps")
    /usr/bin/python3 - "$last" "$NN" "$steps" <<'EOF' || { echo "FAIL meshio read-back"; fail=1; }
import sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
nn0, steps = int(sys.argv[2]), int(sys.argv[3])
u = m.point_data["displacement"]; o = m.point_data["origin"]
assert u.shape == (len(m.points), 3) and np.all(np.isfinite(u)), "displacement"
assert len(m.points) > nn0, "duplicated nodes appended"
assert o.min() >= 1 and o.max() <= nn0, "origin numbers the input nodes"
assert np.all(o[:nn0].ravel() == np.arange(1, nn0 + 1)), "original nodes are their own origin"
assert "region" in m.cell_data, "region"
print("meshio: %d points, max |u| %.3g mm" % (len(m.points), np.abs(u).max()))
EOF
fi

# Bad streams: exit 2, one clear line, nothing half-written.
{ hdr; printf 'step 1\nforce 99999 0 0 1\nend\n'; } >"$T/e1"
check "unknown node" 2 "e1:5:7: expected a node number in 1..$NN" "$T/r1" -- "$B/augsolve" "$T/beam.msh" "$T/e1" -o "$T/r1" -q
{ hdr; printf 'step 1\ndup 1 %d 1 99999\nend\n' $((NN + 1)); } >"$T/e2"
check "unknown tet" 2 "expected a tet number in 1..$NE" "$T/r2" -- "$B/augsolve" "$T/beam.msh" "$T/e2" -o "$T/r2" -q
{ hdr; printf 'step 1\ndup 1 %d 1 1\nend\n' $((NN + 5)); } >"$T/e3"
check "wrong new node number" 2 "expected new node number $((NN + 1))" "$T/r3" -- "$B/augsolve" "$T/beam.msh" "$T/e3" -o "$T/r3" -q
head -n 12 "$T/cut.edits" | grep -v '^end' >"$T/e4"
check "truncated stream" 2 "found the end of the stream" "$T/r4" -- "$B/augsolve" "$T/beam.msh" "$T/e4" -o "$T/r4" -q
{ printf 'keratome-edits 1\nscene %s\nmesh x.msh 5 5\n' "$S"; } >"$T/e5"
check "edits for another mesh" 2 "expected the $NN nodes" "$T/r5" -- "$B/augsolve" "$T/beam.msh" "$T/e5" -o "$T/r5" -q
{ hdr; printf 'step 1\ndup 1 %d 1 %d\nend\ndone 1\n' $((NN + 1)) "$NE"; } >"$T/e6"
check "tet without that node" 2 "e6:5:[0-9]*: expected tets that hold node 1 (.*does not hold that node" "$T/r6" -- "$B/augsolve" "$T/beam.msh" "$T/e6" -o "$T/r6" -q
{ printf 'keratome-edits 1\nmesh %s %s %s\n' "$T/beam.msh" "$NN" "$NE"; } >"$T/e7"
check "no scene" 2 "names no scene" "$T/r7" -- "$B/augsolve" "$T/beam.msh" "$T/e7" -o "$T/r7" -q
check "bad option" 2 "bad --method" "$T/r8" -- "$B/augsolve" "$T/beam.msh" "$T/e7" -o "$T/r8" --method lu

# Numerical failure: a backward error no solve reaches, even after refinement: exit 1.
check "backward error above --tol" 1 "backward error .* exceeds --tol 1e-30 after a step of iterative refinement" "$T/r9" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r9" --method augmented --tol 1e-30 -q
check "--verify-tol exceeded" 1 "differ by" "$T/r10" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r10" --method augmented --verify --verify-tol 1e-30 -q
# The GMRES options went with GMRES: a clear usage error, nothing run.
for opt in "--precond local" "--restart 50" "--refactor auto" "--refactor-sync"; do
    # shellcheck disable=SC2086
    check "removed option $opt" 2 "were removed with GMRES" "$T/r9b" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r9b" --method augmented $opt -q
done

# The planned method (default) checks the whole stream before it factors: a bad tet in the
# last step is reported with its line, nothing is written.
{ sed '/^end/q' "$T/cut.edits"; printf 'step 2\ndup 1 %d 1 %d\nend\ndone 2\n' "$(grep -c '^dup' <(sed '/^end/q' "$T/cut.edits") | awk -v n="$NN" '{print n + $1 + 1}')" "$NE"; } >"$T/e11"
line=$(grep -n '^dup 1 ' "$T/e11" | tail -1 | cut -d: -f1)
check "planned: bad tet in step 2 found before factoring" 2 "e11:$line:[0-9]*: expected tets that hold node 1" "$T/r11" -- "$B/augsolve" "$T/beam.msh" "$T/e11" -o "$T/r11" -q
grep -q "planned: .* factor" "$T/err" && { echo "FAIL planned: factored before the check"; fail=1; }
check "planned: bad --steps" 2 "expected steps in 0" "$T/r12" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r12" --steps 1,99 -q

# A fix edit changes the intact block: the planned method falls back loudly, verified.
{ grep -v '^done' "$T/cut.edits"; printf 'step %d\nfix 1 x 0.001\nend\ndone %d\n' $((steps + 1)) $((steps + 1)); } >"$T/e13"
check "planned: fix edit falls back to augmented" 0 "e13:[0-9]*: step $((steps + 1)) fixes node 1.*falling back to --method augmented" "$T/r13" -- "$B/augsolve" "$T/beam.msh" "$T/e13" -o "$T/r13" --verify --no-vtk -q
grep -q '^method: augmented' "$T/r13/run.yaml" && grep -q '^fallback: ' "$T/r13/run.yaml" ||
    { echo "FAIL fallback not recorded in run.yaml"; fail=1; }

# A planned factor predicted larger than --plan-max-ratio times METIS's on the intact block
# (every plan exceeds ratio 1: its increments add to the intact block's factor) is not
# factored: the run falls back loudly to refactor with METIS, verified, recorded in run.yaml.
check "planned: size check falls back to refactor" 0 "beyond --plan-max-ratio 1.*falling back to --method refactor --ordering metis" "$T/r15" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r15" --plan-max-ratio 1 --verify --no-vtk -q
grep -q '^method: refactor' "$T/r15/run.yaml" && grep -q '^ordering: metis' "$T/r15/run.yaml" &&
    grep -q '^fallback: .*plan-max-ratio' "$T/r15/run.yaml" ||
    { echo "FAIL size fallback not recorded in run.yaml"; fail=1; }
[ "$(wc -l <"$T/r15/steps.tsv")" -eq $((steps + 2)) ] || { echo "FAIL size fallback: not every step"; fail=1; }
check "planned: default ratio keeps the planned method" 0 "" "$T/r16" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r16" --no-vtk -q
grep -q '^method: planned' "$T/r16/run.yaml" && ! grep -q '^fallback' "$T/r16/run.yaml" ||
    { echo "FAIL default ratio: the planned method fell back"; fail=1; }
check "bad --plan-max-ratio" 2 "plan-max-ratio expects" "$T/r17" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r17" --plan-max-ratio -1

# --steps: only the listed steps are written, each as in the full run (one factorization).
check "planned: --steps" 0 "" "$T/r14" -- "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/r14" --steps 2,4-5 -q
[ "$(cut -f1 "$T/r14/steps.tsv" | tr '\n' ' ')" = "step 0 2 4 5 " ] || { echo "FAIL --steps rows: $(cut -f1 "$T/r14/steps.tsv" | tr '\n' ' ')"; fail=1; }
for k in 0002 0004 0005; do
    cmp -s "$T/r14/step-$k.vtk" "$T/ok/step-$k.vtk" || { echo "FAIL --steps: step-$k.vtk differs from the full run"; fail=1; }
done
[ -e "$T/r14/step-0003.vtk" ] && { echo "FAIL --steps wrote step 3"; fail=1; }
exit $fail
