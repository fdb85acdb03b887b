# common.sh: helpers every part uses (run, mesh, cut_edits, solve, plot, ...) and the case sizes.
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
# ------------------------------------------------------------------ helpers

# run NAME TIMEOUT CMD...: stdout -> logs/NAME.out, stderr -> logs/NAME.err, ledger row.
run() {
    local name=$1 to=$2 t0 rc dt
    shift 2
    t0=$(now)
    rm -f "$LOGS/$name.time"
    timeout -k 10 "$to" /usr/bin/time -f '%U\t%S\t%M' -o "$LOGS/$name.time" "$@" \
        >"$LOGS/$name.out" 2>"$LOGS/$name.err"
    rc=$?
    dt=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }')
    [ $rc -eq 124 ] && echo "bench: timed out after $to s" >>"$LOGS/$name.err"
    # wall and CPU seconds (the CPU share shows how loaded the shared machine was), peak RSS
    local cpu
    cpu=$(awk -F'\t' 'NF == 3 { printf "%.1f\t%.0f", $1 + $2, $3 / 1024 }' "$LOGS/$name.time" 2>/dev/null)
    printf '%s\t%s\t%d\t%s\t%s\t%s\n' "$(date +%FT%T)" "$name" "$rc" "$dt" "${cpu:-NaN	NaN}" "$*" >>"$R/ledger.tsv"
    [ $rc -ne 0 ] && log "  $name: exit $rc: $(grep -v '^$' "$LOGS/$name.err" | tail -n 1 | cut -c1-200)"
    return $rc
}

# mesh SCENE OUT [mesh-prep options]: cached while newer than the scene and the tool.
mesh() {
    local scene=$1 out=$2
    shift 2
    if [ -s "$out" ] && [ "$out" -nt "$scene" ] && [ "$out" -nt "$B/mesh-prep" ]; then return 0; fi
    log "mesh-prep $(basename "$scene") $* -> $(basename "$out")"
    run "mesh-$(basename "$out" .msh)" "$T_MESH" "$B/mesh-prep" "$scene" -o "$out" -q "$@"
}

# cut PLAN MESH OUT [cutplan options]: cached while newer than plan, mesh and tool.
cut_edits() {
    local plan=$1 msh=$2 out=$3
    shift 3
    if [ -s "$out" ] && [ "$out" -nt "$plan" ] && [ "$out" -nt "$msh" ] && [ "$out" -nt "$B/cutplan" ]; then
        return 0
    fi
    run "cut-$(basename "$out" .edits)" "$T_MESH" "$B/cutplan" "$plan" "$msh" -o "$out" -q "$@"
}

# Node count of an ASCII MSH 4.1 file.
mesh_nodes() { awk '/^\$Nodes/ { getline; print $2; exit }' "$1"; }

# Canonical step rows (the columns of bench_steps without its tag).
CANON="method step n_dofs m new_dofs iters closure_max t_update_ms t_step1_ms t_step2_ms t_step3_ms t_total_ms rel_residual verify_rel_diff nnz_L t_factor_ms status"
STEPS_HEADER="exp	model	size	nodes	$(echo $CANON | tr ' ' '\t')"

# canon_aug METHOD STEPS_TSV: augsolve's steps.tsv in the canonical columns (by header name).
canon_aug() {
    awk -F'\t' -v OFS='\t' -v meth="$1" -v cols="$CANON" -f "$BENCH/awk/common-canon-aug.awk" "$2"
}

