#!/bin/bash
# augsolve_heal.sh BUILD_DIR: the healed wound (keratome-scene(5), WOUND; lib/fem/wound.h) through
# the pipeline, on a coarse P2 eye (plans/eye.yaml physics) with paired 60-degree LRIs cut in two
# steps of 30 degrees. Checks that can fail:
#   1. augsolve --verify with the wound healed: the planned method equals a fresh factorization
#      of every step's bridged cut mesh within 1e-10 (steps.tsv verify_rel_diff);
#   2. run.yaml records the wound (state healed, its k) and the last step's VTK carries the
#      cell field bridge (k on the tets of the cut faces, 0 elsewhere; a second reader, meshio);
#   3. the scar closes the wound: curvature's SIA of the healed run is below the immediate one's;
#   4. the derivative of heal = ln k (augsolve --uncertainty, dudp_heal) equals the central
#      difference of two runs at k e^(+-1e-3) to 2e-6 relative at the last step, and the
#      stream methods' derivative (--method refactor: the fresh reference of kt_fem_sens_fresh)
#      equals the planned one to 1e-8.
set -u
build="$1"
tmp=$(mktemp -d /tmp/kt-heal.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
fail() { echo "augsolve_heal: FAILED: $*"; exit 1; }
bash tests/lib/coarse-eye.sh 0.7 0.6 0.9 3 "$tmp/eye.yaml" || fail "could not coarsen the eye"
grep -q "^wound:" "$tmp/eye.yaml" && fail "plans/eye.yaml has a wound: section (the test adds its own)"
k=0.2
healed() { # NAME K: the eye with the wound healed at bridge stiffness K MPa/mm
    cp "$tmp/eye.yaml" "$tmp/$1.yaml"
    printf 'wound:\n  state: healed\n  bridge_stiffness: %s MPa/mm\n' "$2" >> "$tmp/$1.yaml"
}
healed heal $k
healed hp "$(/usr/bin/python3 -c "import math; print(repr($k * math.exp(1e-3)))")"
healed hm "$(/usr/bin/python3 -c "import math; print(repr($k * math.exp(-1e-3)))")"
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 30 deg|' \
    plans/lri-paired-60.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || fail "mesh-prep"
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || fail "cutplan"
aug() { # RUN SCENE [options]
    local run=$1 scene=$2
    shift 2
    "$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" --scene "$tmp/$scene.yaml" -o "$tmp/$run" "$@" \
        2> "$tmp/$run.err" || fail "augsolve $run $*: $(cat "$tmp/$run.err")"
}
aug heal heal --verify --verify-tol 1e-10 --uncertainty
aug imm eye
aug hp hp --steps 2
aug hm hm --steps 2
aug ref heal --method refactor --uncertainty --steps 2
for r in heal imm; do
    "$build/curvature" -q --no-png --no-report "$tmp/$r" > /dev/null 2> "$tmp/$r.curv.err" ||
        fail "curvature $r: $(cat "$tmp/$r.curv.err")"
done
/usr/bin/python3 - "$tmp" "$k" <<'PY' || exit 1
import csv, math, sys
tmp, k = sys.argv[1], float(sys.argv[2])
sys.path.insert(0, "tests/lib")
from vtkvec import point_vectors
import meshio

def fail(msg):
    print("augsolve_heal: FAILED:", msg)
    sys.exit(1)

def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f, delimiter="\t"))

# 1. planned == fresh on every step of the healed run
st = rows(f"{tmp}/heal/steps.tsv")
worst = max(float(r["verify_rel_diff"]) for r in st)
if not (len(st) == 3 and worst <= 1e-10):
    fail(f"--verify: {len(st)} steps, worst planned vs fresh {worst:.3g}")
# 2. provenance and the bridge field
run = open(f"{tmp}/heal/run.yaml").read()
line = [l for l in run.splitlines() if l.strip().startswith("wound:")]
if not line or "state: healed" not in line[0] or f"k_MPa_per_mm: {k:g}," not in line[0]:
    fail(f"run.yaml's wound line: {line}")
m = meshio.read(f"{tmp}/heal/step-0002.vtk")
b = m.cell_data.get("bridge")
if b is None:
    fail("step 2 has no cell field bridge")
vals = set(float(x) for blk in b for x in blk.ravel())
if vals != {0.0, k}:
    fail(f"bridge values {sorted(vals)[:5]} (expected 0 and {k})")
nb = sum(int((blk == k).sum()) for blk in b)
# 3. SIA healed < immediate
def sia(run):
    return float(rows(f"{tmp}/{run}/curvature.tsv")[-1]["sia_D"])
sh, si = sia("heal"), sia("imm")
print(f"augsolve_heal: paired 60 (coarse eye): SIA {si:.3f} D immediate, {sh:.3f} D healed at k {k} MPa/mm; "
      f"{nb} bridged tets; planned vs fresh {worst:.2e}")
if not (0 < sh < si):
    fail(f"SIA healed {sh} not below immediate {si}")
# 4. d u / d ln k against two runs
d = point_vectors(f"{tmp}/heal/step-0002.vtk")
dref = point_vectors(f"{tmp}/ref/step-0002.vtk")
up = point_vectors(f"{tmp}/hp/step-0002.vtk")["displacement"]
um = point_vectors(f"{tmp}/hm/step-0002.vtk")["displacement"]
if "dudp_heal" not in d or "dudp_heal" not in dref:
    fail(f"no dudp_heal field: {sorted(d)}")
an = [c for t in d["dudp_heal"] for c in t]
rf = [c for t in dref["dudp_heal"] for c in t]
fd = [(a - b) / 2e-3 for ta, tb in zip(up, um) for a, b in zip(ta, tb)]
big = max(abs(x) for x in fd)
rel = max(abs(a - b) for a, b in zip(an, fd)) / big
rel_ref = max(abs(a - b) for a, b in zip(an, rf)) / big
print(f"augsolve_heal: du/dln k at step 2: max {big:.4g} mm, vs two runs {rel:.2e}, planned vs refactor {rel_ref:.2e}")
if not (big > 0 and rel <= 2e-6 and rel_ref <= 1e-8):
    fail(f"dudp_heal: vs central difference {rel:.3g} (> 2e-6) or planned vs refactor {rel_ref:.3g} (> 1e-8)")
tsv = rows(f"{tmp}/heal/uncertainty.tsv")
h = [r for r in tsv if r.get("param", r.get(list(r)[0])) == "heal"]
if not h:
    fail("uncertainty.tsv has no heal row")
print("augsolve_heal: passed")
PY
