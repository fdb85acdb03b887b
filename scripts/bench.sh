#!/usr/bin/env bash
# bench.sh BUILD_DIR [--full|--smoke] [--only PART[,PART...]] [--results DIR] [--budget S] [-h]
#
# The keratome benchmark suite (issue 6, and augsolve's benchmark of issue 3). Five parts, each
# runnable alone, in this order:
#   bandwidth  STREAM triad; full and closure-restricted solves against bytes / bandwidth
#   paper      the paper's section 4 on the same kinds of meshes: beam 5x5xh and brick series,
#              progressive constraints (4.3.1) and an advancing planar cut (4.3.2), the bunny
#              cut and the eye LRI plan; augmented vs refactor vs Jacobi-PCG vs CG on the same
#              steps; Fig. 4, 5, 6, 7, 9, 10, 11; the HEADLINE table
#   ordering   AMD, METIS, constrained (and METIS with the set last) on the eye and the beam
#   tradeoff   eye LRI: GMRES tolerance, preconditioner, re-factorization policy, element order
#              and resolution against time and the dioptre error; Pareto plot
#   stability  Poisson ratio to 0.4999, long beams, stiffness contrast to 1e6, slivers, 95%
#              incisions, >= 5,000 duplicated nodes: accurate (verified) or loud?
#   planned    issue 11: the planned method against refactor with METIS, refactor in
#              mesh-prep's order and Jacobi-PCG on the beam 5x5x1024 cut, the eye LRI plan and
#              the bunny cut; the table per case comes from bench_table (lib/io/benchtab.c)
# Results (TSV, SVG, PNG, logs) go to RESULTS (default results/, git-ignored); every run is
# recorded in RESULTS/ledger.tsv (command, exit status, seconds), its stdout/stderr in logs/.
# Every run is bounded by timeout(1) and the baselines by a wall budget, so the suite cannot
# hang. The quick default stops the beam series at h = 256 and the brick series at 16 cells
# (the headline's 5x5x1024 beam cut runs in both modes); --full adds h = 512, 1024, the 20-cell
# brick, and larger eyes; --smoke checks the suite itself in minutes (tiny beams and bricks, no
# eye, bunny or long beam); --replot redoes the tables and plots of earlier runs (paper,
# tradeoff); --cases REGEX reruns only the solver runs whose EXP-MODEL-SIZE matches (e.g.
# 'cut-bunny', '^lri-eye'), keeping the other rows of paper/steps.tsv (in the stability part:
# the CASE-PARAM rows, e.g. '^nu-beam|^beam-length'); --methods LIST (e.g.
# refactor+metis,augmented@1e-8) only those solver labels. --budget S: wall seconds per
# baseline run (CG, Jacobi-PCG, and in the planned part refactor in mesh-prep's order; default
# 240, x4 with --full). OPENBLAS_NUM_THREADS defaults to 1 (shared 2-core machines: two
# OpenBLAS threads on a loaded machine were 10x slower here, see tests/bench/README.md).
set -uo pipefail
shopt -s nullglob

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
PARTS_ALL="bandwidth paper ordering tradeoff stability planned"

usage() {
    awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "${BASH_SOURCE[0]}"
    exit "${1:-2}"
}

[ $# -ge 1 ] || usage 2
case $1 in -h|--help) usage 0 ;; esac
B=$(cd "$1" 2>/dev/null && pwd) || { echo "bench: no build folder $1" >&2; exit 2; }
shift
FULL=0
SMOKE=0
REPLOT=0
CASES=""
METHODS=""
ONLY=$PARTS_ALL
R=$ROOT/results
BUDGET_CG=${KT_BENCH_BUDGET:-240}
while [ $# -gt 0 ]; do
    case $1 in
        --full) FULL=1 ;;
        --smoke) SMOKE=1 ;;
        --replot) REPLOT=1 ;;
        --cases) CASES=$2; shift ;;
        --methods) METHODS=" ${2//,/ } "; shift ;;
        --only) ONLY=${2//,/ }; shift ;;
        --results) R=$2; shift ;;
        --budget) BUDGET_CG=$2; shift ;;
        -h|--help) usage 0 ;;
        *) echo "bench: unknown option $1 (see --help)" >&2; exit 2 ;;
    esac
    shift
done
for p in $ONLY; do
    case " $PARTS_ALL " in *" $p "*) ;; *) echo "bench: unknown part $p ($PARTS_ALL)" >&2; exit 2 ;; esac
done
mkdir -p "$R" && R=$(cd "$R" && pwd)
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
export LC_ALL=C

for t in mesh-prep cutplan augsolve curvature bench_stream bench_cond bench_solves bench_steps bench_table; do
    [ -x "$B/$t" ] || { echo "bench: $B/$t is not built (cmake --build $B)" >&2; exit 2; }
done
command -v gnuplot >/dev/null || echo "bench: gnuplot not found: tables only, no plots" >&2

PL=$ROOT/plans
GP=$ROOT/tests/bench
MESHES=$R/meshes
EDITS=$R/edits
LOGS=$R/logs
RUNS=$R/runs
SCN=$R/scenes
mkdir -p "$MESHES" "$EDITS" "$LOGS" "$RUNS" "$SCN"

T_MESH=900      # one mesh-prep or cutplan
T_RUN=1800      # one solver run (augsolve, bench_*)
T_STAB=600      # one run of the stability part
if [ "$FULL" = 1 ]; then T_RUN=5400; T_STAB=3600; BUDGET_CG=$((BUDGET_CG * 4)); fi

log() { printf '[bench %s] %s\n' "$(date +%H:%M:%S)" "$*" >&2; }
now() { date +%s.%N; }

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
    awk -F'\t' -v OFS='\t' -v meth="$1" -v cols="$CANON" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; n = split(cols, k, " "); next }
        {
            line = ""
            for (j = 1; j <= n; j++) {
                if (k[j] == "method") v = meth
                else if (k[j] == "status") v = "ok"
                else if (k[j] == "t_factor_ms") v = (NR == 2 && $(c["t_update_ms"]) != "NaN" && meth == "augmented") ? $(c["t_update_ms"]) : "NaN"
                else v = (k[j] in c) ? $(c[k[j]]) : "NaN"
                line = line (j > 1 ? OFS : "") v
            }
            print line
        }' "$2"
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
    mesh "$PL/$m-$s.yaml" "$MESHES/$m-$s.msh" || return 1
    cut_edits "$PL/cut-$m-$s.yaml" "$MESHES/$m-$s.msh" "$EDITS/cut-$m-$s.edits"
    cut_edits "$PL/deform-$m-$s.yaml" "$MESHES/$m-$s.msh" "$EDITS/deform-$m-$s.edits"
    return 0
}

prep_eye() {
    mesh "$PL/eye.yaml" "$MESHES/eye.msh" || return 1
    cut_edits "$PL/lri-paired-60.yaml" "$MESHES/eye.msh" "$EDITS/lri-eye.edits"
}

