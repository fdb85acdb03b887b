#!/bin/bash
# meshprep_departure.sh BUILD_DIR: a scene's measured anterior surface (keratome-scene(5),
# eye.anterior_departure) read by mesh-prep and checked by a second reader. The default eye,
# coarsened, gets an aspheric base (Q -0.2) and a departure of order 4 (astigmatism, coma,
# trefoil, spherical terms of a few um) over a 4 mm zone tapered to 0 at 5.85 mm, and a
# posterior departure. mesh-prep meshes it twice: the same bytes. Python (meshio, numpy)
# evaluates the format as keratome-scene(5) states it, with its own Zernike polynomials (OSA/ANSI
# index, normalized, the radial polynomial from its factorial sum), the aspheric base (the
# biconic of the eye's radii with Q, its apex at the toric's less the conic's height at the
# corneal edge) and the C2 extension beyond the zone: every anterior node within 1e-8 mm, the
# taper reached (nodes past 5.85 mm on the base). Bad departures are refused with file:line:col and exit 2, nothing written.
set -u
build="$1"
py=/usr/bin/python3
tmp=$(mktemp -d /tmp/kt-meshprep-departure.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0
printf 'leak:libgmsh.so\n' > "$tmp/lsan.supp"
export LSAN_OPTIONS="suppressions=$tmp/lsan.supp:print_suppressions=0"
bash tests/lib/coarse-eye.sh 0.6 0.5 0.8 2.5 "$tmp/oval.yaml" || { echo "FAILED: could not coarsen the eye"; exit 1; }
# The eye made round (vertical white-to-white = horizontal): the checks below state the format
# on the surface of revolution, its taper reached in every meridian (on the default oval eye
# the anterior surface ends inside 5.85 mm but in the horizontal meridian; the oval with the
# measured surfaces: tests/optics/test_measured_eye.c).
sed 's/^\(    vertical:\) *10.6 mm/\1 11.7 mm/' "$tmp/oval.yaml" > "$tmp/base.yaml"
grep -q '^    vertical: 11.7 mm' "$tmp/base.yaml" || { echo "FAILED: could not make the eye round"; exit 1; }

# The departure blocks, inserted into the eye block before its white_to_white mapping.
ant='  anterior_departure:
    asphericity: -0.2
    zernike_order: 4
    radius: 4 mm
    taper: 5.85 mm
    coefficients: [0 um, 0 um, 0 um, 2 um, 3 um, -1.5 um, 1 um, -3 um, 2 um, 1.5 um,
                   0.5 um, 0 um, 4 um, -0.8 um, -1 um]'
post='  posterior_departure:
    zernike_order: 3
    radius: 2.5 mm
    taper: 5 mm
    coefficients: [0 um, 0 um, 0 um, 3 um, 0 um, 2 um, 0 um, 1 um, 2 um, 0 um]'
scene() { # OUT ANTERIOR_BLOCK POSTERIOR_BLOCK
    awk -v a="$2" -v p="$3" '/^  white_to_white:/ { if (a != "") print a; if (p != "") print p } { print }' \
        "$tmp/base.yaml" > "$1"
}
scene "$tmp/dep.yaml" "$ant" "$post"
for k in 1 2; do
    if ! "$build/mesh-prep" -q "$tmp/dep.yaml" -o "$tmp/dep$k.msh" --chosen-only > "$tmp/summary$k" 2> "$tmp/err$k"; then
        echo "FAILED: mesh-prep on the measured eye: $(cat "$tmp/err$k")"; exit 1
    fi
done
if cmp -s "$tmp/dep1.msh" "$tmp/dep2.msh"; then echo "ok   the same scene meshed twice: the same bytes"
else echo "FAILED: two meshings of the measured eye differ"; fail=1; fi

cat > "$tmp/check.py" <<'EOF'
import math, sys
import meshio
import numpy as np
m = meshio.read(sys.argv[1])
# the eye's geometry (keratome-scene(5), THE EYE): radii, axis, white-to-white, globe
rs, rf, axis, wtw, Rg, Q = 7.667, 7.938, 90.0, 11.7, 12.0, -0.2
a, b = 4.0, 5.85
coef = np.array([0, 0, 0, 2, 3, -1.5, 1, -3, 2, 1.5, 0.5, 0, 4, -0.8, -1]) * 1e-3
Ra, rc = 2 / (1 / rs + 1 / rf), wtw / 2
c = 1 / Ra  # the mean apical curvature: the aspheric base's apex drops by its conic's height at the edge
c0 = c * rc**2 / (1 + math.sqrt(1 - (c * rc)**2)) - c * rc**2 / (1 + math.sqrt(1 - (1 + Q) * (c * rc)**2))
z_apex = math.sqrt(Rg**2 - rc**2) - math.sqrt(Ra**2 - rc**2) + Ra - c0
def zern(j, rho, t):
    n = math.ceil((-3 + math.sqrt(9 + 8 * j)) / 2)
    mm = 2 * j - n * (n + 2)
    R = sum((-1)**s * math.factorial(n - s) / (math.factorial(s) * math.factorial((n + abs(mm)) // 2 - s)
            * math.factorial((n - abs(mm)) // 2 - s)) * rho**(n - 2 * s) for s in range((n - abs(mm)) // 2 + 1))
    N = math.sqrt((1 if mm == 0 else 2) * (n + 1))
    return N * R * (math.cos(mm * t) if mm >= 0 else math.sin(-mm * t))
def P(r, t):
    return sum(c * zern(j, r / a, t) for j, c in enumerate(coef))
def D(x, y):
    r, t = math.hypot(x, y), math.atan2(y, x)
    if r <= a: return P(r, t)
    if r >= b: return 0.0
    h = 1e-3
    d0, dr, drr = P(a, t), (P(a + h, t) - P(a - h, t)) / (2 * h), (P(a + h, t) - 2 * P(a, t) + P(a - h, t)) / h**2
    s, tt = r - a, (r - a) / (b - a)
    return (d0 + s * dr + 0.5 * s * s * drr) * (1 - tt**3 * (10 - 15 * tt + 6 * tt * tt))
def base_sag(x, y):
    th = math.radians(axis)
    u, v = x * math.cos(th) + y * math.sin(th), -x * math.sin(th) + y * math.cos(th)
    q1, q2 = u * u / rs + v * v / rf, u * u / rs**2 + v * v / rf**2
    return q1 / (1 + math.sqrt(1 - (1 + Q) * q2))
tag = m.field_data["anterior"][0]
nodes = set()
for block, phys in zip(m.cells, m.cell_data["gmsh:physical"]):
    if block.type.startswith("triangle"):
        nodes.update(block.data[phys == tag].ravel().tolist())
worst, worst_out, big, n_out = 0.0, 0.0, 0.0, 0
for i in nodes:
    x, y, z = m.points[i]
    d = D(x, y)
    big = max(big, abs(d))
    worst = max(worst, abs(z - (z_apex - base_sag(x, y) + d)))
    if math.hypot(x, y) >= b:
        n_out += 1
        worst_out = max(worst_out, abs(z - (z_apex - base_sag(x, y))))
fails = 0
def check(cond, what):
    global fails
    print(("ok   " if cond else "FAILED: ") + what)
    fails += not cond
check(len(nodes) > 500 and big > 4e-3, f"{len(nodes)} anterior nodes, the departure up to {1000 * big:.2f} um")
check(worst < 1e-8, f"every anterior node on the aspheric base + departure as keratome-scene(5) states it: worst {worst:.2e} mm")
check(n_out > 50 and worst_out < 1e-8, f"{n_out} anterior nodes past the taper on the base alone: worst {worst_out:.2e} mm")
sys.exit(1 if fails else 0)
EOF
$py "$tmp/check.py" "$tmp/dep1.msh" || fail=1

# Bad departures: file:line:col, exit 2, no mesh written.
bad() { # NAME EXPECTED ANTERIOR_BLOCK [POSTERIOR_BLOCK]
    scene "$tmp/$1.yaml" "$3" "${4:-}"
    "$build/mesh-prep" -q "$tmp/$1.yaml" -o "$tmp/$1.msh" > /dev/null 2> "$tmp/$1.err"
    local rc=$?
    if [ $rc -eq 2 ] && grep -q "$tmp/$1.yaml:[0-9]*:[0-9]*: $2" "$tmp/$1.err" && [ ! -e "$tmp/$1.msh" ]; then
        echo "ok   $1: $(head -c 160 "$tmp/$1.err")"
    else
        echo "FAILED: $1: exit $rc, $(cat "$tmp/$1.err")"; fail=1
    fi
}
bad taper "eye.anterior_departure.taper: expected more than radius (4 mm) and at most the corneal edge" \
    "$(printf '%s' "$ant" | sed 's/taper: 5.85 mm/taper: 6 mm/')"
bad count "eye.anterior_departure.coefficients (zernike_order 4): expected 15 items, found 14" \
    "$(printf '%s' "$ant" | sed 's/-0.8 um, //')"
bad order "eye.anterior_departure.zernike_order" "$(printf '%s' "$ant" | sed 's/zernike_order: 4/zernike_order: 13/')"
bad conic "eye.posterior_departure: unknown key 'asphericity'" "" "$(printf '%s' "$post" | sed 's/    zernike_order: 3/    asphericity: -0.2\n    zernike_order: 3/')"
[ $fail -eq 0 ] && echo "meshprep_departure: passed" || echo "meshprep_departure: FAILED"
exit $fail
