#!/usr/bin/env bash
# curvature_pipeline.sh BUILD_DIR: curvature on synthetic run folders (P1 and P2 tet meshes of a
# corneal shell whose anterior surface is an exact torus at every step, with a crack of
# duplicated nodes from step 1 on; written by `test_curv --make-run`). Checks, with second
# readers: K, axis, flattening, steepening, coupling and SIA against the analytic values
# (expected.tsv: K = 337.5/R of the torus's principal circles); the input pair reads in meshio;
# surface-NNNN.vtk (UNSTRUCTURED_GRID of triangles, parsed by an independent reader below and
# read back by meshio with the same points, triangles and fields) has the anterior nodes, the
# analytic displacement, elevation against an independently fitted sphere and axial power against
# the analytic torus; the PNGs are PNGs of the documented size; --mesh mode gives the same table.
set -euo pipefail
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
PY=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt_curvpipe_XXXXXX)
trap 'rm -rf "$tmp"' EXIT

for variant in p1 p2; do
    dir=$tmp/$variant
    flag=""
    [ $variant = p2 ] && flag=--order2
    "$B/test_curv" --make-run "$dir" $flag
    "$B/curvature" -q "$dir" > "$dir/summary.txt"
    grep -q "^pre-op (step 0): K 44.41 D @ 90 / 42.72 D @ 0" "$dir/summary.txt"
    # --mesh mode on the same files, into another folder: the same table
    "$B/curvature" -q --no-png --no-vtk -o "$tmp/$variant-mesh" --mesh "$dir/eye.msh" \
        "$dir"/step-000{0,1,2,3}.vtk > /dev/null
    cmp <(cut -f1-24 "$dir/curvature.tsv") <(cut -f1-24 "$tmp/$variant-mesh/curvature.tsv")
    $PY - "$dir" <<'EOF'
import sys, os, struct, csv, math
import numpy as np
import meshio

d = sys.argv[1]
def table(p):
    with open(p) as f:
        return list(csv.DictReader(f, delimiter='\t'))
got, exp = table(d + '/curvature.tsv'), table(d + '/expected.tsv')
assert len(got) == len(exp) == 4, (len(got), len(exp))
worst = {}
def near(key, tol, g, e, label):
    a, b = float(g), float(e)
    if math.isnan(b):
        assert math.isnan(a), (label, key, a)
        return
    err = abs(a - b)
    if key.endswith('axis_deg'):
        err = min(err % 180, 180 - err % 180)
    worst[key] = max(worst.get(key, 0), err)
    assert err <= tol, f"{label}: {key} {a} vs {b} (tolerance {tol})"
for g, e in zip(got, exp):
    s = 'step ' + g['step']
    for key, tol in [('k_steep_D', 0.01), ('k_flat_D', 0.01), ('axis_steep_deg', 0.5), ('cyl_D', 0.01),
                     ('flattening_D', 0.01), ('steepening_D', 0.01), ('sia_D', 0.01)]:
        near(key, tol, g[key], e[key], s)
    if g['step'] != '0':
        near('sia_axis_deg', 0.5, g['sia_axis_deg'], e['sia_axis_deg'], s)
        near('coupling_ratio', 0.02 * float(e['coupling_ratio']), g['coupling_ratio'], e['coupling_ratio'], s)
    else:
        assert g['coupling_ratio'] == 'NaN', g['coupling_ratio']

# The input pair reads in meshio; the anterior nodes of the input mesh.
msh = meshio.read(d + '/eye.msh')
tag = msh.field_data['anterior'][0]
ant = set()
for blk, phys in zip(msh.cells, msh.cell_data['gmsh:physical']):
    if blk.type.startswith('triangle'):
        for row, p in zip(blk.data, phys):
            if p == tag:
                ant.update(int(i) for i in row)
tri_ref = [blk.data[phys == tag] for blk, phys in zip(msh.cells, msh.cell_data['gmsh:physical'])
           if blk.type.startswith('triangle')]
tri_ref = np.concatenate(tri_ref)

