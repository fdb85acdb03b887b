# stability-verify.awk: from scripts/bench/stability.sh (stab_case): augsolve --verify's steps.tsv
# (the run's own code path) -> steps after step 0, failed steps (0: augsolve exited 0), the
# largest verify_rel_diff and rel_residual, the most refinement steps, the last step's DOFs and m
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
        { n++
          v = $(c["verify_rel_diff"]); if (v == "NaN" || v + 0 > vd) vd = (v == "NaN" ? "NaN" : v + 0)
          r = $(c["rel_residual"]); if (r != "NaN" && r + 0 > rr) rr = r + 0
          if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0; nd = $(c["n_dofs"]); m = $(c["m"])
          if (vd == "NaN") nanv = 1 }
        END { printf "%d\t0\t%s\t%.2e\t%d\t%s\t%s", n - 1, nanv ? "NaN" : sprintf("%.2e", vd), rr, it, nd, m }
