#!/usr/bin/env bash
# bounds_inputs.sh BUILD_DIR: every reader is bounded while it reads (issue 26, items 6, 10, 11
# and 13). /dev/zero, an endless FIFO (fed by `yes`) and a 30-byte OFF declaring 1e9 vertices
# end with exit 2 at once, under `ulimit -v` so that a reader which loads them whole fails the
# test (out of memory, exit 1) instead of eating the machine, and under `timeout` so that one
# which never ends fails too. Implausible physical values (IOP -15 mmHg, E 1e-300 MPa, K 1e308
# D, no cylinder), NaN and 1e308 mesh coordinates, a directory as an input, a UTF-8
# byte-order mark and control characters in bad input are refused with exit 2 and one line.
set -u
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt_bounds_in_XXXXXX)
feeders=()
trap 'for p in "${feeders[@]}"; do kill "$p" 2>/dev/null; done; rm -rf "$tmp"' EXIT
fails=0
LIMIT_KB=1000000 # 1 GB of address space: the tools need a fraction; /dev/zero read whole, more

# expect CODE PATTERN CMD...: CMD (under the memory limit and a 60 s timeout) exits CODE with
# one stderr line matching PATTERN (an extended regex).
expect() {
    local code=$1 pattern=$2 rc
    shift 2
    (ulimit -v $LIMIT_KB; exec timeout 60 "$@") >"$tmp/stdout" 2>"$tmp/stderr" </dev/null
    rc=$?
    local why=""
    [ $rc -eq "$code" ] || why="exit $rc, expected $code"
    [ "$(wc -l <"$tmp/stderr")" -eq 1 ] || why="$why; $(wc -l <"$tmp/stderr") stderr lines"
    grep -qE -- "$pattern" "$tmp/stderr" || why="$why; stderr lacks '$pattern'"
    if [ -n "$why" ]; then
        echo "FAIL $*: $why"; head -c 600 "$tmp/stderr"; fails=$((fails + 1))
    else
        echo "ok   $(head -c 200 "$tmp/stderr")"
    fi
}

# fifo NAME: a FIFO $tmp/NAME fed by `yes` for ever (or until its reader stops).
fifo() {
    mkfifo "$tmp/$1"
    yes >"$tmp/$1" 2>/dev/null </dev/null &
    feeders+=($!)
}

# A small mesh and its edits stream to start from.
"$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/beam.msh" >/dev/null || { echo "FAIL mesh-prep"; exit 1; }
"$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o "$tmp/beam.edits" || { echo "FAIL cutplan"; exit 1; }
"$B/test_curv" --make-run "$tmp/run" >/dev/null || { echo "FAIL test_curv --make-run"; exit 1; }

# ---- item 6: /dev/zero, an endless FIFO, a huge declared count -----------------------------
for f in yes-msh yes-edits yes-vtk yes-tsv; do fifo $f; done
expect 2 "^cutplan: /dev/zero:1:1: expected a section header, found a NUL byte" \
    "$B/cutplan" -q plans/bench/cut-beam-8.yaml /dev/zero -o "$tmp/x.edits"
expect 2 "^cutplan: .*/yes-msh:1:1: expected a section header such as .Nodes, found 'y'" \
    "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/yes-msh" -o "$tmp/x.edits"
expect 2 "^augsolve: /dev/zero:1: expected text, found a NUL byte" \
    "$B/augsolve" "$tmp/beam.msh" /dev/zero -o "$tmp/run-zero"
expect 2 "^augsolve: .*/yes-edits:1:1: expected 'keratome-edits 1'" \
    "$B/augsolve" "$tmp/beam.msh" "$tmp/yes-edits" -o "$tmp/run-yes"
expect 2 "^augsolve: /dev/zero:1:1: expected a section header, found a NUL byte" \
    "$B/augsolve" /dev/zero "$tmp/beam.edits" -o "$tmp/run-zero2"
expect 2 "^curvature: /dev/zero:1:1: expected '# vtk DataFile Version x.y'" \
    "$B/curvature" -q --mesh "$tmp/run/eye.msh" /dev/zero -o "$tmp/curv-zero"
expect 2 "^curvature: .*/yes-vtk:1:1: expected '# vtk DataFile Version x.y'" \
    "$B/curvature" -q --mesh "$tmp/run/eye.msh" "$tmp/yes-vtk" -o "$tmp/curv-yes"
expect 2 "^lri-nomogram: /dev/zero:1: expected text, found a NUL byte" \
    "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 /dev/zero
