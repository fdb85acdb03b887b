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
    cases="beam-64:zmax beam-256:zmax brick-8:zmax brick-16:zmax eye:incision-ring-1 bunny:-"
    [ "$FULL" = 1 ] && cases="$cases beam-1024:zmax brick-20:zmax"
    printf 'tag\tkind\tnode\tclosure_dofs\tentries\tbytes\ttime_ms\n' >"$D/solves.tsv"
    for c in $cases; do
        m=${c%%:*} set=${c#*:}
        case $m in
            eye) prep_eye ;;
            bunny) prep_bunny ;;
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
    printf '%s\n' "$STEPS_HEADER" >"$S"
    local beams=$BEAMS
    case " $beams " in *" 1024 "*) ;; *) beams="$beams 1024" ;; esac # the headline beam
    for m in beam brick; do
        local sizes=$BRICKS
        [ $m = beam ] && sizes=$beams
        for s in $sizes; do
            prep_box $m "$s" || continue
            for exp in cut deform; do
                # the quick mode runs only the headline's cut on the 5x5x1024 beam
                [ "$FULL" != 1 ] && [ $m = beam ] && [ "$s" = 1024 ] && [ $exp = deform ] && continue
                for meth in $(paper_methods $m "$s"); do
                    log "  $exp $m-$s $meth"
                    solve $exp $m "$s" "$MESHES/$m-$s.msh" "$EDITS/$exp-$m-$s.edits" "$meth" "$S"
                done
            done
        done
    done
    if prep_eye; then
        for meth in augmented refactor pcg-jacobi cg; do
            log "  lri eye $meth"
            solve lri eye default "$MESHES/eye.msh" "$EDITS/lri-eye.edits" "$meth" "$S"
        done
    fi
    if prep_bunny; then
        for meth in augmented refactor pcg-jacobi cg; do
            log "  cut bunny $meth"
            solve cut bunny default "$MESHES/bunny-snapped.msh" "$EDITS/cut-bunny.edits" "$meth" "$S"
        done
    fi
    # the background re-factorization (policy auto: start when the update time since the last
    # factor exceeds the factor's time), against the same runs without it
    local big_beam=${BEAMS##* } big_brick=${BRICKS##* }
    for c in "cut beam $big_beam $MESHES/beam-$big_beam.msh $EDITS/cut-beam-$big_beam.edits" \
             "cut brick $big_brick $MESHES/brick-$big_brick.msh $EDITS/cut-brick-$big_brick.edits" \
             "lri eye default $MESHES/eye.msh $EDITS/lri-eye.edits" \
             "cut bunny default $MESHES/bunny-snapped.msh $EDITS/cut-bunny.edits"; do
        set -- $c
        [ -s "$4" ] && [ -s "$5" ] || continue
        log "  $1 $2-$3 augmented --refactor auto"
        SUFFIX=-auto solve "$1-auto" "$2" "$3" "$4" "$5" augmented "$S" --refactor auto
    done
    paper_tables "$D"
    paper_plots "$D"
}

