# tradeoff.sh: the tradeoff part (scripts/bench.sh --only tradeoff).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: tradeoff
# Eye LRI plan. (1) Solver settings on the default P1 eye: the augmented method's tolerance,
# refactor and Jacobi-PCG; each run with --verify (difference to a fresh factorization every
# step) and read by curvature; the dioptre error is against the refactor run on the same mesh
# (a fresh factorization every step). (2) Element order and resolution: P1 and P2 eyes with the
# scene's mesh sizes scaled, solved exactly (refactor) so that only the discretization differs;
# the dioptre error is against the most resolved run.

# scale_eye FACTOR < scene > scene: every mesh_size field times FACTOR
scale_eye() {
    awk -v f="$1" -f "$BENCH/awk/tradeoff-scale-eye.awk"
}

# truncate_edits IN OUT N: the first N steps of a stream, ended by its 'done' record
# (keratome-edits(5))
truncate_edits() {
    awk -v n="$3" '/^step / { s = $2 + 0; if (s > n) exit } /^done / { exit } { print }
                   END { print "done " (s > n ? n : s) }' "$1" >"$2"
}

# trade_run NAME MESH EDITS SCENE [augsolve options]: augsolve with VTKs and --verify (never
# failing on it), then curvature. Appends one row to $TR.
trade_run() {
    local name=$1 msh=$2 ed=$3 scene=$4 rc crc
    shift 4
    name=${name//[^A-Za-z0-9.+-]/_}
    rm -rf "${RUNS:?}/tr-$name"
    run "tr-$name" "$T_RUN" "$B/augsolve" "$msh" "$ed" -o "$RUNS/tr-$name" --scene "$scene" --binary -q "$@"
    rc=$?
    crc=NaN
    if [ $rc -eq 0 ]; then
        run "tr-$name-curv" "$T_RUN" "$B/curvature" "$RUNS/tr-$name" -q --no-png --no-vtk
        crc=$?
    fi
    printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$(mesh_nodes "$msh")" "$rc" "$crc" "$*" >>"$TR.runs"
}

part_tradeoff() {
    local D=$R/tradeoff
    mkdir -p "$D"
    TR=$D/tradeoff
    : >"$TR.runs"
    # --smoke: the smallest eye (prep_eye), one tolerance, one resolution
    [ $WITH_EYE = 1 ] || [ "$SMOKE" = 1 ] || { log "  no eye in this mode: tradeoff skipped"; return 0; }
    prep_eye || { log "  no eye mesh: tradeoff stops"; return 1; }
    local nst=4 ed=$EDITS/lri-eye.edits
    [ "$SMOKE" = 1 ] && nst=2
    if [ "$FULL" != 1 ]; then
        truncate_edits "$EDITS/lri-eye.edits" "$EDITS/lri-eye-$nst.edits" $nst
        ed=$EDITS/lri-eye-$nst.edits
    fi
    # (1) solver settings
    local tols="1e-4 1e-6 1e-8 1e-10 1e-12" tol
    [ "$SMOKE" = 1 ] && tols="1e-10"
    log "  reference: refactor on the default eye"
    trade_run ref-p1 "$MESHES/eye.msh" "$ed" "$EYE_SCENE" --method refactor
    # the augmented method is a direct bordered solve since issue 11 (no GMRES, no preconditioner,
    # no background re-factorization): --tol is its backward-error bound
    for tol in $tols; do
        log "  augmented --tol $tol"
        trade_run "aug-$tol" "$MESHES/eye.msh" "$ed" "$EYE_SCENE" --tol $tol --verify --verify-tol 1e300
    done
    log "  pcg-jacobi --tol 1e-8"
    [ "$SMOKE" = 1 ] || trade_run pcg-1e-8 "$MESHES/eye.msh" "$ed" "$EYE_SCENE" --method pcg-jacobi --tol 1e-8 --verify --verify-tol 1e300
    # (2) order and resolution: scaled mesh sizes
    # scales of the scene's mesh sizes (the default eye is P2 at scale 1)
    local p1s="1.6 1 0.75" p2s="1.6 1.25 1" sc o scene msh base=$PL/eye.yaml
    [ "$FULL" = 1 ] && p1s="1.6 1 0.75 0.6" p2s="1.6 1.25 1 0.8"
    [ "$SMOKE" = 1 ] && p1s="" p2s="1" base=$EYE_SCENE
    for o in 1 2; do
        local scales=$p1s
        [ $o = 2 ] && scales=$p2s
        for sc in $scales; do
            scene=$SCN/eye-s$sc.yaml
            scale_eye "$sc" <"$base" >"$scene.tmp" && { cmp -s "$scene.tmp" "$scene" || mv "$scene.tmp" "$scene"; }
            rm -f "$scene.tmp"
            msh=$MESHES/eye-p$o-s$sc.msh
            mesh "$scene" "$msh" --order $o || continue
            cut_edits "$PL/lri-paired-60.yaml" "$msh" "$EDITS/lri-eye-p$o-s$sc.edits" || continue
            local red=$EDITS/lri-eye-p$o-s$sc.edits
            if [ "$FULL" != 1 ]; then
                truncate_edits "$red" "$EDITS/lri-eye-p$o-s$sc-$nst.edits" $nst
                red=$EDITS/lri-eye-p$o-s$sc-$nst.edits
            fi
            log "  P$o eye, mesh sizes x $sc: refactor (all steps; --smoke: the first $nst)"
            if [ "$SMOKE" = 1 ]; then
                trade_run "res-p$o-s$sc" "$msh" "$red" "$scene" --method refactor
            else
                trade_run "res-p$o-s$sc" "$msh" "$EDITS/lri-eye-p$o-s$sc.edits" "$scene" --method refactor
            fi
            log "  P$o eye, mesh sizes x $sc: augmented, defaults, --verify"
            trade_run "res-p$o-s$sc-aug" "$msh" "$red" "$scene" --verify --verify-tol 1e300
        done
    done
    trade_tables "$D"
}

# curvature.tsv of a run -> "step flattening coupling" lines
curv_cols() {
    awk -F'\t' -f "$BENCH/awk/tradeoff-curv-cols.awk" "$1"
}

trade_tables() {
    local D=$1 name nodes rc crc opts run ref
    printf 'setting\tnodes\texit\tsteps\tstep_ms_median\tstep_ms_mean\trefinement_iters_max\tverify_rel_diff_max\trel_residual_max\tflattening_D\tcoupling_ratio\tflattening_err_D\tcoupling_err\treference\n' >"$D/tradeoff.tsv"
    # the most resolved run of the resolution study: the last P2 one, else the last P1 one
    local best
    best=$(awk -F'\t' '$1 ~ /^res-p2/ && $1 !~ /-aug$/ && $3 == 0 && $4 == 0 { b = $1 } END { print b }' "$TR.runs")
    [ -n "$best" ] || best=$(awk -F'\t' '$1 ~ /^res-p1/ && $1 !~ /-aug$/ && $3 == 0 && $4 == 0 { b = $1 } END { print b }' "$TR.runs")
    while IFS=$'\t' read -r name nodes rc crc opts; do
        run=$RUNS/tr-$name
        # exact runs of the resolution study against the most resolved one; augmented runs
        # against the exact run on their own mesh
        case $name in res-*-aug) ref=${name%-aug} ;; res-*) ref=$best ;; *) ref=ref-p1 ;; esac
        local st="" cv="" cr=""
        [ -s "$run/steps.tsv" ] && st=$(awk -F'\t' -f "$BENCH/awk/tradeoff-trade-tables.awk" "$run/steps.tsv")
        [ -n "$st" ] || st="0	NaN	NaN	NaN	NaN	NaN"
        if [ -s "$run/curvature.tsv" ] && [ -s "$RUNS/tr-$ref/curvature.tsv" ]; then
            cv=$(curv_cols "$run/curvature.tsv" | tail -n 1 | awk '{ printf "%.4f\t%.4f", $2, $3 }')
            # the largest difference over the steps both runs have
            cr=$(join <(curv_cols "$run/curvature.tsv" | sort -k1,1) <(curv_cols "$RUNS/tr-$ref/curvature.tsv" | sort -k1,1) |
                awk -f "$BENCH/awk/tradeoff-trade-tables-2.awk")
        fi
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$nodes" "$rc" "$st" "${cv:-NaN	NaN}" "${cr:-NaN	NaN}" "$ref" >>"$D/tradeoff.tsv"
    done <"$TR.runs"
    column -t -s $'\t' "$D/tradeoff.tsv" >&2
    # Pareto: time per step against the flattening error (a zero error is drawn at 1e-6 D)
    awk -F'\t' -v OFS='\t' -f "$BENCH/awk/tradeoff-trade-tables-3.awk" \
        "$D/tradeoff.tsv" >"$D/pareto.tsv"
    plot pareto.gp "$D/pareto" "in='$D/pareto.tsv'"
}

