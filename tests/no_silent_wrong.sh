#!/usr/bin/env bash
# no_silent_wrong.sh BUILD_DIR: issue 26's silent wrong answers, each end to end through the tools.
#  1. an edits stream cut short in the documented `cutplan -o - | augsolve -` pipe (after step k,
#     or after the header alone) is refused: exit 2, no run.yaml, no steps.tsv;
#  2. a run folder holds one run: a shorter plan run into a longer run's folder leaves no step
#     file of the longer one, curvature reads the steps run.yaml lists, and refuses another plan;
#  3. an edits force of 1e308 (NaN in the solve) fails every method; nan/inf/hex are bad input;
#  4. paths holding " #", quotes and a newline go through mesh-prep, cutplan and augsolve;
# 12. a dup that leaves a node in no tetrahedron: exit 2 naming the step, nothing factored;
# 13. an incision inside the optical zone is refused; `curvature --meridian 400` is refused;
#     keratome-plan(5) and cutplan agree on depth_fraction.
# Every check fails on the tools before issue 26 (run it with their build dir to see).
set -uo pipefail
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt_nosilent.XXXXXX)
trap 'rm -rf "$T"' EXIT
PY=/usr/bin/python3
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }
# expect NAME RC PATTERN -- command: exit status RC and PATTERN on stderr
expect() {
    local name=$1 want=$2 pat=$3
    shift 4
    "$@" >"$T/out" 2>"$T/err"
    local rc=$?
    if [ "$rc" != "$want" ]; then bad "$name: exit $rc, expected $want: $(head -c 400 "$T/err")"
    elif [ -n "$pat" ] && ! grep -q -- "$pat" "$T/err"; then bad "$name: stderr lacks '$pat': $(head -c 400 "$T/err")"
    else ok "$name"; fi
}
# no_result NAME RUN_DIR: nothing a reader takes as a result
no_result() {
    if [ -e "$2/run.yaml" ] || [ -e "$2/steps.tsv" ]; then bad "$1: left $(ls "$2" | tr '\n' ' ')"
    else ok "$1: no run.yaml, no steps.tsv"; fi
}

"$B/mesh-prep" -q plans/bench/beam-16.yaml -o "$T/beam.msh" >/dev/null || { echo "FAIL mesh-prep"; exit 1; }
"$B/cutplan" -q plans/bench/cut-beam-16.yaml "$T/beam.msh" -o "$T/cut.edits" || { echo "FAIL cutplan"; exit 1; }
nsteps=$(grep -c '^step ' "$T/cut.edits")

# ---- 1. the stream's end
expect "the full pipe" 0 "" -- bash -c "'$B/cutplan' -q plans/bench/cut-beam-16.yaml '$T/beam.msh' -o - | '$B/augsolve' -q '$T/beam.msh' - -o '$T/full'"
grep -qx "steps: $nsteps" "$T/full/run.yaml" 2>/dev/null && ok "full pipe: run.yaml steps: $nsteps" || bad "full pipe: run.yaml steps"
grep -qx "done $nsteps" "$T/cut.edits" && ok "the stream ends with 'done $nsteps'" || bad "no 'done $nsteps' record"
for k in 1 3 $((nsteps - 1)); do
    # the stream up to the 'end' of step k: every step whole, only the rest missing
    lines=$(grep -n '^end$' "$T/cut.edits" | sed -n "${k}p" | cut -d: -f1)
    for m in planned augmented; do
        rm -rf "$T/cut$k$m"
        expect "pipe cut after step $k of $nsteps ($m)" 2 "found the end of the stream (cut short" -- bash -c \
            "'$B/cutplan' -q plans/bench/cut-beam-16.yaml '$T/beam.msh' -o - | head -n $lines | '$B/augsolve' -q '$T/beam.msh' - -o '$T/cut$k$m' --method $m"
        no_result "cut after step $k ($m)" "$T/cut$k$m"
    done
done
hlines=$(grep -n '^mesh ' "$T/cut.edits" | cut -d: -f1)
expect "header-only stream" 2 "<stdin>:$hlines: expected 'step 1', found the end of the stream (a header alone, cut short" -- bash -c \
    "'$B/cutplan' -q plans/bench/cut-beam-16.yaml '$T/beam.msh' -o - | head -n $hlines | '$B/augsolve' -q '$T/beam.msh' - -o '$T/hdr'"
no_result "header-only stream" "$T/hdr"

