#!/usr/bin/env bash
# task.sh OUT NAME: one eye of the uncertainty study, start to end; make, GNU parallel and Slurm
# all run the study's jobs through it (through make, which decides what is out of date):
#   mesh-prep OUT/scenes/NAME.yaml -> OUT/runs/NAME/eye.msh, then cutplan OUT/plans/NAME.yaml |
#   augsolve | curvature into OUT/runs/NAME/run/ (curvature.tsv, steps.tsv, run.yaml, the logs,
#   time.tsv); the mesh and the step VTKs are deleted afterwards unless KEEP_VTK=1, except for
#   the nominal eye's, kept so that curvature can read its bands again with --sens.
# The nominal eye is solved with augsolve --uncertainty (issue 21: the first-order band, its sd
# the study's: gen.sh writes them into the nominal scene); the sampled eyes without it.
# Everything is written under a temporary name and renamed when the job succeeded: a failed or
# interrupted job leaves nothing make would take as done. BLAS threads are pinned to one.
# Environment: KT_BUILD (the tools' folder), KEEP_VTK, AUGSOLVE_FLAGS (added to augsolve).
set -euo pipefail
out=$1 name=$2
B=${KT_BUILD:?KT_BUILD not set}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
for tool in mesh-prep cutplan augsolve curvature; do
    [ -x "$B/$tool" ] || { echo "task.sh: $B/$tool not built (bash scripts/build.sh)" >&2; exit 2; }
done
now() { date +%s.%N; }
dt() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
mkdir -p "$out/runs"
part=$out/runs/$name.part$$
rm -rf "$part"
trap 'rm -rf "$part"' EXIT
mkdir -p "$part"
t0=$(now)
"$B/mesh-prep" -q "$out/scenes/$name.yaml" -o "$part/eye.msh" > "$part/mesh-prep.log" 2>&1 ||
    { tail -n 20 "$part/mesh-prep.log" >&2; echo "task.sh: mesh-prep $name failed" >&2; exit 1; }
t1=$(now)
flags=()
if [ "$name" = nominal ]; then flags=(--uncertainty); fi
set +e
"$B/cutplan" -q "$out/plans/$name.yaml" "$part/eye.msh" -o - 2> "$part/cutplan.log" |
    "$B/augsolve" -q "$part/eye.msh" - -o "$part/run" "${flags[@]}" ${AUGSOLVE_FLAGS:-} > "$part/augsolve.log" 2>&1
st=("${PIPESTATUS[@]}")
set -e
if [ "${st[0]}" -ne 0 ] || [ "${st[1]}" -ne 0 ]; then
    tail -n 20 "$part/cutplan.log" "$part/augsolve.log" >&2
    echo "task.sh: run $name failed (cutplan ${st[0]}, augsolve ${st[1]})" >&2
    exit 1
fi
t2=$(now)
"$B/curvature" -q --no-png --no-vtk --no-report "$part/run" > "$part/curvature.txt" 2> "$part/curvature.log" ||
    { tail -n 20 "$part/curvature.log" >&2; echo "task.sh: curvature $name failed" >&2; exit 1; }
t3=$(now)
mv "$part"/*.log "$part/curvature.txt" "$part/run/"
if [ "$name" != nominal ] && [ "${KEEP_VTK:-0}" != 1 ]; then rm -f "$part"/run/step-*.vtk "$part/eye.msh"; fi
printf 'eye\tmesh_prep_s\tsolve_s\tcurvature_s\tuncertainty\n%s\t%s\t%s\t%s\t%s\n' "$name" "$(dt "$t0" "$t1")" \
    "$(dt "$t1" "$t2")" "$(dt "$t2" "$t3")" "${flags[*]:-off}" > "$part/run/time.tsv"
rm -rf "$out/runs/$name"
mv "$part" "$out/runs/$name"
trap - EXIT
