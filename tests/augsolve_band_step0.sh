#!/bin/bash
# augsolve_band_step0.sh BUILD_DIR: augsolve --uncertainty does not solve for the derivatives of
# step 0 of a prestressed scene; it writes zeros (augsolve(1), First-order uncertainty). The
# claim: the intact eye's field is zero for every value of every quantity (its right-hand side
# is the pressure minus the internal forces of the prestress that this very pressure causes in
# this geometry), so its derivatives are zero exactly. Checks that can fail, on a coarse P2 eye
# (plans/eye.yaml physics), a single 30-degree LRI in 2 steps:
#   1. the --uncertainty run's step-0 dudp_<q> fields are zero and its step-1 fields are not;
#   2. the claim itself, with two more runs per quantity (no --uncertainty: each solves its own
#      prestress and step 0 in full) at iop and E_inplane +-10%: each run's step-0 field is zero
#      to rounding (< 1e-9 mm), and the central difference of the two at step 0 is below 1e-6
#      of the step-1 derivative (at step 1 the same runs move by 1e-2 or more of it);
#   3. the guard: the same scene with loads.reference loaded (no prestress: step 0 moves) gets
#      its step-0 derivative solved: dudp_iop at step 0 is not zero and agrees with the central
#      difference of two runs at iop +-0.1% to 1e-4 relative.
set -u
build="$1"
tmp=$(mktemp -d /tmp/kt-band-step0.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
fail() { echo "augsolve_band_step0: FAILED: $*"; exit 1; }
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$tmp/eye.yaml" || fail "could not coarsen the eye"
grep -q "reference: prestressed" "$tmp/eye.yaml" || fail "eye.yaml is not prestressed"
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 15 deg|' \
    plans/lri-single-30.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || fail "mesh-prep"
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || fail "cutplan"
aug() { # RUN SCENE [options]
    local run=$1 scene=$2
    shift 2
    "$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" --scene "$scene" -o "$tmp/$run" --steps 1 "$@" \
        2> "$tmp/$run.err" || fail "augsolve $run $*: $(cat "$tmp/$run.err")"
}
variant() { # NAME SCENE SED
    sed -e "$3" "$2" > "$tmp/$1.yaml"
    cmp -s "$2" "$tmp/$1.yaml" && fail "variant $1 did not change the scene"
    aug "$1" "$tmp/$1.yaml"
}
aug base "$tmp/eye.yaml" --uncertainty
variant Ip "$tmp/eye.yaml" 's/value: 15 mmHg/value: 16.5 mmHg/'
variant Im "$tmp/eye.yaml" 's/value: 15 mmHg/value: 13.5 mmHg/'
variant Ep "$tmp/eye.yaml" 's/E_inplane: 2.0 MPa/E_inplane: 2.2 MPa/g'
variant Em "$tmp/eye.yaml" 's/E_inplane: 2.0 MPa/E_inplane: 1.8 MPa/g'
sed -e 's/^  reference: prestressed/  reference: loaded/' "$tmp/eye.yaml" > "$tmp/loaded.yaml"
grep -q "^  reference: loaded" "$tmp/loaded.yaml" || fail "could not make the loaded scene"
aug loaded "$tmp/loaded.yaml" --uncertainty
variant Lp "$tmp/loaded.yaml" 's/value: 15 mmHg/value: 15.015 mmHg/'
variant Lm "$tmp/loaded.yaml" 's/value: 15 mmHg/value: 14.985 mmHg/'
python3 - "$tmp" <<'PY' || exit 1
import sys
tmp = sys.argv[1]

sys.path.insert(0, "tests/lib")
from vtkvec import point_vectors

def read_vtk(path):
    """name -> flat list of floats"""
    return {k: [c for t in v for c in t] for k, v in point_vectors(path).items()}

def fail(msg):
    print("augsolve_band_step0: FAILED:", msg)
    sys.exit(1)

def step(run, s):
    return read_vtk(f"{tmp}/{run}/step-{s:04d}.vtk")

base0, base1 = step("base", 0), step("base", 1)
qs = [k[5:] for k in base0 if k.startswith("dudp_")]
if sorted(qs) != sorted(["E_inplane", "G_transverse", "iop", "limbal_density"]):
    fail(f"step 0's derivative fields: {qs}")
# 1. written zeros at step 0, a derivative at step 1
for q in qs:
    if any(x != 0 for x in base0["dudp_" + q]):
        fail(f"step 0: dudp_{q} is not zero")
    if not max(abs(x) for x in base1["dudp_" + q]) > 0:
        fail(f"step 1: dudp_{q} is zero")
# 2. the claim: u(step 0) = 0 whatever q, by two runs each side
for q, p, m, dh in (("iop", "Ip", "Im", 3.0), ("E_inplane", "Ep", "Em", 0.4)):
    u0p, u0m = step(p, 0)["displacement"], step(m, 0)["displacement"]
    big0 = max(abs(x) for x in u0p + u0m)
    if not big0 < 1e-9:
        fail(f"{q} +-10%: step 0 moves by {big0:.3g} mm")
    d1 = max(abs(x) for x in base1["dudp_" + q])
    fd0 = max(abs(a - b) / dh for a, b in zip(u0p, u0m))
    fd1 = max(abs(a - b) / dh for a, b in zip(step(p, 1)["displacement"], step(m, 1)["displacement"]))
    print(f"augsolve_band_step0: d/d{q} at step 0 by two runs: {fd0:.3g} mm per unit "
          f"(step 1's derivative {d1:.4g}, the same runs' difference at step 1 {fd1:.4g})")
    if not (fd0 <= 1e-6 * d1 and fd1 >= 1e-2 * d1):
        fail(f"d/d{q} at step 0 by two runs {fd0:.3g} against step 1's {d1:.3g} (their step 1 {fd1:.3g})")
# 3. without prestress step 0 moves, and its derivative is solved
l0 = step("loaded", 0)
d = l0["dudp_iop"]
fd = [(a - b) / 0.03 for a, b in zip(step("Lp", 0)["displacement"], step("Lm", 0)["displacement"])]
big = max(abs(x) for x in fd)
rel = max(abs(a - b) for a, b in zip(d, fd)) / big if big > 0 else float("nan")
print(f"augsolve_band_step0: reference loaded, step 0: dudp_iop max {max(abs(x) for x in d):.4g}, "
      f"two runs {big:.4g} mm per mmHg, relative difference {rel:.2e}")
if not (big > 0 and rel <= 1e-4):
    fail(f"reference loaded: step 0's dudp_iop and the two runs differ by {rel:.3g} (> 1e-4)")
print("augsolve_band_step0: passed")
PY