# ---- 3. NaN must fail the accuracy checks; non-finite numbers are bad input
sed 's/^force \([0-9]*\) \([^ ]*\) .*/force \1 0 1e308 0/' "$T/cut.edits" >"$T/big.edits"
for m in planned augmented refactor cg pcg-jacobi newton; do
    "$B/augsolve" -q "$T/beam.msh" "$T/big.edits" -o "$T/big-$m" --method $m >/dev/null 2>"$T/err"
    rc=$?
    if [ $rc = 1 ] || [ $rc = 2 ]; then ok "force 1e308, $m: exit $rc ($(head -c 120 "$T/err"))"
    else bad "force 1e308, $m: exit $rc"; fi
    no_result "force 1e308, $m" "$T/big-$m"
done
fl=$(grep -n '^force ' "$T/cut.edits" | head -1 | cut -d: -f1)
for v in nan inf -inf 1e999 0x1p3; do
    awk -v l="$fl" -v v="$v" 'NR == l { $4 = v } { print }' "$T/cut.edits" >"$T/nf.edits"
    col=$(sed -n "${fl}p" "$T/nf.edits" | awk '{ print length($1) + length($2) + length($3) + 4 }')
    expect "force component $v" 2 "nf.edits:$fl:$col: expected a force component in N (a finite number), found $v" -- \
        "$B/augsolve" -q "$T/beam.msh" "$T/nf.edits" -o "$T/nf"
done

# ---- 12. a dup that leaves its node in no tetrahedron
tets=$($PY - "$T/beam.msh" <<'EOF'
import sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
tet = np.vstack([c.data for c in m.cells if c.type == "tetra"])
hold = [i + 1 for i, t in enumerate(tet) if 0 in t]
print(len(hold), *hold)
EOF
)
tets=$(echo "$tets" | tail -n 1) # meshio may print a blank line first
nn=$(grep '^mesh ' "$T/cut.edits" | awk '{ print $(NF-1) }')
{ sed -n "1,${hlines}p" "$T/cut.edits"; printf 'step 1 "orphan"\ndup 1 %d %s\nend\ndone 1\n' $((nn + 1)) "$tets"; } >"$T/orphan.edits"
for m in planned augmented; do
    expect "dup leaving node 1 in no tet ($m)" 2 "step 1.*node 1" -- "$B/augsolve" -q "$T/beam.msh" "$T/orphan.edits" -o "$T/orphan-$m" --method $m
    no_result "orphan dup ($m)" "$T/orphan-$m"
done

# ---- 4. " #", quotes and a newline in every path
D="$T/in #1 \"q\" 'x'"$'\n'"line2"
mkdir -p "$D"
cp plans/bench/beam-16.yaml "$D/beam #2.yaml"
sed 's/^scene: .*/scene: "beam #2.yaml"/' plans/bench/cut-beam-16.yaml >"$D/cut \"beam\" #2.yaml"
printf 'not a scene\n' >"$D/beam" # what " #" cut to a comment would name
expect "mesh-prep into an odd folder" 0 "" -- "$B/mesh-prep" -q "$D/beam #2.yaml" -o "$D/m #.msh"
expect "cutplan, odd paths" 0 "" -- "$B/cutplan" -q "$D/cut \"beam\" #2.yaml" "$D/m #.msh" -o "$D/e #.edits"
expect "augsolve, odd paths" 0 "" -- "$B/augsolve" -q "$D/m #.msh" "$D/e #.edits" -o "$D/run #"
$PY - "$D" <<'EOF' && ok "run.yaml's paths resolve to the odd files" || bad "run.yaml paths"
import os, sys, yaml
d = sys.argv[1]
r = yaml.safe_load(open(os.path.join(d, "run #", "run.yaml")))
want = {"mesh": "m #.msh", "scene": "beam #2.yaml", "plan": 'cut "beam" #2.yaml', "edits": "e #.edits"}
for k, f in want.items():
    got = os.path.join(d, "run #", r[k])
    assert os.path.samefile(got, os.path.join(d, f)), (k, r[k])
EOF

# a path longer than the header's 1023 bytes: refused, not cut to name another file
L=$T/$(printf 'a%.0s' {1..250})/$(printf 'b%.0s' {1..250})/$(printf 'c%.0s' {1..250})/$(printf 'd%.0s' {1..250})
mkdir -p "$L" && cp "$T/beam.msh" "$L/beam.msh"
expect "a mesh path over 1023 bytes" 2 "expected a path of at most 1023 bytes" -- "$B/cutplan" -q plans/bench/cut-beam-16.yaml "$L/beam.msh" -o "$T/long.edits"
[ ! -e "$T/long.edits" ] && ok "long path: no edits written" || bad "long path: edits written"

