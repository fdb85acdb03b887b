#!/bin/bash
# cutplan_pipeline.sh BUILD_DIR: mesh-prep beam-16 and brick-4, then cutplan the shipped cut and
# deform plans. A second reader (Python, with meshio for the mesh) parses the edits, applies the
# duplications itself and checks: header counts match the mesh, new nodes are numbered in
# sequence, the cut separates the two sides of the plane (tets holding a new node lie on the
# +normal side, tets keeping a duplicated node on the other), the count is one grid row per
# step, the pull forces balance; '-o -' streams exactly what '-o FILE' writes.
set -u
build="$1"
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-cutplan-pipe.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { # check NAME COMMAND...: run, count a failure
    if ! "${@:2}"; then echo "FAILED: $1"; fail=1; fi
}

cat > "$tmp/check.py" <<'EOF'
import sys
import meshio
import numpy as np

mesh_path, edits_path, axis, coord, rows, row_nodes, kind = sys.argv[1:8]
axis, coord, rows, row_nodes = int(axis), float(coord), int(rows), int(row_nodes)
m = meshio.read(mesh_path)
tets = np.vstack([c.data for c in m.cells if c.type == "tetra"])
pts = m.points.copy()
lines = [l.split() for l in open(edits_path) if l.strip() and not l.startswith("#")]
assert lines[0] == ["keratome-edits", "1"], lines[0]
nhead = next(i for i, l in enumerate(lines) if l[0] == "mesh") + 1
head = {l[0]: l for l in lines[1:nhead]}
assert len(head["hash"]) == 2 and len(head["hash"][1]) == 16, head.get("hash")
assert int(head["mesh"][-2]) == len(pts) and int(head["mesh"][-1]) == len(tets), head["mesh"]
assert head["scene"][1].startswith('"/') and head["plan"][1].startswith('"/'), "absolute paths, quoted"
assert lines[-1] == ["done", str(sum(l[0] == "step" for l in lines))], lines[-1]
nn = len(pts)
steps, dups, forces, fixes = 0, [], {}, []
cur = tets.copy()
for l in lines[nhead:]:
    if l[0] == "step":
        steps += 1
        assert int(l[1]) == steps, l
    elif l[0] == "dup":
        node, new, count = int(l[1]) - 1, int(l[2]) - 1, int(l[3])
        el = [int(x) - 1 for x in l[4:]]
        assert len(el) == count and new == nn, f"new node {new + 1}, expected {nn + 1}"
        for t in el:
            hit = cur[t] == node
            assert hit.sum() == 1, f"tet {t + 1} does not hold node {node + 1}"
            cur[t][hit] = new
        pts = np.vstack([pts, pts[node]])
        dups.append((node, new))
        nn += 1
    elif l[0] == "force":
        forces[int(l[1]) - 1] = np.array([float(x) for x in l[2:5]])
    elif l[0] == "fix":
        fixes.append((int(l[1]) - 1, l[2], [float(x) for x in l[3:]]))
if kind == "cut":
    assert steps == rows, f"{steps} steps, expected {rows}"
    assert len(dups) == rows * row_nodes, f"{len(dups)} duplicated, expected {rows * row_nodes}"
    split = {o for o, _ in dups}
    cen = pts[cur].mean(axis=1)[:, axis] - coord
    for t in range(len(cur)):
        for v in cur[t]:
            if v >= len(m.points):
                assert cen[t] > 0, f"tet {t + 1} holds new node {v + 1} on the - side"
            elif v in split:
                assert cen[t] < 0, f"tet {t + 1} keeps split node {v + 1} on the + side"
    total = sum(forces.values())
    assert np.allclose(total, 0, atol=1e-15), f"pull forces do not balance: {total}"
    pos = sum(f for v, f in forces.items() if v >= len(m.points))
    assert pos[axis] > 0, "the new side is pulled along +normal"
else:
    assert steps == rows and len(fixes) == rows * row_nodes, f"{steps} steps, {len(fixes)} fixes"
print(f"{edits_path}: {steps} steps, {len(dups)} duplicated, {len(forces)} forces, {len(fixes)} fixes")
EOF

for s in beam-16 brick-4; do
    check "mesh-prep $s" "$build/mesh-prep" -q plans/bench/$s.yaml -o "$tmp/$s.msh" > /dev/null
    check "cutplan cut-$s" "$build/cutplan" -q plans/bench/cut-$s.yaml "$tmp/$s.msh" -o "$tmp/cut-$s.edits"
    check "cutplan deform-$s" "$build/cutplan" -q plans/bench/deform-$s.yaml "$tmp/$s.msh" -o "$tmp/deform-$s.edits"
done
# beam-16: plane y = 2 mm, 7 rows of 5 nodes; brick-4: plane x = 0.5 mm, 4 rows of 5 nodes
check "beam cut read back" $py "$tmp/check.py" "$tmp/beam-16.msh" "$tmp/cut-beam-16.edits" 1 2.0 7 5 cut
check "brick cut read back" $py "$tmp/check.py" "$tmp/brick-4.msh" "$tmp/cut-brick-4.edits" 0 0.5 4 5 cut
check "beam deform read back" $py "$tmp/check.py" "$tmp/beam-16.msh" "$tmp/deform-beam-16.edits" 1 0 25 1 deform
check "brick deform read back" $py "$tmp/check.py" "$tmp/brick-4.msh" "$tmp/deform-brick-4.edits" 1 0 25 1 deform

# stdout streams the same bytes; progress stays on stderr
"$build/cutplan" plans/bench/cut-beam-16.yaml "$tmp/beam-16.msh" -o - > "$tmp/stream.edits" 2> "$tmp/stream.err"
check "cutplan -o - exits 0" test $? -eq 0
check "stream equals file" cmp -s "$tmp/stream.edits" "$tmp/cut-beam-16.edits"
check "summary on stderr" grep -q "7 steps, 35 nodes duplicated" "$tmp/stream.err"
# a P2 mesh: the mid-edge nodes on the cut duplicate with the vertices (more nodes per row)
check "mesh-prep P2" "$build/mesh-prep" -q plans/bench/beam-16.yaml --order 2 -o "$tmp/beam2.msh" > /dev/null
check "cutplan P2" "$build/cutplan" -q plans/bench/cut-beam-16.yaml "$tmp/beam2.msh" -o "$tmp/p2.edits"
n1=$(grep -c '^dup' "$tmp/cut-beam-16.edits"); n2=$(grep -c '^dup' "$tmp/p2.edits")
check "P2 duplicates mid-edge nodes too ($n2 > 2 x $n1)" test "$n2" -gt $((2 * n1))
check "--help" "$build/cutplan" --help > /dev/null
exit $fail
