#!/usr/bin/env bash
# bench.sh BUILD_DIR [--full] [--only PART[,PART...]] [--results DIR] [--budget S] [-h]
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
# Results (TSV, SVG, PNG, logs) go to RESULTS (default results/, git-ignored); every run is
# recorded in RESULTS/ledger.tsv (command, exit status, seconds), its stdout/stderr in logs/.
# Every run is bounded by timeout(1) and the baselines by a wall budget, so the suite cannot
# hang. The quick default stops the beam series at h = 256 and the brick series at 16 cells
# (the headline's 5x5x1024 beam cut runs in both modes); --full adds h = 512, 1024, the 20-cell
# brick, and larger eyes. OPENBLAS_NUM_THREADS defaults to 1 (shared 2-core machines: two
# OpenBLAS threads on a loaded machine were 10x slower here, see tests/bench/README.md).
set -uo pipefail
shopt -s nullglob

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
PARTS_ALL="bandwidth paper ordering tradeoff stability"

usage() {
    sed -n '2,25p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    exit "${1:-2}"
}

[ $# -ge 1 ] || usage 2
case $1 in -h|--help) usage 0 ;; esac
B=$(cd "$1" 2>/dev/null && pwd) || { echo "bench: no build folder $1" >&2; exit 2; }
shift
FULL=0
ONLY=$PARTS_ALL
R=$ROOT/results
BUDGET_CG=${KT_BENCH_BUDGET:-240}
while [ $# -gt 0 ]; do
    case $1 in
        --full) FULL=1 ;;
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

for t in mesh-prep cutplan augsolve curvature bench_stream bench_cond bench_solves bench_steps; do
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
if [ "$FULL" = 1 ]; then T_RUN=5400; BUDGET_CG=$((BUDGET_CG * 4)); fi

log() { printf '[bench %s] %s\n' "$(date +%H:%M:%S)" "$*" >&2; }
now() { date +%s.%N; }

# ------------------------------------------------------------------ helpers

# run NAME TIMEOUT CMD...: stdout -> logs/NAME.out, stderr -> logs/NAME.err, ledger row.
run() {
    local name=$1 to=$2 t0 rc dt
    shift 2
    t0=$(now)
    timeout -k 10 "$to" "$@" >"$LOGS/$name.out" 2>"$LOGS/$name.err"
    rc=$?
    dt=$(awk -v a="$t0" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }')
    [ $rc -eq 124 ] && echo "bench: timed out after $to s" >>"$LOGS/$name.err"
    printf '%s\t%s\t%d\t%s\t%s\n' "$(date +%FT%T)" "$name" "$rc" "$dt" "$*" >>"$R/ledger.tsv"
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
CANON="method step n_dofs m new_dofs iters closure_max t_update_ms t_step1_ms t_step2_ms t_step3_ms t_total_ms rel_residual refactor verify_rel_diff nnz_L t_factor_ms status"
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
    local exp=$1 model=$2 size=$3 msh=$4 ed=$5 meth=$6 out=$7 name nodes rc
    shift 7
    name="$exp-$model-$size-$meth${SUFFIX:-}"
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
    } | awk -v p="$exp	$model	$size	$nodes" 'NF { print p "\t" $0 }' >>"$out"
}

# plot SCRIPT OUT_PREFIX [gnuplot -e assignments]: SVG and PNG.
plot() {
    local gp=$1 out=$2
    shift 2
    command -v gnuplot >/dev/null || return 0
    local args=(-e "out='$out'")
    for a in "$@"; do args+=(-e "$a"); done
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
        printf 'mode\t%s\n' "$([ "$FULL" = 1 ] && echo full || echo quick)"
        printf 'commit\t%s\n' "$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null)$(git -C "$ROOT" diff --quiet 2>/dev/null || echo ' (with uncommitted changes)')"
    } >"$R/machine-$1.tsv"
}

# ------------------------------------------------------------------ sizes

BEAMS="4 8 16 32 64 128 256"
BRICKS="4 8 12 16"
if [ "$FULL" = 1 ]; then BEAMS="$BEAMS 512 1024"; BRICKS="$BRICKS 20"; fi

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
        [ "$B/cutplan" -nt "$EDITS/cut-bunny.edits" ]; then
        run cut-bunny "$T_MESH" "$B/cutplan" "$PL/cut-bunny.yaml" "$MESHES/bunny.msh" \
            -o "$EDITS/cut-bunny.edits" --mesh-out "$MESHES/bunny-snapped.msh" -q
    fi
}

# @PARTS@

# ------------------------------------------------------------------ main

T0=$(now)
log "results in $R; parts: $ONLY; $([ "$FULL" = 1 ] && echo full || echo quick) mode; build $B"
[ -f "$R/ledger.tsv" ] || printf 'time\tname\texit\tseconds\tcommand\n' >"$R/ledger.tsv"
for p in $ONLY; do
    machine "$p"
    log "== part $p"
    t=$(now)
    "part_$p"
    log "== part $p done in $(awk -v a="$t" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s"
done
log "all done in $(awk -v a="$T0" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s; see $R"
