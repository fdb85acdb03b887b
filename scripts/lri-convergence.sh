#!/usr/bin/env bash
# lri-convergence.sh BUILD SCENE OUT LABEL [PLAN]: one row of the wound-convergence table
# (docs/physics.md, "Convergence at the wound"). Meshes SCENE (mesh-prep), runs PLAN
# (default plans/lri-paired-60.yaml, with its scene: replaced by SCENE) as the demo does -
# cutplan | augsolve with the planned method (one factorization of the final cut mesh, every
# step by substitution) - reads it with curvature, and appends one TSV row to OUT/table.tsv:
#   label nodes dofs nnz_L mesh_s factor_s step_ms flattening_D steepening_D coupling_ratio
#   dk_mean_D sia_D peak_MiB
# step_ms is the mean update+solve time of the steps after step 0 (steps.tsv t_total_ms),
# factor_s the factorization (augsolve's planned line), peak_MiB augsolve's peak resident size.
set -euo pipefail
B=$(realpath "$1") SCENE=$(realpath "$2") OUT=$3 LABEL=$4 PLAN=${5:-plans/lri-paired-60.yaml}
D="$OUT/$LABEL"
mkdir -p "$D"
sed -e "s|^scene:.*|scene: $SCENE|" "$PLAN" > "$D/plan.yaml"
t0=$(date +%s.%N)
"$B/mesh-prep" "$SCENE" -o "$D/eye.msh" > "$D/mesh-prep.txt" 2>&1
t1=$(date +%s.%N)
"$B/cutplan" "$D/plan.yaml" "$D/eye.msh" -o - -q |
    /usr/bin/time -f 'peak_kib %M' "$B/augsolve" "$D/eye.msh" - -o "$D/run" 2> "$D/augsolve.txt"
"$B/curvature" "$D/run" -q > /dev/null
nodes=$(awk '/^\$Nodes/ { getline; print $2; exit }' "$D/eye.msh")
factor=$(sed -n 's/.*factor \([0-9.e+]*\) nonzeros in \([0-9.]*\) s.*/\1 \2/p' "$D/augsolve.txt")
peak=$(awk '$1 == "peak_kib" { printf "%.0f", $2 / 1024 }' "$D/augsolve.txt")
[ -f "$OUT/table.tsv" ] || printf 'label\tnodes\tdofs\tnnz_L\tmesh_s\tfactor_s\tstep_ms\tflattening_D\tsteepening_D\tcoupling_ratio\tdk_mean_D\tsia_D\tpeak_MiB\n' > "$OUT/table.tsv"
step=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["step"] > 0 { s += $c["t_total_ms"]; n++ } { d = $c["n_dofs"] }
    END { printf "%s\t%.1f", d, n ? s / n : 0 }' "$D/run/steps.tsv")
awk -F'\t' -v l="$LABEL" -v nn="$nodes" -v st="$step" -v fa="$factor" -v ms="$(echo "$t1 - $t0" | bc)" -v pk="$peak" '
    NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    { last = $0 }
    END { split(last, f, "\t"); split(st, s, "\t"); split(fa, a, " ");
          printf "%s\t%s\t%s\t%.3g\t%.0f\t%.1f\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\n", l, nn, s[1], a[1], ms,
                 a[2], s[2], f[c["flattening_D"]], f[c["steepening_D"]], f[c["coupling_ratio"]],
                 f[c["dk_mean_D"]], f[c["sia_D"]], pk }' "$D/run/curvature.tsv" | tee -a "$OUT/table.tsv"