prep_bunny() {
    mesh "$PL/bunny.yaml" "$MESHES/bunny.msh" || return 1
    # the bunny has no surface on the cutting plane: cutplan snaps and writes the mesh it cut
    if [ ! -s "$EDITS/cut-bunny.edits" ] || [ "$MESHES/bunny.msh" -nt "$EDITS/cut-bunny.edits" ] ||
        [ "$B/cutplan" -nt "$EDITS/cut-bunny.edits" ] || [ "$PL/cut-bunny.yaml" -nt "$EDITS/cut-bunny.edits" ]; then
        run cut-bunny "$T_MESH" "$B/cutplan" "$PL/cut-bunny.yaml" "$MESHES/bunny.msh" \
            -o "$EDITS/cut-bunny.edits" --mesh-out "$MESHES/bunny-snapped.msh" -q && return 0
        # refused (snapping would invert a tet on this mesh): the same plan snapping less
        log "  the shipped cut-bunny plan was refused; using snap.fraction 0.15 (scenes/cut-bunny-snap0.15.yaml)"
        derive "$PL/cut-bunny.yaml" "$SCN/cut-bunny-snap0.15.yaml" -e "s|^scene: .*|scene: $PL/bunny.yaml|" \
            -e "s|^  fraction: .*|  fraction: 0.15|"
        run cut-bunny-snap0.15 "$T_MESH" "$B/cutplan" "$SCN/cut-bunny-snap0.15.yaml" "$MESHES/bunny.msh" \
            -o "$EDITS/cut-bunny.edits" --mesh-out "$MESHES/bunny-snapped.msh" -q
    fi
}

