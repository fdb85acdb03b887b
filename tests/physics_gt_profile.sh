#!/bin/bash
# physics_gt_profile.sh BUILD_DIR: the depth profile of the transverse shear modulus
# (materials.cornea.G_transverse_profile, keratome-scene(5), MATERIALS). A coarse P2 default eye
# with the profile on (the Petsche 2012 thirds) in the cornea only, a single 30-degree LRI in one
# step. A second reader (meshio) reads step 0's CELL_DATA and checks against a recomputation that
# does not use keratome's depth rule: each cornea tet's relative depth is its centroid's distance
# to the anterior surface over the sum of its distances to the anterior and the inner (posterior)
# surface, both taken from the mesh's own surface triangles (the plane of the triangle with the
# nearest centroid). Checks: every cornea tet's G_transverse is one of the three values
# G_transverse x (7.71, 1.99, 1.31) / H (H their harmonic mean: the layers in series keep
# G_transverse), each of them occurs, their harmonic mean is G_transverse; every tet whose
# independent depth is clear of the thirds' boundaries (by 0.06 of the thickness) has its
# third's value; the limbus keeps G_transverse and the sclera its isotropic E / 2 (1 + nu); the
# profile moves the cut's answer (the last step's displacement differs from the run without it).
# Bad values of the field are refused with file:line:col (exit 2).
set -u
build="$1"
PY=/usr/bin/python3 # Debian's interpreter: the one that sees numpy and meshio
$PY -c 'import meshio, numpy' 2>/dev/null || { echo "FAILED: meshio/numpy not importable by $PY"; exit 1; }
tmp=$(mktemp -d /tmp/kt-gtprof.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$tmp/flat.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
sed -e 's/^    G_transverse: 9.5 kPa /    G_transverse: 9.5 kPa\n    G_transverse_profile: on/' "$tmp/flat.yaml" > "$tmp/eye.yaml"
grep -q "incision: 0.5 mm" "$tmp/eye.yaml" && grep -q "^    G_transverse_profile: on" "$tmp/eye.yaml" ||
    { echo "FAILED: could not coarsen the eye or set the profile"; exit 1; }

# bad values: file:line:col, exit 2
fails=0
bad() { # SED_EXPR EXPECTED_TEXT
    sed -e "s/^    G_transverse_profile: on/    G_transverse_profile: $1/" "$tmp/eye.yaml" > "$tmp/bad.yaml"
    "$build/mesh-prep" -q "$tmp/bad.yaml" -o "$tmp/bad.msh" > /dev/null 2> "$tmp/bad.err"
    rc=$?
    if [ $rc -ne 2 ] || ! grep -q "bad.yaml:[0-9]*:[0-9]*: .*$2" "$tmp/bad.err" || [ -e "$tmp/bad.msh" ]; then
        echo "FAILED: G_transverse_profile: $1: exit $rc, $(cat "$tmp/bad.err")"; fails=1
    fi
}
bad "maybe" "expected off, on or a list of three moduli"
bad "[7.71 kPa, 1.99 kPa]" "G_transverse_profile"
bad "[7.71 kPa, 1.99 kPa, -1 kPa]" "G_transverse_profile"
bad "[7.71, 1.99, 1.31]" "G_transverse_profile"
[ $fails = 0 ] || exit 1

sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 30 deg|' \
    plans/lri-single-30.yaml > "$tmp/plan.yaml"
sed -e "s|^scene:.*|scene: $tmp/flat.yaml|" "$tmp/plan.yaml" > "$tmp/plan-flat.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || { echo "FAILED: mesh-prep"; exit 1; }
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || { echo "FAILED: cutplan"; exit 1; }
"$build/cutplan" -q "$tmp/plan-flat.yaml" "$tmp/eye.msh" -o "$tmp/flat.edits" || { echo "FAILED: cutplan (flat)"; exit 1; }
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/run" 2> "$tmp/err" || { echo "FAILED: augsolve: $(cat "$tmp/err")"; exit 1; }
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/flat.edits" -o "$tmp/flat" 2> "$tmp/err" || { echo "FAILED: augsolve (flat): $(cat "$tmp/err")"; exit 1; }
grep -q "G_transverse_profile_MPa: \[0.00771, 0.00199, 0.00131\]" "$tmp/run/run.yaml" ||
    { echo "FAILED: run.yaml does not record the profile"; exit 1; }
$PY - "$tmp" <<'PY' || exit 1
import math, sys
import meshio, numpy as np

tmp = sys.argv[1]
errs = []
def check(ok, what):
    if not ok: errs.append(what)

G, E_s, nu_s = 9.5e-3, 3.0, 0.49               # MPa: plans/eye.yaml's G_transverse, sclera
third = np.array([7.71, 1.99, 1.31])            # Petsche 2012, kPa (only the ratios matter)
H = 3 / np.sum(1 / third)
want = G * third / H                            # anterior, middle, posterior

msh = meshio.read(f"{tmp}/eye.msh")
names = {v[0]: k for k, v in msh.field_data.items() if v[1] == 2}   # surface tag -> name
tri = {"anterior": [], "inner": []}
for cb, tags in zip(msh.cells, msh.cell_data["gmsh:physical"]):
    if cb.type.startswith("triangle"):
        for t, c in zip(tags, cb.data):
            if names.get(int(t)) in tri: tri[names[int(t)]].append(c[:3])
surf = {}
for k, c in tri.items():
    c = np.array(c)
    p = msh.points[c]
    nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    surf[k] = (p.mean(axis=1), nrm / np.linalg.norm(nrm, axis=1)[:, None])
check(len(tri["anterior"]) > 50 and len(tri["inner"]) > 50, "anterior/inner triangles missing")

def dist(pts, k):
    cen, nrm = surf[k]
    out = np.empty(len(pts))
    for i, p in enumerate(pts):
        j = np.argmin(np.sum((cen - p) ** 2, axis=1))
        out[i] = abs(np.dot(p - cen[j], nrm[j]))
    return out

v = meshio.read(f"{tmp}/run/step-0000.vtk")
tets = [cb.data for cb in v.cells if cb.type in ("tetra10", "tetra")][0]
reg = np.asarray(v.cell_data["region"][0]).reshape(-1).astype(int)
gt = np.asarray(v.cell_data["G_transverse"][0]).reshape(-1)
rtag = {n: v[0] for n, v in msh.field_data.items() if v[1] == 3}
pc = v.points[tets[:, :4]].mean(axis=1)
rho = np.hypot(pc[:, 0], pc[:, 1])

cor = np.flatnonzero(reg == rtag["cornea"])
rel = np.abs(gt[cor][:, None] - want[None, :]) / want[None, :]
check(np.all(np.min(rel, axis=1) <= 1e-12), f"cornea G_transverse outside the three thirds' values "
      f"({np.count_nonzero(np.min(rel, axis=1) > 1e-12)} tets)")
counts = [int(np.count_nonzero(rel[:, k] <= 1e-12)) for k in range(3)]
check(min(counts) > 0, f"a third has no tets: {counts}")
vals = np.unique(np.round(gt[cor], 15))
check(len(vals) == 3 and abs(3 / np.sum(1 / vals) - G) <= 1e-12 * G,
      f"harmonic mean of the cornea's values {vals} is not {G}")
# independent depth, away from the corneal edge (where the anterior group ends)
ids = cor[rho[cor] < 4.5]
da, dp = dist(pc[ids], "anterior"), dist(pc[ids], "inner")
s = da / (da + dp)
clear = (np.abs(s - 1 / 3) > 0.06) & (np.abs(s - 2 / 3) > 0.06)
exp = want[np.where(s < 1 / 3, 0, np.where(s < 2 / 3, 1, 2))]
bad = np.flatnonzero(clear & (np.abs(gt[ids] - exp) > 1e-12 * exp))
check(np.count_nonzero(clear) >= 100, f"only {np.count_nonzero(clear)} tets clear of the boundaries")
check(len(bad) == 0, f"{len(bad)} of {np.count_nonzero(clear)} tets not in their third's value "
      f"(e.g. depth {s[bad[:3]]}, G {gt[ids][bad[:3]]})")
lim = reg == rtag["limbus"]
check(np.all(np.abs(gt[lim] - G) <= 1e-12 * G), "limbus G_transverse is not the uniform value")
scl = reg == rtag["sclera"]
check(np.all(np.abs(gt[scl] - E_s / (2 * (1 + nu_s))) <= 1e-12), "sclera G is not E / 2 (1 + nu)")

def last_u(run):
    import glob
    f = sorted(glob.glob(f"{run}/step-*.vtk"))[-1]
    return np.asarray(meshio.read(f).point_data["displacement"])
up, uf = last_u(f"{tmp}/run"), last_u(f"{tmp}/flat")
gap = np.linalg.norm(up - uf) / np.linalg.norm(uf)
check(math.isfinite(gap) and gap > 1e-3, f"the profile did not change the cut's field (gap {gap:.3g})")
print(f"gt_profile: cornea tets per third {counts}, G {want * 1e3} kPa; independent depth: "
      f"{np.count_nonzero(clear)} tets checked; field gap with/without {gap:.3f}")
if errs:
    print("FAILED: " + "; ".join(errs[:8])); sys.exit(1)
PY
echo "physics_gt_profile: ok"
