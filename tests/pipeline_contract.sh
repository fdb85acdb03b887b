#!/usr/bin/env bash
# pipeline_contract.sh BUILD_DIR: the contract between the tools (issue 15).
# - cutplan writes the mesh's content hash into the edits header; augsolve takes the same mesh
#   in another file format (binary MSH: same hash) and refuses a mesh with the same counts but
#   other coordinates (exit 2, naming both hashes), leaving no run folder files;
# - a plan asking for more steps than keratome-plan(5) allows (degrees_per_step: 1e-9 deg) is
#   refused at load time with exit 2 and its file:line:col;
# - run.yaml holds paths relative to the run folder: after the tree holding the run and its
#   inputs is moved, each path still names the file it named.
set -uo pipefail
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt_contract.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }

mkdir -p "$T/tree/in"
cp plans/bench/beam-4.yaml plans/bench/cut-beam-4.yaml "$T/tree/in/"
in="$T/tree/in"
"$B/mesh-prep" -q "$in/beam-4.yaml" -o "$in/beam.msh" >/dev/null || { echo "mesh-prep failed"; exit 1; }
"$B/mesh-prep" -q --binary "$in/beam-4.yaml" -o "$in/beam-bin.msh" >/dev/null || exit 1
# same grid, other spacing: the same node and tet counts, other coordinates
sed 's/^  size: .*/  size: [5 mm, 5 mm, 4 mm]/' "$in/beam-4.yaml" > "$in/wide.yaml"
"$B/mesh-prep" -q "$in/wide.yaml" -o "$in/wide.msh" >/dev/null || exit 1
"$B/cutplan" -q "$in/cut-beam-4.yaml" "$in/beam.msh" -o "$in/cut.edits" || { echo "cutplan failed"; exit 1; }

if grep -Eq '^hash [0-9a-f]{16}$' "$in/cut.edits"; then ok "edits header has the mesh hash"
else bad "edits header lacks 'hash <16 hex>'"; head -5 "$in/cut.edits"; fi

"$B/augsolve" -q "$in/beam-bin.msh" "$in/cut.edits" -o "$T/bin-run" --no-vtk 2>"$T/err"
rc=$?
[ $rc -eq 0 ] && ok "binary MSH of the same mesh: same hash, accepted" ||
    { bad "binary MSH of the same mesh refused (exit $rc)"; cat "$T/err"; }

"$B/augsolve" -q "$in/wide.msh" "$in/cut.edits" -o "$T/wide-run" 2>"$T/err"
rc=$?
want=$(grep -m1 '^hash ' "$in/cut.edits" | cut -d' ' -f2)
if [ $rc -eq 2 ] && [ "$(wc -l <"$T/err")" -eq 1 ] && grep -q "header hash $want, mesh .*wide.msh hashes to" "$T/err"; then
    ok "other coordinates, same counts: exit 2: $(cat "$T/err")"
else
    bad "other coordinates, same counts: exit $rc"; cat "$T/err"
fi
[ -z "$(ls -A "$T/wide-run" 2>/dev/null)" ] || bad "refused run left files: $(ls "$T/wide-run")"

# The issue's runaway plan: refused when loaded, before the mesh is even read.
cat > "$T/tiny.yaml" <<EOP
name: tiny
scene: $PWD/plans/eye.yaml
incisions:
  - meridian: 90 deg
    arc: 60 deg
    depth_fraction: 0.9
    position: {surface: incision-ring-1}
progression:
  degrees_per_step: 1e-9 deg
EOP
"$B/cutplan" -q "$T/tiny.yaml" "$T/no-such.msh" -o "$T/tiny.edits" 2>"$T/err"
rc=$?
if [ $rc -eq 2 ] && grep -q "tiny.yaml:9:21: progression.degrees_per_step: expected at most 3600 steps" "$T/err" &&
    [ ! -e "$T/tiny.edits" ]; then
    ok "degrees_per_step 1e-9 deg: exit 2: $(cat "$T/err")"
else
    bad "degrees_per_step 1e-9 deg: exit $rc"; cat "$T/err"
fi

# A run folder inside the tree; then the whole tree moves.
"$B/augsolve" -q "$in/beam.msh" "$in/cut.edits" -o "$T/tree/run" --no-vtk 2>"$T/err" ||
    { bad "augsolve run"; cat "$T/err"; }