# solve EXP MODEL SIZE MESH EDITS METHOD OUT [solver options]: one method over the edits;
# canonical rows prefixed by exp, model, size, nodes are appended to OUT. augmented and
# refactor run in augsolve itself (the tool a user runs); when it stops on a numerical failure
# (it writes nothing then) the rows up to the failing step come from bench_steps. CG and
# Jacobi-PCG run in bench_steps, which goes on past a step that misses its tolerance and stops
# at the wall budget.
solve() {
    local exp=$1 model=$2 size=$3 label=$6 out=$7 name nodes rc msh=$4 ed=$5 meth
    shift 7
    # METHOD[+ORDERING][@TOL]: the method with augsolve's --ordering and --tol, labelled so in
    # the method column
    meth=${label%%[@+]*}
    [[ $label == *@* ]] && set -- "$@" --tol "${label#*@}"
    if [[ $label == *+* ]]; then local o=${label#*+}; set -- "$@" --ordering "${o%%@*}"; fi
    # --methods LIST: only these labels
    if [ -n "$METHODS" ] && [[ $METHODS != *" $label "* ]]; then return 0; fi
    name="$exp-$model-$size-${label//[@+]/-}${SUFFIX:-}"
    # --cases REGEX: only the runs whose EXP-MODEL-SIZE matches
    if [ -n "$CASES" ] && ! [[ "$exp-$model-$size" =~ $CASES ]]; then return 0; fi
    nodes=$(mesh_nodes "$msh")
    [ -s "$ed" ] || { log "  $name: no edits ($ed)"; return 1; }
    {
        case $meth in
            augmented|refactor)
                rm -rf "${RUNS:?}/$name"
                run "$name" "$T_RUN" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name" --method "$meth" \
                    --no-vtk -q "$@"
                rc=$?
                if [ $rc -eq 0 ]; then
                    canon_aug "$meth" "$RUNS/$name/steps.tsv"
                elif [ $rc -eq 1 ]; then
                    run "$name-rows" "$T_RUN" "$B/bench_steps" "$msh" "$ed" --method "$meth" \
                        --budget "$BUDGET_CG" "$@"
                    tail -n +2 "$LOGS/$name-rows.out" | cut -f2-
                fi
                ;;
            *)
                run "$name" "$T_RUN" "$B/bench_steps" "$msh" "$ed" --method "$meth" --keep-going \
                    --budget "$BUDGET_CG" "$@"
                tail -n +2 "$LOGS/$name.out" | cut -f2-
                ;;
        esac
    } | awk -F'\t' -v OFS='\t' -v p="$exp	$model	$size	$nodes" -v lb="$label" 'NF { $1 = lb; print p, $0 }' >>"$out"
}

# plot SCRIPT OUT_PREFIX [gnuplot -e assignments]: SVG and PNG.
plot() {
    local gp=$1 out=$2
    shift 2
    command -v gnuplot >/dev/null || return 0
    local args=(-e "out='$out'") a f keep
    for a in "$@"; do
        # files='...': keep only series with data; no plot when none has any
        if [[ $a == files=* ]]; then
            keep=""
            for f in $(eval "echo ${a#files=}"); do [ -f "$f" ] && [ "$(wc -l <"$f")" -gt 1 ] && keep="$keep $f"; done
            [ -n "$keep" ] || return 0
            a="files='${keep# }'"
        fi
        if [[ $a == in=* ]]; then
            f=$(eval "echo ${a#in=}")
            [ -s "$f" ] && [ "$(wc -l <"$f")" -gt 1 ] || return 0
        fi
        args+=(-e "$a")
    done
    gnuplot "${args[@]}" "$GP/$gp" 2>>"$LOGS/gnuplot.err" || log "  gnuplot $gp -> $out failed (logs/gnuplot.err)"
}

# Per-series files for the generic series plot: filter FILE by awk condition, print x y.
series() { # IN OUT AWK_COND XCOL YCOL
    awk -F'\t' -v OFS='\t' -v xc="$4" -v yc="$5" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print xc, yc; next }
        '"$3"' { print $(c[xc]), $(c[yc]) }' "$1" >"$2"
}

machine() {
    {
        printf 'date\t%s\n' "$(date '+%F %T %Z')"
        printf 'host\t%s\n' "$(hostname)"
        printf 'nproc\t%s\n' "$(nproc)"
        printf 'cpu\t%s\n' "$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo)"
        printf 'caches\t%s\n' "$(lscpu 2>/dev/null | awk -F: '/L[123][di]? cache/ { gsub(/^ +/, "", $2); printf "%s %s; ", $1, $2 }')"
        printf 'memory\t%s\n' "$(awk '/^MemTotal/ { printf "%.1f GiB", $2 / 1048576 }' /proc/meminfo)"
        printf 'loadavg\t%s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
        printf 'openblas_threads\t%s\n' "$OPENBLAS_NUM_THREADS"
        printf 'mode\t%s\n' "$([ "$FULL" = 1 ] && echo full || { [ "$SMOKE" = 1 ] && echo smoke || echo quick; })"
        printf 'commit\t%s\n' "$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null)$(git -C "$ROOT" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
    } >"$R/machine-$1.tsv"
}

# ------------------------------------------------------------------ sizes