# ---- 2. one run per folder (a coarse eye, as tests/cutplan_eye.sh makes it)
bash tests/lib/coarse-eye.sh --order 1 0.6 0.3 0.8 2.5 "$T/eye.yaml" || { echo "FAIL could not coarsen the eye"; exit 1; }
cp plans/lri-paired-60.yaml plans/lri-paired-30.yaml "$T/"
"$B/mesh-prep" -q "$T/eye.yaml" -o "$T/eye.msh" >/dev/null || { echo "FAIL eye mesh-prep"; exit 1; }
R="$T/run"
for p in 60 30; do
    "$B/cutplan" -q "$T/lri-paired-$p.yaml" "$T/eye.msh" -o "$T/$p.edits" &&
        "$B/augsolve" -q "$T/eye.msh" "$T/$p.edits" -o "$R" || bad "eye: plan $p"
    [ $p = 60 ] && "$B/curvature" -q --no-png "$R" >/dev/null
done
s30=$(grep -c '^step ' "$T/30.edits")
s60=$(grep -c '^step ' "$T/60.edits")
[ "$s60" -gt "$s30" ] || bad "the 60-degree plan should have more steps ($s60) than the 30 ($s30)"
left=$(cd "$R" && ls | grep -E '^(step|surface|axial)-[0-9]+\.(vtk|png)$' | sed 's/[^0-9]//g' | sort -n | tail -1)
[ "$((10#$left))" = "$s30" ] && ok "re-run into the folder: the last file is step $s30 (not $s60)" ||
    bad "re-run into the folder: files up to $left remain (the run has $s30 steps)"
[ ! -e "$R/report.html" ] && ok "the longer run's report is gone" || bad "the longer run's report.html remains"
expect "curvature on the re-run folder" 0 "" -- "$B/curvature" -q --no-png --json "$R"
rows=$(($(wc -l <"$R/curvature.tsv") - 1))
[ "$rows" = $((s30 + 1)) ] && ok "curvature read steps 0..$s30" || bad "curvature read $rows steps, expected $((s30 + 1))"
cp "$R/step-0001.vtk" "$R/step-$(printf %04d $((s30 + 1))).vtk"
expect "a step file beyond run.yaml's steps" 2 "not a step of this run" -- "$B/curvature" -q --no-png "$R"
rm "$R/step-$(printf %04d $((s30 + 1))).vtk"
expect "curvature --plan of another plan" 2 "not the plan this run was made from" -- "$B/curvature" -q --no-png --plan "$T/lri-paired-60.yaml" "$R"

# ---- 13. plan and argument semantics
expect "curvature --meridian 400" 2 "--meridian 400: expected an angle in \[0, 360)" -- "$B/curvature" -q --no-png --meridian 400 "$R"
expect "curvature --meridian 0x28" 2 "--meridian 0x28" -- "$B/curvature" -q --no-png --meridian 0x28 "$R"
expect "curvature --meridian ' 40'" 2 "--meridian  40" -- "$B/curvature" -q --no-png --meridian " 40" "$R"
expect "augsolve --tol 0x1p-30" 2 "--tol" -- "$B/augsolve" -q "$T/beam.msh" "$T/cut.edits" -o "$T/tol" --tol 0x1p-30
expect "augsolve --steps ' 1'" 2 "--steps" -- "$B/augsolve" -q "$T/beam.msh" "$T/cut.edits" -o "$T/st" --steps " 1"
$PY - "$T/lri-paired-60.yaml" "$T/oz.yaml" <<'EOF'
import sys, yaml
p = yaml.safe_load(open(sys.argv[1]))
for inc in p["incisions"]:
    inc["position"] = {"diameter": "4 mm"}
p["scene"] = "eye.yaml"
yaml.safe_dump(p, open(sys.argv[2], "w"))
EOF
expect "an incision inside the optical zone" 2 "diameter: expected a diameter outside the eye's optical zone" -- \
    "$B/cutplan" -q "$T/oz.yaml" "$T/eye.msh" -o "$T/oz.edits" --mesh-out "$T/oz.msh"
[ ! -e "$T/oz.edits" ] && ok "optical zone: no edits written" || bad "optical zone: edits written"
if man -l man/man5/keratome-plan.5 2>/dev/null | tr -s ' \n' ' ' | grep -q "a fraction in (0, 1) of the local"; then
    ok "keratome-plan(5): depth_fraction in (0, 1), as cutplan checks"
else bad "keratome-plan(5) does not say depth_fraction in (0, 1)"; fi
sed 's/^    depth_fraction: .*/    depth_fraction: 1/' "$T/lri-paired-60.yaml" >"$T/df1.yaml"
expect "depth_fraction 1" 2 "depth_fraction: expected a number in (0, 1)" -- "$B/cutplan" -q "$T/df1.yaml" "$T/eye.msh" -o "$T/df1.edits"

exit $fail
