#!/usr/bin/env bash
# augsolve_output.sh BUILD_DIR: --output means one thing for every method (augsolve(1)): on the
# cut beam, each method (planned, augmented, refactor, cg, pcg-jacobi) run with --output ymax
# (a surface) and --output body (a region) writes step VTKs whose displacement is NaN at the
# same nodes for every method, non-NaN on the set, and equal there to the planned method's
# full field (direct methods 1e-10, CG to its tolerance); an unknown set exits 2 for every
# method. (tests/solve/test_solver.c checks a region that is not the whole mesh.)
set -uo pipefail
B=${1:?build dir}
/usr/bin/python3 -c 'import meshio' 2>/dev/null || { echo "skip: no python3 meshio"; exit 77; }
T=$(mktemp -d /tmp/augsolve_output.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail=0
"$B/mesh-prep" plans/bench/beam-16.yaml -o "$T/beam.msh" -q >/dev/null || { echo "FAIL mesh-prep"; exit 1; }
"$B/cutplan" plans/bench/cut-beam-16.yaml "$T/beam.msh" -o "$T/cut.edits" -q || { echo "FAIL cutplan"; exit 1; }
run() { # run NAME METHOD OUTPUT
    "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/$1" --method "$2" --output "$3" --tol 1e-12 \
        --verify --verify-tol 1e-6 -q 2>"$T/err" || { echo "FAIL $1: $(cat "$T/err")"; fail=1; }
}
run full planned all
for m in planned augmented refactor cg pcg-jacobi; do
    for s in ymax body; do run "$m-$s" "$m" "$s"; done
    "$B/augsolve" "$T/beam.msh" "$T/cut.edits" -o "$T/$m-bad" --method "$m" --output nosuchset -q \
        2>"$T/err"
    rc=$?
    if [ $rc = 2 ] && grep -q "nosuchset" "$T/err"; then echo "ok   $m: --output nosuchset exits 2"
    else echo "FAIL $m: --output nosuchset: exit $rc: $(cat "$T/err")"; fail=1; fi
done
[ $fail = 0 ] || exit 1
/usr/bin/python3 - "$T" <<'EOF' || fail=1
import glob, os, sys
import meshio, numpy as np
T = sys.argv[1]
steps = sorted(os.path.basename(p) for p in glob.glob(f"{T}/full/step-*.vtk"))
assert len(steps) > 2, "steps of the full run"
bad = 0
for s in ("ymax", "body"):
    before = bad
    for st in steps:
        full = meshio.read(f"{T}/full/{st}").point_data["displacement"]
        masks = {}
        for m in ("planned", "augmented", "refactor", "cg", "pcg-jacobi"):
            u = meshio.read(f"{T}/{m}-{s}/{st}").point_data["displacement"]
            nan = np.isnan(u)
            on = ~nan.any(axis=1)
            masks[m] = on
            tol = 1e-6 if m in ("cg", "pcg-jacobi") else 1e-10
            diff = np.abs(u[on] - full[on]).max() if on.any() else np.nan
            scale = np.abs(full[on]).max() if on.any() else np.nan
            d = diff / scale if scale > 0 else diff  # step 0 of the beam: no load, u = 0
            if not (nan.all(axis=1) | on).all() or not on.any() or not (d <= tol):
                print(f"FAIL {m} --output {s} {st}: {on.sum()} of {len(on)} nodes on the set, "
                      f"relative difference {d:.3g} from planned's full field")
                bad = 1
            if s == "ymax" and on.all():
                print(f"FAIL {m} --output ymax {st}: no NaN off the surface")
                bad = 1
        for m, on in masks.items():
            if not np.array_equal(on, masks["planned"]):
                print(f"FAIL --output {s} {st}: {m}'s NaN mask differs from planned's "
                      f"({on.sum()} vs {masks['planned'].sum()} nodes)")
                bad = 1
    if bad == before:
        print(f"ok   --output {s}: one NaN mask and planned's values on the set, {len(steps)} steps x 5 methods")
sys.exit(bad)
EOF
exit $fail