expect 2 "^lri-nomogram: .*/yes-tsv:1:1: expected a header with column eye" \
    "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 "$tmp/yes-tsv"
expect 2 "^mesh-prep: /dev/zero: byte 1048577: expected a YAML file of at most 1048576 bytes|^mesh-prep: /dev/zero: expected a YAML file" \
    "$B/mesh-prep" -q /dev/zero -o "$tmp/x.msh"
# a stream of lines of one step that never ends: refused at 4 edits a node (+1024)
{ sed -n '/^step 1/q;p' "$tmp/beam.edits"; echo "step 1"; } >"$tmp/endless.head"
mkfifo "$tmp/endless"
( cat "$tmp/endless.head"; yes "force 1 0 0 0" ) >"$tmp/endless" 2>/dev/null &
feeders+=($!)
expect 2 "^augsolve: .*/endless:[0-9]+:1: expected at most [0-9]+ edits in step 1" \
    "$B/augsolve" "$tmp/beam.msh" "$tmp/endless" -o "$tmp/run-endless"
# a 30-byte OFF declaring 1e9 vertices (CGAL would size its arrays from it: 9.6 GB)
if "$B/mesh-prep" --version >/dev/null && [ -f share/data/bunny00.off ]; then
    printf 'OFF\n1000000000 1 0\n0 0 0\n3 0 0 0\n' >"$tmp/huge.off"
    sed "s|file: .*|file: $tmp/huge.off|" plans/bench/bunny.yaml >"$tmp/huge.yaml"
    expect 2 "huge.off: expected counts the file can hold: 1000000000 vertices" \
        "$B/mesh-prep" -q "$tmp/huge.yaml" -o "$tmp/huge.msh"
    sed "s|file: .*|file: /dev/zero|" plans/bench/bunny.yaml >"$tmp/zero.yaml"
    expect 2 "/dev/zero: expected a regular file, found a device" \
        "$B/mesh-prep" -q "$tmp/zero.yaml" -o "$tmp/zero.msh"
fi

# ---- item 11: NaN and 1e308 coordinates ----------------------------------------------------
# the first node's x: in MSH 4.1 the coordinates follow the block's tags (lines 4.. of $Nodes)
for bad in nan 1e308 inf; do
    awk -v bad=$bad '/^\$Nodes/ {n = NR} n && NR == n + 2 {split($0, h); first = n + 3 + h[4]}
        first && NR == first {$1 = bad} {print}' "$tmp/beam.msh" >"$tmp/coord-$bad.msh"
    expect 2 "coord-$bad.msh:[0-9]+:1: expected a node coordinate within \\+-1e\\+06 mm, found (nan|inf|1e\\+308)" \
        "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/coord-$bad.msh" -o "$tmp/x.edits"
done

# ---- item 10: plausible physical values ----------------------------------------------------
scene() { # scene NAME FROM SED-EXPR: a copy of plans/FROM with one edit
    sed "$3" "plans/$2" >"$tmp/$1.yaml"
    echo "$tmp/$1.yaml"
}
s=$(scene iop eye.yaml 's/value: 15 mmHg/value: -15 mmHg/')
expect 2 "iop.yaml:[0-9]+:[0-9]+: loads.pressure.value: expected a pressure in \[0.000133322, 0.0133322\] MPa" \
    "$B/mesh-prep" -q "$s" -o "$tmp/x.msh"
s=$(scene iophigh eye.yaml 's/value: 15 mmHg/value: 1e308 mmHg/')
expect 2 "iophigh.yaml:[0-9]+:[0-9]+: loads.pressure.value: expected a pressure in" \
    "$B/mesh-prep" -q "$s" -o "$tmp/x.msh"
s=$(scene soft bench/beam-8.yaml 's/E: 1 MPa/E: 1e-300 MPa/')
expect 2 "soft.yaml:[0-9]+:[0-9]+: materials.body.E: expected a pressure in \[1e-06, 1000\] MPa" \
    "$B/mesh-prep" -q "$s" -o "$tmp/x.msh"
s=$(scene stiff eye.yaml 's/sclera: {E: 3.0 MPa/sclera: {E: 1e308 MPa/')
expect 2 "stiff.yaml:[0-9]+:[0-9]+: materials.sclera.E: expected a pressure in" \
    "$B/mesh-prep" -q "$s" -o "$tmp/x.msh"