# ================================================================== part: bandwidth
# STREAM triad, then the solves: a full solve against bytes(L) / bandwidth, a closure solve
# against bytes(closure) / bandwidth (model in tests/bench/solves.c).
part_bandwidth() {
    local D=$R/bandwidth cases c m set name
    mkdir -p "$D"
    run stream-1 600 "$B/bench_stream" --mb 256 --trials 10 --threads 1
    run stream-2 600 "$B/bench_stream" --mb 256 --trials 10 --threads 2
    { head -n 1 "$LOGS/stream-1.out"; tail -n 1 "$LOGS/stream-1.out"; tail -n 1 "$LOGS/stream-2.out"; } >"$D/stream.tsv"
    BW=$(awk -F'\t' 'NR == 2 { print $5 }' "$D/stream.tsv")
    [ -n "$BW" ] || { log "  no STREAM figure: bandwidth part stops"; return 1; }
    log "  STREAM triad: $BW GB/s (1 thread, best of 10)"
    cases="beam-64:zmax beam-256:zmax brick-8:zmax brick-16:zmax"
    [ $WITH_EYE = 1 ] && cases="$cases eye:incision-ring-1"
    [ $WITH_BUNNY = 1 ] && cases="$cases bunny:-"
    [ "$FULL" = 1 ] && cases="$cases beam-1024:zmax brick-20:zmax"
    [ "$SMOKE" = 1 ] && cases="beam-8:zmax brick-4:zmax"
    printf 'tag\tkind\tnode\tclosure_dofs\tentries\tbytes\ttime_ms\n' >"$D/solves.tsv"
    for c in $cases; do
        m=${c%%:*} set=${c#*:}
        case $m in
            eye) prep_eye ;;
            bunny) mesh "$PL/bunny.yaml" "$MESHES/bunny.msh" ;;
            *) mesh "$PL/$m.yaml" "$MESHES/$m.msh" ;;
        esac || continue
        local scene=$PL/$m.yaml
        local args=(--sample 40 --spread 40 --reps 5 --tag "$m")
        [ "$set" != - ] && args+=(--set "$set")
        log "  solves on $m"
        run "solves-$m" "$T_RUN" "$B/bench_solves" "$MESHES/$m.msh" "$scene" "${args[@]}" &&
            tail -n +2 "$LOGS/solves-$m.out" >>"$D/solves.tsv"
    done
    # measured time against the streaming bound bytes / bandwidth
    awk -F'\t' -v OFS='\t' -v bw="$BW" '
        NR == 1 { print $0, "bound_ms", "ratio"; next }
        $6 > 0 { b = $6 / (bw * 1e9) * 1e3; print $0, sprintf("%.6f", b), sprintf("%.2f", $7 / b) }' \
        "$D/solves.tsv" >"$D/solves-bound.tsv"
    awk -F'\t' -v OFS='\t' '
        function med(key,   n, i, j, t, a) { n = cnt[key]; for (i = 1; i <= n; i++) a[i] = v[key, i]
            for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
            return n ? a[int((n + 1) / 2)] : "NaN" }
        NR == 1 { next }
        { k = $1 SUBSEP $2; cnt[k]++; v[k, cnt[k]] = $9; cl[k, cnt[k]] = $4; tm[k, cnt[k]] = $7
          if (!($1 in seen)) { seen[$1] = 1; order[++no] = $1 } n[$1] = ($2 == "full-super") ? $4 : n[$1]
          if ($2 == "full-super") { fs[$1] = $7; fsr[$1] = $9 } if ($2 == "full-simpl") { fp[$1] = $7; fpr[$1] = $9 }
          if ($2 ~ /closure/) { ct[$2 SUBSEP $1] += $7; cc[$2 SUBSEP $1] += $4; cn[$2 SUBSEP $1]++ } }
        END {
            print "tag", "n_dofs", "full_super_ms", "full_super_x_bound", "full_simpl_ms", "full_simpl_x_bound",
                  "set_closure_mean_dofs", "set_closure_ms_mean", "set_closure_x_bound_median",
                  "spread_closure_mean_dofs", "spread_closure_ms_mean", "spread_closure_x_bound_median"
            for (i = 1; i <= no; i++) { t = order[i]; s = "closure-set" SUBSEP t; p = "closure-spread" SUBSEP t
                printf "%s\t%s\t%.3f\t%s\t%.3f\t%s\t", t, n[t], fs[t], fsr[t], fp[t], fpr[t]
                if (cn[s]) printf "%.0f\t%.4f\t%s\t", cc[s] / cn[s], ct[s] / cn[s], med(t SUBSEP "closure-set"); else printf "NaN\tNaN\tNaN\t"
                if (cn[p]) printf "%.0f\t%.4f\t%s\n", cc[p] / cn[p], ct[p] / cn[p], med(t SUBSEP "closure-spread"); else printf "NaN\tNaN\tNaN\n" }
        }' "$D/solves-bound.tsv" >"$D/summary.tsv"
    column -t -s $'\t' "$D/summary.tsv" >&2
    plot bandwidth.gp "$D/bandwidth" "in='$D/solves-bound.tsv'" "bw=$BW"
}

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
    # the headline cases again with GMRES stopped at looser tolerances (augsolve's default is
    # 1e-10): 1e-8, and on the beam, whose cut GMRES cannot follow further, 1e-6 and 1e-4
    for c in "cut beam $HEAD_BEAM $MESHES/beam-$HEAD_BEAM.msh $EDITS/cut-beam-$HEAD_BEAM.edits 1e-8 1e-6 1e-4" \
             "lri eye default $MESHES/eye.msh $EDITS/lri-eye.edits 1e-8" \
             "cut bunny default $MESHES/bunny-snapped.msh $EDITS/cut-bunny.edits 1e-8"; do
        set -- $c
        [ -s "$4" ] && [ -s "$5" ] || continue
        local case=("$1" "$2" "$3" "$4" "$5") tol
        shift 5
        for tol in "$@"; do
            log "  ${case[0]} ${case[1]}-${case[2]} augmented --tol $tol"
            solve "${case[@]}" "augmented@$tol" "$S"
        done
        # what a user would otherwise run is a fresh factorization in its best ordering, not
        # in the one chosen for the augmented method's closures
        log "  ${case[0]} ${case[1]}-${case[2]} refactor --ordering metis"
        solve "${case[@]}" "refactor+metis" "$S"
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
    awk -F'\t' -v OFS='\t' -v hb="$HEAD_BEAM" -v AL="$al" -v hdr=$hdr '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        function key() { return $1 SUBSEP $2 SUBSEP $3 }
        ($1 == "cut" && $2 == "beam" && $3 == hb) || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
            k = key(); st = $(c["step"]) + 0; meth = $(c["method"])
            if (!(k in seen)) { seen[k] = 1; order[++nk] = k; nodes[k] = $4 }
            t[k, meth, st] = $(c["t_total_ms"]); ok[k, meth, st] = $(c["status"])
            if (st > maxst[k]) maxst[k] = st
            if (meth == AL) {
                if (st == 0) { nnz[k] = $(c["nnz_L"]); tf[k] = $(c["t_factor_ms"]); ndof[k] = $(c["n_dofs"]) }
                if ($(c["m"]) + 0 > mm[k]) mm[k] = $(c["m"]) + 0
                if ($(c["iters"]) + 0 > it[k]) it[k] = $(c["iters"]) + 0
                if ($(c["closure_max"]) + 0 > cl[k]) cl[k] = $(c["closure_max"]) + 0
                if ($(c["rel_residual"]) + 0 > rr[k]) rr[k] = $(c["rel_residual"]) + 0
            }
        }
        function sortv(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } }
        END {
            if (hdr) print "case", "variant", "nodes", "dofs", "nnz_L", "factor_ms", "steps_total", "steps_aug_ok", "aug_ms_median", "aug_ms_max",
                  "refactor_ms_median", "refactor_metis_ms_median", "pcg_ms_median", "refactor_over_aug_median", "refactor_over_aug_min",
                  "refactor_metis_over_aug_median",
                  "pcg_over_aug_median", "pcg_over_aug_min", "pcg_steps_failed", "pcg_steps_faster_than_aug",
                  "m_max", "gmres_iters_max", "closure_max", "aug_rel_residual_max"
            for (q = 1; q <= nk; q++) {
                k = order[q]; split(k, kk, SUBSEP); na = nr = np = nra = npa = nm = nma = 0; pf = 0; pw = 0; lb = ""
                for (st = 1; st <= maxst[k]; st++) {
                    # the baselines over all their steps; the ratios on the steps both completed
                    if (ok[k, "refactor", st] == "ok") Rr[++nr] = t[k, "refactor", st]
                    if (ok[k, "refactor+metis", st] == "ok") Mr[++nm] = t[k, "refactor+metis", st]
                    if (ok[k, "pcg-jacobi", st] == "ok") P[++np] = t[k, "pcg-jacobi", st]
                    else if ((k SUBSEP "pcg-jacobi" SUBSEP st) in ok) pf++
                    if (ok[k, AL, st] != "ok") continue
                    a = t[k, AL, st]; A[++na] = a
                    if (ok[k, "refactor", st] == "ok") RA[++nra] = t[k, "refactor", st] / a
                    if (ok[k, "refactor+metis", st] == "ok") MA[++nma] = t[k, "refactor+metis", st] / a
                    if (ok[k, "pcg-jacobi", st] == "ok") { PA[++npa] = t[k, "pcg-jacobi", st] / a; if (t[k, "pcg-jacobi", st] < a) pw++ }
                    else if (ok[k, "pcg-jacobi", st] == "fail") { PA[++npa] = t[k, "pcg-jacobi", st] / a; lb = ">" }
                }
                sortv(A, na); sortv(Rr, nr); sortv(P, np); sortv(RA, nra); sortv(PA, npa); sortv(Mr, nm); sortv(MA, nma)
                if (!((k SUBSEP AL SUBSEP 0) in ok)) continue
                printf "%s-%s-%s\t%s\t%s\t%s\t%.0f\t%.1f\t%d\t%d\t", kk[1], kk[2], kk[3], AL, nodes[k], ndof[k], nnz[k], tf[k], maxst[k], na
                printf "%s\t%s\t%s\t%s\t%s\t", na ? sprintf("%.2f", A[int((na + 1) / 2)]) : "NaN", na ? sprintf("%.2f", A[na]) : "NaN", nr ? sprintf("%.2f", Rr[int((nr + 1) / 2)]) : "NaN", nm ? sprintf("%.2f", Mr[int((nm + 1) / 2)]) : "NaN", np ? sprintf("%.2f", P[int((np + 1) / 2)]) : "NaN"
                printf "%s\t%s\t%s\t", nra ? sprintf("%.1f", RA[int((nra + 1) / 2)]) : "NaN", nra ? sprintf("%.1f", RA[1]) : "NaN", nma ? sprintf("%.2f", MA[int((nma + 1) / 2)]) : "NaN"
                printf "%s\t%s\t%d\t%d\t", npa ? lb sprintf("%.1f", PA[int((npa + 1) / 2)]) : "NaN", npa ? sprintf("%.2f", PA[1]) : "NaN", pf, pw
                printf "%d\t%d\t%d\t%.1e\n", mm[k], it[k], cl[k], rr[k]
                delete A; delete Rr; delete P; delete RA; delete PA; delete Mr; delete MA
            }
        }' "$S"
    hdr=0
    done >"$D/headline.tsv"
    # per-step detail of the headline cases
    awk -F'\t' -v OFS='\t' -v hb="$HEAD_BEAM" '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        ($1 == "cut" && $2 == "beam" && $3 == hb) || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
            k = $1 "-" $2 "-" $3; st = $(c["step"]); if (!((k, st) in s)) { s[k, st] = 1; rows[++n] = k SUBSEP st }
            t[k, st, $(c["method"])] = $(c["t_total_ms"]) ($(c["status"]) == "ok" ? "" : "(" $(c["status"]) ")")
            if ($(c["method"]) == "augmented") { mm[k, st] = $(c["m"]); it[k, st] = $(c["iters"]); cl[k, st] = $(c["closure_max"]) }
        }
        END { print "case", "step", "m", "gmres_iters", "closure_max", "augmented_ms", "augmented_tol1e-8_ms", "augmented_tol1e-4_ms", "refactor_ms", "refactor_metis_ms", "pcg_jacobi_ms", "cg_ms"
            for (i = 1; i <= n; i++) { split(rows[i], r, SUBSEP); k = r[1]; st = r[2]
                print k, st, mm[k, st], it[k, st], cl[k, st], t[k, st, "augmented"], t[k, st, "augmented@1e-8"], t[k, st, "augmented@1e-4"], t[k, st, "refactor"], t[k, st, "refactor+metis"], t[k, st, "pcg-jacobi"], t[k, st, "cg"] } }' \
        "$S" >"$D/headline-steps.tsv"
    # the step at which the cumulative update time of the augmented method equals one
    # factorization (the median refactor step: assembly, analysis, factorization, solve)
    awk -F'\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
            k = $1 SUBSEP $2 SUBSEP $3; if (!(k in seen)) { seen[k] = 1; order[++nk] = k; nodes[k] = $4 }
            if ($(c["method"]) == "augmented") { na[k]++; ta[k, na[k]] = $(c["t_total_ms"]) }
            if ($(c["method"]) == "refactor") { nr[k]++; tr[k, nr[k]] = $(c["t_total_ms"]) }
        }
        END { print "exp", "model", "size", "nodes", "refactor_ms_median", "steps", "crossover_step", "aug_cumulative_ms"
            for (q = 1; q <= nk; q++) { k = order[q]; if (!na[k] || !nr[k]) continue
                n = nr[k]; for (i = 1; i <= n; i++) x[i] = tr[k, i]
                for (i = 2; i <= n; i++) { y = x[i]; for (j = i - 1; j >= 1 && x[j] > y; j--) x[j + 1] = x[j]; x[j + 1] = y }
                f = x[int((n + 1) / 2)]; cum = 0; cs = ""
                for (i = 1; i <= na[k]; i++) { cum += ta[k, i]; if (cs == "" && cum >= f) cs = i }
                split(k, kk, SUBSEP)
                print kk[1], kk[2], kk[3], nodes[k], sprintf("%.1f", f), na[k], (cs == "" ? ">" na[k] : cs), sprintf("%.1f", cum) } }' \
        "$S" >"$D/crossover.tsv"
    # Fig. 11a: the largest GMRES iteration count per mesh
    awk -F'\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "exp", "model", "size", "nodes", "gmres_iters_max", "steps_failed"; next }
        $(c["method"]) == "augmented" && ($1 == "cut" || $1 == "deform" || $1 == "lri") {
            k = $1 SUBSEP $2 SUBSEP $3 SUBSEP $4; if (!(k in mx)) { order[++n] = k; mx[k] = 0 }
            if ($(c["iters"]) + 0 > mx[k]) mx[k] = $(c["iters"]) + 0; if ($(c["status"]) != "ok") fl[k]++ }
        END { for (i = 1; i <= n; i++) { split(order[i], kk, SUBSEP); print kk[1], kk[2], kk[3], kk[4], mx[order[i]], fl[order[i]] + 0 } }' \
        "$S" >"$D/gmres-iters.tsv"
    # the split of the augmented step time (Fig. 10b), every case: fraction of the total
    awk -F'\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "exp", "model", "size", "steps", "update_pct", "step1_pct", "step2_pct", "step3_pct", "total_ms"; next }
        $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
            k = $1 SUBSEP $2 SUBSEP $3; if (!(k in n)) order[++nk] = k; n[k]++
            u[k] += $(c["t_update_ms"]); a[k] += $(c["t_step1_ms"]); b[k] += $(c["t_step2_ms"]); d[k] += $(c["t_step3_ms"]) }
        END { for (i = 1; i <= nk; i++) { k = order[i]; T = u[k] + a[k] + b[k] + d[k]; split(k, kk, SUBSEP)
            printf "%s\t%s\t%s\t%d\t%.1f\t%.1f\t%.1f\t%.1f\t%.1f\n", kk[1], kk[2], kk[3], n[k], 100 * u[k] / T, 100 * a[k] / T, 100 * b[k] / T, 100 * d[k] / T, T } }' \
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
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v sz="$3" -v me="$4" -v ttl="$5" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", ttl; next }
            $1 == e && $2 == mo && $3 == sz && $(c["method"]) == me && $(c["step"]) + 0 >= 1 {
                print $(c["step"]), ($(c["status"]) == "ok" && $(c["t_total_ms"]) > 0) ? 1000 / $(c["t_total_ms"]) : "NaN" }' \
            "$S" >"$F/rate-$1-$2-$3-$4.tsv"
        echo "$F/rate-$1-$2-$3-$4.tsv"
    }
    # per-size files at one step: EXP MODEL METHOD STEP -> nodes, Hz
    size_file() {
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v me="$3" -v st="$4" -v ttl="$5" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "nodes", ttl; next }
            $1 == e && $2 == mo && $(c["method"]) == me && $(c["step"]) + 0 == st && $(c["status"]) == "ok" {
                print $4, 1000 / $(c["t_total_ms"]) }' "$S" | sort -n -k1,1 >"$F/size-$1-$2-$3-$4.tsv"
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
            awk -F'\t' -v OFS='\t' -v e=$exp -v mo=$m -v st=$st '
                NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "nodes", mo " step " st; next }
                $1 == e && $2 == mo && $(c["method"]) == "augmented" && $(c["step"]) + 0 == st && $(c["status"]) == "ok" {
                    print $4, $(c["closure_max"]) }' "$S" | sort -n -k1,1 >"$F/fig4-$m-$st.tsv"
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
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", "update", "step1", "step2", "step3"; next }
            $1 == e && $2 == mo && $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
                print $(c["step"]), $(c["t_update_ms"]), $(c["t_step1_ms"]), $(c["t_step2_ms"]), $(c["t_step3_ms"]) }' \
            "$S" >"$F/fig10b-$2.tsv"
        plot split.gp "$F/fig10b-$2" "in='$F/fig10b-$2.tsv'" "ttl='$2: split of the augmented step time'"
    done
    # Fig. 11a: largest GMRES iteration count against nodes; 11b: relative residual per step
    files=""
    for m in beam brick; do
        for exp in cut deform; do
            awk -F'\t' -v OFS='\t' -v e=$exp -v mo=$m 'NR == 1 { print "nodes", mo " " e; next }
                $1 == e && $2 == mo { print $4, $5 }' "$D/gmres-iters.tsv" | sort -n -k1,1 >"$F/fig11a-$m-$exp.tsv"
            files="$files $F/fig11a-$m-$exp.tsv"
        done
    done
    plot series.gp "$F/fig11a" "files='$files'" "logx=1" "xl='nodes'" "yl='largest GMRES iteration count'" \
        "ttl='GMRES iterations against mesh size'"
    files=""
    for c in "cut beam $big_beam" "cut beam $HEAD_BEAM" "cut brick $big_brick" "cut bunny default" "lri eye default"; do
        set -- $c
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v sz="$3" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", mo "-" sz; next }
            $1 == e && $2 == mo && $3 == sz && $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 {
                print $(c["step"]), $(c["rel_residual"]) }' "$S" >"$F/fig11b-$2-$3.tsv"
        files="$files $F/fig11b-$2-$3.tsv"
    done
    plot series.gp "$F/fig11b" "files='$files'" "logy=1" "xl='cut step (depth)'" \
        "yl='||K u - f|| / ||f||'" "ttl='Relative residual against cut depth (augmented)'"
}

