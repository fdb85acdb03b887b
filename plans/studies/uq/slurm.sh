#!/usr/bin/env bash
# slurm.sh OUT HERE "SUBMAKE" FINAL "TARGETS": the study's jobs on Slurm (ENGINE=slurm). Two
# submissions, both running `make TARGET` through SUBMAKE (so an up-to-date target costs nothing
# and a rerun resumes): a job array with one task per eye (TARGETS), then FINAL (the summary or
# the --sens file) after the whole array succeeded (--kill-on-invalid-dep: a failed task cancels
# it). It waits for FINAL (sbatch --wait) and exits with its status. Every task asks for one CPU
# and pins its BLAS threads. SBATCH_ARGS (word-split) is added to every sbatch, e.g.
# "-p short --mem=8G". Task logs: OUT/slurm/.
set -euo pipefail
out=$1 here=$2 make_cmd=$3 final=$4
read -r -a targets <<< "$5"
read -r -a extra <<< "${SBATCH_ARGS:-}"
log=$out/slurm
mkdir -p "$log"
printf '%s\n' "${targets[@]}" > "$log/targets.txt"
common=(--parsable --cpus-per-task=1 --kill-on-invalid-dep=yes -D "$here"
        --export=ALL,OPENBLAS_NUM_THREADS=1,OMP_NUM_THREADS=1 "${extra[@]}")
task='t=$(sed -n "$((SLURM_ARRAY_TASK_ID + 1))p" "$1"); shift; exec "$@" "$t"'
dep=()
if [ ${#targets[@]} -gt 0 ]; then
    id=$(sbatch "${common[@]}" -J kt-uq-eyes --array=0-$((${#targets[@]} - 1)) \
        -o "$log/eye-%a.out" --wrap "bash -c '$task' task $log/targets.txt $make_cmd")
    id=${id%%;*}
    echo "slurm: eyes: job array $id (${#targets[@]} tasks)"
    dep=(--dependency=afterok:$id)
fi
echo "slurm: $final after them; waiting"
if ! sbatch "${common[@]}" "${dep[@]}" -J kt-uq-final -o "$log/final.out" --wait \
        --wrap "$make_cmd $final" > "$log/final.id"; then
    echo "slurm: the study failed; task logs in $log:" >&2
    grep -l -i -E 'error|failed' "$log"/*.out >&2 || true
    exit 1
fi
cat "$log/final.out"
