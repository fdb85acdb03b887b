#!/bin/bash
# bench_steps_eye.sh BUILD_DIR: bench_steps (the benchmarks' stepper) solves the same problem as
# augsolve on the prestressed eye (plans/eye.yaml physics: lamellar cornea and limbus, linearized
# about the measured geometry under IOP; kt_physics_problem), on a coarse P1 mesh (15k nodes)
# under a single 30-degree LRI in 3 steps. Checks, per step's field (bench_steps --field,
# augsolve's step VTK):
#   - step 0 (the intact eye, prestressed: at rest) has no displacement in either tool;
#   - bench_steps --method refactor agrees with augsolve's default (planned) method to 1e-8
#     relative (max norm) at the last step, whose field is not zero (the cut moves the cornea);
#   - bench_steps --method pcg-jacobi (steps 0 and 1: 8,000 iterations a step here) runs
#     without a set-up error (its isotropic fallback once stopped it with "Young's modulus
#     0 MPa") and agrees with augsolve's step 1 to 1e-6 at its default --tol 1e-10.
set -u
build="$1"
for t in mesh-prep cutplan augsolve bench_steps; do
    [ -x "$build/$t" ] || { echo "SKIP: $build/$t not built"; exit 77; }
done
tmp=$(mktemp -d /tmp/kt-bsteps.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh --order 1 0.7 0.5 0.9 3 "$tmp/eye.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
grep -q "reference: prestressed" "$tmp/eye.yaml" || { echo "FAILED: eye.yaml is not prestressed"; exit 1; }
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 10 deg|' \
    plans/lri-single-30.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || { echo "FAILED: mesh-prep"; exit 1; }
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || { echo "FAILED: cutplan"; exit 1; }
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/run" 2> "$tmp/err" ||
    { echo "FAILED: augsolve: $(cat "$tmp/err")"; exit 1; }
last=$(ls "$tmp"/run/step-*.vtk | tail -n 1)
last=${last##*step-}
for m in refactor pcg-jacobi; do
    steps=1000000
    [ $m = pcg-jacobi ] && steps=1
    "$build/bench_steps" "$tmp/eye.msh" "$tmp/lri.edits" --method "$m" --max-steps $steps \
        --field "$tmp/$m" > "$tmp/$m.tsv" 2> "$tmp/err" ||
        { echo "FAILED: bench_steps --method $m: $(cat "$tmp/err")"; exit 1; }
done
python3 - "$tmp" "${last%.vtk}" <<'PY' || exit 1
import sys
tmp, last = sys.argv[1], sys.argv[2]
sys.path.insert(0, "tests/lib")
from vtkvec import flat as vtk_u
def txt_u(path):
    return [float(x) for x in open(path).read().split()]
def rel(a, b):
    if len(a) != len(b) or not a: return float("inf")
    return max(abs(x - y) for x, y in zip(a, b)) / max(abs(y) for y in b)
errs, out = [], []
a0 = vtk_u(f"{tmp}/run/step-0000.vtk")
if not a0 or max(abs(x) for x in a0) > 1e-9: errs.append("augsolve's step 0 moves (or is unread)")
for m, step, tol in (("refactor", int(last), 1e-8), ("pcg-jacobi", 1, 1e-6)):
    rows = [l.rstrip("\n").split("\t") for l in open(f"{tmp}/{m}.tsv")]
    c = {k: i for i, k in enumerate(rows[0])}
    st = [r[c["status"]] for r in rows[1:]]
    if st != ["ok"] * (step + 1): errs.append(f"{m}: statuses {st} (expected {step + 1} steps ok)")
    # step 0: the prestressed intact eye is at rest (no displacement) in both
    d0 = max(abs(x) for x in txt_u(f"{tmp}/{m}-0000.txt") + [0])
    if d0 > 1e-9: errs.append(f"{m}: step 0 |u| {d0:.3g} mm (expected 0)")
    a = vtk_u(f"{tmp}/run/step-{step:04d}.vtk")
    if not a or max(abs(x) for x in a) < 1e-6: errs.append(f"augsolve's step {step} has no displacement")
    r = rel(txt_u(f"{tmp}/{m}-{step:04d}.txt"), a)
    t = sum(float(x[c["t_total_ms"]]) for x in rows[1:])
    out.append(f"{m} step {step} {r:.2e} ({t / 1e3:.1f} s)")
    if not r <= tol: errs.append(f"{m}: step {step} differs from augsolve's by {r:.3g} (> {tol:g})")
print("bench_steps against augsolve (relative, max norm): " + ", ".join(out))
if errs:
    print("FAILED: " + "; ".join(errs)); sys.exit(1)
PY
echo "bench_steps_eye: ok"
