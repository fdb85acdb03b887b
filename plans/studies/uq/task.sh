#!/usr/bin/env bash
# task.sh OUT NAME: one eye of the uncertainty study, start to end; make, GNU parallel and Slurm
# all run the study's jobs through it (through make, which decides what is out of date):
#   mesh-prep OUT/scenes/NAME.yaml -> OUT/runs/NAME/eye.msh (one mesh), then for every family F
#   of OUT/study.mk: cutplan OUT/plans/NAME-F.yaml | augsolve | curvature into
#   OUT/runs/NAME/run-F/ (curvature.tsv, steps.tsv, run.yaml, the logs); OUT/runs/NAME/time.tsv
#   (make's target) last. The mesh and the step VTKs are deleted afterwards unless KEEP_VTK=1,
#   except for the nominal eye's, kept so that curvature can read its bands again with --sens.
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
t1m=$(now)
flags=()
if [ "$name" = nominal ]; then flags=(--uncertainty); fi
read -r -a families < <(sed -n 's/^FAMILIES := //p' "$out/study.mk")
[ ${#families[@]} -gt 0 ] || { echo "task.sh: $out/study.mk: no FAMILIES line (rerun gen.sh: make)" >&2; exit 2; }
rows=() mesh_s=$(dt "$t0" "$t1m")
for fam in "${families[@]}"; do
    t1=$(now)
    r=$part/run-$fam
    set +e
    "$B/cutplan" -q "$out/plans/$name-$fam.yaml" "$part/eye.msh" -o - 2> "$part/cutplan-$fam.log" |
        "$B/augsolve" -q "$part/eye.msh" - -o "$r" "${flags[@]}" ${AUGSOLVE_FLAGS:-} > "$part/augsolve-$fam.log" 2>&1
    st=("${PIPESTATUS[@]}")
    set -e
    if [ "${st[0]}" -ne 0 ] || [ "${st[1]}" -ne 0 ]; then
        tail -n 20 "$part/cutplan-$fam.log" "$part/augsolve-$fam.log" >&2
        echo "task.sh: run $name $fam failed (cutplan ${st[0]}, augsolve ${st[1]})" >&2
        exit 1
    fi
    t2=$(now)
    "$B/curvature" -q --no-png --no-vtk --no-report "$r" > "$part/curvature-$fam.txt" 2> "$part/curvature-$fam.log" ||
        { tail -n 20 "$part/curvature-$fam.log" >&2; echo "task.sh: curvature $name $fam failed" >&2; exit 1; }
    t3=$(now)
    for f in cutplan augsolve curvature; do mv "$part/$f-$fam.log" "$r/$f.log"; done
    mv "$part/curvature-$fam.txt" "$r/curvature.txt"
    if [ "$name" != nominal ] && [ "${KEEP_VTK:-0}" != 1 ]; then rm -f "$r"/step-*.vtk; fi
    rows+=("$(printf '%s\t%s\t%s\t%s\t%s\t%s' "$name" "$fam" "$mesh_s" "$(dt "$t1" "$t2")" "$(dt "$t2" "$t3")" "${flags[*]:-off}")")
    mesh_s=0.00   # the one mesh counted once
done
if [ "$name" != nominal ] && [ "${KEEP_VTK:-0}" != 1 ]; then rm -f "$part/eye.msh"; fi
{ printf 'eye\tfamily\tmesh_prep_s\tsolve_s\tcurvature_s\tuncertainty\n'; printf '%s\n' "${rows[@]}"; } > "$part/time.tsv"
rm -rf "$out/runs/$name"
mv "$part" "$out/runs/$name"
trap - EXIT
