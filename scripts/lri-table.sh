#!/usr/bin/env bash
# lri-table.sh BUILD SCENE OUT [PLAN...]: the arc table of the physics (docs/physics.md).
# Meshes SCENE once (mesh-prep), then solves each plan (default: plans/lri-{single,paired}-
# {30,45,60,75,90}.yaml) in ONE step (the whole arc opened at once: the model is linear, so the
# final state does not depend on the steps) with augsolve's default method (planned; for a
# one-step plan it falls back to a fresh factorization per step when that is cheaper, as its
# run.yaml says), reads it with curvature and prints one TSV row per plan to stdout and OUT/table.tsv:
#   plan arc paired flattening_D steepening_D coupling_ratio dk_mean_D sia_D nodes seconds
# The plans' scene: is replaced by SCENE (so a variant scene gives the sensitivity runs).
# lri-table.sh BUILD SCENE OUT --series [STEP_DEG [PLAN...]]: the same table from one planned
# run per plan (default plans/lri-{single,paired}-90.yaml): each cut centre-out, STEP_DEG (15)
# of total arc per step, every step solved exactly from ONE factorization (augsolve's default
# planned method), one row per step (arc = the step's total arc, curvature.tsv arc_deg;
# seconds = the whole run's, on the row of its last step). A centre-out cut that has opened
# A degrees is the arc of A degrees centred on the plan's meridian: the same faces as the
# one-step plan of A degrees (compare one row with the default mode).
set -euo pipefail
B=$1 SCENE=$(realpath "$2") OUT=$3
shift 3
series=0 sdeg=15
if [ "${1:-}" = --series ]; then
    series=1; shift
    if [ $# -gt 0 ] && [[ $1 =~ ^[0-9]+$ ]]; then sdeg=$1; shift; fi
fi
plans=("$@")
if [ ${#plans[@]} -eq 0 ]; then
    if [ $series = 1 ]; then plans=(plans/lri-single-90.yaml plans/lri-paired-90.yaml)
    else for k in single paired; do for a in 30 45 60 75 90; do plans+=("plans/lri-$k-$a.yaml"); done; done; fi
fi
mkdir -p "$OUT"
[ -f "$OUT/eye.msh" ] || "$B/mesh-prep" "$SCENE" -o "$OUT/eye.msh" -q > "$OUT/mesh-prep.txt"
nodes=$(awk '/^\$Nodes/ { getline; print $2; exit }' "$OUT/eye.msh")
printf 'plan\tarc\tpaired\tflattening_D\tsteepening_D\tcoupling_ratio\tdk_mean_D\tsia_D\tnodes\tseconds\n' > "$OUT/table.tsv"
for p in "${plans[@]}"; do
    name=$(basename "$p" .yaml)
    if [ $series = 1 ]; then
        paired=$(grep -q 'paired: true' "$p" && echo yes || echo no)
        sed -e "s|^scene:.*|scene: $SCENE|" -e "s|degrees_per_step:.*|degrees_per_step: $sdeg deg|" \
            -e "s|direction:.*|direction: centre-out|" "$p" > "$OUT/$name-series.yaml"
        grep -q 'direction: centre-out' "$OUT/$name-series.yaml" || { echo "lri-table: $p has no direction: to set" >&2; exit 1; }
        t0=$(date +%s.%N)
        "$B/cutplan" "$OUT/$name-series.yaml" "$OUT/eye.msh" -o - -q |
            "$B/augsolve" "$OUT/eye.msh" - -o "$OUT/$name-series" -q
        "$B/curvature" "$OUT/$name-series" -q --no-png --no-report > /dev/null
        t1=$(date +%s.%N)
        awk -F'\t' -v n="${name%-*}" -v pr="$paired" -v nn="$nodes" -v t="$(echo "$t1 - $t0" | bc)" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $c["step"] > 0 { r[++k] = $0 }
            END { for (j = 1; j <= k; j++) { split(r[j], f, "\t");
                      printf "%s-%d\t%d\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\t%s\n", n, f[c["arc_deg"]], f[c["arc_deg"]], pr,
                             f[c["flattening_D"]], f[c["steepening_D"]], f[c["coupling_ratio"]], f[c["dk_mean_D"]],
                             f[c["sia_D"]], nn, j == k ? sprintf("%.0f", t) : "-" } }' \
            "$OUT/$name-series/curvature.tsv" | tee -a "$OUT/table.tsv"
        continue
    fi
    arc=$(awk '$1 == "arc:" { print $2; exit }' "$p")
    paired=$(grep -q 'paired: true' "$p" && echo yes || echo no)
    sed -e "s|^scene:.*|scene: $SCENE|" -e "s|degrees_per_step:.*|degrees_per_step: $arc deg|" "$p" > "$OUT/$name.yaml"
    t0=$(date +%s.%N)
    "$B/cutplan" "$OUT/$name.yaml" "$OUT/eye.msh" -o - -q |
        "$B/augsolve" "$OUT/eye.msh" - -o "$OUT/$name" -q
    "$B/curvature" "$OUT/$name" -q --no-png --no-report > /dev/null
    t1=$(date +%s.%N)
    awk -F'\t' -v n="$name" -v a="$arc" -v pr="$paired" -v nn="$nodes" -v t="$(echo "$t1 - $t0" | bc)" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { last = $0 }
        END { split(last, f, "\t");
              printf "%s\t%s\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\t%.0f\n", n, a, pr, f[c["flattening_D"]],
                     f[c["steepening_D"]], f[c["coupling_ratio"]], f[c["dk_mean_D"]], f[c["sia_D"]], nn, t }' \
        "$OUT/$name/curvature.tsv" | tee -a "$OUT/table.tsv"
done
