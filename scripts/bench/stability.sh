# stability.sh: the stability part (scripts/bench.sh --only stability).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: stability
# Each case: a condition number estimate of the intact stiffness (bench_cond), the run a user
# makes (augsolve, defaults, no --verify: its exit status and message), and, when it exits 0,
# the same run again with --verify --verify-tol 1e300 (the same code path: the front door, the
# planned method or the fallback it takes, every step compared with a fresh METIS factorization
# and the difference recorded, never judged: its steps.tsv gives the largest difference, the
# relative residual, refinement steps). Verdict:
#   accurate  difference to a fresh factorization <= 1e-8 (augsolve's --verify-tol default)
#   as-fresh  above 1e-8 but below cond * 1e-16 (what a fresh factorization itself can claim)
#             with a residual <= 1e-8
#   loud      augsolve stopped with exit 1 and a message (no --verify run: its steps would stop
#             at the same step)
#   SILENT    augsolve exited 0 and the answer is neither: silently wrong
#   SILENT-singular-K  augsolve exited 0 while the --verify run's fresh factorization found the
#             stiffness singular
#   error     augsolve exited 0 but its --verify run failed otherwise (see its log)
#   verify-timeout  augsolve exited 0 but its --verify run ran out of time (no verdict)

# derive SRC DST SED_EXPRESSION...: a scene or plan with fields replaced (cached while unchanged)
derive() {
    local src=$1 dst=$2
    shift 2
    sed "$@" "$src" >"$dst.tmp"
    if cmp -s "$dst.tmp" "$dst"; then rm -f "$dst.tmp"; else mv "$dst.tmp" "$dst"; fi
}

# stab_case CASE PARAM MESH EDITS SCENE [solver options]
stab_case() {
    local cs=$1 par=$2 msh=$3 ed=$4 scene=$5 name
    shift 5
    name="st-$cs-${par//[^A-Za-z0-9.+-]/_}"
    # --cases REGEX: only the cases whose CASE-PARAM matches
    if [ -n "$CASES" ] && ! [[ "$cs-$par" =~ $CASES ]]; then return 0; fi
    log "  $cs $par"
    local cond="NaN	NaN	NaN	NaN"
    if run "$name-cond" "$T_STAB" "$B/bench_cond" "$msh" "$scene" --tag "$name"; then
        cond=$(awk -F'\t' 'NR == 2 { printf "%s\t%s\t%s\t%s", $7, $3, $9, $10 }' "$LOGS/$name-cond.out")
    fi
    rm -rf "${RUNS:?}/$name"
    run "$name" "$T_STAB" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name" --scene "$scene" --no-vtk -q "$@"
    local rc=$? msg
    msg=$(grep -v '^$' "$LOGS/$name.err" | tail -n 1 | tr '\t' ' ' | cut -c1-160)
    local ver="NaN	NaN	NaN	NaN	NaN	NaN	NaN" singular=0 verdict
    if [ $rc -eq 0 ]; then
        rm -rf "${RUNS:?}/$name-verify"
        run "$name-verify" "$T_STAB" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name-verify" --scene "$scene" \
            --no-vtk -q --verify --verify-tol 1e300 "$@"
        local vrc=$?
        if [ $vrc -eq 0 ]; then
            ver=$(awk -F'\t' -f "$BENCH/awk/stability-verify.awk" "$RUNS/$name-verify/steps.tsv")
        elif [ $vrc -eq 124 ]; then
            singular=-2 # the --verify run timed out: no verdict
        else
            # the fresh factorization of --verify found the current stiffness singular (a mechanism)
            singular=$(grep -c 'not positive definite' "$LOGS/$name-verify.err")
            [ "$singular" -gt 0 ] || singular=-1
        fi
    fi
    local dup
    dup=$(awk '$1 == "dup" { n++ } END { print n + 0 }' "$ed")
    verdict=$(printf '%s\t%s\t%s\t%s\n' "$rc" "$cond" "$ver" "$singular" | awk -F'\t' -f "$BENCH/awk/stability-stab-case-2.awk")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$cs" "$par" "$(mesh_nodes "$msh")" "$dup" "$cond" "$ver" \
        "$rc" "$verdict" "$msg" >>"$ST"
}