# ================================================================== part: ordering
# The same cut under each elimination order mesh-prep offers: nnz(L), flops and closures from
# mesh-prep's symbolic analysis, factor and solve times from bench_solves, per-step times and
# closures of the augmented method from augsolve.
part_ordering() {
    local D=$R/ordering S c model scene plan set ord msh ed files
    D=$R/ordering S=$D/steps.tsv
    mkdir -p "$D"
    printf '%s\n' "$STEPS_HEADER" >"$S"
    printf 'model\tordering\tnodes\tnnz_L\tflops\tetree_height\tclosure_mean\tclosure_max\tclosure_set\tfactor_ms\tfull_solve_ms\tset_closure_solve_ms\tsteps\taug_ms_median\taug_ms_max\tclosure_max_median\tgmres_iters_max\taug_status\n' >"$D/ordering.tsv"
    local beam=$ORD_BEAM cases=""
    [ $WITH_EYE = 1 ] && cases="eye:$PL/eye.yaml:$PL/lri-paired-60.yaml:incision-ring-1"
    cases="$cases beam-$beam:$PL/beam-$beam.yaml:$PL/cut-beam-$beam.yaml:zmax"
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
            solves=$(awk -F'\t' '$2 == "factor" { f = $7 } $2 == "full-super" { s = $7 }
                $2 == "closure-set" { c += $7; n++ }
                END { printf "%.1f\t%.2f\t%s", f, s, n ? sprintf("%.3f", c / n) : "NaN" }' "$LOGS/ord-solves-$model-$ord.out" 2>/dev/null)
            steps=$(awk -F'\t' -v mo="$model" -v o="$ord" '
                NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
                $1 == "ordering" && $2 == mo && $3 == o && $(c["step"]) + 0 >= 1 {
                    if ($(c["status"]) != "ok") { st = $(c["status"]); next }
                    n++; t[n] = $(c["t_total_ms"]); cl[n] = $(c["closure_max"]); if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0 }
                function med(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } return a[int((n + 1) / 2)] }
                END { if (!n) { printf "0\tNaN\tNaN\tNaN\tNaN\t%s", st ? st : "none"; exit }
                      mx = 0; for (i = 1; i <= n; i++) if (t[i] > mx) mx = t[i]
                      printf "%d\t%.2f\t%.2f\t%s\t%d\t%s", n, med(t, n), mx, med(cl, n), it, st ? st : "ok" }' "$S")
            printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$model" "$ord" "$(mesh_nodes "$msh")" "$ana" "$solves" "$steps" >>"$D/ordering.tsv"
        done
        files=""
        for ord in amd metis constrained metis-last; do
            awk -F'\t' -v OFS='\t' -v mo="$model" -v o="$ord" '
                NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", o; next }
                $1 == "ordering" && $2 == mo && $3 == o && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
                    print $(c["step"]), $(c["t_total_ms"]) }' "$S" >"$D/steps-$model-$ord.tsv"
            files="$files $D/steps-$model-$ord.tsv"
        done
        plot series.gp "$D/ordering-$model" "files='$files'" "logy=1" "xl='step'" "yl='augmented step time (ms)'" \
            "ttl='$model: augmented step time under each ordering'"
    done
    column -t -s $'\t' "$D/ordering.tsv" >&2
}

