#!/usr/bin/env bash
# slurm.sh OUT SET HERE "EYE_TARGETS" "RUN_TARGETS": the study's jobs on Slurm (ENGINE=slurm).
# Three submissions, all running `make TARGET` (so an up-to-date target costs nothing and a rerun
# resumes): a job array with one task per eye mesh; a job array with one task per run, after the
# whole eye array succeeded; the summary, after the run array succeeded. It waits for the
# summary (sbatch --wait) and exits with its status. A failed task cancels what depends on it
# (--kill-on-invalid-dep). Every task asks for one CPU and pins its BLAS threads.
# SBATCH_ARGS (word-split) is added to every sbatch, e.g. "-p short --mem=8G"; Slurm's own
# SBATCH_* variables apply as usual. Task logs: OUT/slurm/.
set -euo pipefail
out=$1 set=$2 here=$3
read -r -a eyes <<< "$4"
read -r -a runs <<< "$5"
read -r -a extra <<< "${SBATCH_ARGS:-}"
log=$out/slurm
mkdir -p "$log"
printf '%s\n' "${eyes[@]}" > "$log/eyes.txt"
printf '%s\n' "${runs[@]}" > "$log/runs.txt"
make_cmd="env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL make --no-print-directory -f $here/Makefile"
make_cmd+=" OUT=$out SET=$set KT_BUILD=$KT_BUILD ENGINE=local"
common=(--parsable --cpus-per-task=1 --kill-on-invalid-dep=yes -D "$here"
        --export=ALL,OPENBLAS_NUM_THREADS=1,OMP_NUM_THREADS=1 "${extra[@]}")
# array task i makes line i+1 of a list
task='t=$(sed -n "$((SLURM_ARRAY_TASK_ID + 1))p" "$1"); shift; exec "$@" "$t"'

dep=()
if [ ${#eyes[@]} -gt 0 ]; then
    id=$(sbatch "${common[@]}" -J kt-eyes --array=0-$((${#eyes[@]} - 1)) \
        -o "$log/eye-%a.out" --wrap "bash -c '$task' task $log/eyes.txt $make_cmd")
    id=${id%%;*}
    echo "slurm: eyes: job array $id (${#eyes[@]} tasks)"
    dep=(--dependency=afterok:$id)
fi
if [ ${#runs[@]} -gt 0 ]; then
    id=$(sbatch "${common[@]}" "${dep[@]}" -J kt-runs --array=0-$((${#runs[@]} - 1)) \
        -o "$log/run-%a.out" --wrap "bash -c '$task' task $log/runs.txt $make_cmd")
    id=${id%%;*}
    echo "slurm: runs: job array $id (${#runs[@]} tasks)"
    dep=(--dependency=afterok:$id)
fi
echo "slurm: summary after them; waiting"
if ! sbatch "${common[@]}" "${dep[@]}" -J kt-summary -o "$log/summary.out" --wait \
        --wrap "$make_cmd summary" > "$log/summary.id"; then
    echo "slurm: the study failed; task logs in $log:" >&2
    grep -l -i -E 'error|failed' "$log"/*.out >&2 || true
    exit 1
fi
cat "$log/summary.out"
