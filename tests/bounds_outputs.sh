#!/usr/bin/env bash
# bounds_outputs.sh BUILD_DIR: outputs are never lost in silence nor put where they damage
# (issue 26, items 5, 8 and 13).
# - An output path naming a device or a FIFO is written to, never replaced by a renamed file:
#   mesh-prep -o, cutplan -o and --mesh-out to a private character device (mknod'd like
#   /dev/null, when run as root) and to a FIFO; /dev/null itself is tried only after the
#   private device came through unharmed, so that a regression cannot replace the system's.
# - An output path naming a directory is refused (exit 2) before any work.
# - A full or closed stdout is exit 1 with a message, for every tool that writes to it.
# - Temporaries of killed runs (NAME.tmp.HOST.PID.XXXXXX of a dead PID) are removed by the next
#   run; a live process's and another name's are left alone.
# - An output that names an input (the same file, also through a symbolic or a hard link) is
#   refused, exit 2, and the input is unchanged (issue 36, item 3): mesh-prep, cutplan -o and
#   --mesh-out, augsolve (a run folder holding an input it would write), lri-plan (an input
#   inside the plan folder, which is replaced whole).
# - A write error stops the run at the first failed file and names it and its cause, ENOSPC as
#   "disk full" (issue 36, item 6): /dev/full for mesh-prep and cutplan; a tiny tmpfs (mounted
#   when run as root; skipped otherwise) that holds augsolve's first step files and not the next.
set -u
B=$(cd "$1" && pwd)
cd "$(dirname "$0")/.."
tmp=$(mktemp -d /tmp/kt_bounds_out_XXXXXX)
trap 'umount "$tmp/tiny" 2>/dev/null; rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }

"$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/beam.msh" >/dev/null || { fail "mesh-prep"; exit 1; }
"$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o "$tmp/beam.edits" || { fail "cutplan"; exit 1; }

# ---- item 5: devices and FIFOs are written through ----------------------------------------
# through NAME TARGET CMD...: CMD exits 0 and TARGET is still a character device
through() {
    local name=$1 target=$2 rc=0
    shift 2
    timeout 60 "$@" >/dev/null 2>"$tmp/stderr" || rc=$?
    if [ $rc -ne 0 ]; then fail "$name: exit $rc"; cat "$tmp/stderr"; fi
    if [ -c "$target" ]; then echo "ok   $name: $target is still a character device"
    else fail "$name: $target is no longer a character device"; ls -l "$target"; fi
}
if mknod "$tmp/null" c 1 3 2>/dev/null; then
    through "mesh-prep -o device" "$tmp/null" "$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/null"
    through "cutplan -o device" "$tmp/null" "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o "$tmp/null"
    through "cutplan --mesh-out device" "$tmp/null" \
        "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o "$tmp/x.edits" --mesh-out "$tmp/null"
    # a failed cut must not remove the device it wrote the mesh to
    sed 's/pull_surface: zmax/pull_surface: nosuch/' plans/bench/cut-beam-8.yaml >"$tmp/badcut.yaml"
    cp plans/bench/beam-8.yaml "$tmp/"
    timeout 60 "$B/cutplan" -q "$tmp/badcut.yaml" "$tmp/beam.msh" -o "$tmp/y.edits" --mesh-out "$tmp/null" 2>/dev/null
    [ -c "$tmp/null" ] || fail "a refused cut removed its --mesh-out device"
    if [ $fails -eq 0 ]; then
        through "mesh-prep -o /dev/null" /dev/null "$B/mesh-prep" -q plans/bench/beam-8.yaml -o /dev/null
        through "cutplan -o /dev/null" /dev/null "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o /dev/null
    fi
else
    echo "skip device nodes: mknod needs root"
