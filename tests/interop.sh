#!/bin/bash
# interop.sh BUILD_DIR: keratome's MSH 4.1 and legacy VTK files read by second readers (gmsh
# itself and meshio under /usr/bin/python3), and meshes that gmsh wrote read back by keratome.
# Sample files come from `test_msh --samples` and `test_vtk --samples`; counts and geometry of
# what keratome reads come from `test_msh --counts` / `--compare`.
set -u
B=$(cd "${1:?usage: interop.sh BUILD_DIR}" && pwd)
PY=/usr/bin/python3 # Debian's interpreter: the one that sees numpy and meshio
D=$(mktemp -d /tmp/kt-interop-XXXXXX)
trap 'rm -rf "$D"' EXIT
pass=0
fail=0

ok() { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
check() { # check DESCRIPTION COMMAND...
    local what=$1
    shift
    if "$@"; then ok; else bad "$what"; fi
}
value() { awk -v k="$1" '$1 == k { print $2 }' "$2"; } # value KEY COUNTSFILE

command -v gmsh >/dev/null || { echo "FAIL: gmsh not found"; echo "0 passed, 1 failed"; exit 1; }
$PY -c 'import meshio' 2>/dev/null || { echo "FAIL: meshio not importable by $PY"; echo "0 passed, 1 failed"; exit 1; }

check "test_msh --samples" "$B/test_msh" --samples "$D"
check "test_vtk --samples" "$B/test_vtk" --samples "$D"

# --- 1. gmsh reads our MSH: its counts, its coherence check, and its own re-save ---------------
for f in msh-p1 msh-p1-bin msh-p2 msh-p2-bin vtk-p1 vtk-p2; do
    F=$D/$f.msh
    "$B/test_msh" --counts "$F" >"$D/$f.counts" || { bad "$f: keratome cannot read its own file"; continue; }
    nodes=$(value nodes "$D/$f.counts")
    elems=$(($(value tets "$D/$f.counts") + $(value triangles "$D/$f.counts")))
    gmsh "$F" -check >"$D/$f.check" 2>&1
    rc=$?
    # A triangle in two groups is written once per group (lib/mesh/mesh.h), which gmsh's coherence
    # check reports as duplicate elements: expect exactly those ("bottom-too" in msh-*).
    dup=$(awk '$1 == "group" && $4 == "bottom-too" { print $5 }' "$D/$f.counts")
    if [ -n "$dup" ]; then
        check "$f: gmsh -check reports exactly the $dup twice-listed triangles" \
            test "$(grep -E '^Error' "$D/$f.check")" = "Error   : $dup duplicate elements"
    else
        check "$f: gmsh -check passes" test $rc = 0
        check "$f: gmsh reports no error" bash -c "! grep -q -E '^Error' '$D/$f.check'"
    fi
    check "$f: gmsh counts $nodes nodes" grep -q -E "^Info *: $nodes nodes\$" "$D/$f.check"
    check "$f: gmsh counts $elems elements" grep -q -E "^Info *: $elems elements\$" "$D/$f.check"
    bin=
    case $f in *-bin) bin=-bin ;; esac
    gmsh "$F" -save $bin -format msh41 -o "$D/$f-gmsh.msh" >/dev/null 2>&1
    check "$f: gmsh re-save is the same mesh" "$B/test_msh" --compare "$F" "$D/$f-gmsh.msh"
done
grep -E 'midedge|check' "$D/msh-p2.counts" | sed 's/^/msh-p2: /'

# gmsh's own VTK export of our P2 mesh: gmsh's reading of our MSH node order + its VTK order.
gmsh "$D/vtk-p2.msh" -save -o "$D/vtk-p2-gmsh.vtk" >/dev/null 2>&1
check "gmsh exports vtk-p2.msh to VTK" test -s "$D/vtk-p2-gmsh.vtk"
# gmsh reads our POLYDATA (meshio 5.0 cannot); meshio then reads gmsh's MSH 2.2 of it.
for f in surf surf-bin; do
    gmsh "$D/$f.vtk" -save -format msh22 -o "$D/$f-gmsh22.msh" >"$D/$f.log" 2>&1
    check "$f: gmsh reads our POLYDATA" test $? = 0 -a -s "$D/$f-gmsh22.msh"
