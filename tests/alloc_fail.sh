#!/usr/bin/env bash
# alloc_fail.sh BUILD_DIR: every allocation along a small pipeline fails once. With
# KT_ALLOC_FAIL=N the N-th kt_calloc/kt_realloc of a process fails (lib/core/util.h); for
# N = 1, 2, ... each tool - mesh-prep on a 3 x 3 x 3 box, cutplan, augsolve, curvature on a
# synthetic eye run folder (test_curv --make-run) - must end with exit 1, an "out of memory"
# line on stderr, no output file, no temporary file left and, in a sanitizer build
# (-DKT_SANITIZE=ON), no leak; until N passes the tool's last allocation and it succeeds.
# KT_ALLOC_STRIDE=K tries every K-th N only (default 1: every one); KT_ALLOC_TOOLS="augsolve
# curvature" sweeps only those tools.
set -uo pipefail
B=$(cd "${1:?build dir}" && pwd)
cd "$(dirname "$0")/.."
T=$(mktemp -d /tmp/kt_allocfail.XXXXXX)
trap 'rm -rf "$T"' EXIT
stride=${KT_ALLOC_STRIDE:-1}
export OPENBLAS_NUM_THREADS=1
# LeakSanitizer's exit code 23 tells a leak from the tools' own 1 and 2.
export ASAN_OPTIONS=detect_leaks=1:exitcode=23
export LSAN_OPTIONS=exitcode=23:suppressions=$PWD/tests/lsan.supp
fail=0

cat > "$T/box.yaml" <<'EOP'
name: tiny
model: box
box: {nodes: [3, 3, 3], size: [2 mm, 2 mm, 2 mm], fixed: zmin}
materials:
  body: {E: 1 MPa, nu: 0.3}
fixation:
  - {surface: fixed, components: xyz, value: [0 mm, 0 mm, 0 mm]}
EOP
cat > "$T/cut.yaml" <<'EOP'
name: tiny-cut
scene: box.yaml
planar_cut: {point: [0 mm, 1 mm, 0 mm], normal: [0, 1, 0], advance: [0, 0, -1], length: 1 mm,
             nodes_per_step: 3, pull_force: 0.1 mN, pull_surface: zmax}
EOP
"$B/mesh-prep" -q "$T/box.yaml" -o "$T/box.msh" >/dev/null || { echo "mesh-prep failed"; exit 1; }
"$B/cutplan" -q "$T/cut.yaml" "$T/box.msh" -o "$T/cut.edits" || { echo "cutplan failed"; exit 1; }
"$B/test_curv" --make-run "$T/eye-run" >/dev/null || { echo "test_curv --make-run failed"; exit 1; }

# sweep NAME OUTPUT -- command: run with KT_ALLOC_FAIL=1, 2, ... until the command succeeds.
# ALLOW (a regex, default none) names files a failed run may leave in OUTPUT: augsolve's step
# VTKs, each complete (written atomically), never a result without the run.yaml written last.
sweep() {
    local name=$1 out=$2 n=1 bad=0 rc
    shift 3
    case " ${KT_ALLOC_TOOLS:-$name} " in *" $name "*) ;; *) return ;; esac
    while :; do
        rm -rf "$out"
        KT_ALLOC_FAIL=$n "$@" >/dev/null 2>"$T/err"
        rc=$?
        [ $rc -eq 0 ] && break
        local why=""
        [ $rc -eq 1 ] || why="exit $rc"
        grep -q "out of memory" "$T/err" || why="$why; no 'out of memory' message"
        if [ -d "$out" ]; then
            local left
            left=$(ls -A "$out" | grep -Ev "${ALLOW:-^$}" | tr '\n' ' ')
            [ -z "$left" ] || why="$why; left $left"
        elif [ -e "$out" ]; then why="$why; left $out"; fi
        ls -A "$T" | grep -q '\.tmp\.' && why="$why; left a temporary file"
        if [ -n "$why" ]; then
            echo "FAIL $name, allocation $n: $why"; head -3 "$T/err" | sed 's/^/    /'
            bad=$((bad + 1)); rm -f "$T"/*.tmp.*
            [ $bad -ge 5 ] && break
        fi
        n=$((n + stride))
        [ $n -gt 200000 ] && { echo "FAIL $name: still failing at allocation $n"; bad=1; break; }
    done
    [ $bad -eq 0 ] && echo "ok   $name: allocations 1..$((n - 1)) each fail cleanly, $n runs through" ||
        fail=1
}

sweep mesh-prep "$T/out.msh" -- "$B/mesh-prep" -q "$T/box.yaml" -o "$T/out.msh"
sweep cutplan "$T/out.edits" -- "$B/cutplan" -q "$T/cut.yaml" "$T/box.msh" -o "$T/out.edits"
ALLOW='^step-[0-9]{4}\.vtk$' sweep augsolve "$T/run" -- "$B/augsolve" -q "$T/box.msh" "$T/cut.edits" -o "$T/run"
sweep curvature "$T/curv" -- "$B/curvature" -q --no-png "$T/eye-run" -o "$T/curv"
exit $fail
