# uncertainty.sh: the uncertainty part (scripts/bench.sh --only uncertainty).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: uncertainty
# Issue 21: what augsolve --uncertainty costs on the demo (plans/eye.yaml cut by
# plans/lri-paired-60.yaml, the planned method; --smoke: the smallest eye that still cuts). Per
# variant the same plan twice, without and with --uncertainty: whole run, step VTKs written as
# the demo writes them (all), and (--full, --smoke) with --output anterior (the restricted back
# substitution); with --full the runs alternate twice (plain, uncertain, plain, uncertain) so a
# change of the machine's load falls on both. uncertainty/uncertainty.tsv: wall and CPU seconds and peak memory of each run,
# the CPU ratio, and where the derivatives' time goes (augsolve's log: the prestress solve with
# its derivatives, the derivative matrices, the steps' extra substitutions). Target (issue 21):
# at most +25%.
unc_case() { # CASE MESH EDITS
    local c=$1 msh=$2 ed=$3 D=$R/uncertainty v u name args
    [ -s "$ed" ] || { log "  $c: no edits ($ed)"; return 1; }
    local outs="all" reps="plain uncertainty"
    { [ "$FULL" = 1 ] || [ "$SMOKE" = 1 ]; } && outs="all anterior"
    [ "$FULL" = 1 ] && reps="plain uncertainty plain2 uncertainty2"
    for v in $outs; do
        args=()
        [ $v = anterior ] && args=(--output anterior)
        for u in $reps; do
            name=unc-$c-$v-$u
            local extra=()
            [[ $u == uncertainty* ]] && extra=(--uncertainty)
            log "  $c: $v $u"
            rm -rf "${RUNS:?}/$name"
            run "$name" "$T_RUN" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name" "${args[@]}" "${extra[@]}" ||
                continue
            rm -f "$RUNS/$name"/step-*.vtk # written (their cost counts), not kept
            awk -F'\t' -v n="$name" -v c="$c" -v v="$v" -v u="${u%2}" -v la="$(cut -d' ' -f1 /proc/loadavg)" \
                -v pre="$(sed -n 's/.*prestress .*(\([0-9.]*\) s).*/\1/p' "$LOGS/$name.err")" \
                -v mat="$(sed -n 's/.*derivative quantities, their matrices in \([0-9.]*\) s.*/\1/p' "$LOGS/$name.err")" \
                -v stp="$(sed -n 's/.*quantities, \([0-9.]*\) s in the steps.*/\1/p' "$LOGS/$name.err")" \
                '$2 == n { r = $0; w = $4; cpu = $5; mb = $6 }
                 END { printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", c, v, u, w, cpu, mb,
                       pre == "" ? "NaN" : pre, mat == "" ? "NaN" : mat, stp == "" ? "NaN" : stp, la }' \
                "$R/ledger.tsv" >>"$D/runs.tsv"
        done
    done
}

part_uncertainty() {
    local D=$R/uncertainty
    mkdir -p "$D"
    printf 'case\toutput\trun\twall_s\tcpu_s\tpeak_mb\tprestress_s\tderiv_matrices_s\tderiv_steps_s\tload1\n' >"$D/runs.tsv"
    [ $WITH_EYE = 1 ] || [ "$SMOKE" = 1 ] || return 0
    prep_eye && unc_case eye "$MESHES/eye.msh" "$EDITS/lri-eye.edits"
    # per case and output: the means of the two runs each way, and the ratio with / without
    awk -F'\t' -f "$BENCH/awk/uncertainty-summary.awk" "$D/runs.tsv" >"$D/uncertainty.tsv"
    cat "$D/uncertainty.tsv" >&2
}
