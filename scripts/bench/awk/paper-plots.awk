# paper-plots.awk: from scripts/bench/paper.sh (paper_plots)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", ttl; next }
$1 == e && $2 == mo && $3 == sz && $(c["method"]) == me && $(c["step"]) + 0 >= 1 {
    print $(c["step"]), ($(c["status"]) == "ok" && $(c["t_total_ms"]) > 0) ? 1000 / $(c["t_total_ms"]) : "NaN" }