# ================================================================== part: tradeoff
# Eye LRI plan. (1) Solver settings on the default P1 eye: GMRES tolerance x preconditioner,
# re-factorization policies; each run with --verify (difference to a fresh factorization every
# step) and read by curvature; the dioptre error is against the refactor run on the same mesh
# (a fresh factorization every step). (2) Element order and resolution: P1 and P2 eyes with the
# scene's mesh sizes scaled, solved exactly (refactor) so that only the discretization differs;
# the dioptre error is against the most resolved run.

# scale_eye FACTOR < scene > scene: every mesh_size field times FACTOR
scale_eye() {
    awk -v f="$1" '
        /^  mesh_size:/ { inb = 1; print; next }
        inb && /^    [a-z_]+: *[0-9.]+ mm/ { match($0, /[0-9.]+ mm/); v = substr($0, RSTART, RLENGTH - 3) * f
            sub(/[0-9.]+ mm/, sprintf("%.4g mm", v)); print; next }
        inb && !/^    / { inb = 0 }
        { print }'
}

# truncate_edits IN OUT N: the header and the first N steps
truncate_edits() { awk -v n="$3" '/^step / && $2 + 0 > n { exit } { print }' "$1" >"$2"; }

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
    [ $WITH_EYE = 1 ] || { log "  no eye in this mode: tradeoff skipped"; return 0; }
    prep_eye || { log "  no eye mesh: tradeoff stops"; return 1; }
    local nst=4 ed=$EDITS/lri-eye.edits
    if [ "$FULL" != 1 ]; then
        truncate_edits "$EDITS/lri-eye.edits" "$EDITS/lri-eye-$nst.edits" $nst
        ed=$EDITS/lri-eye-$nst.edits
    fi
    # (1) solver settings
    local tols="1e-4 1e-6 1e-8 1e-10 1e-12" tol
    log "  reference: refactor on the default eye"
    trade_run ref-p1 "$MESHES/eye.msh" "$ed" "$PL/eye.yaml" --method refactor
    # the augmented method is a direct bordered solve since issue 11 (no GMRES, no preconditioner,
    # no background re-factorization): --tol is its backward-error bound
    for tol in $tols; do
        log "  augmented --tol $tol"
        trade_run "aug-$tol" "$MESHES/eye.msh" "$ed" "$PL/eye.yaml" --tol $tol --verify --verify-tol 1e300
    done
    log "  pcg-jacobi --tol 1e-8"
    trade_run pcg-1e-8 "$MESHES/eye.msh" "$ed" "$PL/eye.yaml" --method pcg-jacobi --tol 1e-8 --verify --verify-tol 1e300
    # (2) order and resolution: scaled mesh sizes
    # scales of the scene's mesh sizes (the default eye is P2 at scale 1)
    local p1s="1.6 1 0.75" p2s="1.6 1.25 1" sc o scene msh
    [ "$FULL" = 1 ] && p1s="1.6 1 0.75 0.6" p2s="1.6 1.25 1 0.8"
    for o in 1 2; do
        local scales=$p1s
        [ $o = 2 ] && scales=$p2s
        for sc in $scales; do
            scene=$SCN/eye-s$sc.yaml
            scale_eye "$sc" <"$PL/eye.yaml" >"$scene.tmp" && { cmp -s "$scene.tmp" "$scene" || mv "$scene.tmp" "$scene"; }
            rm -f "$scene.tmp"
            msh=$MESHES/eye-p$o-s$sc.msh
            mesh "$scene" "$msh" --order $o || continue
            cut_edits "$PL/lri-paired-60.yaml" "$msh" "$EDITS/lri-eye-p$o-s$sc.edits" || continue
            log "  P$o eye, mesh sizes x $sc: refactor (all steps)"
            trade_run "res-p$o-s$sc" "$msh" "$EDITS/lri-eye-p$o-s$sc.edits" "$scene" --method refactor
            local red=$EDITS/lri-eye-p$o-s$sc.edits
            if [ "$FULL" != 1 ]; then
                truncate_edits "$red" "$EDITS/lri-eye-p$o-s$sc-$nst.edits" $nst
                red=$EDITS/lri-eye-p$o-s$sc-$nst.edits
            fi
            log "  P$o eye, mesh sizes x $sc: augmented, defaults, --verify"
            trade_run "res-p$o-s$sc-aug" "$msh" "$red" "$scene" --verify --verify-tol 1e300
        done
    done
    trade_tables "$D"
}

