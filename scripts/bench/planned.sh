# planned.sh: the planned part (scripts/bench.sh --only planned).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
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

