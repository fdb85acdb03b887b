# tradeoff-curv-cols.awk: from scripts/bench/tradeoff.sh (curv_cols)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { print $(c["step"]), $(c["flattening_D"]), $(c["coupling_ratio"]) }
