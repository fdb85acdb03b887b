#!/usr/bin/env bash
# task.sh OUT RUN I: one lri-plan run of the calibration study (make, GNU parallel and Slurm run
# the study's jobs through make, which runs this): the model eye OUT/patients/RUN.yaml planned on
# the base scene of grid point I (OUT/bases/kI.yaml: a healed wound of the grid's stiffness), its
# plan.json kept as OUT/runs/RUN/kI.json (the curves, their SIA vectors and derivatives:
# lri-plan(1), FILES) with its CPU seconds in kI.time. The plan folder is written under
# OUT/work and deleted when the run succeeded (KEEP=1 keeps it). Everything is written under a
# temporary name and renamed when whole: a failed or interrupted run leaves nothing make takes
# as done. Environment: KT_BUILD (the tools' folder), LRIPLAN (lri-plan's options, e.g. --fast).
# BLAS threads pinned to one.
set -euo pipefail
out=$1 run=$2 i=$3
B=${KT_BUILD:?KT_BUILD not set}
export OPENBLAS_NUM_THREADS=1 OMP_NUM_THREADS=1
[ -x "$B/lri-plan" ] || { echo "task.sh: $B/lri-plan not built (bash scripts/build.sh)" >&2; exit 2; }
mkdir -p "$out/runs/$run" "$out/work"
dir=$out/work/$run-k$i
log=$out/runs/$run/k$i.log
part=$out/runs/$run/k$i.json.part$$
trap 'rm -f "$part"' EXIT
if ! /usr/bin/time -f '%U %S %M' -o "$out/runs/$run/k$i.time.part$$" \
        "$B/lri-plan" -q ${LRIPLAN:-} --base "$out/bases/k$i.yaml" "$out/patients/$run.yaml" -o "$dir" > "$log" 2>&1; then
    tail -n 20 "$log" >&2
    echo "task.sh: lri-plan $run at grid point $i failed (log: $log)" >&2
    rm -f "$out/runs/$run/k$i.time.part$$"
    exit 1
fi
cp "$dir/plan.json" "$part"
mv -f "$out/runs/$run/k$i.time.part$$" "$out/runs/$run/k$i.time"
mv -f "$part" "$out/runs/$run/k$i.json"
trap - EXIT
[ "${KEEP:-0}" = 1 ] || rm -rf "$dir"