done

# --- 2. gmsh writes meshes, keratome reads them -------------------------------------------------
cat >"$D/box.geo" <<'EOF'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 0.8, 1.3};
Physical Volume("body", 7) = {1};
Physical Surface("bottom", 3) = {5};
Physical Surface("sides", 4) = {1, 2, 5};
Mesh.MeshSizeMax = 0.35;
EOF
# g1: ASCII with parametric nodes; g2: binary, 10-node tets; g3: ASCII, every element saved.
gmsh -3 "$D/box.geo" -format msh41 -save_parametric -o "$D/g1.msh" >/dev/null 2>&1
check "gmsh -3 (parametric)" test -s "$D/g1.msh"
gmsh -3 -order 2 -bin "$D/box.geo" -format msh41 -o "$D/g2.msh" >/dev/null 2>&1
check "gmsh -3 -order 2 -bin" test -s "$D/g2.msh"
gmsh -3 "$D/box.geo" -format msh41 -save_all -o "$D/g3.msh" >/dev/null 2>&1
check "gmsh -3 -save_all" test -s "$D/g3.msh"
for g in g1 g2 g3; do
    check "$g: keratome reads gmsh's file" "$B/test_msh" --counts "$D/$g.msh" >"$D/$g.counts"
    sed "s/^/$g: /" "$D/$g.counts" | tr '\n' ' ' | sed 's/$/\n/'
    # meshio 5.0 cannot read gmsh 4.8's MSH 4.1 files (parametric nodes; cell-data blocks), so
    # gmsh converts to MSH 2.2 for meshio to count.
    gmsh "$D/$g.msh" -save -format msh22 -o "$D/$g-22.msh" >/dev/null 2>&1
    check "$g: keratome's geometry check" grep -q '^check ok$' "$D/$g.counts"
done
check "g1 (parametric) and g3 (save_all) hold the same mesh" "$B/test_msh" --compare "$D/g1.msh" "$D/g3.msh"

# --- 3. meshio reads everything ---------------------------------------------------------------
$PY - "$D" >"$D/meshio.log" 2>&1 <<'EOF'
import sys, numpy as np, meshio
D = sys.argv[1]
def res(ok, what):
    print(("PASS " if ok else "FAIL ") + what)

def counts(name):
    c = {"group": []}
    for line in open(f"{D}/{name}.counts"):
        w = line.split()
        if w[0] == "group": c["group"].append((int(w[1]), int(w[2]), w[3], int(w[4])))
        elif w[0] != "check": c[w[0]] = w[1]
    return c

def cells_of(m, types):
    blocks = [c.data for c in m.cells if c.type in types]
    return np.concatenate(blocks) if blocks else np.zeros((0, 0), int)

# Our MSH files: meshio's counts and groups equal keratome's.
for f in ["msh-p1", "msh-p1-bin", "msh-p2", "msh-p2-bin"]:
    c = counts(f)
    try:
        m = meshio.read(f"{D}/{f}.msh")
    except Exception as e:
        res(False, f"{f}: meshio read: {e}"); continue
    tet = ("tetra", "tetra10"); tri = ("triangle", "triangle6")
    res(len(m.points) == int(c["nodes"]), f"{f}: meshio points {len(m.points)}")
    res(len(cells_of(m, tet)) == int(c["tets"]), f"{f}: meshio tetrahedra")
    res(len(cells_of(m, tri)) == int(c["triangles"]), f"{f}: meshio triangles")
    sets = {k: sum(len(x) for x in v if x is not None) for k, v in m.cell_sets.items()}
    res(all(sets.get(name) == n for d, t, name, n in c["group"]), f"{f}: meshio group sizes {sets}")
