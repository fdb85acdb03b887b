#!/bin/bash
# meshprep_errors.sh BUILD_DIR: bad scenes and bad usage make mesh-prep exit 2 with one line
# on stderr naming file:line:col (or the file) and what was expected, and leave no output.
set -u
bin="$1/mesh-prep"
tmp=$(mktemp -d /tmp/kt-meshprep-err.XXXXXX)
trap 'rm -rf "$tmp"' EXIT
fail=0

# expect_fail NAME PATTERN ARGS...: exit 2, exactly one stderr line matching PATTERN, nothing
# on stdout, and no file left in the output folder.
expect_fail() {
    local name=$1 pattern=$2
    shift 2
    rm -rf "$tmp/out"
    mkdir "$tmp/out"
    "$bin" "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    local rc=$?
    local lines
    lines=$(wc -l <"$tmp/stderr")
    if [ $rc -ne 2 ]; then echo "FAILED $name: exit $rc, expected 2"; fail=1; fi
    if [ "$lines" -ne 1 ]; then echo "FAILED $name: $lines lines on stderr"; cat "$tmp/stderr"; fail=1; fi
    if ! grep -qE -- "$pattern" "$tmp/stderr"; then
        echo "FAILED $name: stderr does not match '$pattern':"; cat "$tmp/stderr"; fail=1
    fi
    if [ -s "$tmp/stdout" ]; then echo "FAILED $name: output on stdout"; fail=1; fi
    if [ -n "$(ls -A "$tmp/out")" ]; then echo "FAILED $name: left $(ls -A "$tmp/out")"; fail=1; fi
}

scene() { # scene NAME TEXT: write a scene file
    printf '%s' "$2" >"$tmp/$1.yaml"
}

scene malformed $'model: eye\neye:\n  extent: [90 deg\n'
expect_fail malformed "malformed.yaml:4:1: expected well-formed YAML" "$tmp/malformed.yaml" -o "$tmp/out/x.msh"

scene unknown $'model: eye\neye:\n  central_thicknes: 540 um\n'
expect_fail "unknown key" "unknown.yaml:3:3: eye: unknown key 'central_thicknes'" "$tmp/unknown.yaml" -o "$tmp/out/x.msh"

scene negative $'model: eye\neye:\n  peripheral_thickness: -0.6 mm\n'
expect_fail "negative thickness" "negative.yaml:3:25: eye.peripheral_thickness: expected a length in \[0.05, 5\] mm" \
    "$tmp/negative.yaml" -o "$tmp/out/x.msh"

# a limbal band of 0 would divide by zero in the fibre frames (lib/model/eye_fibre.c)
scene band0 $'model: eye\neye:\n  fibres: {limbal_band: 0 mm}\n'
expect_fail "limbal band 0" "band0.yaml:3:25: eye.fibres.limbal_band: expected a length in \\(0, 5\\] mm" \
    "$tmp/band0.yaml" -o "$tmp/out/x.msh"

# the toric posterior (keratome-scene(5)): one of the two forms, the pair together, steep at
# most flat, radii and axis in range; each refused before any meshing
scene postboth $'model: eye\neye:\n  posterior_radius: 6.7 mm\n  posterior_radius_steep: 6.5 mm\n  posterior_radius_flat: 6.9 mm\n'
expect_fail "posterior radius and pair" "postboth.yaml:3:21: eye.posterior_radius: expected either posterior_radius or the steep/flat pair" \
    "$tmp/postboth.yaml" -o "$tmp/out/x.msh"
scene posthalf $'model: eye\neye:\n  posterior_radius_steep: 6.5 mm\n'
expect_fail "posterior steep without flat" "posthalf.yaml:3:27: eye.posterior_radius_steep: expected posterior_radius_steep and posterior_radius_flat together" \
    "$tmp/posthalf.yaml" -o "$tmp/out/x.msh"
scene postorder $'model: eye\neye:\n  posterior_radius_steep: 6.9 mm\n  posterior_radius_flat: 6.5 mm\n'
expect_fail "posterior steep flatter than flat" "postorder.yaml:3:27: eye.posterior_radius_steep: expected at most posterior_radius_flat" \
    "$tmp/postorder.yaml" -o "$tmp/out/x.msh"
scene postaxis $'model: eye\neye:\n  posterior_radius_steep: 6.5 mm\n  posterior_radius_flat: 6.9 mm\n  posterior_steep_axis: 200 deg\n'
expect_fail "posterior axis out of range" "postaxis.yaml:5:25: eye.posterior_steep_axis: expected an angle in \[0, 180\]" \
    "$tmp/postaxis.yaml" -o "$tmp/out/x.msh"
scene postrange $'model: eye\neye:\n  posterior_radius_steep: 0.5 mm\n  posterior_radius_flat: 6.9 mm\n'
expect_fail "posterior radius out of range" "postrange.yaml:3:27: eye.posterior_radius_steep: expected a length in \[1, 50\] mm" \
    "$tmp/postrange.yaml" -o "$tmp/out/x.msh"
scene postcyl $'model: eye\neye:\n  posterior_radius_steep: 5 mm\n  posterior_radius_flat: 10 mm\n'
expect_fail "posterior cylinder too large" "eye.posterior_radius_steep: .*expected" "$tmp/postcyl.yaml" -o "$tmp/out/x.msh"

scene oz $'model: eye\neye:\n  white_to_white: 11.7 mm\n  optical_zone: 12 mm\n'
expect_fail "optical zone outside the cornea" "oz.yaml:4:17: eye.optical_zone: expected a diameter inside the clear cornea" \
    "$tmp/oz.yaml" -o "$tmp/out/x.msh"

