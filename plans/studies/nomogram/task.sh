#!/usr/bin/env bash
# task.sh eye OUT EYE | task.sh run OUT RUN: one job of the nomogram study; make, GNU parallel
# and Slurm all run the study's jobs through it (through make, which decides what is out of date).
#   eye: mesh-prep OUT/scenes/EYE.yaml -> OUT/eyes/EYE.msh (and EYE.time.tsv)
#   run: cutplan OUT/plans/RUN.yaml | augsolve --uncertainty | curvature -> OUT/runs/RUN/
#        (curvature.tsv with its band columns, derivatives.tsv, uncertainty.tsv, steps.tsv, the
#        step VTKs unless KEEP_VTK=0, time.tsv). The band (issue 21): the derivatives of the
#        scene's derivative quantities (keratome-scene(5), UNCERTAINTY; the thickness and the
#        depth, marked fd, are left out: they need their own meshes).
# Everything is written under a temporary name and renamed when the job succeeded: a failed or
# interrupted job leaves nothing that make would take as done, and a rerun starts it afresh.
# BLAS threads are pinned (OPENBLAS_NUM_THREADS=1, OMP_NUM_THREADS=1) so that jobs running side by
# side do not oversubscribe the cores. Environment: KT_BUILD (the tools' folder), KEEP_VTK (0:
# delete the step VTKs once curvature has read them), AUGSOLVE_FLAGS (added to augsolve's
# options, word-split; default none: augsolve's default method).
set -euo pipefail
kind=$1 out=$2 name=$3
B=${KT_BUILD:?KT_BUILD not set}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
for tool in mesh-prep cutplan augsolve curvature; do
    [ -x "$B/$tool" ] || { echo "task.sh: $B/$tool not built (bash scripts/build.sh)" >&2; exit 2; }
done
now() { date +%s.%N; }
dt() { awk -v a="$1" -v b="$2" 'BEGIN { print b - a }'; }
# CPU seconds (user + system) of the tools this shell ran: line 2 of bash's times, which must run
# in this shell (a command substitution is a new process with no children), saved in $1.
cpu() { awk 'NR == 2 { for (i = 1; i <= 2; i++) { split($i, p, /[ms]/); s += p[1] * 60 + p[2] }
        printf "%.2f", s }' "$1"; rm -f "$1"; }
case $kind in
eye)
    mkdir -p "$out/eyes"
    part=$out/eyes/$name.part$$.msh
    rm -f "$part"
    trap 'rm -f "$part"' EXIT
    t0=$(now)
    "$B/mesh-prep" "$out/scenes/$name.yaml" -o "$part" > "$out/eyes/$name.log" 2>&1 ||
        { tail -n 20 "$out/eyes/$name.log" >&2; echo "task.sh: mesh-prep $name failed" >&2; exit 1; }
    t1=$(now)
    times > "$out/eyes/$name.times"
    printf 'eye\tmesh_prep_s\tcpu_s\n%s\t%.2f\t%s\n' "$name" "$(dt "$t0" "$t1")" \
        "$(cpu "$out/eyes/$name.times")" > "$out/eyes/$name.time.tsv"
    mv -f "$part" "$out/eyes/$name.msh"
    trap - EXIT
    ;;
run)
    eye=$(awk -F'\t' 'NR == 2 { print $2 }' "$out/plans/$name.meta")
    mkdir -p "$out/runs"
    part=$out/runs/$name.part$$
    rm -rf "$part"
    trap 'rm -rf "$part"' EXIT
    mkdir -p "$part"
    t0=$(now)
    set +e
    "$B/cutplan" "$out/plans/$name.yaml" "$out/eyes/$eye.msh" -o - 2> "$part/cutplan.log" |
        "$B/augsolve" "$out/eyes/$eye.msh" - -o "$part" --uncertainty ${AUGSOLVE_FLAGS:-} > "$part/augsolve.log" 2>&1
    st=("${PIPESTATUS[@]}")
    set -e
    if [ "${st[0]}" -ne 0 ] || [ "${st[1]}" -ne 0 ]; then
        tail -n 20 "$part/cutplan.log" "$part/augsolve.log" >&2
        echo "task.sh: run $name failed (cutplan ${st[0]}, augsolve ${st[1]})" >&2
        exit 1
    fi
    t1=$(now)
    "$B/curvature" -q --no-png --no-vtk "$part" > "$part/curvature.log" 2>&1 ||
        { tail -n 20 "$part/curvature.log" >&2; echo "task.sh: curvature $name failed" >&2; exit 1; }
    t2=$(now)
    [ "${KEEP_VTK:-1}" = 0 ] && rm -f "$part"/step-*.vtk
    times > "$part/times.txt"
    printf 'run\tsolve_s\tcurvature_s\tcpu_s\n%s\t%.2f\t%.2f\t%s\n' "$name" "$(dt "$t0" "$t1")" \
        "$(dt "$t1" "$t2")" "$(cpu "$part/times.txt")" > "$part/time.tsv"
    rm -rf "$out/runs/$name"
    mv "$part" "$out/runs/$name"
    trap - EXIT
    ;;
*)
    echo "usage: task.sh eye|run OUT NAME" >&2; exit 2 ;;
esac