# ASCII and binary carry the same numbers.
for o in (1, 2):
    a, b = meshio.read(f"{D}/msh-p{o}.msh"), meshio.read(f"{D}/msh-p{o}-bin.msh")
    same = np.array_equal(a.points, b.points) and all(
        x.type == y.type and np.array_equal(x.data, y.data) for x, y in zip(a.cells, b.cells))
    res(same, f"msh-p{o}: ASCII and binary identical through meshio")

# Our VTK files against the same mesh's MSH (meshio converts gmsh node order to VTK's itself).
for o in (1, 2):
    ref = meshio.read(f"{D}/vtk-p{o}.msh")
    tt = "tetra10" if o == 2 else "tetra"
    rtet = cells_of(ref, (tt,))
    rreg = np.concatenate([p for c, p in zip(ref.cells, ref.cell_data["gmsh:physical"]) if c.type == tt])
    for enc in ("", "-bin"):
        f = f"vtk-p{o}{enc}"
        try:
            v = meshio.read(f"{D}/{f}.vtk")
        except Exception as e:
            res(False, f"{f}: meshio read: {e}"); continue
        res(np.array_equal(v.points, ref.points), f"{f}: points equal the MSH's, bit for bit")
        vt = cells_of(v, (tt,))
        reg = v.cell_data.get("region")
        reg = None if reg is None else np.ravel(reg[0])
        # The MSH groups tets by region, the VTK keeps mesh order: compare (tet, region) rows as sets.
        same = reg is not None and len(v.cells) == 1 and vt.shape == rtet.shape and np.array_equal(
            np.unique(np.column_stack([vt, reg]), axis=0), np.unique(np.column_stack([rtet, rreg]), axis=0))
        res(same, f"{f}: {tt} rows and their region equal meshio's reading of the MSH")
        x = v.points
        if o == 2:  # VTK quadratic tetra: node 4+k is the midpoint of edge 01 12 20 03 13 23
            ed = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
            dev = max(np.abs(0.5 * (x[vt[:, a]] + x[vt[:, b]]) - x[vt[:, 4 + k]]).max() for k, (a, b) in enumerate(ed))
            res(dev < 1e-15, f"{f}: mid-edge nodes at VTK's edge midpoints (max dev {dev:.2g})")
        u = v.point_data.get("displacement")
        want = np.column_stack([1e-3 * np.sin(3 * x[:, 0]), x[:, 0] * x[:, 1] * x[:, 2], 0.25 * x[:, 2] ** 2 - x[:, 1]])
        res(u is not None and u.shape == want.shape and np.abs(u - want).max() <= 1e-15,
            f"{f}: point_data displacement = analytic field" + ("" if u is None else f" (max diff {np.abs(u - want).max():.2g})"))
        org = v.point_data.get("origin")
        res(org is not None and np.array_equal(np.ravel(org), np.arange(1, len(x) + 1)), f"{f}: point_data origin = 1..nn")
        cx = x[vt[:, :4], 0].mean(axis=1)
        res(reg is not None and set(np.unique(reg)) == {1, 2} and np.all(reg[cx < 0.45] == 1) and np.all(reg[cx > 0.55] == 2),
            f"{f}: region 2 is the x > 0.5 half")
        p0, p1, p2, p3 = (x[vt[:, k]] for k in range(4))
        vol = np.einsum("ij,ij->i", np.cross(p1 - p0, p2 - p0), p3 - p0) / 6
        cv = v.cell_data.get("volume")
        res(cv is not None and np.allclose(np.ravel(cv[0]), vol, rtol=1e-13, atol=0), f"{f}: cell_data volume = tet volumes")
        par = v.cell_data.get("parity")
        res(par is not None and np.array_equal(np.ravel(par[0]), np.arange(len(vt)) % 3), f"{f}: cell_data parity = i mod 3")
        s6 = v.cell_data.get("sym6")
        want6 = (np.arange(len(vt)) % 7)[:, None] + np.arange(6)[None, :] / 8.0
        res(s6 is not None and np.asarray(s6[0]).shape == (len(vt), 6) and np.array_equal(np.asarray(s6[0]), want6),
            f"{f}: cell_data sym6 (a 6-component FIELD array) = i mod 7 + k/8")

