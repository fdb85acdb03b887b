# paper.sh: the paper part (scripts/bench.sh --only paper).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: paper
# Rate per step (Hz) = 1000 / t_total_ms. Step 0 (the intact solve, with the factorization of
# the augmented method) is left out of every per-step figure.
paper_methods() { # MODEL SIZE -> the methods run on it
    local m="augmented refactor pcg-jacobi cg"
    # CG on the longest beams only runs into the budget: the full mode tries it
    if [ "$FULL" != 1 ] && [ "$1" = beam ] && [ "$2" -ge 512 ]; then m="augmented refactor pcg-jacobi"; fi
    echo "$m"
}

part_paper() {
    local D=$R/paper F S s m meth exp
    D=$R/paper F=$D/fig S=$D/steps.tsv
    mkdir -p "$D" "$F"
    if [ -n "$CASES" ] && [ -s "$S" ]; then
        # rerun only the selected cases: drop their old rows, keep the rest
        awk -F'\t' -v re="$CASES" -v ms="$METHODS" 'NR == 1 || ($1 "-" $2 "-" $3) !~ re || (ms != "" && index(ms, " " $5 " ") == 0)' \
            "$S" >"$S.tmp" && mv "$S.tmp" "$S"
    else
        printf '%s\n' "$STEPS_HEADER" >"$S"
    fi
    local beams=$BEAMS
    case " $beams " in *" $HEAD_BEAM "*) ;; *) beams="$beams $HEAD_BEAM" ;; esac # the headline beam
    for m in beam brick; do
        local sizes=$BRICKS
        [ $m = beam ] && sizes=$beams
        for s in $sizes; do
            prep_box $m "$s" || continue
            for exp in cut deform; do
                # the quick mode runs only the headline's cut on the 5x5x1024 beam
                [ "$FULL" != 1 ] && [ $m = beam ] && [ "$s" = "$HEAD_BEAM" ] && [ $exp = deform ] &&
                    [ "$SMOKE" != 1 ] && continue
                for meth in $(paper_methods $m "$s"); do
                    log "  $exp $m-$s $meth"
                    solve $exp $m "$s" "$MESHES/$m-$s.msh" "$EDITS/$exp-$m-$s.edits" "$meth" "$S"
                done
            done
        done
    done
    if [ $WITH_EYE = 1 ] && prep_eye; then
        for meth in augmented refactor pcg-jacobi cg; do
            log "  lri eye $meth"
            solve lri eye default "$MESHES/eye.msh" "$EDITS/lri-eye.edits" "$meth" "$S"
        done
    fi
    if [ $WITH_BUNNY = 1 ] && prep_bunny; then
        for meth in augmented refactor pcg-jacobi cg; do
            log "  cut bunny $meth"
            solve cut bunny default "$MESHES/bunny-snapped.msh" "$EDITS/cut-bunny.edits" "$meth" "$S"
        done
    fi
    # what a user would otherwise run is a fresh factorization in its best ordering, not in the
    # one chosen for the augmented method's closures
    for c in "cut beam $HEAD_BEAM $MESHES/beam-$HEAD_BEAM.msh $EDITS/cut-beam-$HEAD_BEAM.edits" \
             "lri eye default $MESHES/eye.msh $EDITS/lri-eye.edits" \
             "cut bunny default $MESHES/bunny-snapped.msh $EDITS/cut-bunny.edits"; do
        set -- $c
        [ -s "$4" ] && [ -s "$5" ] || continue
        log "  $1 $2-$3 refactor --ordering metis"
        solve "$1" "$2" "$3" "$4" "$5" "refactor+metis" "$S"
    done
    paper_tables "$D"
    paper_plots "$D"
}

# Tables from steps.tsv.
paper_tables() {
    local D=$1 S=$1/steps.tsv
    # HEADLINE: per-step time ratios on the same steps. A baseline step that missed its
    # tolerance (status fail) or ran out of budget gives a lower bound (">").
    local al hdr=1
    for al in augmented augmented@1e-8 augmented@1e-6 augmented@1e-4; do
    awk -F'\t' -v OFS='\t' -v hb="$HEAD_BEAM" -v AL="$al" -v hdr=$hdr -f "$BENCH/awk/paper-tables.awk" "$S"
    hdr=0
    done >"$D/headline.tsv"
    # per-step detail of the headline cases
    awk -F'\t' -v OFS='\t' -v hb="$HEAD_BEAM" -f "$BENCH/awk/paper-tables-2.awk" \
        "$S" >"$D/headline-steps.tsv"
    # the step at which the cumulative update time of the augmented method equals one
    # factorization (the median refactor step: assembly, analysis, factorization, solve)
    awk -F'\t' -v OFS='\t' -f "$BENCH/awk/paper-tables-3.awk" \
        "$S" >"$D/crossover.tsv"
    # the split of the augmented step time (Fig. 10b), every case: fraction of the total
    awk -F'\t' -v OFS='\t' -f "$BENCH/awk/paper-tables-4.awk" \
        "$S" >"$D/split.tsv"
    for f in headline crossover split; do
        log "  $f.tsv"
        column -t -s $'\t' "$D/$f.tsv" >&2
    done
}

