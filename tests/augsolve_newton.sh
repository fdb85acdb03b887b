#!/usr/bin/env bash
# augsolve_newton.sh BUILD_DIR: augsolve --method newton (the geometrically nonlinear reference
# behind the front door, augsolve(1)) on a coarse P1 prestressed eye (plans/eye.yaml physics,
# as in bench_nonlin_eye.sh) and a single 30-degree LRI in 3 steps (steps 0 and 3 solved):
#   - at a small load (IOP 1 mmHg, the moduli five times the defaults: load over stiffness
#     1/75 of the default eye's; the scene's plausibility range stops IOP at 1 mmHg) its step
#     VTKs read with meshio and its displacement equals --method planned's to 1e-3 relative
#     (max norm; step 0: both zero to 1e-9 mm);
#   - at full load (15 mmHg, default moduli), with --output anterior, it differs from planned's
#     on the anterior surface by a measurable amount (printed; 10 times the small load's at
#     least: the gap grows with the load, as a geometric nonlinearity does), its NaN mask is
#     planned's with --output anterior, and steps.tsv holds Newton iterations and a converged
#     relative residual; run.yaml names the method;
#   - --verify with --method newton exits 2 before anything is solved (no steps.tsv), and so
#     does --output with a set the mesh lacks.
# Every check fails on NaN.
set -uo pipefail
B=${1:?build dir}
for t in mesh-prep cutplan augsolve; do
    [ -x "$B/$t" ] || { echo "skip: $B/$t not built"; exit 77; }
done
/usr/bin/python3 -c 'import meshio' 2>/dev/null || { echo "skip: no python3 meshio"; exit 77; }
T=$(mktemp -d /tmp/augsolve_newton.XXXXXX)
trap 'rm -rf "$T"' EXIT
printf 'leak:libgmsh.so\n' > "$T/lsan.supp"
export LSAN_OPTIONS="suppressions=$T/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh --order 1 0.7 0.5 0.9 3 "$T/eye.yaml" ||
    { echo "FAIL: could not coarsen the eye"; exit 1; }
sed -e 's/^\(  pressure: {surface: inner, value: \)15 mmHg}/\11 mmHg}/' \
    -e 's/E_inplane: 2.0 MPa/E_inplane: 10 MPa/g' -e 's/G_transverse: 9.5 kPa/G_transverse: 47.5 kPa/g' \
    -e 's/sclera: {E: 3.0 MPa, nu: 0.49}/sclera: {E: 15 MPa, nu: 0.49}/' "$T/eye.yaml" > "$T/small.yaml"
grep -q "^order: 1 " "$T/eye.yaml" && grep -q "reference: prestressed" "$T/eye.yaml" &&
    [ "$(diff "$T/eye.yaml" "$T/small.yaml" | grep -c '^>')" = 5 ] ||
    { echo "FAIL: could not derive the coarse and the small-load eye from plans/eye.yaml"; exit 1; }
sed -e "s|^scene:.*|scene: $T/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 10 deg|' \
    plans/lri-single-30.yaml > "$T/plan.yaml"
"$B/mesh-prep" -q "$T/eye.yaml" -o "$T/eye.msh" > /dev/null || { echo "FAIL: mesh-prep"; exit 1; }
"$B/cutplan" -q "$T/plan.yaml" "$T/eye.msh" -o "$T/lri.edits" || { echo "FAIL: cutplan"; exit 1; }
fail=0
run() { # run NAME METHOD [augsolve options]
    local name=$1 method=$2; shift 2
    "$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/$name" --method "$method" --steps 3 -q "$@" \
        2> "$T/err" || { echo "FAIL $name: $(cat "$T/err")"; fail=1; }
}
run small-planned planned --scene "$T/small.yaml"
run small-newton newton --scene "$T/small.yaml"
run full-planned planned
run ant-planned planned --output anterior
run ant-newton newton --output anterior
"$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/verify" --method newton --verify -q 2> "$T/err"
rc=$?
if [ $rc = 2 ] && grep -q -- "--verify" "$T/err" && [ ! -e "$T/verify/steps.tsv" ]; then
    echo "ok   --method newton --verify exits 2: $(cat "$T/err")"