fi
# a FIFO: the reader gets the whole mesh, the FIFO stays a FIFO
mkfifo "$tmp/fifo"
timeout 60 cat "$tmp/fifo" >"$tmp/fifo.msh" &
reader=$!
rc=0
timeout 60 "$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/fifo" >/dev/null 2>"$tmp/stderr" || rc=$?
[ -p "$tmp/fifo" ] || { rm -f "$tmp/fifo"; mkfifo "$tmp/fifo"; echo >"$tmp/fifo"; } # free the reader
wait $reader
if [ $rc -eq 0 ] && [ -p "$tmp/fifo" ] && cmp -s "$tmp/fifo.msh" "$tmp/beam.msh"; then
    echo "ok   mesh-prep -o FIFO: the reader got the mesh, the FIFO is still a FIFO"
else fail "mesh-prep -o FIFO: exit $rc, $(ls -l "$tmp/fifo"), $(wc -c <"$tmp/fifo.msh") bytes read"; fi
# a symbolic link stays a link: the file it leads to is replaced
ln -s beam-copy.msh "$tmp/link.msh"
: >"$tmp/beam-copy.msh"
"$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/link.msh" >/dev/null
if [ -L "$tmp/link.msh" ] && cmp -s "$tmp/beam-copy.msh" "$tmp/beam.msh"; then echo "ok   output through a symbolic link"
else fail "output through a symbolic link: $(ls -l "$tmp/link.msh")"; fi

# ---- item 13: a directory as the output: exit 2 before meshing ----------------------------
mkdir "$tmp/outdir.msh"
rc=0
timeout 60 "$B/mesh-prep" plans/bench/beam-8.yaml -o "$tmp/outdir.msh" >"$tmp/stdout" 2>"$tmp/stderr" || rc=$?
if [ $rc -eq 2 ] && grep -q "outdir.msh: cannot write the output file: is a directory" "$tmp/stderr" &&
    ! grep -q "beam-8\|nodes\|ordering" "$tmp/stderr" && [ ! -s "$tmp/stdout" ] &&
    [ -z "$(ls -A "$tmp" | grep '\.tmp\.')" ]; then
    echo "ok   mesh-prep -o DIRECTORY: $(cat "$tmp/stderr")"
else fail "mesh-prep -o DIRECTORY: exit $rc"; cat "$tmp/stderr"; fi
rc=0
timeout 60 "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o "$tmp/outdir.msh" 2>"$tmp/stderr" || rc=$?
[ $rc -eq 2 ] && grep -q "is a directory" "$tmp/stderr" && echo "ok   cutplan -o DIRECTORY" ||
    { fail "cutplan -o DIRECTORY: exit $rc"; cat "$tmp/stderr"; }

# ---- item 8: a full or closed stdout is exit 1 -----------------------------------------------
"$B/test_curv" --make-run "$tmp/run" >/dev/null
printf 'eye\tage_y\tcyl_pre_D\taxis_deg\tincisions\tarc_deg\tdepth\tdiameter_mm\tsia_D\tsia_axis_deg\n' >"$tmp/nomo.tsv"
for arc in 30 60 90; do printf 'a\t60\t1.5\t90\t1\t%s\t0.9\t10.5\t%s\t0\n' $arc "0.0$arc" >>"$tmp/nomo.tsv"; done
# lost NAME CMD...: with stdout on /dev/full and with stdout closed, CMD exits 1 with a message
lost() {
    local name=$1 rc
    shift
    for how in full closed; do
        rc=0
        if [ $how = full ]; then timeout 120 "$@" >/dev/full 2>"$tmp/stderr" || rc=$?
        else timeout 120 "$@" >&- 2>"$tmp/stderr" || rc=$?; fi
        if [ $rc -eq 1 ] && grep -q "write failed: \(disk full (No space left on device)\|Bad file descriptor\)" "$tmp/stderr"; then
            echo "ok   $name, stdout $how: $(tail -1 "$tmp/stderr")"
        else fail "$name, stdout $how: exit $rc"; tail -3 "$tmp/stderr"; fi
    done
}
lost "curvature" "$B/curvature" -q --no-png --no-report "$tmp/run" -o "$tmp/curv1"
lost "curvature --json" "$B/curvature" -q --json --no-png --no-report "$tmp/run" -o "$tmp/curv2"
lost "lri-nomogram" "$B/lri-nomogram" --k-steep 44.5 --k-flat 43 --axis 90 --age 66 "$tmp/nomo.tsv"
lost "mesh-prep summary" "$B/mesh-prep" plans/bench/beam-8.yaml -o "$tmp/summary.msh"
lost "mesh-prep -o -" "$B/mesh-prep" -q plans/bench/beam-8.yaml -o -
lost "cutplan -o -" "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o -
lost "mesh-prep --help" "$B/mesh-prep" --help
lost "augsolve --help" "$B/augsolve" --help
# with stdout closed, no output file may take descriptor 1 and swallow what stdout was meant for
"$B/mesh-prep" plans/bench/beam-8.yaml -o "$tmp/closed.msh" >&- 2>/dev/null
if [ -f "$tmp/closed.msh" ] && grep -q "nodes" "$tmp/closed.msh" 2>/dev/null &&
    ! grep -q '^\$MeshFormat' "$tmp/closed.msh"; then fail "the summary went into the mesh file"; fi

