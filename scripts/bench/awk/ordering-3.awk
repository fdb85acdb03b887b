# ordering-3.awk: from scripts/bench/ordering.sh (part_ordering)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", o; next }
$1 == "ordering" && $2 == mo && $3 == o && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
    print $(c["step"]), $(c["t_total_ms"]) }
