# nonlin.sh: the nonlin part (scripts/bench.sh --only nonlin; not in the default parts: it is
# long). Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ================================================================== part: nonlin
# Issue 22, part 3: what linearizing costs on the eye. Per LRI plan (paired and single, each arc
# opened in ONE step: the final state of a linear or a restarted nonlinear solve does not depend
# on the steps):
#   planned   augsolve's default method (one factorization; its wall time, prestress solve and
#             step 0 included) read by curvature (zone 3 mm, toric fit): the figures of the arc
#             table (scripts/lri-table.sh);
#   linear    bench_nonlin's linear column: one full step of the total Lagrangian assembly from
#             the prestressed state (= the planned answer to its tolerance; tests/
#             bench_nonlin_eye.sh), keratometry by bench_nonlin's own toric fit;
#   newton    bench_nonlin's geometrically nonlinear reference (kt_newton_plan, the code of
#             augsolve --method newton): the cut released in NL_INC load increments (default 4),
#             a factorization per Newton iteration; the same keratometry as linear.
# SIA, flattening, steepening, coupling ratio, mean-K change of linear and newton are read the
# same way, so their ratio is the price of linearizing; planned against linear shows how
# bench_nonlin's fit reads the same field against curvature's.
# The eye (KT_NONLIN_EYE): mid (the quick default: plans/eye.yaml with the incision floor at
# 60 um instead of 42 um: 2% less SIA than the converged default, the factorization about a
# third), default (plans/eye.yaml: --full), smoke (the bench's smoke eye). The arcs
# (KT_NONLIN_ARCS): "60" (quick), "30 60 90" (--full), "30" (--smoke); increments
# KT_NONLIN_INCREMENTS (4). Writes nonlin/nonlin.tsv (one row per plan) and nonlin/nonlin.md,
# with the load average before and after each plan.
part_nonlin() {
    local D=$R/nonlin eye arcs inc scene msh k a name plan ed t0 tp l0 l1 nl
    mkdir -p "$D"
    eye=${KT_NONLIN_EYE:-$([ "$FULL" = 1 ] && echo default || { [ "$SMOKE" = 1 ] && echo smoke || echo mid; })}
    arcs=${KT_NONLIN_ARCS:-$([ "$FULL" = 1 ] && echo "30 60 90" || { [ "$SMOKE" = 1 ] && echo 30 || echo 60; })}
    inc=${KT_NONLIN_INCREMENTS:-4}
    scene=$SCN/nonlin-$eye.yaml
    case $eye in
        default) cp "$PL/eye.yaml" "$scene.tmp" ;;
        mid) sed -e 's/^    incision_floor: 42 um/    incision_floor: 60 um/' "$PL/eye.yaml" >"$scene.tmp"
             grep -q "incision_floor: 60 um" "$scene.tmp" || { log "  nonlin: could not set the floor"; return 1; } ;;
        smoke) scale_eye 4 <"$PL/eye.yaml" | sed -e '/^    incision_floor:/d' -e 's/^  extent: [0-9]* deg/  extent: 60 deg/' >"$scene.tmp" ;;
        *) log "  nonlin: unknown KT_NONLIN_EYE $eye (default, mid, smoke)"; return 1 ;;
    esac
    cmp -s "$scene.tmp" "$scene" || mv "$scene.tmp" "$scene"
    rm -f "$scene.tmp"
    msh=$MESHES/nonlin-$eye.msh
    mesh "$scene" "$msh" || return 1
    [ -s "$D/nonlin.tsv" ] || printf 'eye\tnodes\tplan\tarc\tplanned_s\tplanned_flat_D\tplanned_steep_D\tplanned_cr\tplanned_dk_D\tplanned_sia_D\tlinear_s\tnewton_s\tnewton_iters\tlinear_sia_D\tnewton_sia_D\tlinear_flat_D\tnewton_flat_D\tlinear_steep_D\tnewton_steep_D\tlinear_cr\tnewton_cr\tlinear_dk_D\tnewton_dk_D\tfield_gap\tload_before\tload_after\n' >"$D/nonlin.tsv"
    for k in paired single; do
        for a in $arcs; do
            name=nonlin-$eye-$k-$a
            if [ -n "$CASES" ] && ! [[ $name =~ $CASES ]]; then continue; fi
            [ -f "$PL/lri-$k-$a.yaml" ] || { log "  nonlin: no plan lri-$k-$a"; continue; }
            plan=$SCN/$name.yaml ed=$EDITS/$name.edits
            sed -e "s|^scene:.*|scene: $scene|" -e "s|degrees_per_step:.*|degrees_per_step: $a deg|" \
                "$PL/lri-$k-$a.yaml" >"$plan.tmp"
            cmp -s "$plan.tmp" "$plan" || mv "$plan.tmp" "$plan"
            rm -f "$plan.tmp"
            cut_edits "$plan" "$msh" "$ed" || continue
            l0=$(cut -d' ' -f1 /proc/loadavg)
            log "  $name: planned (load $l0)"
            rm -rf "${RUNS:?}/$name"
            t0=$(now)
            run "$name-planned" "$T_RUN" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name" -q &&
                run "$name-curvature" "$T_RUN" "$B/curvature" "$RUNS/$name" -q --no-png --no-report --no-vtk ||
                continue
            tp=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }')
            log "  $name: newton, $inc increments"
            run "$name-newton" "$((T_RUN * 3))" "$B/bench_nonlin" "$msh" "$scene" "$ed" --increments "$inc" || continue
            l1=$(cut -d' ' -f1 /proc/loadavg)
            nl=$LOGS/$name-newton.out
            awk -F'\t' -v eye="$eye" -v nn="$(mesh_nodes "$msh")" -v k="$k" -v a="$a" -v tp="$tp" -v l0="$l0" -v l1="$l1" '
                FNR == 1 { file++ }
                file == 1 && FNR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
                file == 1 { split($0, p, "\t"); next }
                /^# \|\|u_newton/ { gap = $0; sub(/.*= /, "", gap); next }
                /^#/ { next }
                $1 == "method" { for (i = 1; i <= NF; i++) h[$i] = i; next }
                { m[$1, "s"] = $h["seconds"]; m[$1, "it"] = $h["iterations"]; m[$1, "sia"] = $h["sia_D"]
                  m[$1, "fl"] = $h["flattening_D"]; m[$1, "st"] = $h["steepening_D"]; m[$1, "cr"] = $h["coupling"]
                  m[$1, "dk"] = $h["dK_mean_D"] }
                END { printf "%s\t%s\t%s\t%s\t%s\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n",
                        eye, nn, k, a, tp, p[c["flattening_D"]], p[c["steepening_D"]], p[c["coupling_ratio"]],
                        p[c["dk_mean_D"]], p[c["sia_D"]], m["linear", "s"], m["newton", "s"], m["newton", "it"],
                        m["linear", "sia"], m["newton", "sia"], m["linear", "fl"], m["newton", "fl"],
                        m["linear", "st"], m["newton", "st"], m["linear", "cr"], m["newton", "cr"],
                        m["linear", "dk"], m["newton", "dk"], gap, l0, l1 }' \
                <(awk 'NR == 1 || $1 != "" { r = $0 } NR == 1 { print } END { print r }' "$RUNS/$name/curvature.tsv") "$nl" \
                >>"$D/nonlin.tsv"
            tail -n 1 "$D/nonlin.tsv" >&2
        done
    done
    awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i
        print "| eye (nodes) | plan | planned s | newton s (iterations) | SIA D planned / linear / newton | flattening D lin / nl | steepening D lin / nl | coupling lin / nl | mean K D lin / nl | field gap | load |"
        print "|---|---|---:|---:|---|---|---|---|---|---:|---|"; next }
        { printf "| %s (%s) | %s %s | %s | %s (%s) | %s / %.3f / %.3f | %.3f / %.3f | %.3f / %.3f | %.3f / %.3f | %+.3f / %+.3f | %.1f%% | %s -> %s |\n",
            $c["eye"], $c["nodes"], $c["plan"], $c["arc"], $c["planned_s"], $c["newton_s"], $c["newton_iters"],
            $c["planned_sia_D"], $c["linear_sia_D"], $c["newton_sia_D"], $c["linear_flat_D"], $c["newton_flat_D"],
            $c["linear_steep_D"], $c["newton_steep_D"], $c["linear_cr"], $c["newton_cr"], $c["linear_dk_D"],
            $c["newton_dk_D"], 100 * $c["field_gap"], $c["load_before"], $c["load_after"] }' "$D/nonlin.tsv" >"$D/nonlin.md"
    cat "$D/nonlin.md" >&2
}
