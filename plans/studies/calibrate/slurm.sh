#!/usr/bin/env bash
# slurm.sh OUT HERE "RUN_TARGETS" GRID: the calibration study's runs on Slurm (ENGINE=slurm): a
# job array with one task per lri-plan run (each `make TARGET`, so an up-to-date target costs
# nothing and a rerun resumes), then the fit after the whole array succeeded. It waits for the
# fit (sbatch --wait) and exits with its status. Every task asks for one CPU and pins its BLAS
# threads. SBATCH_ARGS (word-split) is added to every sbatch. Task logs: OUT/slurm/.
set -euo pipefail
out=$1 here=$2 grid=$4
read -r -a runs <<< "$3"
read -r -a extra <<< "${SBATCH_ARGS:-}"
log=$out/slurm
mkdir -p "$log"
printf '%s\n' "${runs[@]}" > "$log/runs.txt"
make_cmd="env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make --no-print-directory -f $here/Makefile"
make_cmd+=" OUT=$out KT_BUILD=$KT_BUILD ENGINE=local GRID='$grid'"
common=(--parsable --cpus-per-task=1 --kill-on-invalid-dep=yes -D "$here"
        --export=ALL,OPENBLAS_NUM_THREADS=1,OMP_NUM_THREADS=1 "${extra[@]}")
task='t=$(sed -n "$((SLURM_ARRAY_TASK_ID + 1))p" "$1"); shift; exec "$@" "$t"'
id=$(sbatch "${common[@]}" -J kt-calib --array=0-$((${#runs[@]} - 1)) \
    -o "$log/run-%a.out" --wrap "bash -c '$task' task $log/runs.txt $make_cmd")
id=${id%%;*}
echo "slurm: runs: job array $id (${#runs[@]} tasks); the fit after them; waiting"
if ! sbatch "${common[@]}" --dependency=afterok:$id -J kt-calib-fit -o "$log/fit.out" --wait \
        --wrap "$make_cmd fit" > "$log/fit.id"; then
    echo "slurm: the study failed; task logs in $log:" >&2
    grep -l -i -E 'error|failed' "$log"/*.out >&2 || true
    exit 1
fi
cat "$log/fit.out"