# ---- item 13: temporaries of dead processes are cleaned, live ones kept ----------------------
host=$(hostname | tr './' '__')
sh -c 'exit 0' & dead=$!; wait $dead
stale="$tmp/clean.msh.tmp.$host.$dead.AbC123"
live="$tmp/clean.msh.tmp.$host.$$.XyZ789"
other="$tmp/other.msh.tmp.$host.$dead.AbC123"
elsewhere="$tmp/clean.msh.tmp.otherhost.$dead.AbC123"
for f in "$stale" "$live" "$other" "$elsewhere"; do echo partial >"$f"; done
"$B/mesh-prep" -q plans/bench/beam-8.yaml -o "$tmp/clean.msh" >/dev/null
if [ ! -e "$stale" ] && [ -e "$live" ] && [ -e "$other" ] && [ -e "$elsewhere" ] && [ -s "$tmp/clean.msh" ]; then
    echo "ok   a dead run's temporary removed; a live one, another target's and another host's kept"
else fail "temporaries: $(ls "$tmp" | grep '\.tmp\.' | tr '\n' ' ')"; fi

# ---- issue 36, item 3: no output over an input ----------------------------------------------
# refused NAME FILE CMD...: CMD exits 2 with "refusing" on stderr and FILE keeps its bytes
refused() {
    local name=$1 file=$2 rc=0 sum
    shift 2
    sum=$(md5sum <"$file")
    timeout 60 "$@" >/dev/null 2>"$tmp/stderr" || rc=$?
    if [ $rc -ne 2 ]; then fail "$name: exit $rc, expected 2"; cat "$tmp/stderr"
    elif ! grep -q "refusing" "$tmp/stderr"; then fail "$name: no refusal message"; cat "$tmp/stderr"
    elif [ "$(md5sum <"$file")" != "$sum" ]; then fail "$name: $file changed"
    else echo "ok   $name: $(head -1 "$tmp/stderr")"; fi
}
mkdir -p "$tmp/in"
cp plans/bench/beam-8.yaml plans/bench/cut-beam-8.yaml "$tmp/in/"
cp "$tmp/beam.msh" "$tmp/beam.edits" "$tmp/in/"
ln -s beam-8.yaml "$tmp/in/link.yaml"
ln "$tmp/in/beam-8.yaml" "$tmp/in/hard.yaml"
refused "mesh-prep S.yaml -o S.yaml" "$tmp/in/beam-8.yaml" "$B/mesh-prep" -q "$tmp/in/beam-8.yaml" -o "$tmp/in/beam-8.yaml"
refused "mesh-prep -o a symbolic link to the scene" "$tmp/in/beam-8.yaml" "$B/mesh-prep" -q "$tmp/in/beam-8.yaml" -o "$tmp/in/link.yaml"
refused "mesh-prep -o a hard link to the scene" "$tmp/in/beam-8.yaml" "$B/mesh-prep" -q "$tmp/in/beam-8.yaml" -o "$tmp/in/hard.yaml"
refused "cutplan P M -o M" "$tmp/in/beam.msh" "$B/cutplan" -q "$tmp/in/cut-beam-8.yaml" "$tmp/in/beam.msh" -o "$tmp/in/beam.msh"
refused "cutplan -o the plan" "$tmp/in/cut-beam-8.yaml" "$B/cutplan" -q "$tmp/in/cut-beam-8.yaml" "$tmp/in/beam.msh" -o "$tmp/in/cut-beam-8.yaml"
refused "cutplan --mesh-out the plan's scene" "$tmp/in/beam-8.yaml" \
    "$B/cutplan" -q "$tmp/in/cut-beam-8.yaml" "$tmp/in/beam.msh" -o "$tmp/in/x.edits" --mesh-out "$tmp/in/beam-8.yaml"
