# tradeoff-trade-tables-3.awk: from scripts/bench/tradeoff.sh (trade_tables)
NR == 1 { print "step_ms", "flattening_err_D", "setting"; next }
        $5 != "NaN" && $12 != "NaN" { e = $12 + 0; if (e < 1e-6) e = 1e-6; print $5, e, $1 }