# Tables from steps.tsv.
paper_tables() {
    local D=$1 S=$1/steps.tsv
    # HEADLINE: per-step time ratios on the same steps. A baseline step that missed its
    # tolerance (status fail) or ran out of budget gives a lower bound (">").
    awk -F'\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        function key() { return $1 SUBSEP $2 SUBSEP $3 }
        ($1 == "cut" && $2 == "beam" && $3 == "1024") || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
            k = key(); st = $(c["step"]) + 0; meth = $(c["method"])
            if (!(k in seen)) { seen[k] = 1; order[++nk] = k; nodes[k] = $4 }
            t[k, meth, st] = $(c["t_total_ms"]); ok[k, meth, st] = $(c["status"])
            if (st > maxst[k]) maxst[k] = st
            if (meth == "augmented") {
                if (st == 0) { nnz[k] = $(c["nnz_L"]); tf[k] = $(c["t_factor_ms"]); ndof[k] = $(c["n_dofs"]) }
                if ($(c["m"]) + 0 > mm[k]) mm[k] = $(c["m"]) + 0
                if ($(c["iters"]) + 0 > it[k]) it[k] = $(c["iters"]) + 0
                if ($(c["closure_max"]) + 0 > cl[k]) cl[k] = $(c["closure_max"]) + 0
                if ($(c["rel_residual"]) + 0 > rr[k]) rr[k] = $(c["rel_residual"]) + 0
            }
        }
        function sortv(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } }
        END {
            print "case", "nodes", "dofs", "nnz_L", "factor_ms", "steps", "aug_ms_median", "aug_ms_max",
                  "refactor_ms_median", "pcg_ms_median", "refactor_over_aug_median", "refactor_over_aug_min",
                  "pcg_over_aug_median", "pcg_over_aug_min", "pcg_steps_failed", "pcg_steps_faster_than_aug",
                  "m_max", "gmres_iters_max", "closure_max", "aug_rel_residual_max"
            for (q = 1; q <= nk; q++) {
                k = order[q]; split(k, kk, SUBSEP); na = nr = np = nra = npa = 0; pf = 0; pw = 0; lb = ""
                for (st = 1; st <= maxst[k]; st++) {
                    if (ok[k, "augmented", st] != "ok") continue
                    a = t[k, "augmented", st]; A[++na] = a
                    if (ok[k, "refactor", st] == "ok") { Rr[++nr] = t[k, "refactor", st]; RA[++nra] = t[k, "refactor", st] / a }
                    if ((k SUBSEP "pcg-jacobi" SUBSEP st) in ok) {
                        if (ok[k, "pcg-jacobi", st] == "ok") { P[++np] = t[k, "pcg-jacobi", st]; PA[++npa] = t[k, "pcg-jacobi", st] / a; if (t[k, "pcg-jacobi", st] < a) pw++ }
                        else { pf++; if (ok[k, "pcg-jacobi", st] == "fail") { PA[++npa] = t[k, "pcg-jacobi", st] / a; lb = ">" } }
                    }
                }
                sortv(A, na); sortv(Rr, nr); sortv(P, np); sortv(RA, nra); sortv(PA, npa)
                printf "%s-%s-%s\t%s\t%s\t%.0f\t%.1f\t%d\t", kk[1], kk[2], kk[3], nodes[k], ndof[k], nnz[k], tf[k], na
                printf "%.2f\t%.2f\t%s\t%s\t", A[int((na + 1) / 2)], A[na], nr ? sprintf("%.2f", Rr[int((nr + 1) / 2)]) : "NaN", np ? sprintf("%.2f", P[int((np + 1) / 2)]) : "NaN"
                printf "%s\t%s\t", nra ? sprintf("%.1f", RA[int((nra + 1) / 2)]) : "NaN", nra ? sprintf("%.1f", RA[1]) : "NaN"
                printf "%s\t%s\t%d\t%d\t", npa ? lb sprintf("%.1f", PA[int((npa + 1) / 2)]) : "NaN", npa ? sprintf("%.2f", PA[1]) : "NaN", pf, pw
                printf "%d\t%d\t%d\t%.1e\n", mm[k], it[k], cl[k], rr[k]
                delete A; delete Rr; delete P; delete RA; delete PA
            }
        }' "$S" >"$D/headline.tsv"
    # per-step detail of the headline cases
    awk -F'\t' -v OFS='\t' '
        NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        ($1 == "cut" && $2 == "beam" && $3 == "1024") || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
            k = $1 "-" $2 "-" $3; st = $(c["step"]); if (!((k, st) in s)) { s[k, st] = 1; rows[++n] = k SUBSEP st }
            t[k, st, $(c["method"])] = $(c["t_total_ms"]) ($(c["status"]) == "ok" ? "" : "(" $(c["status"]) ")")
            if ($(c["method"]) == "augmented") { mm[k, st] = $(c["m"]); it[k, st] = $(c["iters"]); cl[k, st] = $(c["closure_max"]) }
        }
        END { print "case", "step", "m", "gmres_iters", "closure_max", "augmented_ms", "refactor_ms", "pcg_jacobi_ms", "cg_ms"
            for (i = 1; i <= n; i++) { split(rows[i], r, SUBSEP); k = r[1]; st = r[2]
                print k, st, mm[k, st], it[k, st], cl[k, st], t[k, st, "augmented"], t[k, st, "refactor"], t[k, st, "pcg-jacobi"], t[k, st, "cg"] } }' \
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
    for c in "cut beam $big_beam" "cut beam 1024" "cut brick $big_brick" "cut bunny default" "lri eye default"; do
        set -- $c
        awk -F'\t' -v OFS='\t' -v e="$1" -v mo="$2" -v sz="$3" '
            NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", mo "-" sz; next }
            $1 == e && $2 == mo && $3 == sz && $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 {
                print $(c["step"]), $(c["rel_residual"]) }' "$S" >"$F/fig11b-$2-$3.tsv"
        files="$files $F/fig11b-$2-$3.tsv"
    done
    plot series.gp "$F/fig11b" "files='$files'" "logy=1" "xl='cut step (depth)'" \
        "yl='||K u - f|| / ||f||'" "ttl='Relative residual against cut depth (augmented)'"
    # the background re-factorization: per-step time with and without it
    for c in "cut beam $big_beam" "cut brick $big_brick" "lri eye default" "cut bunny default"; do
        set -- $c
        files="$(rate_file "$1" "$2" "$3" augmented "never") $(rate_file "$1-auto" "$2" "$3" augmented "auto")"
        plot series.gp "$F/refactor-auto-$2-$3" "files='$files'" "logy=1" "xl='step'" "yl='update rate (Hz)'" \
            "ttl='$2 $3: augmented, background re-factorization never vs auto'"
    done
}

# @PARTS@

# ------------------------------------------------------------------ main

T0=$(now)
log "results in $R; parts: $ONLY; $([ "$FULL" = 1 ] && echo full || echo quick) mode; build $B"
[ -f "$R/ledger.tsv" ] || printf 'time\tname\texit\twall_s\tcpu_s\tpeak_mb\tcommand\n' >"$R/ledger.tsv"
for p in $ONLY; do
    machine "$p"
    log "== part $p"
    t=$(now)
    "part_$p"
    log "== part $p done in $(awk -v a="$t" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s"
done
log "all done in $(awk -v a="$T0" -v b="$(now)" 'BEGIN { printf "%.0f", b - a }') s; see $R"