else echo "FAIL --method newton --verify: exit $rc, $(cat "$T/err")"; fail=1; fi
"$B/augsolve" "$T/eye.msh" "$T/lri.edits" -o "$T/noset" --method newton --output nosuchset -q 2> "$T/err"
rc=$?
if [ $rc = 2 ] && grep -q nosuchset "$T/err" && [ ! -e "$T/noset/steps.tsv" ]; then
    echo "ok   --method newton --output nosuchset exits 2"
else echo "FAIL --method newton --output nosuchset: exit $rc, $(cat "$T/err")"; fail=1; fi
[ $fail = 0 ] || exit 1
/usr/bin/python3 - "$T" <<'EOF' || fail=1
import sys
import meshio, numpy as np
T = sys.argv[1]
bad = []
def u(run, k):
    return np.asarray(meshio.read(f"{T}/{run}/step-{k:04d}.vtk").point_data["displacement"])
def rel(a, b, on=None):  # max |a - b| / max |b| over the rows on (NaN stays NaN)
    if on is not None: a, b = a[on], b[on]
    big = np.abs(b).max()
    return np.abs(a - b).max() / big if big > 0 else float("nan")
# the small load
d0 = np.abs(u("small-newton", 0) - u("small-planned", 0)).max()
if not d0 <= 1e-9: bad.append(f"small load, step 0: newton and planned differ by {d0:g} mm")
small = rel(u("small-newton", 3), u("small-planned", 3))
if not small <= 1e-3: bad.append(f"small load, step 3: newton - planned {small:.3g} (> 1e-3)")
# the full load on the anterior surface
full = u("full-planned", 3)
a_n, a_p = u("ant-newton", 3), u("ant-planned", 3)
on_n, on_p = ~np.isnan(a_n).any(axis=1), ~np.isnan(a_p).any(axis=1)
if not (np.isnan(a_n).all(axis=1) | on_n).all() or not on_n.any() or on_n.all():
    bad.append(f"--output anterior: {on_n.sum()} of {len(on_n)} nodes on the set")
for k in (0, 3):
    m_n = ~np.isnan(u("ant-newton", k)).any(axis=1)
    m_p = ~np.isnan(u("ant-planned", k)).any(axis=1)
    if not np.array_equal(m_n, m_p): bad.append(f"step {k}: newton's NaN mask differs from planned's")
gap = rel(a_n, full, on_n)
if not 1e-3 <= gap <= 0.2: bad.append(f"full load: newton - planned {gap:.3g} on the anterior surface "
                                      "(expected 1e-3 to 0.2)")
if not gap >= 10 * small: bad.append(f"full-load gap {gap:.3g} not 10x the small load's {small:.3g}")
# steps.tsv and run.yaml
rows = [l.rstrip("\n").split("\t") for l in open(f"{T}/ant-newton/steps.tsv")]
c = {k: i for i, k in enumerate(rows[0])}
last = {k: rows[-1][i] for k, i in c.items()}
if [r[0] for r in rows[1:]] != ["0", "3"]: bad.append(f"steps.tsv steps {[r[0] for r in rows[1:]]}")
elif not (int(last["iters"]) >= 1 and float(last["rel_residual"]) <= 1e-10
          and float(last["t_total_ms"]) > 0):
    bad.append(f"steps.tsv step 3: {last}")
if "method: newton\n" not in open(f"{T}/ant-newton/run.yaml").read():
    bad.append("run.yaml does not name method newton")
print(f"augsolve --method newton: step 3 vs planned (max norm, relative): {small:.3e} at "
      f"IOP 1 mmHg and 5x moduli, {gap:.3e} at 15 mmHg on the anterior surface; "
      f"{last['iters']} Newton iterations, residual {last['rel_residual']}")
if bad:
    print("FAIL: " + "; ".join(bad)); sys.exit(1)
EOF
[ $fail = 0 ] || exit 1
echo "augsolve_newton: ok"