part_stability() {
    local D=$R/stability nu c s msh ed sc
    mkdir -p "$D"
    ST=$D/stability.tsv
    if [ -n "$CASES" ] && [ -s "$ST" ]; then
        # rerun only the selected cases: drop their old rows, keep the rest
        awk -F'\t' -v re="$CASES" 'NR == 1 || ($1 "-" $2) !~ re' "$ST" >"$ST.tmp" && mv "$ST.tmp" "$ST"
    else
        printf 'case\tparam\tnodes\tdup_nodes\tcond\tpivot_ratio\tlanczos_change\tmin_quality\tsteps\tsteps_failed\tverify_rel_diff_max\trel_residual_max\trefinement_iters_max\tn_dofs_end\tm_end\taugsolve_exit\tverdict\taugsolve_message\n' >"$ST"
    fi
    # --cases REGEX that selects no eye case: the eye is not meshed (nor cut, nor deepened)
    local want_eye=0 k
    for k in nu-eye-0.3 contrast-eye-1 depth-eye-0.95; do
        if [ -z "$CASES" ] || [[ $k =~ $CASES ]]; then want_eye=$WITH_EYE; fi
    done
    # Poisson ratio: the 5x5x128 beam cut and the eye LRI (first steps in quick mode)
    local nb=$NU_BEAM eyed=$EDITS/lri-eye.edits WITH_EYE=$want_eye
    prep_box beam $nb
    if [ $WITH_EYE = 1 ]; then
        prep_eye
        if [ "$FULL" != 1 ]; then truncate_edits "$EDITS/lri-eye.edits" "$EDITS/lri-eye-4.edits" 4; eyed=$EDITS/lri-eye-4.edits; fi
    fi
    for nu in 0.3 0.45 0.49 0.499 0.4999; do
        derive "$PB/beam-$nb.yaml" "$SCN/beam-$nb-nu$nu.yaml" -e "s/nu: 0\.3}/nu: $nu}/"
        stab_case nu-beam-$nb "$nu" "$MESHES/beam-$nb.msh" "$EDITS/cut-beam-$nb.edits" "$SCN/beam-$nb-nu$nu.yaml"
        [ $WITH_EYE = 1 ] || continue
        derive "$PL/eye.yaml" "$SCN/eye-nu$nu.yaml" -e "s/nu: 0\.49}/nu: $nu}/"
        stab_case nu-eye "$nu" "$MESHES/eye.msh" "$eyed" "$SCN/eye-nu$nu.yaml"
    done
    # long beams (the paper: condition numbers up to 3.3e12 at h = 1024)
    for s in $LONG_BEAMS; do
        prep_box beam "$s" || continue
        stab_case beam-length "$s" "$MESHES/beam-$s.msh" "$EDITS/cut-beam-$s.edits" "$PB/beam-$s.yaml"
    done
    # region stiffness contrast: sclera / cornea = 1 ... 1e6 (limbus at the geometric mean)
    for c in 1 1e2 1e4 1e6; do
        [ $WITH_EYE = 1 ] || break
        local es el
        es=$(awk -v c="$c" 'BEGIN { printf "%g", 0.3 * c }')
        el=$(awk -v c="$c" 'BEGIN { printf "%g", 0.3 * sqrt(c) }')
        derive "$PL/eye.yaml" "$SCN/eye-contrast$c.yaml" \
            -e "s/^  limbus: {E: [0-9.]* MPa/  limbus: {E: $el MPa/" -e "s/^  sclera: {E: [0-9.]* MPa/  sclera: {E: $es MPa/"
        stab_case contrast-eye "$c" "$MESHES/eye.msh" "$eyed" "$SCN/eye-contrast$c.yaml"
    done
    # slivers next to the cut: a tilted plane through the 8-cell brick, every node within half
    # its shortest edge snapped onto it, the quality floor lowered to 1e-3
    prep_box brick 8
    # (plane x = 0.53 mm tilted by normal [1, 0.2, 0.05]: snapped at the default 0.25 and at
    # 0.5; the plane with normal [1, 0.25, 0.25] is a second tilt that this grid cuts badly)
    for c in "tilt1-snap0.25:0.25:0.05:1, 0.2, 0.05" "tilt1-snap0.5:0.5:0.001:1, 0.2, 0.05" \
             "tilt2-snap0.25:0.25:0.05:1, 0.25, 0.25"; do
        local tag=${c%%:*} rest=${c#*:} fr mq nrm
        fr=${rest%%:*} rest=${rest#*:} mq=${rest%%:*} nrm=${rest#*:}
        local pl=$SCN/cut-brick-8-$tag.yaml
        derive "$PB/cut-brick-8.yaml" "$pl" -e "s|^scene: .*|scene: $PB/brick-8.yaml|" \
            -e "s|^  point: .*|  point: [0.53 mm, 0 mm, 0 mm]|" -e "s|^  normal: .*|  normal: [$nrm]|" \
            -e "\$a snap:\n  fraction: $fr\n  min_quality: $mq" -e "/^  pull_surface:/d"
        if [ -n "$CASES" ] && ! [[ "slivers-brick-8-$tag" =~ $CASES ]]; then continue; fi
        if run "cut-brick-8-$tag" "$T_MESH" "$B/cutplan" "$pl" "$MESHES/brick-8.msh" -o "$EDITS/cut-brick-8-$tag.edits" \
            --mesh-out "$MESHES/brick-8-$tag.msh" -q; then
            stab_case slivers-brick-8 "$tag" "$MESHES/brick-8-$tag.msh" "$EDITS/cut-brick-8-$tag.edits" "$PB/brick-8.yaml"
        else
            printf 'slivers-brick-8\t%s\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tcutplan-refused\t%s\n' \
                "$tag" "$(tail -n 1 "$LOGS/cut-brick-8-$tag.err" | cut -c1-160)" >>"$ST"
        fi
    done
    # incisions to 95% of the local thickness (the ring itself moved to 95%)
    derive "$PL/eye.yaml" "$SCN/eye-depth95.yaml" -e "s/depth_fraction: 0\.9 /depth_fraction: 0.95/"
    derive "$PL/lri-paired-60.yaml" "$SCN/lri-depth95.yaml" -e "s|^scene: .*|scene: $SCN/eye-depth95.yaml|" \
        -e "s/depth_fraction: 0\.9 /depth_fraction: 0.95/"
    if [ $WITH_EYE = 1 ] && mesh "$SCN/eye-depth95.yaml" "$MESHES/eye-depth95.msh" &&
        cut_edits "$SCN/lri-depth95.yaml" "$MESHES/eye-depth95.msh" "$EDITS/lri-depth95.edits"; then
        ed=$EDITS/lri-depth95.edits
        [ "$FULL" != 1 ] && { truncate_edits "$ed" "$EDITS/lri-depth95-4.edits" 4; ed=$EDITS/lri-depth95-4.edits; }
        stab_case depth-eye 0.95 "$MESHES/eye-depth95.msh" "$ed" "$SCN/eye-depth95.yaml"
    fi
    # >= 5,000 duplicated nodes: the 5x5x1024 beam split along 1000 mm, 50 rows a step
    [ $WITH_DUP = 1 ] && prep_box beam 1024 &&
    derive "$PB/cut-beam-1024.yaml" "$SCN/cut-beam-1024-long.yaml" -e "s|^scene: .*|scene: $PB/beam-1024.yaml|" \
        -e "s|^  length: .*|  length: 1000 mm|" -e "s|^  nodes_per_step: .*|  nodes_per_step: 250|"
    if [ $WITH_DUP = 1 ] && cut_edits "$SCN/cut-beam-1024-long.yaml" "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits"; then
        stab_case dup5000-beam-1024 default "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits" "$PB/beam-1024.yaml"
        # what the failure message advises on this cond ~ 1e12 beam: a looser tolerance
        stab_case dup5000-beam-1024 "tol1e-6" "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits" \
            "$PB/beam-1024.yaml" --tol 1e-6
    fi
    column -t -s $'\t' "$ST" >&2
}

