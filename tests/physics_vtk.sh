#!/bin/bash
# physics_vtk.sh BUILD_DIR: augsolve's step files carry every per-tet input of the physics as
# CELL_DATA (keratome-vtk(5)), and two second readers get back what the solver used. A coarse
# P2 default eye (plans/eye.yaml: lamellar cornea and limbus, prestressed), a single 30-degree
# LRI in one step, written ASCII and BINARY. meshio and VTK 9 (python3-vtk9) read the files;
# for tets of every region the test recomputes, from the tet's vertices and the scene's
# documented rules (keratome-scene(5), eye.fibres and MATERIALS), the lamellar frame a1 a2 n c,
# the limbal weight and the material constants (orthotropic lamellae: E_inplane_2 differs, so
# the circumferential modulus's formula is tested), checks that sigma0 is the membrane stress
# of the pressurized cornea (p R / 2t at the apex, traction-free normal stress) and that the
# apex membrane stress augsolve prints is the mean keratome-scene(5) states, and that the
# cut's step carries the same regions as step 0 and none of the per-tet inputs (tets keep their
# numbers: step-0000.vtk holds them for every step, keratome-vtk(5)).
set -u
build="$1"
PY=/usr/bin/python3 # Debian's interpreter: the one that sees numpy, meshio and vtk
$PY -c 'import meshio, numpy, yaml' 2>/dev/null || { echo "FAILED: meshio/numpy/yaml not importable by $PY"; exit 1; }
$PY -c 'import vtk' 2>/dev/null || { echo "FAILED: python3-vtk9 missing (scripts/setup.sh --test)"; exit 1; }
tmp=$(mktemp -d /tmp/kt-physvtk.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh 0.7 0.5 0.9 3 "$tmp/coarse.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
# orthotropic lamellae (E_inplane_2 differs from E_inplane in cornea and limbus), so that the
# circumferential modulus (limbal_density - 1) w (E_inplane + E_inplane_2) / 2 is told apart
# from (limbal_density - 1) w E_inplane
sed -e 's/^    E_inplane: 2.0 MPa /    E_inplane_2: 2.6 MPa\n&/' \
    -e 's/^  limbus: {model: fibre, E_inplane: 2.0 MPa,/  limbus: {model: fibre, E_inplane: 2.0 MPa, E_inplane_2: 3.0 MPa,/' \
    "$tmp/coarse.yaml" > "$tmp/eye.yaml"
[ "$(grep -c 'E_inplane_2: ' "$tmp/eye.yaml")" = 2 ] || { echo "FAILED: plans/eye.yaml's cornea and limbus entries changed; E_inplane_2 not set"; exit 1; }
sed -e "s|^scene:.*|scene: $tmp/eye.yaml|" -e 's|degrees_per_step:.*|degrees_per_step: 30 deg|' \
    plans/lri-single-30.yaml > "$tmp/plan.yaml"
"$build/mesh-prep" -q "$tmp/eye.yaml" -o "$tmp/eye.msh" > /dev/null || { echo "FAILED: mesh-prep"; exit 1; }
"$build/cutplan" -q "$tmp/plan.yaml" "$tmp/eye.msh" -o "$tmp/lri.edits" || { echo "FAILED: cutplan"; exit 1; }
"$build/augsolve" "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/ascii" 2> "$tmp/err" || { echo "FAILED: augsolve: $(cat "$tmp/err")"; exit 1; }
# the apex membrane stress augsolve prints (kPa, 4 significant digits)
apex=$(sed -n 's/.*apex membrane stress \([-0-9.e+]*\) kPa.*/\1/p' "$tmp/err")
[ -n "$apex" ] || { echo "FAILED: augsolve printed no apex membrane stress: $(cat "$tmp/err")"; exit 1; }
"$build/augsolve" -q "$tmp/eye.msh" "$tmp/lri.edits" -o "$tmp/bin" --binary 2> "$tmp/err" || { echo "FAILED: augsolve --binary: $(cat "$tmp/err")"; exit 1; }
$PY - "$tmp" "$apex" <<'PY' || exit 1
import math, re, sys
import meshio, numpy as np, yaml
import vtk
from vtk.util.numpy_support import vtk_to_numpy

tmp = sys.argv[1]
apex_printed = float(sys.argv[2])  # kPa
errs = []
def check(ok, what):
    if not ok: errs.append(what)

# --- the scene, with its units (keratome-scene(5)) ----------------------------------------------
UNIT = {"MPa": 1.0, "kPa": 1e-3, "Pa": 1e-6, "mm": 1.0, "um": 1e-3, "mmHg": 0.133322387415e-3, "deg": 1.0}
def q(v):
    if not isinstance(v, str): return float(v)
    num, unit = v.split()
    return float(num) * UNIT[unit]
sc = yaml.safe_load(open(f"{tmp}/eye.yaml"))
eye, mats = sc["eye"], sc["materials"]
Rs, Rf, Rg = (q(eye[k]) for k in ("anterior_radius_steep", "anterior_radius_flat", "globe_radius"))
# white_to_white: a length (the horizontal) or {horizontal, vertical}; the vertical one of a
# length is 1.1 mm less (keratome-scene(5)); the cornea's edge is their ellipse
ww = eye["white_to_white"]
wtw, wtw_v = (q(ww["horizontal"]), q(ww["vertical"])) if isinstance(ww, dict) else (q(ww), q(ww) - 1.1)
band, dens = q(eye["fibres"]["limbal_band"]), float(eye["fibres"]["limbal_density"])
p_iop = q(sc["loads"]["pressure"]["value"])
# mean anterior sphere: radius 2 / (1/Rs + 1/Rf), through the corneal edge (rho = wtw/2) on the
# globe (radius Rg about the origin); its centre on the axis at z_ca
Ra, rc = 2 / (1 / Rs + 1 / Rf), wtw / 2
z_ca = math.sqrt(Rg**2 - rc**2) - math.sqrt(Ra**2 - rc**2)

# region tags from the mesh's physical names
txt = open(f"{tmp}/eye.msh").read()
blk = txt.split("$PhysicalNames\n")[1].split("$EndPhysicalNames")[0].strip().split("\n")[1:]
tag = {m.group(3): int(m.group(2)) for m in (re.match(r'(\d+) (\d+) "(.*)"', l) for l in blk) if m.group(1) == "3"}
check(set(tag) == {"cornea", "limbus", "sclera"}, f"volume groups {sorted(tag)}")

def unit(v): return v / np.linalg.norm(v)
def cround(x): return math.copysign(math.floor(abs(x) + 0.5), x)  # C's round()

def expected(pc, region):
    """The documented per-tet inputs at centroid pc of a tet of `region`."""
    cornea = region == "cornea"
    n = unit(pc - np.array([0, 0, z_ca if cornea else 0.0]))
    a1 = unit(np.array([1.0, 0, 0]) - n[0] * n)
    a2 = np.cross(n, a1)
    rho = math.hypot(pc[0], pc[1])
    # on the oval cornea: the edge in this meridian, the normal / tangent of the ellipse of the
    # white-to-white's semi-axes a, b through pc as radial / circumferential
    a, b = rc, wtw_v / 2
    edge = a * b / math.hypot(b * pc[0] / rho, a * pc[1] / rho)
    nx, ny = pc[0] * b * b, pc[1] * a * a
    w = 1.0
    if cornea:
        s = min(max((rho - (edge - band)) / band, 0.0), 1.0)
        w = s * s * (3 - 2 * s)
    t = np.array([-ny, nx, 0]) / math.hypot(nx, ny)
    c = unit(t - t.dot(n) * n)
    # the turn: w times the tangent-plane angle from a1 to the radial direction c x n, reduced
    # to [-45, 45] deg, about n from a1 towards a2
    r = np.cross(c, n)
    psi = math.atan2(r @ a2, r @ a1)
    th = w * (psi - math.pi / 2 * cround(psi / (math.pi / 2)))
    b1 = math.cos(th) * a1 + math.sin(th) * a2
    m = mats[region]
    if region in ("cornea", "limbus"):
        E1 = q(m["E_inplane"])
        E2 = q(m["E_inplane_2"]) if "E_inplane_2" in m else E1
        cst = [E1, E2, q(m["G_transverse"]), float(m["nu"]), (dens - 1) * w * (E1 + E2) / 2, 1]
    else:
        E, nu = q(m["E"]), float(m["nu"])
        cst = [E, E, E / (2 * (1 + nu)), nu, 0.0, 0]
    return {"a1": b1, "a2": np.cross(n, b1), "n": n, "c": c, "limbal_weight": w}, cst

CST = ["E_inplane", "E_inplane_2", "G_transverse", "nu", "E_circumferential", "lamellar"]
NAMES = ["region", "a1", "a2", "n", "c", "limbal_weight", "sigma0"] + CST

def read_meshio(path, names=NAMES):
    v = meshio.read(path)
    cells = [cb.data for cb in v.cells if cb.type in ("tetra10", "tetra")]
    check(len(cells) == 1, f"{path}: one block of tets")
    d = {}
    for k in names:
        a = v.cell_data.get(k)
        check(a is not None, f"{path}: CELL_DATA {k} missing (meshio)")
        if a is not None: d[k] = np.asarray(a[0]).reshape(len(cells[0]), -1)
    return v.points, cells[0], d

def read_vtk(path, names=NAMES):
    r = vtk.vtkUnstructuredGridReader()
    r.SetFileName(path)
    r.ReadAllScalarsOn(); r.ReadAllVectorsOn(); r.ReadAllFieldsOn()
    r.Update()
    g = r.GetOutput()
    cd = g.GetCellData()
    d = {}
    for k in names:
        a = cd.GetArray(k)
        check(a is not None, f"{path}: CELL_DATA {k} missing (VTK {vtk.vtkVersion.GetVTKVersion()})")
        if a is not None: d[k] = vtk_to_numpy(a).reshape(g.GetNumberOfCells(), -1).astype(float)
    return d

x, tets, d = read_meshio(f"{tmp}/ascii/step-0000.vtk")
ne = len(tets)
# 1. the two readers, the two encodings and the two steps agree value for value; the cut's step
# carries the regions and not the constant per-tet inputs (written once, in step-0000.vtk)
for path in (f"{tmp}/ascii/step-0000.vtk", f"{tmp}/bin/step-0000.vtk", f"{tmp}/bin/step-0001.vtk", f"{tmp}/ascii/step-0001.vtk"):
    names = NAMES if path.endswith("0000.vtk") else ["region"]
    dv = read_vtk(path, names)
    dm = read_meshio(path, names)[2]
    for k in names:
        if k in d and k in dv and k in dm:
            check(np.array_equal(dv[k], d[k]) and np.array_equal(dm[k], d[k]), f"{path}: {k} differs from ascii step 0")
    if not path.endswith("0000.vtk"):
        extra = sorted(k for k in meshio.read(path).cell_data if k != "region")
        check(not extra, f"{path}: repeats step 0's per-tet inputs {extra}")
if errs: print("FAILED: " + "; ".join(errs[:8])); sys.exit(1)

# 2. recompute tets of every region from their vertices (VTK's first 4 nodes)
region_of = {t: r for r, t in tag.items()}
rng = np.random.default_rng(7)
pc = x[tets[:, :4]].mean(axis=1)
rho = np.hypot(pc[:, 0], pc[:, 1])
reg = d["region"][:, 0].astype(int)
picks = []
for r in ("cornea", "limbus", "sclera"):
    ids = np.flatnonzero((reg == tag[r]) & (rho > 0.05))
    picks += list(rng.choice(ids, 12, replace=False))
    if r == "cornea":  # and the limbal band, where the frame turns and w is between 0 and 1
        band_ids = np.flatnonzero((reg == tag[r]) & (rho > rc - band + 0.2) & (rho < rc - 0.2))
        picks += list(rng.choice(band_ids, 12, replace=False))
fd, cd = [], []  # np.max of these lists propagates a NaN, which then fails the checks
for t in picks:
    fr, cst = expected(pc[t], region_of[reg[t]])
    for k, v in fr.items():
        fd.append(np.max(np.abs(d[k][t] - v)))
    for k, v in zip(CST, cst):
        cd.append(abs(d[k][t][0] - v) / abs(v) if v else abs(d[k][t][0]))
fmax, cmax = float(np.max(fd)), float(np.max(cd))
check(fmax < 1e-12, f"frames and limbal weight differ from the recomputed ones by {fmax:.3g}")
check(cmax < 1e-12, f"material constants differ from the scene's by {cmax:.3g} (relative)")
wb = d["limbal_weight"][picks, 0]
check(np.min(wb) < 0.5 < np.max(wb) and np.min(wb) >= 0, "the picks span the limbal band")

# 3. sigma0 (xx yy zz xy yz xz, volume average): the pressurized cornea's membrane stress
S = d["sigma0"]
def tensor(s): return np.array([[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]])
apex = np.flatnonzero((reg == tag["cornea"]) & (rho < 1.0))
mem = np.mean([0.5 * (d["a1"][t] @ tensor(S[t]) @ d["a1"][t] + d["a2"][t] @ tensor(S[t]) @ d["a2"][t]) for t in apex])
snn = np.mean([d["n"][t] @ tensor(S[t]) @ d["n"][t] for t in apex])
t_c = q(eye["central_thickness"])
laplace = p_iop * Ra / (2 * t_c)
print(f"{ne} tets; {len(picks)} recomputed: frames to {fmax:.2e}, constants to {cmax:.2e}; "
      f"apex ({len(apex)} tets): in-plane sigma0 {1e3 * mem:.3f} kPa (p R / 2t = {1e3 * laplace:.3f}), "
      f"normal {1e3 * snn:.3f} kPa (p = {1e3 * p_iop:.3f})")
check(abs(mem / laplace - 1) < 0.15, f"apex in-plane prestress {mem:.4g} MPa, p R / 2t = {laplace:.4g}")
check(-p_iop < snn < 0, f"apex normal prestress {snn:.4g} MPa, expected between -p and 0")
check(np.all(np.isfinite(S)), "sigma0 not finite")
# 4. the printed apex membrane stress is what keratome-scene(5) (LOADS) says it is: over the
# tets whose centroid lies within 0.5 mm of the axis and 1 mm below the highest node, the
# volume-weighted (4-vertex volume) mean of (sigma_11 + sigma_22 + sigma_33) / 2 of sigma0
X = x[tets[:, :4]]
vol = np.abs(np.einsum("ij,ij->i", X[:, 1] - X[:, 0], np.cross(X[:, 2] - X[:, 0], X[:, 3] - X[:, 0]))) / 6
win = (rho <= 0.5) & (pc[:, 2] >= x[:, 2].max() - 1.0)
apex_mean = 1e3 * np.sum(vol[win] * 0.5 * S[win, :3].sum(axis=1)) / np.sum(vol[win])
digit = 10 ** (math.floor(math.log10(abs(apex_mean))) - 3)  # the last of the 4 printed digits
print(f"apex membrane stress: printed {apex_printed} kPa, recomputed from sigma0 {apex_mean:.4f} kPa ({win.sum()} tets)")
check(win.sum() >= 4 and abs(apex_printed - apex_mean) <= 0.51 * digit,
      f"printed apex membrane stress {apex_printed} kPa, the stated mean {apex_mean:.4f} kPa")
if errs: print("FAILED: " + "; ".join(errs)); sys.exit(1)
print("physics_vtk: ok")
PY
