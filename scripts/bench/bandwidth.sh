# bandwidth.sh: the bandwidth part (scripts/bench.sh --only bandwidth).
# Sourced by scripts/bench.sh, which parses the options and sets the folders.
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
            bunny) mesh "$PB/bunny.yaml" "$MESHES/bunny.msh" ;;
            *) mesh "$PB/$m.yaml" "$MESHES/$m.msh" ;;
        esac || continue
        local scene=$PB/$m.yaml
        [ "$m" = eye ] && scene=$PL/eye.yaml
        local args=(--sample 40 --spread 40 --reps 5 --tag "$m")
        [ "$set" != - ] && args+=(--set "$set")
        log "  solves on $m"
        run "solves-$m" "$T_RUN" "$B/bench_solves" "$MESHES/$m.msh" "$scene" "${args[@]}" &&
            tail -n +2 "$LOGS/solves-$m.out" >>"$D/solves.tsv"
    done
    # measured time against the streaming bound bytes / bandwidth
    awk -F'\t' -v OFS='\t' -v bw="$BW" -f "$BENCH/awk/bandwidth.awk" \
        "$D/solves.tsv" >"$D/solves-bound.tsv"
    awk -F'\t' -v OFS='\t' -f "$BENCH/awk/bandwidth-2.awk" "$D/solves-bound.tsv" >"$D/summary.tsv"
    column -t -s $'\t' "$D/summary.tsv" >&2
    plot bandwidth.gp "$D/bandwidth" "in='$D/solves-bound.tsv'" "bw=$BW"
}