sed 's/pull_force: 0.2 mN/pull_force: 1e300 N/' plans/bench/cut-beam-8.yaml >"$tmp/pull.yaml"
cp plans/bench/beam-8.yaml "$tmp/"
expect 2 "pull.yaml:[0-9]+:[0-9]+: planar_cut.pull_force: expected a force in \[0, 10\] N" \
    "$B/cutplan" -q "$tmp/pull.yaml" "$tmp/beam.msh" -o "$tmp/x.edits"
printf 'eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\n' >"$tmp/nomo.tsv"
for arc in 30 60 90; do
    printf 'a\t60\t1.5\t90\t1\t%s\t0.9\t10.5\t%s\t0\n' $arc "0.0$arc" >>"$tmp/nomo.tsv"
done
expect 2 "^lri-nomogram: --k-steep 1e308: expected a keratometry reading in \[20, 70\] D" \
    "$B/lri-nomogram" --k-steep 1e308 --k-flat 43 --axis 90 --age 66 "$tmp/nomo.tsv"
expect 2 "^lri-nomogram: --k-steep 44 --k-flat 44: expected a cylinder K steep - K flat in \(0, 10\] D" \
    "$B/lri-nomogram" --k-steep 44 --k-flat 44 --axis 90 --age 66 "$tmp/nomo.tsv"
expect 2 "^lri-nomogram: --target 0: expected a cylinder to correct in \(0, 10\] D" \
    "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --target 0 --axis 90 --age 66 "$tmp/nomo.tsv"

# ---- item 13: directories, a byte-order mark, control characters ---------------------------
mkdir "$tmp/dir.edits" "$tmp/dir.tsv" "$tmp/dir.msh"
expect 2 "^augsolve: .*/dir.edits: cannot read: is a directory" \
    "$B/augsolve" "$tmp/beam.msh" "$tmp/dir.edits" -o "$tmp/run-dir"
expect 2 "^cutplan: .*/dir.msh: cannot read: is a directory" \
    "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/dir.msh" -o "$tmp/x.edits"
expect 2 "^lri-nomogram: .*/dir.tsv: cannot read the nomogram table: is a directory" \
    "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 "$tmp/dir.tsv"
# a UTF-8 byte-order mark is skipped by every reader (YAML, MSH, edits, nomogram table)
printf '\xef\xbb\xbf' | cat - "$tmp/nomo.tsv" >"$tmp/bom.tsv"
(ulimit -v $LIMIT_KB; timeout 60 "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 "$tmp/nomo.tsv") >"$tmp/plain.out" 2>&1
(ulimit -v $LIMIT_KB; timeout 60 "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 "$tmp/bom.tsv") >"$tmp/bom.out" 2>&1
if cmp -s "$tmp/plain.out" "$tmp/bom.out" && grep -q "^1	" "$tmp/bom.out"; then echo "ok   nomogram table with a BOM"
else echo "FAIL nomogram table with a BOM:"; cat "$tmp/bom.out"; fails=$((fails + 1)); fi
printf '\xef\xbb\xbf' | cat - "$tmp/beam.msh" >"$tmp/bom.msh"
printf '\xef\xbb\xbf' | cat - "$tmp/beam.edits" >"$tmp/bom.edits"
if (ulimit -v $LIMIT_KB; timeout 120 "$B/augsolve" "$tmp/bom.msh" "$tmp/bom.edits" -o "$tmp/run-bom" -q) >/dev/null 2>"$tmp/stderr"; then
    echo "ok   MSH and edits stream with a BOM"
else echo "FAIL MSH and edits stream with a BOM:"; cat "$tmp/stderr"; fails=$((fails + 1)); fi
# control characters quoted from bad input are escaped, never sent to the terminal
{ sed -n '/^step 1/q;p' "$tmp/beam.edits"; printf '\033]0;owned\007\033[2J 1\n'; } >"$tmp/ctl.edits"
expect 2 "^augsolve: .*/ctl.edits:[0-9]+:1: expected 'step 1'( or 'done 0')?, found '\\\\x1b\]0;owned\\\\x07\\\\x1b\[2J'" \
    "$B/augsolve" "$tmp/beam.msh" "$tmp/ctl.edits" -o "$tmp/run-ctl"
if grep -q $'\033' "$tmp/stderr"; then echo "FAIL an escape byte reached stderr"; fails=$((fails + 1)); fi

if [ $fails -ne 0 ]; then echo "$fails failure(s)"; exit 1; fi
echo "all input bounds hold"