# curvature.tsv of a run -> "step flattening coupling" lines
curv_cols() {
    awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { print $(c["step"]), $(c["flattening_D"]), $(c["coupling_ratio"]) }' "$1"
}

trade_tables() {
    local D=$1 name nodes rc crc opts run ref
    printf 'setting\tnodes\texit\tsteps\tstep_ms_median\tstep_ms_mean\tgmres_iters_max\tverify_rel_diff_max\trel_residual_max\tflattening_D\tcoupling_ratio\tflattening_err_D\tcoupling_err\treference\n' >"$D/tradeoff.tsv"
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
        [ -s "$run/steps.tsv" ] && st=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $(c["step"]) + 0 >= 1 { n++; t[n] = $(c["t_total_ms"]); s += t[n]
                if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0
                v = $(c["verify_rel_diff"]); if (v != "NaN" && v + 0 > vd) vd = v + 0
                r = $(c["rel_residual"]); if (r != "NaN" && r + 0 > rr) rr = r + 0 }
            END { for (i = 2; i <= n; i++) { x = t[i]; for (j = i - 1; j >= 1 && t[j] > x; j--) t[j + 1] = t[j]; t[j + 1] = x }
                  if (n) printf "%d\t%.1f\t%.1f\t%d\t%.2e\t%.2e", n, t[int((n + 1) / 2)], s / n, it, vd, rr }' "$run/steps.tsv")
        [ -n "$st" ] || st="0	NaN	NaN	NaN	NaN	NaN"
        if [ -s "$run/curvature.tsv" ] && [ -s "$RUNS/tr-$ref/curvature.tsv" ]; then
            cv=$(curv_cols "$run/curvature.tsv" | tail -n 1 | awk '{ printf "%.4f\t%.4f", $2, $3 }')
            # the largest difference over the steps both runs have
            cr=$(join <(curv_cols "$run/curvature.tsv" | sort -k1,1) <(curv_cols "$RUNS/tr-$ref/curvature.tsv" | sort -k1,1) |
                awk '{ d = $2 - $4; if (d < 0) d = -d; if (d > fe) fe = d
                       if ($3 != "NaN" && $5 != "NaN") { d = $3 - $5; if (d < 0) d = -d; if (d > ce) ce = d } }
                     END { printf "%.4f\t%.4f", fe, ce }')
        fi
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$nodes" "$rc" "$st" "${cv:-NaN	NaN}" "${cr:-NaN	NaN}" "$ref" >>"$D/tradeoff.tsv"
    done <"$TR.runs"
    column -t -s $'\t' "$D/tradeoff.tsv" >&2
    # Pareto: time per step against the flattening error (a zero error is drawn at 1e-6 D)
    awk -F'\t' -v OFS='\t' 'NR == 1 { print "step_ms", "flattening_err_D", "setting"; next }
        $5 != "NaN" && $12 != "NaN" { e = $12 + 0; if (e < 1e-6) e = 1e-6; print $5, e, $1 }' \
        "$D/tradeoff.tsv" >"$D/pareto.tsv"
    plot pareto.gp "$D/pareto" "in='$D/pareto.tsv'"
}

