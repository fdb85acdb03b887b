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
#   tradeoff   eye LRI: the augmented method's tolerance against refactor and Jacobi-PCG, element
#              order and resolution against time and the dioptre error; Pareto plot
#   stability  Poisson ratio to 0.4999, long beams, stiffness contrast to 1e6, slivers, 95%
#              incisions, >= 5,000 duplicated nodes: accurate (verified) or loud?
#   planned    issue 11: the planned method against refactor with METIS, refactor in
#              mesh-prep's order and Jacobi-PCG on the beam 5x5x1024 cut, the eye LRI plan and
#              the bunny cut; the table per case comes from bench_table (lib/io/benchtab.c)
#   nonlin     (only with --only nonlin: long) issue 22: the planned method against the
#              geometrically nonlinear reference (bench_nonlin) on paired and single LRI arcs:
#              SIA, flattening, steepening, coupling, mean K, times (scripts/bench/nonlin.sh)
#   uncertainty issue 21: augsolve --uncertainty against the same plan without it on the demo
#              (plans/eye.yaml, plans/lri-paired-60.yaml): CPU and wall seconds, peak memory,
#              where the derivatives' time goes
# The parts live in scripts/bench/PART.sh (their helpers in common.sh, the report in report.sh)
# and their longer awk programs in scripts/bench/awk/; tests/bench/smoke.sh (ctest -L bench) runs
# every part with --smoke and checks its tables.
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
PARTS_ALL="bandwidth paper ordering tradeoff stability planned uncertainty"
PARTS_OPT="nonlin"   # valid with --only, not run by default (long)

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
    case " $PARTS_ALL $PARTS_OPT " in *" $p "*) ;; *) echo "bench: unknown part $p ($PARTS_ALL $PARTS_OPT)" >&2; exit 2 ;; esac
done
mkdir -p "$R" && R=$(cd "$R" && pwd)
export OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
export LC_ALL=C

for t in mesh-prep cutplan augsolve curvature bench_stream bench_cond bench_solves bench_steps bench_table bench_nonlin; do
    [ -x "$B/$t" ] || { echo "bench: $B/$t is not built (cmake --build $B)" >&2; exit 2; }
done
command -v gnuplot >/dev/null || echo "bench: gnuplot not found: tables only, no plots" >&2

PL=$ROOT/plans
PB=$ROOT/plans/bench   # the benchmark scenes and plans (beams, bricks, bunny, liver)
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

BENCH=$ROOT/scripts/bench
# the parts, their helpers and their awk programs (scripts/bench/awk/)
for f in common bandwidth paper ordering tradeoff stability planned nonlin uncertainty report; do
    # shellcheck source=/dev/null
    . "$BENCH/$f.sh"
done

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