paper_plots() {
    local D=$1 S=$1/steps.tsv F=$1/fig files meth m s st exp lbl
    local big_beam=${BEAMS##* } big_brick=${BRICKS##* }
    # per-step rate files: EXP MODEL SIZE METHOD -> F/rate-EXP-MODEL-SIZE-METHOD.tsv (step, Hz)
    rate_file() {
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v sz="$3" -v me="$4" -v ttl="$5" -f "$BENCH/awk/paper-plots.awk" \
            "$S" >"$F/rate-$1-$2-$3-$4.tsv"
        echo "$F/rate-$1-$2-$3-$4.tsv"
    }
    # per-size files at one step: EXP MODEL METHOD STEP -> nodes, Hz
    size_file() {
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v me="$3" -v st="$4" -v ttl="$5" -f "$BENCH/awk/paper-plots-2.awk" "$S" | sort -n -k1,1 >"$F/size-$1-$2-$3-$4.tsv"
        echo "$F/size-$1-$2-$3-$4.tsv"
    }
    # Fig. 5 (deformation) and 7 (cut): rate per step, largest quick mesh of each series
    for exp in deform cut; do
        for m in beam brick; do
            s=$big_brick
            [ $m = beam ] && s=$big_beam
            files=""
            for meth in augmented refactor pcg-jacobi cg; do files="$files $(rate_file $exp $m "$s" $meth "$meth")"; done
            local fig=fig5
            [ $exp = cut ] && fig=fig7
            plot series.gp "$F/$fig-$m" "files='$files'" "logy=1" "xl='step'" "yl='update rate (Hz)'" \
                "ttl='$exp: $m $s, update rate per step'" "keypos='outside right'"
        done
    done
    # Fig. 6 (deformation) and 9 (cut): rate against mesh size at steps 2, 8 and 16
    for exp in deform cut; do
        for m in beam brick; do
            files=""
            for meth in augmented pcg-jacobi cg refactor; do
                for st in 2 8 16; do files="$files $(size_file $exp $m $meth $st "$meth step $st")"; done
            done
            local fig=fig6
            [ $exp = cut ] && fig=fig9
            plot series.gp "$F/$fig-$m" "files='$files'" "logx=1" "logy=1" "xl='nodes'" \
                "yl='update rate (Hz)'" "ttl='$exp: $m series, rate at steps 2, 8, 16'" "keypos='outside right'"
        done
    done
    # Fig. 4: largest closure against node count, cut steps 2, 8, 16
    files=""
    for m in beam brick bunny eye; do
        exp=cut
        [ $m = eye ] && exp=lri
        for st in 2 8 16; do
            awk -F'\t' -v OFS='\t' -v e=$exp -v mo=$m -v st=$st -f "$BENCH/awk/paper-plots-3.awk" "$S" | sort -n -k1,1 >"$F/fig4-$m-$st.tsv"
            [ "$(wc -l <"$F/fig4-$m-$st.tsv")" -gt 1 ] && files="$files $F/fig4-$m-$st.tsv"
        done
    done
    plot series.gp "$F/fig4" "files='$files'" "logx=1" "logy=1" "xl='nodes'" "yl='|closure_L(J a2)| (DOFs)'" \
        "ttl='Largest closure of a step against node count'" "keypos='outside right'"
    # Fig. 10: the bunny: rate per step (a) and the split of the augmented step (b); same for the eye
    for c in "cut bunny" "lri eye"; do
        set -- $c
        files=""
        for meth in augmented refactor pcg-jacobi cg; do files="$files $(rate_file "$1" "$2" default $meth "$meth")"; done
        plot series.gp "$F/fig10a-$2" "files='$files'" "logy=1" "xl='step'" "yl='update rate (Hz)'" \
            "ttl='$1: $2, update rate per step'" "keypos='outside right'"
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -f "$BENCH/awk/paper-plots-4.awk" \
            "$S" >"$F/fig10b-$2.tsv"
        plot split.gp "$F/fig10b-$2" "in='$F/fig10b-$2.tsv'" "ttl='$2: split of the augmented step time'"
    done
    # Fig. 11b: relative residual per step (the paper's 11a, GMRES iterations, has no
    # counterpart since augsolve solves directly)
    files=""
    for c in "cut beam $big_beam" "cut beam $HEAD_BEAM" "cut brick $big_brick" "cut bunny default" "lri eye default"; do
        set -- $c
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v sz="$3" -f "$BENCH/awk/paper-plots-5.awk" "$S" >"$F/fig11b-$2-$3.tsv"
        files="$files $F/fig11b-$2-$3.tsv"
    done
    plot series.gp "$F/fig11b" "files='$files'" "logy=1" "xl='cut step (depth)'" \
        "yl='||K u - f|| / ||f||'" "ttl='Relative residual against cut depth (augmented)'"
}