def area(xyz, tri):
    a, b, c = xyz[tri[:, 0]], xyz[tri[:, 1]], xyz[tri[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
if tri_ref.shape[1] == 6:  # tri6: area of the straight sub-triangles of corner+mid nodes
    t = tri_ref
    tri_ref = np.concatenate([t[:, [0, 3, 5]], t[:, [3, 1, 4]], t[:, [5, 4, 2]], t[:, [3, 4, 5]]])
area_ref = area(msh.points, tri_ref)

def read_surface(path):
    """Independent reader of legacy VTK triangles (UNSTRUCTURED_GRID, ASCII or big-endian BINARY)."""
    data = open(path, 'rb').read()
    pos = 0
    def line():
        nonlocal pos
        e = data.index(b'\n', pos)
        s = data[pos:e].decode()
        pos = e + 1
        return s
    assert line().startswith('# vtk DataFile')
    line()
    binary = line().strip() == 'BINARY'
    def block(n, typ):
        nonlocal pos
        if binary:
            size = {'double': 8, 'float': 4, 'int': 4}[typ]
            fmt = '>' + {'double': 'd', 'float': 'f', 'int': 'i'}[typ] * n
            v = struct.unpack_from(fmt, data, pos)
            pos += n * size
            if pos < len(data) and data[pos:pos + 1] == b'\n':
                pos += 1
            return np.array(v)
        out = []
        while len(out) < n:
            out += line().split()
        return np.array(out, dtype=float)
    pts = tri = None
    fields = {}
    npts = 0
    while pos < len(data):
        s = line().split()
        if not s:
            continue
        if s[0] == 'DATASET':
            assert s[1] == 'UNSTRUCTURED_GRID', s
        elif s[0] == 'POINTS':
            npts = int(s[1])
            pts = block(3 * npts, s[2]).reshape(-1, 3)
        elif s[0] == 'CELLS':
            raw = block(int(s[2]), 'int').astype(int).reshape(int(s[1]), -1)
            assert (raw[:, 0] == 3).all()
            tri = raw[:, 1:]
        elif s[0] == 'CELL_TYPES':
            assert (block(int(s[1]), 'int') == 5).all()  # VTK_TRIANGLE
        elif s[0] in ('POINT_DATA', 'CELL_DATA'):
            assert s[0] == 'POINT_DATA' and int(s[1]) == npts
        elif s[0] == 'SCALARS':
            assert line().startswith('LOOKUP_TABLE')
            fields[s[1]] = block(npts * int(s[3] if len(s) > 3 else 1), s[2])
        elif s[0] == 'VECTORS':
            fields[s[1]] = block(3 * npts, s[2]).reshape(-1, 3)
        else:
            raise AssertionError('unexpected line ' + ' '.join(s))
    return pts, tri, fields

def torus(rs, rf, x, y):  # steep circle along y (90 deg), flat along x
    xs, yf = y, -x
    rho = rf - rs + np.sqrt(rs * rs - xs * xs)
    return -rf + np.sqrt(rho * rho - yf * yf)

for k in range(4):
    step = meshio.read(f'{d}/step-{k:04d}.vtk')
    origin = step.point_data['origin'].astype(int).ravel()
    n_ant = sum(1 for o in origin if o - 1 in ant)
    pts, tri, f = read_surface(f'{d}/surface-{k:04d}.vtk')
    # a second reader: meshio (it reads no POLYDATA) gives the same points, triangles and fields
    ms = meshio.read(f'{d}/surface-{k:04d}.vtk')
    assert [b.type for b in ms.cells] == ['triangle'] and (ms.cells[0].data == tri).all()
    assert np.array_equal(ms.points, pts)
    for name in ('displacement', 'elevation', 'axial_power', 'origin'):
        a, b = np.asarray(ms.point_data[name], dtype=float).reshape(f[name].shape), f[name]
        assert np.array_equal(np.isnan(a), np.isnan(b)) and np.allclose(a[~np.isnan(a)], b[~np.isnan(b)], rtol=0, atol=0)
    assert len(pts) == n_ant, (len(pts), n_ant)
    assert set(f) == {'displacement', 'elevation', 'axial_power', 'origin'}, f.keys()
    assert all(int(o) - 1 in ant for o in f['origin'])
    # the same surface: the triangle area equals the input mesh's anterior group's
    assert abs(area(pts, tri) - area_ref) < 1e-9 * area_ref, (area(pts, tri), area_ref)
    # outward (+z) orientation
    a, b, c = pts[tri[:, 0]], pts[tri[:, 1]], pts[tri[:, 2]]
    assert (np.cross(b - a, c - a)[:, 2] > 0).all()
    rs, rf = 7.6 + 0.05 * k, 7.9 - 0.03 * k
    x, y = pts[:, 0], pts[:, 1]
    du = f['displacement'][:, 2] - (torus(rs, rf, x, y) - torus(7.6, 7.9, x, y))
    assert np.abs(du).max() < 1e-12 and np.abs(f['displacement'][:, :2]).max() == 0
    q = pts + f['displacement']
    ap = f['axial_power']
    inside = ~np.isnan(ap)
    assert inside.sum() > 0.5 * len(ap)
    # elevation: against a sphere fitted here (linear least squares) to the map disk's points
    A = np.c_[2 * q[inside], np.ones(inside.sum())]
    sol = np.linalg.lstsq(A, (q[inside] ** 2).sum(1), rcond=None)[0]
    R = math.sqrt(sol[3] + (sol[:3] ** 2).sum())
    elev = 1000 * (np.linalg.norm(q - sol[:3], axis=1) - R)
    assert np.abs(elev - f['elevation']).max() < 1e-6, np.abs(elev - f['elevation']).max()
    # axial power against the analytic torus: (n-1) sin(normal angle) / r about the z axis
    h = 1e-5
    qi, api = q[inside], ap[inside]
    r = np.hypot(qi[:, 0], qi[:, 1])
    sel = (r > 0.2) & (r < 3.0)
    zx = (torus(rs, rf, qi[:, 0] + h, qi[:, 1]) - torus(rs, rf, qi[:, 0] - h, qi[:, 1])) / (2 * h)
    zy = (torus(rs, rf, qi[:, 0], qi[:, 1] + h) - torus(rs, rf, qi[:, 0], qi[:, 1] - h)) / (2 * h)
    g = np.hypot(zx, zy)
    with np.errstate(invalid='ignore', divide='ignore'):
        exact = 337.5 * g / np.sqrt(1 + g * g) / r
    err = np.abs(api - exact)[sel].max()
    worst['axial_power_D (r 0.2..3 mm)'] = max(worst.get('axial_power_D (r 0.2..3 mm)', 0), err)
    assert err < 0.02, err
    # the PNG: signature and IHDR size
    png = open(f'{d}/axial-{k:04d}.png', 'rb').read(24)
    assert png[:8] == b'\x89PNG\r\n\x1a\n' and struct.unpack('>II', png[16:24]) == (720, 580)
print(os.path.basename(d), 'worst errors:', ', '.join(f'{k} {v:.2e}' for k, v in worst.items()))
EOF
done

# The demo plan's incised meridian (90) and target ("correct 1.5 D @ 90": TIA 1.5 D @ 0) on the
# P1 run: the analytic SIA is (cyl0 - cyl_k) @ 0, so CI = SIA / 1.5, DV = 1.5 - SIA @ 0, AE = 0.
"$B/curvature" -q --no-png --no-vtk --plan plans/lri-paired-60.yaml -o "$tmp/plan" "$tmp/p1" > "$tmp/plan.txt"
grep -q "^incised meridian 90.0 deg (the plan's first incision)" "$tmp/plan.txt"
grep -q "^target: correct 1.50 D @ 90, TIA 1.50 D @ 0; step 3: SIA 1.35 D" "$tmp/plan.txt"
$PY - "$tmp/plan/curvature.tsv" "$tmp/p1/expected.tsv" <<'EOF'
import sys, csv
rows = [list(csv.DictReader(open(p), delimiter='\t')) for p in sys.argv[1:]]
for g, e in zip(*rows):
    sia = float(e['sia_D'])
    assert float(g['tia_D']) == 1.5 and float(g['tia_axis_deg']) == 0, g
    assert abs(float(g['correction_index']) - sia / 1.5) < 1e-3, (g['correction_index'], sia / 1.5)
    assert abs(float(g['dv_D']) - (1.5 - sia)) < 1e-3, (g['dv_D'], 1.5 - sia)
    if g['step'] != '0':
        assert abs(float(g['angle_error_deg'])) < 0.01 and float(g['dv_axis_deg']) == 0, g
print('plan target: CI and DV as analytic')
EOF
echo "curvature_pipeline: ok"
