# tradeoff-trade-tables.awk: from scripts/bench/tradeoff.sh (trade_tables)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
            $(c["step"]) + 0 >= 1 { n++; t[n] = $(c["t_total_ms"]); s += t[n]
                if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0
                v = $(c["verify_rel_diff"]); if (v != "NaN" && v + 0 > vd) vd = v + 0
                r = $(c["rel_residual"]); if (r != "NaN" && r + 0 > rr) rr = r + 0 }
            END { for (i = 2; i <= n; i++) { x = t[i]; for (j = i - 1; j >= 1 && t[j] > x; j--) t[j + 1] = t[j]; t[j + 1] = x }
                  if (n) printf "%d\t%.1f\t%.1f\t%d\t%.2e\t%.2e", n, t[int((n + 1) / 2)], s / n, it, vd, rr }