mkdir -p "$tmp/run"
cp "$tmp/beam.msh" "$tmp/run/step-0001.vtk"
refused "augsolve with an input named like its step file" "$tmp/run/step-0001.vtk" \
    "$B/augsolve" -q "$tmp/run/step-0001.vtk" "$tmp/in/beam.edits" -o "$tmp/run"
cp plans/patients/wtr-od.yaml "$tmp/run/patient.yaml"
refused "lri-plan with its patient inside the plan folder" "$tmp/run/patient.yaml" \
    "$B/lri-plan" -q "$tmp/run/patient.yaml" -o "$tmp"
# the mesh in its run folder (scripts/demo.sh's layout) is no output of augsolve: it runs
"$B/cutplan" -q "$tmp/in/cut-beam-8.yaml" "$tmp/in/beam.msh" -o "$tmp/in/beam.edits" &&
    cp "$tmp/in/beam.msh" "$tmp/run/eye.msh" &&
    "$B/augsolve" -q --no-vtk "$tmp/run/eye.msh" "$tmp/in/beam.edits" -o "$tmp/run" ||
    fail "augsolve with its mesh in the run folder (not an output) was refused"

# ---- issue 36, item 6: a full disk stops the run, naming the file and "disk full" -----------
# full NAME PATTERN CMD...: CMD exits 1 with PATTERN on stderr
full() {
    local name=$1 pat=$2 rc=0
    shift 2
    timeout 60 "$@" >/dev/null 2>"$tmp/stderr" || rc=$?
    if [ $rc -ne 1 ]; then fail "$name: exit $rc, expected 1"; cat "$tmp/stderr"
    elif ! grep -q -- "$pat" "$tmp/stderr"; then fail "$name: stderr lacks '$pat'"; cat "$tmp/stderr"
    else echo "ok   $name: $(tail -1 "$tmp/stderr")"; fi
}
if [ -w /dev/full ]; then
    full "mesh-prep -o /dev/full" "/dev/full: write failed: disk full" "$B/mesh-prep" -q plans/bench/beam-8.yaml -o /dev/full
    full "cutplan -o /dev/full" "/dev/full: write failed: disk full" \
        "$B/cutplan" -q plans/bench/cut-beam-8.yaml "$tmp/beam.msh" -o /dev/full
fi
mkdir -p "$tmp/tiny"
if mount -t tmpfs -o size=100k kt-full "$tmp/tiny" 2>/dev/null; then
    # step-0000.vtk (51 kB) and step-0001.vtk (32 kB) fit, step-0002.vtk does not
    full "augsolve on a full disk" "run/step-0002.vtk: write failed: disk full (No space left on device)" \
        "$B/augsolve" -q "$tmp/beam.msh" "$tmp/beam.edits" -o "$tmp/tiny/run"
    left=$(ls -A "$tmp/tiny/run" | tr '\n' ' ')
    [ "$left" = "step-0000.vtk step-0001.vtk " ] || fail "augsolve on a full disk left: $left (expected the two whole step files, no temporary, no run.yaml)"
    umount "$tmp/tiny" || fail "umount $tmp/tiny"
else
    echo "skip the full tmpfs: mount needs root"
fi

if [ $fails -ne 0 ]; then echo "$fails failure(s)"; exit 1; fi
echo "all output bounds hold"
