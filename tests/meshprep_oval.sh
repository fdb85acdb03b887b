#!/usr/bin/env bash
# meshprep_oval.sh BUILD_DIR: the oval cornea through the pipeline (keratome-scene(5), THE OVAL
# CORNEA). A coarse version of the default eye (plans/eye.yaml: white_to_white 11.7 x 10.6 mm)
# and the same eye round (vertical 11.7 mm) are meshed; a second reader (Python, meshio) checks
# that the corneal edge (the anterior surface's rim) lies on the white-to-white ellipse and the
# incision ring's top on the ellipse of semi-axes 5.25 and 5.25 - 0.55 mm (the same distance
# inside the edge in every meridian), and that the anterior surface's nodes in the optical zone
# (7 mm, where keratometry is read) are the round eye's, coordinate for coordinate. Then the
# demo's paired 60 deg arcs, cut in one step, through augsolve and curvature on both: the
# pre-operative keratometry (step 0) of the oval eye is the round eye's within 0.01 D (and the
# scene's 44.02 / 42.52 D @ 90 within 0.01 D), and the cut's SIA differs between the two (the
# oval reaches the solve: the vertical arcs lie 0.55 mm further in, on a shorter chord). An arc at
# a diameter with no ring is snapped onto the elliptic cylinder of the oval: the vertices cutplan
# moved lie on it.
set -uo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-oval.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh 0.8 0.4 1.0 2.5 "$tmp/oval.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
grep -q '^    vertical: 10.6 mm' "$tmp/oval.yaml" || { echo "FAILED: plans/eye.yaml has no vertical white-to-white line"; exit 1; }
sed 's|^    vertical: 10.6 mm|    vertical: 11.7 mm|' "$tmp/oval.yaml" > "$tmp/round.yaml"
for v in oval round; do
    "$B/mesh-prep" -q "$tmp/$v.yaml" -o "$tmp/$v.msh" > /dev/null 2> "$tmp/err" || { echo "FAILED: mesh-prep $v: $(cat "$tmp/err")"; exit 1; }
    sed -e "s|^scene:.*|scene: $tmp/$v.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 60 deg|' plans/lri-paired-60.yaml > "$tmp/$v-plan.yaml"
    ("$B/cutplan" -q "$tmp/$v-plan.yaml" "$tmp/$v.msh" -o - | "$B/augsolve" -q "$tmp/$v.msh" - -o "$tmp/$v" &&
     "$B/curvature" -q --no-png --no-report "$tmp/$v" > /dev/null) 2> "$tmp/err" || { echo "FAILED: the pipeline on the $v eye: $(cat "$tmp/err")"; exit 1; }
done
# an arc at a diameter with no ring: snapped onto the elliptic cylinder of the oval (10 mm:
# semi-axes 5 and 4.45 mm)
sed -e "s|^scene:.*|scene: $tmp/oval.yaml|" -e 's|diameter: 9.5 mm|diameter: 10 mm|' plans/lri-paired-60-snapped.yaml > "$tmp/snap.yaml"
grep -q 'diameter: 10 mm' "$tmp/snap.yaml" || { echo "FAILED: plans/lri-paired-60-snapped.yaml has no 9.5 mm diameter"; exit 1; }
"$B/cutplan" -q "$tmp/snap.yaml" "$tmp/oval.msh" -o "$tmp/snap.edits" --mesh-out "$tmp/snap.msh" 2> "$tmp/err" ||
    { echo "FAILED: cutplan, the snapped arc: $(cat "$tmp/err")"; exit 1; }
"$py" - "$tmp" <<'PY'
import math, sys
import meshio, numpy as np
tmp = sys.argv[1]
fails = []
def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond: fails.append(what)
def nodes(m, name):
    tag = m.field_data[name][0]
    out = [b.data[p == tag] for b, p in zip(m.cells, m.cell_data["gmsh:physical"]) if b.type.startswith("triangle")]
    return np.unique(np.vstack(out))
def ellipse(a, b, t): return a * b / np.hypot(b * np.cos(t), a * np.sin(t))
mo, mr = meshio.read(f"{tmp}/oval.msh"), meshio.read(f"{tmp}/round.msh")
x = mo.points
ant, out, ring = nodes(mo, "anterior"), nodes(mo, "outer"), nodes(mo, "incision-ring-1")
edge, top = np.intersect1d(ant, out), np.intersect1d(ant, ring)
for name, ids, a, b in (("corneal edge", edge, 5.85, 5.3), ("ring top", top, 5.25, 4.7)):
    p = x[ids]
    rho, t = np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])
    err = np.abs(rho - ellipse(a, b, t)).max()
    check(len(ids) > 40 and err < 1e-9, f"{name}: {len(ids)} nodes, {err:.1e} mm off the ellipse {2 * a:g} x {2 * b:g} mm")
    check(rho.min() < b + 0.01 and rho.max() > a - 0.01, f"{name}: from {rho.min():.3f} to {rho.max():.3f} mm from the axis")
def zone(m):
    p = m.points[nodes(m, "anterior")]
    return p[np.lexsort(p.T[::-1])][np.hypot(*p[np.lexsort(p.T[::-1])][:, :2].T) <= 3.5]
zo, zr = zone(mo), zone(mr)
check(len(zo) > 50 and zo.shape == zr.shape and np.array_equal(zo, zr),
      f"the optical zone's {len(zo)} anterior nodes are the round eye's, coordinate for coordinate")
def rows(v):
    r = [l.rstrip("\n").split("\t") for l in open(f"{tmp}/{v}/curvature.tsv")]
    return [dict(zip(r[0], map(float, x))) for x in r[1:]]
o, r = rows("oval"), rows("round")
for k in ("k_steep_D", "k_flat_D"):
    check(abs(o[0][k] - r[0][k]) <= 0.01, f"step 0 {k}: oval {o[0][k]:.4f} D, round {r[0][k]:.4f} D")
check(abs(o[0]["k_steep_D"] - 337.5 / 7.667) <= 0.01 and abs(o[0]["k_flat_D"] - 337.5 / 7.938) <= 0.01
      and abs(o[0]["axis_steep_deg"] - 90) < 0.5, "step 0: the scene's keratometry")
ms = meshio.read(f"{tmp}/snap.msh")
corner = np.unique(np.vstack([b.data[:, :4] for b in mo.cells if b.type.startswith("tetra")]))
moved = corner[np.any(ms.points[corner] != x[corner], axis=1)]
p = ms.points[moved]
res = np.abs(p[:, 0] ** 2 / 5.0 ** 2 + p[:, 1] ** 2 / 4.45 ** 2 - 1).max() if len(p) else float("nan")
check(len(p) > 10 and res < 1e-9 and np.hypot(p[:, 0], p[:, 1]).min() < 4.5,
      f"snapped arc at 10 mm: {len(p)} vertices moved onto the ellipse 10 x 8.9 mm (residual {res:.1e})")
so, sr = o[-1]["sia_D"], r[-1]["sia_D"]
check(so > 0.1 and sr > 0.1 and abs(so - sr) > 0.01 * sr, f"paired 60: SIA oval {so:.3f} D, round {sr:.3f} D")
sys.exit(1 if fails else 0)
PY