# ================================================================== part: stability
# Each case: a condition number estimate of the intact stiffness (bench_cond), the run a user
# makes (augsolve, defaults, no --verify: its exit status and message), and the same steps
# through the library with --verify (bench_steps: the largest difference to a fresh
# factorization, the relative residual, GMRES iterations). Verdict:
#   accurate  difference to a fresh factorization <= 1e-8 (augsolve's --verify-tol default)
#   as-fresh  above 1e-8 but below cond * 1e-16 (what a fresh factorization itself can claim)
#             with a residual <= 1e-8
#   loud      augsolve stopped with exit 1 and a message
#   SILENT    augsolve exited 0 and the answer is neither: silently wrong

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
    run "$name-verify" "$T_STAB" "$B/bench_steps" "$msh" "$ed" --scene "$scene" --verify --keep-going \
        --budget "$BUDGET_CG" "$@"
    local ver
    ver=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $(c["status"]) == "budget" { next }
        { n++; if ($(c["status"]) != "ok") bad++
          v = $(c["verify_rel_diff"]); if (v != "NaN" && v + 0 > vd) vd = v + 0
          r = $(c["rel_residual"]); if (r != "NaN" && r + 0 > rr) rr = r + 0
          if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0; nd = $(c["n_dofs"]); m = $(c["m"]) }
        END { printf "%d\t%d\t%.2e\t%.2e\t%d\t%s\t%s", n - 1, bad, vd, rr, it, nd, m }' "$LOGS/$name-verify.out")
    local dup
    dup=$(awk '$1 == "dup" { n++ } END { print n + 0 }' "$ed")
    local verdict singular
    # the fresh factorization of --verify found the current stiffness singular (a mechanism)
    singular=$(grep -c 'not positive definite' "$LOGS/$name-verify.err")
    verdict=$(printf '%s\t%s\t%s\t%s\n' "$rc" "$cond" "$ver" "$singular" | awk -F'\t' '{
        rc = $1; cond = $2; vd = $8; rr = $9; bad = $7; sing = $13
        if (rc != 0) { print (rc == 1 ? "loud" : (rc == 124 ? "timeout" : "error")); exit }
        if (sing > 0) { print "SILENT-singular-K"; exit }
        if (vd + 0 <= 1e-8 && bad == 0) { print "accurate"; exit }
        if (cond != "NaN" && vd + 0 <= cond * 1e-16 && rr + 0 <= 1e-8 && bad == 0) { print "as-fresh"; exit }
        print "SILENT" }')
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
        printf 'case\tparam\tnodes\tdup_nodes\tcond\tpivot_ratio\tlanczos_change\tmin_quality\tsteps\tsteps_failed\tverify_rel_diff_max\trel_residual_max\tgmres_iters_max\tn_dofs_end\tm_end\taugsolve_exit\tverdict\taugsolve_message\n' >"$ST"
    fi
    # Poisson ratio: the 5x5x128 beam cut and the eye LRI (first steps in quick mode)
    local nb=$NU_BEAM eyed=$EDITS/lri-eye.edits
    prep_box beam $nb
    if [ $WITH_EYE = 1 ]; then
        prep_eye
        if [ "$FULL" != 1 ]; then truncate_edits "$EDITS/lri-eye.edits" "$EDITS/lri-eye-4.edits" 4; eyed=$EDITS/lri-eye-4.edits; fi
    fi
    for nu in 0.3 0.45 0.49 0.499 0.4999; do
        derive "$PL/beam-$nb.yaml" "$SCN/beam-$nb-nu$nu.yaml" -e "s/nu: 0\.3}/nu: $nu}/"
        stab_case nu-beam-$nb "$nu" "$MESHES/beam-$nb.msh" "$EDITS/cut-beam-$nb.edits" "$SCN/beam-$nb-nu$nu.yaml"
        [ $WITH_EYE = 1 ] || continue
        derive "$PL/eye.yaml" "$SCN/eye-nu$nu.yaml" -e "s/nu: 0\.49}/nu: $nu}/"
        stab_case nu-eye "$nu" "$MESHES/eye.msh" "$eyed" "$SCN/eye-nu$nu.yaml"
    done
    # long beams (the paper: condition numbers up to 3.3e12 at h = 1024)
    for s in $LONG_BEAMS; do
        prep_box beam "$s" || continue
        stab_case beam-length "$s" "$MESHES/beam-$s.msh" "$EDITS/cut-beam-$s.edits" "$PL/beam-$s.yaml"
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
        derive "$PL/cut-brick-8.yaml" "$pl" -e "s|^scene: .*|scene: $PL/brick-8.yaml|" \
            -e "s|^  point: .*|  point: [0.53 mm, 0 mm, 0 mm]|" -e "s|^  normal: .*|  normal: [$nrm]|" \
            -e "\$a snap:\n  fraction: $fr\n  min_quality: $mq" -e "/^  pull_surface:/d"
        if [ -n "$CASES" ] && ! [[ "slivers-brick-8-$tag" =~ $CASES ]]; then continue; fi
        if run "cut-brick-8-$tag" "$T_MESH" "$B/cutplan" "$pl" "$MESHES/brick-8.msh" -o "$EDITS/cut-brick-8-$tag.edits" \
            --mesh-out "$MESHES/brick-8-$tag.msh" -q; then
            stab_case slivers-brick-8 "$tag" "$MESHES/brick-8-$tag.msh" "$EDITS/cut-brick-8-$tag.edits" "$PL/brick-8.yaml"
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
    derive "$PL/cut-beam-1024.yaml" "$SCN/cut-beam-1024-long.yaml" -e "s|^scene: .*|scene: $PL/beam-1024.yaml|" \
        -e "s|^  length: .*|  length: 1000 mm|" -e "s|^  nodes_per_step: .*|  nodes_per_step: 250|"
    if [ $WITH_DUP = 1 ] && cut_edits "$SCN/cut-beam-1024-long.yaml" "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits"; then
        stab_case dup5000-beam-1024 default "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits" "$PL/beam-1024.yaml"
        stab_case dup5000-beam-1024 "refactor-m>3000" "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits" \
            "$PL/beam-1024.yaml" --refactor 'm>3000' --refactor-sync
        # what the failure message advises on this cond ~ 1e12 beam: a looser tolerance
        stab_case dup5000-beam-1024 "tol1e-6" "$MESHES/beam-1024.msh" "$EDITS/cut-beam-1024-long.edits" \
            "$PL/beam-1024.yaml" --tol 1e-6
    fi
    column -t -s $'\t' "$ST" >&2
}

# ================================================================== part: planned
# Issue 11: per case, the planned method (augsolve's default) and what a user would run instead,
# each over the whole plan in its own run: planned (peak memory, whole plan), refactor with
# METIS (the reference), refactor in mesh-prep's order and Jacobi-PCG (both in bench_steps, the
# library calls augsolve makes on the problem augsolve builds, under the wall budget --budget:
# a step begun before it is spent runs to its end, the later ones are "budget" rows);
# then planned --verify (a fresh METIS factorization after each step in the same process: the
# ratio under the same load, and the accuracy; --verify-tol 1e-10, 1e-6 on the beam, where two
# fresh direct factorizations already differ by ~4e-6: condition ~3e12) and, where the case has an
# output surface, planned --output SET --verify. bench_table (lib/io/benchtab.c, unit-tested)
# writes planned/CASE.md from the step tables and time records; the load average before and
# after each case goes beside it. --cases REGEX selects cases (beam-5x5x1024, eye, bunny),
# --methods the labels planned, refactor+metis, refactor, pcg-jacobi, planned-verify,
# planned-output.
planned_case() { # CASE MESH EDITS SET VERIFY_TOL
    local c=$1 msh=$2 ed=$3 set=$4 vtol=$5 D=$R/planned lab name args tables=()
    [ -s "$ed" ] || { log "  $c: no edits ($ed)"; return 1; }
    if [ -n "$CASES" ] && ! [[ $c =~ $CASES ]]; then return 0; fi
    printf '%s\tbefore\t%s\n' "$c" "$(cut -d' ' -f1-3 /proc/loadavg)" >>"$D/load.tsv"
    for lab in planned refactor+metis refactor pcg-jacobi planned-verify planned-output; do
        if [ -n "$METHODS" ] && [[ $METHODS != *" $lab "* ]]; then continue; fi
        name=planned-$c-${lab//+/-}
        args=()
        case $lab in
            planned) ;;
            refactor+metis) args=(--method refactor --ordering metis) ;;
            planned-verify) args=(--verify --verify-tol "$vtol") ;;
            planned-output) [ "$set" = - ] && continue; args=(--output "$set" --verify --verify-tol "$vtol") ;;
        esac
        log "  $c: $lab"
        if [ $lab = pcg-jacobi ] || [ $lab = refactor ]; then
            # the budget bounds the steps begun; timeout(1) the run (one step may overrun it)
            run "$name" "$((${BUDGET_CG%.*} + T_RUN))" "$B/bench_steps" "$msh" "$ed" --method "$lab" \
                --keep-going --budget "$BUDGET_CG"
            [ -s "$LOGS/$name.out" ] && tables+=("$lab=$LOGS/$name.out,$LOGS/$name.time")
            continue
        fi
        rm -rf "${RUNS:?}/$name"
        run "$name" "$T_RUN" "$B/augsolve" "$msh" "$ed" -o "$RUNS/$name" --no-vtk -q "${args[@]}" &&
            tables+=("$lab=$RUNS/$name/steps.tsv,$LOGS/$name.time")
    done
    printf '%s\tafter\t%s\n' "$c" "$(cut -d' ' -f1-3 /proc/loadavg)" >>"$D/load.tsv"
    local bw=()
    [ -n "${BW:-}" ] && bw=(--bandwidth "$BW")
    "$B/bench_table" --title "### $c (load average $(awk -F'\t' -v c="$c" '$1 == c { printf "%s%s", s, $3; s = " -> " }' "$D/load.tsv"))" \
        "${bw[@]}" "${tables[@]}" >"$D/$c.md" && cat "$D/$c.md" >&2
}