if grep -E '^(mesh|scene|plan|edits): "/' "$T/tree/run/run.yaml"; then bad "run.yaml has absolute paths"
else ok "run.yaml paths are relative"; fi
mv "$T/tree" "$T/moved"
for key in mesh scene plan edits; do
    p=$(sed -n "s/^$key: \"\(.*\)\"$/\1/p" "$T/moved/run/run.yaml")
    if [ -n "$p" ] && [ -f "$T/moved/run/$p" ]; then ok "after the move, run.yaml $key '$p' resolves"
    else bad "after the move, run.yaml $key '$p' does not resolve"; fi
done
# Two augsolve runs into one folder: the second is refused while the first holds it (its edits
# come from a FIFO that this script keeps open until the second run has ended, so the first run
# holds the folder however slowly a loaded machine starts it).
B2="$T/moved/in"
"$B/cutplan" -q "$B2/cut-beam-4.yaml" "$B2/beam.msh" -o "$B2/cut.edits" || bad "cutplan after the move"
# The mesh inside the run folder, as scripts/demo.sh lays it out: run.yaml names it by its
# bare name (a stray "../" here once sent curvature to a file beside the folder).
mkdir -p "$T/inside"
cp "$T/moved/in/beam.msh" "$T/inside/beam.msh"
"$B/augsolve" -q "$T/inside/beam.msh" "$T/moved/in/cut.edits" -o "$T/inside" --no-vtk 2>"$T/err" ||
    { bad "augsolve with the mesh inside its run folder"; cat "$T/err"; }
if grep -qx 'mesh: "beam.msh"' "$T/inside/run.yaml"; then ok "a mesh inside the run folder is named beam.msh"
else bad "a mesh inside the run folder: $(grep '^mesh:' "$T/inside/run.yaml")"; fi

mkfifo "$T/fifoA"
"$B/augsolve" -q "$B2/beam.msh" "$T/fifoA" -o "$T/shared" --no-vtk 2>"$T/errA" &
apid=$!
exec 4>"$T/fifoA"
cat "$B2/cut.edits" >&4
for _ in $(seq 600); do [ -e "$T/shared/.augsolve.lock" ] && break; sleep 0.1; done
"$B/augsolve" -q "$B2/beam.msh" "$B2/cut.edits" -o "$T/shared" --no-vtk 2>"$T/errB"
rc=$?
exec 4>&-
if [ $rc -eq 2 ] && grep -q "another augsolve is writing into this run folder" "$T/errB"; then
    ok "second augsolve into a busy folder: exit 2: $(cat "$T/errB")"
else bad "second augsolve into a busy folder: exit $rc"; cat "$T/errB"; fi
wait $apid && [ -f "$T/shared/run.yaml" ] && ok "the first run completes" ||
    { bad "the first run failed"; cat "$T/errA"; }

# A re-run killed half-way: the earlier result's run.yaml is gone as soon as the re-run claims
# the folder, so the mix of old and new step files is never taken for a result.
mkfifo "$T/fifo"
"$B/augsolve" -q "$B2/beam.msh" "$T/fifo" -o "$T/shared" 2>"$T/errK" &
kpid=$!
exec 3>"$T/fifo"
sed -n '1,/^end$/p' "$B2/cut.edits" >&3     # the header and step 1 only
for _ in $(seq 600); do [ -e "$T/shared/.augsolve.lock" ] && [ ! -e "$T/shared/run.yaml" ] && break; sleep 0.1; done
sleep 1
kill -9 $kpid; wait $kpid 2>/dev/null
exec 3>&-
if [ ! -e "$T/shared/run.yaml" ] && [ ! -e "$T/shared/steps.tsv" ]; then
    ok "killed re-run: no run.yaml or steps.tsv left (left: $(ls -A "$T/shared" | tr '\n' ' '))"
else bad "killed re-run: $(ls -A "$T/shared" | tr '\n' ' ')"; fi
"$B/curvature" -q --no-png "$T/shared" -o "$T/curv" 2>"$T/errC"
rc=$?
[ $rc -eq 2 ] && ok "curvature refuses the killed run's folder: $(cat "$T/errC")" ||
    { bad "curvature on the killed run's folder: exit $rc"; cat "$T/errC"; }
exit $fail
