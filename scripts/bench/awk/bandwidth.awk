# bandwidth.awk: from scripts/bench/bandwidth.sh (part_bandwidth)
NR == 1 { print $0, "bound_ms", "ratio"; next }
$6 > 0 { b = $6 / (bw * 1e9) * 1e3; print $0, sprintf("%.6f", b), sprintf("%.2f", $7 / b) }
