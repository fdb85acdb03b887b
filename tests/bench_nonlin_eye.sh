#!/bin/bash
# bench_nonlin_eye.sh BUILD_DIR: the nonlinear reference on the prestressed eye (plans/eye.yaml
# physics), coarse P1 mesh, a single 30-degree LRI in 3 steps, through bench_nonlin. Checks:
#   - its linear column (one full step of the total Lagrangian assembly from the prestressed
#     state) is augsolve's answer (default planned method) at the last step to 1e-8 relative
#     (max norm), and not zero: the nonlinear reference starts from keratome's linearization;
#   - the Newton reference converged (exit 0, at least one iteration per increment) and its
#     field differs from the linear one by a small, non-zero amount (1e-4 to 10% relative, the
#     L2 gap bench_nonlin prints), with SIAs that are positive and within 20% of each other.
set -u
build="$1"
for t in mesh-prep cutplan augsolve bench_nonlin; do
    [ -x "$build/$t" ] || { echo "SKIP: $build/$t not built"; exit 77; }
done
tmp=$(mktemp -d /tmp/kt-bnonlin.XXXXXX)
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
"$build/bench_nonlin" "$tmp/eye.msh" "$tmp/eye.yaml" "$tmp/lri.edits" --increments 2 \
    --field "$tmp/u" > "$tmp/nl.tsv" 2> "$tmp/err" ||
    { echo "FAILED: bench_nonlin: $(cat "$tmp/err")"; exit 1; }
last=$(ls "$tmp"/run/step-*.vtk | tail -n 1)
python3 - "$tmp" "$last" <<'PY' || exit 1
import math, sys
tmp, last = sys.argv[1], sys.argv[2]
sys.path.insert(0, "tests/lib")
from vtkvec import flat as vtk_u
def txt_u(path):
    return [float(x) for x in open(path).read().split()]
errs = []
a, lin, nl = vtk_u(last), txt_u(f"{tmp}/u-linear.txt"), txt_u(f"{tmp}/u-newton.txt")
if not a or len(a) != len(lin) or len(nl) != len(lin):
    print(f"FAILED: field sizes augsolve {len(a)}, linear {len(lin)}, newton {len(nl)}"); sys.exit(1)
big = max(abs(y) for y in a)
r = max(abs(x - y) for x, y in zip(lin, a)) / big if big > 0 else float("inf")
if not big > 1e-6: errs.append(f"augsolve's last step has no displacement ({big:g} mm)")
if not r <= 1e-8: errs.append(f"linear column differs from augsolve's by {r:.3g} (> 1e-8)")
gap = math.sqrt(sum((x - y) ** 2 for x, y in zip(nl, lin)) / sum(y * y for y in lin))
if not 1e-4 <= gap <= 0.1: errs.append(f"newton - linear gap {gap:.3g} (expected 1e-4 to 0.1)")
rows = [l.rstrip("\n").split("\t") for l in open(f"{tmp}/nl.tsv") if not l.startswith("#")]
c = {k: i for i, k in enumerate(rows[0])}
got = {r[c["method"]]: r for r in rows[1:]}
if set(got) != {"linear", "newton"}: errs.append(f"methods {sorted(got)}")
else:
    s_l, s_n = float(got["linear"][c["sia_D"]]), float(got["newton"][c["sia_D"]])
    its, inc = int(got["newton"][c["iterations"]]), int(got["newton"][c["increments"]])
    if not (s_l > 0 and s_n > 0 and abs(s_n - s_l) <= 0.2 * s_l):
        errs.append(f"SIA linear {s_l} newton {s_n}")
    if not (inc >= 2 and its >= inc): errs.append(f"newton: {its} iterations, {inc} increments")
print(f"bench_nonlin: linear vs augsolve {r:.2e} (max norm), newton vs linear {gap:.2e} (L2)")
if errs:
    print("FAILED: " + "; ".join(errs)); sys.exit(1)
PY
echo "bench_nonlin_eye: ok"
