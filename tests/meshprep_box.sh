#!/bin/bash
# meshprep_box.sh BUILD_DIR: beam-16 through mesh-prep under every ordering; meshio (a second
# reader) reads each MSH back with the right node count and groups; the constrained and
# metis-last orderings put the declared set (face zmax and one layer of tets) last; P2 adds
# one node per edge.
set -u
bin="$1/mesh-prep"
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-meshprep-box.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { # check NAME COMMAND...: run, count a failure
    if ! "${@:2}"; then echo "FAILED: $1"; fail=1; fi
}
meshio_check() { # meshio prints a blank line on reading gmsh files: keep stdout quiet
    $py "$tmp/check.py" "$@" >/dev/null
}

# Reads an MSH with meshio and checks nodes, tets, the fixed face and (optionally) that the
# nodes of surface group 'zmax' are the last ones. Independent of keratome's own reader.
cat > "$tmp/check.py" <<'EOF'
import sys
import meshio
import numpy as np
path, want_nodes, cell_type, last = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4] == "last"
m = meshio.read(path)
n = len(m.points)
assert n == want_nodes, f"{path}: {n} nodes, expected {want_nodes}"
tets = m.cells_dict[cell_type]
assert len(tets) == 6 * 4 * 4 * 15, f"{len(tets)} tets"
tri_type = "triangle" if cell_type == "tetra" else "triangle6"
phys = {name: tag for name, (tag, dim) in m.field_data.items() if dim == 2}
assert set(phys) == {"xmin", "xmax", "ymin", "ymax", "fixed", "zmax"}, phys
def group_nodes(name):
    nodes = set()
    for block, data in zip(m.cells, m.cell_data["gmsh:physical"]):
        if block.type == tri_type:
            nodes |= set(block.data[data == phys[name]].ravel().tolist())
    return nodes
fixed, zmax = group_nodes("fixed"), group_nodes("zmax")
assert np.allclose(m.points[sorted(fixed), 2], 0), "fixed face is not z = 0"
assert np.allclose(m.points[sorted(zmax), 2], 15), "zmax face is not z = 15"
if last:
    # the set: face zmax grown by one layer of tets (ordering.halo 1) = every node at z >= 14
    top = set(np.nonzero(m.points[:, 2] >= 14 - 1e-9)[0].tolist())
    assert zmax <= top and top == set(range(n - len(top), n)), "the zmax set is not last"
# every tet positively oriented after renumbering
p = m.points
a, b, c, d = (p[tets[:, k]] for k in range(4))
vol = np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6
assert (vol > 0).all() and abs(vol.sum() - 4 * 4 * 15) < 1e-9, "volumes"
EOF

for ord in amd metis constrained metis-last natural; do
    out="$tmp/beam-$ord.msh"
    check "mesh-prep --ordering $ord" "$bin" plans/bench/beam-16.yaml -o "$out" --ordering "$ord" -q >"$tmp/sum-$ord.txt"
    last=any
    case $ord in constrained | metis-last) last=last ;; esac
    check "meshio reads $ord" meshio_check "$out" 400 tetra $last
    check "summary marks $ord" grep -q "^\* $ord " "$tmp/sum-$ord.txt"
done

# The summary's table lists the other orderings too, with nnz(L) for each.
check "summary rows" test "$(grep -cE '^[ *] (amd|metis|constrained|metis-last) ' "$tmp/sum-amd.txt")" -eq 4

# Binary output and stdout output read back the same.
check "binary" "$bin" plans/bench/beam-16.yaml -o "$tmp/bin.msh" --binary --ordering constrained -q >/dev/null
check "meshio reads binary" meshio_check "$tmp/bin.msh" 400 tetra last
"$bin" plans/bench/beam-16.yaml -o - --ordering constrained -q >"$tmp/stdout.msh" 2>"$tmp/stdout.err"
check "stdout exit" test $? -eq 0
check "meshio reads stdout" meshio_check "$tmp/stdout.msh" 400 tetra last

# P2: one extra node per edge of the grid, counted here independently of keratome.
edges=$($py -c "
import meshio
m = meshio.read('$tmp/beam-amd.msh')
e = set()
for t in m.cells_dict['tetra']:
    for i in range(4):
        for j in range(i + 1, 4):
            e.add((min(t[i], t[j]), max(t[i], t[j])))
print(len(e))" | tail -n 1)
check "mesh-prep --order 2" "$bin" plans/bench/beam-16.yaml -o "$tmp/p2.msh" --order 2 --ordering constrained -q >/dev/null
check "meshio reads P2" meshio_check "$tmp/p2.msh" $((400 + edges)) tetra10 last

exit $fail