part_planned() {
    local D=$R/planned
    mkdir -p "$D"
    : >"$D/load.tsv"
    run stream-planned 600 "$B/bench_stream" --mb 256 --trials 5 --threads 1 &&
        BW=$(awk -F'\t' 'NR == 2 { print $5 }' "$LOGS/stream-planned.out")
    log "  STREAM triad: ${BW:-?} GB/s (1 thread)"
    # --cases REGEX: only the selected cases' meshes are made
    picked() { [ -z "$CASES" ] || [[ $1 =~ $CASES ]]; }
    picked beam-5x5x$HEAD_BEAM && prep_box beam $HEAD_BEAM &&
        planned_case beam-5x5x$HEAD_BEAM "$MESHES/beam-$HEAD_BEAM.msh" "$EDITS/cut-beam-$HEAD_BEAM.edits" zmax 1e-6
    [ $WITH_EYE = 1 ] && picked eye && prep_eye &&
        planned_case eye "$MESHES/eye.msh" "$EDITS/lri-eye.edits" anterior 1e-10
    [ $WITH_BUNNY = 1 ] && picked bunny && prep_bunny &&
        planned_case bunny "$MESHES/bunny-snapped.msh" "$EDITS/cut-bunny.edits" - 1e-10
    local f
    : >"$D/planned.md"
    for f in beam-5x5x$HEAD_BEAM eye bunny; do
        [ -s "$D/$f.md" ] && { cat "$D/$f.md"; echo; } >>"$D/planned.md"
    done
}

# ================================================================== report
# results/report.md: every table of this results folder as Markdown, with the machine.
md_table() { # TSV [title]
    [ -s "$1" ] || return 0
    [ -n "${2:-}" ] && printf '\n### %s\n\n' "$2"
    printf '(`%s`)\n\n' "${1#$R/}"
    awk -F'\t' 'NR == 1 { s = "|"; t = "|"; for (i = 1; i <= NF; i++) { s = s " " $i " |"; t = t "---|" } print s; print t; next }
        { s = "|"; for (i = 1; i <= NF; i++) s = s " " $i " |"; print s }' "$1"
}

write_report() {
    local f=$R/report.md m
    {
        printf '# keratome benchmark results\n\nGenerated by scripts/bench.sh on %s.\n' "$(date '+%F %T %Z')"
        for m in "$R"/machine-*.tsv; do
            printf '\n## Machine (%s part)\n\n' "$(basename "$m" .tsv | sed 's/^machine-//')"
            awk -F'\t' '{ printf "- %s: %s\n", $1, $2 }' "$m"
        done
        printf '\n## Bandwidth\n'
        md_table "$R/bandwidth/stream.tsv" "STREAM triad"
        md_table "$R/bandwidth/summary.tsv" "Solves against bytes / bandwidth (x_bound = time / bound)"
        printf '\n## Paper (section 4)\n'
        md_table "$R/paper/headline.tsv" "HEADLINE: per-step times, augmented vs refactor vs Jacobi-PCG"
        md_table "$R/paper/headline-steps.tsv" "Headline cases step by step (ms)"
        md_table "$R/paper/crossover.tsv" "Step at which the cumulative augmented update time equals one factorization"
        md_table "$R/paper/split.tsv" "Split of the augmented step time (Fig. 10b)"
        md_table "$R/paper/gmres-iters.tsv" "Largest GMRES iteration count (Fig. 11a)"
        printf '\n## Ordering\n'
        md_table "$R/ordering/ordering.tsv" "Orderings"
        printf '\n## Speed against accuracy (eye LRI)\n'
        md_table "$R/tradeoff/tradeoff.tsv" "Settings"
        printf '\n## Stability\n'
        md_table "$R/stability/stability.tsv" "Extremes"
        if [ -s "$R/planned/planned.md" ]; then
            printf '\n## The planned method (issue 11)\n\n'
            cat "$R/planned/planned.md"
        fi
        printf '\n## Runs that failed or timed out\n\n'
        awk -F'\t' 'NR > 1 && $3 != 0 { printf "- %s: exit %s after %s s\n", $2, $3, $4 }' "$R/ledger.tsv"
    } >"$f"
    log "report: $f"
}

# ------------------------------------------------------------------ main
# Everything runs from this function, called on the script's last line: bash has then read the
# whole file, so editing the script while a long run goes on cannot derail it.
main() {
    T0=$(now)
    log "results in $R; parts: $ONLY; $([ "$FULL" = 1 ] && echo full || { [ "$SMOKE" = 1 ] && echo smoke || echo quick; }) mode; build $B"
    [ -f "$R/ledger.tsv" ] || printf 'time\tname\texit\twall_s\tcpu_s\tpeak_mb\tcommand\n' >"$R/ledger.tsv"
    for p in $ONLY; do
        if [ "$REPLOT" = 1 ]; then
            # tables and plots again from the TSVs a previous run left
            case $p in
                paper) paper_tables "$R/paper"; paper_plots "$R/paper" ;;
                tradeoff) TR=$R/tradeoff/tradeoff; [ -s "$TR.runs" ] && trade_tables "$R/tradeoff" ;;
                *) log "  --replot: part $p builds its table while it runs; nothing to redo" ;;
            esac
            continue
        fi
        machine "$p"
        log "== part $p"
        t=$(now)
        "part_$p"
        log "== part $p done in $(awk -v a="$t" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s"
    done
    write_report
    log "all done in $(awk -v a="$T0" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s; see $R"
}

main "$@"; exit $?
