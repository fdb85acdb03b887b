# paper-plots-5.awk: from scripts/bench/paper.sh (paper_plots)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "step", mo "-" sz; next }
$1 == e && $2 == mo && $3 == sz && $(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 {
    print $(c["step"]), $(c["rel_residual"]) }
