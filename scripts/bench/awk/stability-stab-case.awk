# stability-stab-case.awk: from scripts/bench/stability.sh (stab_case)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        $(c["status"]) == "budget" { next }
        { n++; if ($(c["status"]) != "ok") bad++
          v = $(c["verify_rel_diff"]); if (v != "NaN" && v + 0 > vd) vd = v + 0
          r = $(c["rel_residual"]); if (r != "NaN" && r + 0 > rr) rr = r + 0
          if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0; nd = $(c["n_dofs"]); m = $(c["m"]) }
        END { printf "%d\t%d\t%.2e\t%.2e\t%d\t%s\t%s", n - 1, bad, vd, rr, it, nd, m }
