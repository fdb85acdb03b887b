#!/bin/bash
# meshprep_axes.sh BUILD_DIR: the default eye (coarsened, incision floor kept at 100 um) meshed
# with its steep axis (and its toric posterior's steep axis) at 0, 15, ..., 165 deg, and once
# with ordering.centre set apart from the steep axis (150 deg on a 0 deg eye). Every meshing must succeed (axes above 90 deg once failed
# in gmsh's parser: the floor field's expression held "x*-0.5"), and a second reader (meshio)
# checks that the floor refinement follows the meridian: on the incision ring, the triangles
# within 30 deg of the centre meridian (or its opposite) have a median shortest edge under 0.6x
# that of the triangles more than 60 deg from it.
set -u
build="$1"
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-meshprep-axes.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh --floor 100 0.6 0.3 0.8 2.5 "$tmp/base.yaml" && grep -q "^  steep_axis: 90 deg" "$tmp/base.yaml" &&
    grep -q "^  posterior_steep_axis: 90 deg" "$tmp/base.yaml" ||
    { echo "FAILED: could not coarsen the eye"; exit 1; }

cat > "$tmp/check.py" <<'EOF'
import sys
import meshio
import numpy as np
path, centre = sys.argv[1], float(sys.argv[2])
m = meshio.read(path)
tag = m.field_data["incision-ring-1"][0]
near, far = [], []
for block, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
    if not block.type.startswith("triangle"):
        continue
    for tri in block.data[phys == tag][:, :3]:
        x = m.points[tri]
        e = min(np.linalg.norm(x[i] - x[(i + 1) % 3]) for i in range(3))
        c = x.mean(0)
        d = abs((np.degrees(np.arctan2(c[1], c[0])) - centre + 90) % 180 - 90)  # 0-90 deg
        if d < 30:
            near.append(e)
        elif d > 60:
            far.append(e)
assert near and far, f"{path}: no ring triangles near ({len(near)}) or far ({len(far)})"
ratio = np.median(near) / np.median(far)
assert ratio < 0.6, f"{path}: floor refinement not at {centre} deg (median edge ratio {ratio:.2f})"
EOF

mesh() { # mesh AXIS CENTRE: mesh the eye with that steep axis (and ordering centre, or "")
    local y="$tmp/eye-$1-$2.yaml"
    # the toric posterior (plans/eye.yaml's, steep at 90 deg) turns with the anterior
    sed -e "s/^  steep_axis: 90 deg/  steep_axis: $1 deg/" \
        -e "s/^  posterior_steep_axis: 90 deg/  posterior_steep_axis: $1 deg/" "$tmp/base.yaml" > "$y"
    [ -n "$2" ] && printf '  centre: %s deg\n' "$2" > "$tmp/centre" &&
        sed -i "/^ordering:/r $tmp/centre" "$y"
    if ! "$build/mesh-prep" -q "$y" -o "$tmp/eye.msh" --ordering natural > /dev/null 2> "$tmp/err"; then
        echo "FAILED: steep axis $1 deg${2:+, ordering.centre $2 deg}: mesh-prep: $(tail -1 "$tmp/err")"
        fail=1; return
    fi
    $py "$tmp/check.py" "$tmp/eye.msh" "${2:-$1}" > /dev/null || fail=1
}
for axis in 0 15 30 45 60 75 90 105 120 135 150 165; do mesh "$axis" ""; done
mesh 0 150
[ $fail = 0 ] && echo "meshprep_axes: 13 meshings (steep axis 0-165 deg, one ordering.centre apart): ok"
exit $fail
