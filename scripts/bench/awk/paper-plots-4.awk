# paper-plots-4.awk: from scripts/bench/paper.sh (paper_plots)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", "update", "step1", "step2", "step3"; next }
$1 == e && $2 == mo && $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
    print $(c["step"]), $(c["t_update_ms"]), $(c["t_step1_ms"]), $(c["t_step2_ms"]), $(c["t_step3_ms"]) }
