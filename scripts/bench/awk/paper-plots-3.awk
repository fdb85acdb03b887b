# paper-plots-3.awk: from scripts/bench/paper.sh (paper_plots)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "nodes", mo " step " st; next }
$1 == e && $2 == mo && $(c["method"]) == "augmented" && $(c["step"]) + 0 == st && $(c["status"]) == "ok" {
    print $4, $(c["closure_max"]) }