# gmsh's own VTK export of vtk-p2.msh: the same quadratic tets (in gmsh's element order).
g = meshio.read(f"{D}/vtk-p2-gmsh.vtk")
ours = meshio.read(f"{D}/vtk-p2.vtk")
gt, ot = cells_of(g, ("tetra10",)), cells_of(ours, ("tetra10",))
res(np.allclose(g.points, ours.points, rtol=0, atol=1e-15), "gmsh's VTK export has our points")
res(len(gt) == len(ot) and np.array_equal(np.unique(gt, axis=0), np.unique(ot, axis=0)),
    "gmsh's VTK export of our P2 MSH has exactly our VTK_QUADRATIC_TETRA rows")

# POLYDATA through gmsh: the points of vtk-p1 and its boundary triangles, each on one box face.
ref = meshio.read(f"{D}/vtk-p1.msh")
rtri = cells_of(ref, ("triangle",))
for f in ("surf", "surf-bin"):
    s = meshio.read(f"{D}/{f}-gmsh22.msh")
    t = cells_of(s, ("triangle",))
    # gmsh drops the points no triangle uses and renumbers: compare triangles by coordinates.
    a, b = s.points[t].reshape(-1, 9), ref.points[rtri].reshape(-1, 9)
    key = lambda c: c[np.lexsort(np.round(c, 9).T[::-1])]
    res(len(t) == len(rtri) and np.allclose(key(a), key(b), rtol=0, atol=1e-15),
        f"{f}: gmsh reads our {len(rtri)} triangles at our coordinates")
    x, lo, hi = s.points, s.points.min(axis=0), s.points.max(axis=0)
    onface = np.zeros(len(t), bool)
    for k in range(3):
        onface |= np.all(np.abs(x[t, k] - lo[k]) < 1e-3, axis=1) | np.all(np.abs(x[t, k] - hi[k]) < 1e-3, axis=1)
    res(len(t) > 0 and onface.all(), f"{f}: every triangle lies on a box face")

# gmsh-written meshes: keratome's counts against meshio's reading of gmsh's MSH 2.2 conversion.
for gname in ("g1", "g2", "g3"):
    c = counts(gname)
    m = meshio.read(f"{D}/{gname}-22.msh")
    per = {}
    for cb, p in zip(m.cells, m.cell_data["gmsh:physical"]):
        for tag in np.unique(p):
            per[(cb.type.rstrip("0123456789"), int(tag))] = per.get((cb.type.rstrip("0123456789"), int(tag)), 0) + int((p == tag).sum())
    res(len(m.points) == int(c["nodes"]), f"{gname}: {c['nodes']} nodes (meshio {len(m.points)})")
    mine = {("tetra" if d == 3 else "triangle", t): n for d, t, name, n in c["group"]}
    res(mine == {k: v for k, v in per.items() if k[0] in ("tetra", "triangle")}, f"{gname}: per-group counts {mine} (meshio {per})")
    res(abs(float(c["volume"]) - 1.04) < 1e-12, f"{gname}: volume {c['volume']} = 1 x 0.8 x 1.3")
    res(float(c["midedge_maxdev"]) < 1e-12, f"{gname}: mid-edge nodes at gmsh's edge midpoints")
EOF
check "python/meshio script ran" test $? = 0
while read -r word rest; do
    case $word in
    "") ;;
    PASS) ok ;;
    FAIL) bad "$rest" ;;
    *) echo "$word $rest" >&2 ;;
    esac
done <"$D/meshio.log"

ls -l "$D"/*.msh "$D"/*.vtk | awk '{ printf "%8d %s\n", $5, $NF }' | sed "s|$D/||"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
