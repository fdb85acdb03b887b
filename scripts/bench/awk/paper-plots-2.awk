# paper-plots-2.awk: from scripts/bench/paper.sh (paper_plots)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "nodes", ttl; next }
$1 == e && $2 == mo && $(c["method"]) == me && $(c["step"]) + 0 == st && $(c["status"]) == "ok" {
    print $4, 1000 / $(c["t_total_ms"]) }
