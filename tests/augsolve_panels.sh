#!/bin/bash
# augsolve_panels.sh BUILD_DIR: the planned factor with the increments' block in panels
# (augsolve --plan-panel, aug_plan.h kt_plan_split_panels) on a coarse prestressed eye (as
# augsolve_prestress.sh makes it), a single 30-degree LRI in 3 steps: with narrow panels
# (--plan-panel 8, many panels) and CHOLMOD's own supernodes (--plan-panel 0), every step agrees
# with a fresh factorization to 1e-10 (--verify), and the two runs' fields agree to 1e-10 of
# the largest displacement at every step (the default width runs in every other augsolve
# test). A bad --plan-panel exits 2.
set -u
build="$1"
tmp=$(mktemp -d /tmp/kt-panels.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$tmp/eye.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
grep -q "incision: 0.5 mm" "$tmp/eye.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 10 deg|' \
    plans/lri-single-30.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || { echo "FAILED: mesh-prep"; exit 1; }
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || { echo "FAILED: cutplan"; exit 1; }
for w in 8 0; do
    if ! "$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/run-$w" --plan-panel "$w" \
            --verify --verify-tol 1e-10 2> "$tmp/err-$w"; then
        echo "FAILED: augsolve --plan-panel $w --verify: $(cat "$tmp/err-$w")"; exit 1
    fi
    grep -q "^method: planned" "$tmp/run-$w/run.yaml" || { echo "FAILED: panels $w: not the planned method"; exit 1; }
done
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/bad" --plan-panel -3 2> /dev/null
[ $? -eq 2 ] || { echo "FAILED: --plan-panel -3 did not exit 2"; exit 1; }
/usr/bin/python3 - "$tmp" <<'PY' || exit 1
import glob, os, sys
tmp = sys.argv[1]
sys.path.insert(0, "tests/lib")
from vtkvec import flat
def field(path):
    u = flat(path)
    if not u: raise SystemExit(f"FAILED: no displacement in {path}")
    return u
steps = sorted(os.path.basename(p) for p in glob.glob(f"{tmp}/run-0/step-*.vtk"))
if len(steps) != 4: raise SystemExit(f"FAILED: {len(steps)} step VTKs (expected 4)")
worst = 0
for s in steps:
    ref = field(f"{tmp}/run-0/{s}")
    scale = max(abs(v) for v in ref) or 1.0
    for w in ("8",):
        u = field(f"{tmp}/run-{w}/{s}")
        d = max(abs(a - b) for a, b in zip(u, ref)) / scale
        if not (len(u) == len(ref) and d <= 1e-10):
            raise SystemExit(f"FAILED: {s}: panels {w} differ from CHOLMOD's supernodes by {d:.3g}")
        worst = max(worst, d)
print(f"largest relative difference between the panel widths: {worst:.2e}")
PY
echo "augsolve_panels: ok"
