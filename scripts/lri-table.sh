#!/usr/bin/env bash
# lri-table.sh BUILD SCENE OUT [PLAN...]: the arc table of the physics (README, keratome-scene(5)).
# Meshes SCENE once (mesh-prep), then solves each plan (default: plans/lri-{single,paired}-
# {30,45,60,75,90}.yaml) in ONE step (the whole arc opened at once: the model is linear, so the
# final state does not depend on the steps) with a fresh factorization (augsolve --method
# refactor), reads it with curvature and prints one TSV row per plan to stdout and OUT/table.tsv:
#   plan arc paired flattening_D steepening_D coupling_ratio dk_mean_D sia_D nodes seconds
# The plans' scene: is replaced by SCENE (so a variant scene gives the sensitivity runs).
set -euo pipefail
B=$1 SCENE=$(realpath "$2") OUT=$3
shift 3
plans=("$@")
if [ ${#plans[@]} -eq 0 ]; then
    for k in single paired; do for a in 30 45 60 75 90; do plans+=("plans/lri-$k-$a.yaml"); done; done
fi
mkdir -p "$OUT"
[ -f "$OUT/eye.msh" ] || "$B/mesh-prep" "$SCENE" -o "$OUT/eye.msh" -q > "$OUT/mesh-prep.txt"
nodes=$(awk '/^\$Nodes/ { getline; print $2; exit }' "$OUT/eye.msh")
printf 'plan\tarc\tpaired\tflattening_D\tsteepening_D\tcoupling_ratio\tdk_mean_D\tsia_D\tnodes\tseconds\n' > "$OUT/table.tsv"
for p in "${plans[@]}"; do
    name=$(basename "$p" .yaml)
    arc=$(awk '$1 == "arc:" { print $2; exit }' "$p")
    paired=$(grep -q 'paired: true' "$p" && echo yes || echo no)
    sed -e "s|^scene:.*|scene: $SCENE|" -e "s|degrees_per_step:.*|degrees_per_step: $arc deg|" "$p" > "$OUT/$name.yaml"
    t0=$(date +%s.%N)
    "$B/cutplan" "$OUT/$name.yaml" "$OUT/eye.msh" -o - -q |
        "$B/augsolve" "$OUT/eye.msh" - -o "$OUT/$name" --method refactor --ordering metis -q
    "$B/curvature" "$OUT/$name" -q > /dev/null
    t1=$(date +%s.%N)
    awk -F'\t' -v n="$name" -v a="$arc" -v pr="$paired" -v nn="$nodes" -v t="$(echo "$t1 - $t0" | bc)" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { last = $0 }
        END { split(last, f, "\t");
              printf "%s\t%s\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\t%.0f\n", n, a, pr, f[c["flattening_D"]],
                     f[c["steepening_D"]], f[c["coupling_ratio"]], f[c["dk_mean_D"]], f[c["sia_D"]], nn, t }' \
        "$OUT/$name/curvature.tsv" | tee -a "$OUT/table.tsv"
done