BEAMS="4 8 16 32 64 128 256"
BRICKS="4 8 12 16"
HEAD_BEAM=1024      # the headline's 25,600-node beam
ORD_BEAM=256        # the ordering part's beam
NU_BEAM=128         # the Poisson-ratio sweep's beam
LONG_BEAMS="4 16 64 256 1024"
WITH_EYE=1 WITH_BUNNY=1 WITH_DUP=1
if [ "$FULL" = 1 ]; then BEAMS="$BEAMS 512 1024"; BRICKS="$BRICKS 20"; ORD_BEAM=1024; fi
# --smoke: the suite's own check, minutes: tiny beams and bricks, no eye, bunny or long beam
if [ "$SMOKE" = 1 ]; then
    BEAMS="4 8" BRICKS="4" HEAD_BEAM=8 ORD_BEAM=8 NU_BEAM=8 LONG_BEAMS="4 8"
    WITH_EYE=0 WITH_BUNNY=0 WITH_DUP=0
fi

# beam/brick meshes and edits, cached.
prep_box() { # beam|brick SIZE
    local m=$1 s=$2
    mesh "$PB/$m-$s.yaml" "$MESHES/$m-$s.msh" || return 1
    cut_edits "$PB/cut-$m-$s.yaml" "$MESHES/$m-$s.msh" "$EDITS/cut-$m-$s.edits"
    cut_edits "$PB/deform-$m-$s.yaml" "$MESHES/$m-$s.msh" "$EDITS/deform-$m-$s.edits"
    return 0
}

# The eye and its LRI plan; EYE_SCENE is the scene meshed. --smoke: the smallest eye that still
# cuts (mesh sizes x 4, no incision-floor refinement, the globe cut off at 60 deg: 13,652
# nodes at order 2; order 1 would refine the cornea to central_thickness / 2.5 and be larger).
EYE_SCENE=$PL/eye.yaml
prep_eye() {
    if [ "$SMOKE" = 1 ]; then
        EYE_SCENE=$SCN/eye-smoke.yaml
        scale_eye 4 <"$PL/eye.yaml" | sed -e '/^    incision_floor:/d' -e 's/^  extent: [0-9]* deg/  extent: 60 deg/' \
            >"$EYE_SCENE.tmp"
        cmp -s "$EYE_SCENE.tmp" "$EYE_SCENE" || mv "$EYE_SCENE.tmp" "$EYE_SCENE"
        rm -f "$EYE_SCENE.tmp"
    fi
    mesh "$EYE_SCENE" "$MESHES/eye.msh" || return 1
    cut_edits "$PL/lri-paired-60.yaml" "$MESHES/eye.msh" "$EDITS/lri-eye.edits"
}

prep_bunny() {
    mesh "$PB/bunny.yaml" "$MESHES/bunny.msh" || return 1
    # the bunny has no surface on the cutting plane: cutplan snaps and writes the mesh it cut
    if [ ! -s "$EDITS/cut-bunny.edits" ] || [ "$MESHES/bunny.msh" -nt "$EDITS/cut-bunny.edits" ] ||
        [ "$B/cutplan" -nt "$EDITS/cut-bunny.edits" ] || [ "$PB/cut-bunny.yaml" -nt "$EDITS/cut-bunny.edits" ]; then
        run cut-bunny "$T_MESH" "$B/cutplan" "$PB/cut-bunny.yaml" "$MESHES/bunny.msh" \
            -o "$EDITS/cut-bunny.edits" --mesh-out "$MESHES/bunny-snapped.msh" -q && return 0
        # refused (snapping would invert a tet on this mesh): the same plan snapping less
        log "  the shipped cut-bunny plan was refused; using snap.fraction 0.15 (scenes/cut-bunny-snap0.15.yaml)"
        derive "$PB/cut-bunny.yaml" "$SCN/cut-bunny-snap0.15.yaml" -e "s|^scene: .*|scene: $PB/bunny.yaml|" \
            -e "s|^  fraction: .*|  fraction: 0.15|"
        run cut-bunny-snap0.15 "$T_MESH" "$B/cutplan" "$SCN/cut-bunny-snap0.15.yaml" "$MESHES/bunny.msh" \
            -o "$EDITS/cut-bunny.edits" --mesh-out "$MESHES/bunny-snapped.msh" -q
    fi
}

