# ordering.sh: the ordering part (scripts/bench.sh --only ordering).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: ordering
# The same cut under each elimination order mesh-prep offers: nnz(L), flops and closures from
# mesh-prep's symbolic analysis, factor and solve times from bench_solves, per-step times and
# closures of the augmented method from augsolve.
part_ordering() {
    local D=$R/ordering S c model scene plan set ord msh ed files
    D=$R/ordering S=$D/steps.tsv
    mkdir -p "$D"
    printf '%s\n' "$STEPS_HEADER" >"$S"
    printf 'model\tordering\tnodes\tnnz_L\tflops\tetree_height\tclosure_mean\tclosure_max\tclosure_set\tfactor_ms\tfull_solve_ms\tset_closure_solve_ms\tsteps\taug_ms_median\taug_ms_max\tclosure_max_median\trefinement_iters_max\taug_status\n' >"$D/ordering.tsv"
    local beam=$ORD_BEAM cases=""
    [ $WITH_EYE = 1 ] && cases="eye:$PL/eye.yaml:$PL/lri-paired-60.yaml:incision-ring-1"
    cases="$cases beam-$beam:$PB/beam-$beam.yaml:$PB/cut-beam-$beam.yaml:zmax"
    for c in $cases; do
        set -- ${c//:/ }
        model=$1 scene=$2 plan=$3 set=$4
        for ord in amd metis constrained metis-last; do
            msh=$MESHES/$model-$ord.msh ed=$EDITS/$model-$ord.edits
            mesh "$scene" "$msh" --ordering $ord || continue
            cut_edits "$plan" "$msh" "$ed" || continue
            # the quick mode runs the eye's first 4 steps (its step time grows with m)
            if [ "$FULL" != 1 ] && [ "$model" = eye ]; then
                truncate_edits "$ed" "$EDITS/$model-$ord-4.edits" 4
                ed=$EDITS/$model-$ord-4.edits
            fi
            log "  $model $ord"
            run "ord-solves-$model-$ord" "$T_RUN" "$B/bench_solves" "$msh" "$scene" --set "$set" \
                --sample 20 --spread 0 --reps 3 --tag "$model-$ord"
            # the beams' cut is refused at the default tolerance from h = 256 on (the backward
            # error misses 1e-10: see the stability part): they run at 1e-8
            local lab=augmented
            [ "$model" != eye ] && lab=augmented@1e-8
            SUFFIX= solve ordering "$model" "$ord" "$msh" "$ed" "$lab" "$S"
            # one row: mesh-prep's analysis (its starred row), bench_solves' times, the steps
            local summary ana solves steps
            summary=$LOGS/mesh-$model-$ord.out
            ana=$(awk '/^\* / { printf "%s\t%s\t%s\t%s\t%s\t%s", $3, $4, $5, $6, $7, $8; exit }' "$summary")
            solves=$(awk -F'\t' -f "$BENCH/awk/ordering.awk" "$LOGS/ord-solves-$model-$ord.out" 2>/dev/null)
            steps=$(awk -F'\t' -v mo="$model" -v o="$ord" -f "$BENCH/awk/ordering-2.awk" "$S")
            printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$model" "$ord" "$(mesh_nodes "$msh")" "$ana" "$solves" "$steps" >>"$D/ordering.tsv"
        done
        files=""
        for ord in amd metis constrained metis-last; do
            awk -F'\t' -v OFS='\t' -v mo="$model" -v o="$ord" -f "$BENCH/awk/ordering-3.awk" "$S" >"$D/steps-$model-$ord.tsv"
            files="$files $D/steps-$model-$ord.tsv"
        done
        plot series.gp "$D/ordering-$model" "files='$files'" "logy=1" "xl='step'" "yl='augmented step time (ms)'" \
            "ttl='$model: augmented step time under each ordering'"
    done
    column -t -s $'\t' "$D/ordering.tsv" >&2
}