scene ring $'model: eye\neye:\n  incision_rings:\n    - {name: lri, diameter: 12 mm, depth_fraction: 0.9}\n'
expect_fail "ring outside the cornea" "ring.yaml:4:29: eye.incision_rings\[0\].diameter: expected a diameter in" \
    "$tmp/ring.yaml" -o "$tmp/out/x.msh"

scene floorlow $'model: eye\neye:\n  mesh_size: {incision: 0.2 mm, incision_floor: 2 um}\n'
expect_fail "incision floor below its bound" "floorlow.yaml:3:49: eye.mesh_size.incision_floor: expected a length in \\[0.005, 1\\] mm" \
    "$tmp/floorlow.yaml" -o "$tmp/out/x.msh"

scene floorhigh $'model: eye\neye:\n  mesh_size: {incision: 0.2 mm, incision_floor: 0.3 mm}\n'
expect_fail "incision floor coarser than the ring" "floorhigh.yaml:3:49: eye.mesh_size.incision_floor: expected at most mesh_size.incision \\(0.2 mm\\)" \
    "$tmp/floorhigh.yaml" -o "$tmp/out/x.msh"

scene floorunit $'model: eye\neye:\n  mesh_size:\n    incision_floor: 30\n'
expect_fail "incision floor without a unit" "floorunit.yaml:4:21: eye.mesh_size.incision_floor: expected a length" \
    "$tmp/floorunit.yaml" -o "$tmp/out/x.msh"

# The eye's sizes bound the work before any meshing: 20 um everywhere asks for about a billion
# tets (estimated from the regions' volumes), refused at the mesh_size block.
scene budget $'model: eye\norder: 2\neye:\n  mesh_size: {optical_zone: 20 um, incision: 20 um, cornea: 20 um, sclera: 20 um}\n'
expect_fail "eye sizes beyond the tet budget" "budget.yaml:4:14: eye.mesh_size: expected sizes that ask for at most 2000000 tets at order 2" \
    "$tmp/budget.yaml" -o "$tmp/out/x.msh"

scene nofile $'model: surface\nsurface:\n  file: missing.off\n  facet_size: 1 mm\n  facet_distance: 0.1 mm\n  cell_size: 1 mm\n'
expect_fail "missing model file" "nofile.yaml:3:9: surface.file: expected an existing, readable file" \
    "$tmp/nofile.yaml" -o "$tmp/out/x.msh"

# the wound: section (keratome-scene(5), WOUND)
wound() { # wound NAME PATTERN TEXT: a scene with that wound section must be refused
    scene "$1" "model: eye"$'\n'"$3"
    expect_fail "wound $1" "$1.yaml:$2" "$tmp/$1.yaml" -o "$tmp/out/x.msh"
}
wound wstate "3:10: wound.state: expected one of: immediate, healed, got 'scarred'" $'wound:\n  state: scarred\n'
wound wunitless "4:21: wound.bridge_stiffness: expected a stiffness per area with a unit \\(MPa/mm" \
    $'wound:\n  state: healed\n  bridge_stiffness: 0.5\n'
wound wdim "3:21: wound.bridge_stiffness: expected a stiffness per area .* got a pressure in '0.5 MPa'" \
    $'wound:\n  bridge_stiffness: 0.5 MPa\n'
wound wneg "3:21: wound.bridge_stiffness: expected a stiffness per area in \\[0, 1e\\+06\\] MPa/mm, got '-1 MPa/mm'" \
    $'wound:\n  bridge_stiffness: -1 MPa/mm\n'
wound wrate "3:13: wound.age_rate: expected a rate per year in \\[-0.2, 0.2\\] /y, got '1 /y'" $'wound:\n  age_rate: 1 /y\n'
wound wmonths "3:11: wound.months: expected a time \\(months, d, wk, y\\), got a length in '4 mm'" $'wound:\n  months: 4 mm\n'
wound wkey "3:3: wound: unknown key 'stiffness'" $'wound:\n  stiffness: 1 MPa/mm\n'
wound wtau "3:14: wound.heal_time: expected a time in \\(0, 600\\] months, got '0 months'" $'wound:\n  heal_time: 0 months\n'
wound wage "3:8: wound.age: expected a number in \\[0, 130\\], got '200'" $'wound:\n  age: 200\n'
wound wscalar "2:8: wound: expected a mapping" $'wound: healed\n'

expect_fail "missing scene file" "no-such-scene.yaml: cannot open" "$tmp/no-such-scene.yaml" -o "$tmp/out/x.msh"

expect_fail "nonexistent output folder" "$tmp/out/none/x.msh: cannot create output file" \
    plans/bench/beam-4.yaml -o "$tmp/out/none/x.msh"

expect_fail "no output option" "expected -o OUT.msh" plans/bench/beam-4.yaml
expect_fail "bad ordering" "unknown --ordering: rcm" plans/bench/beam-4.yaml -o "$tmp/out/x.msh" --ordering rcm
expect_fail "bad order" "--order expects 1 or 2" plans/bench/beam-4.yaml -o "$tmp/out/x.msh" --order 3

# A good scene into the same folder does leave its file (the checks above can see files).
"$bin" plans/bench/beam-4.yaml -o "$tmp/out/ok.msh" -q >/dev/null 2>&1
if [ ! -s "$tmp/out/ok.msh" ]; then echo "FAILED: good scene wrote nothing"; fail=1; fi

exit $fail
