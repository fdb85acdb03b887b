# paper-tables-4.awk: from scripts/bench/paper.sh (paper_tables)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; print "exp", "model", "size", "steps", "update_pct", "step1_pct", "step2_pct", "step3_pct", "total_ms"; next }
$(c["method"]) == "augmented" && $(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
    k = $1 SUBSEP $2 SUBSEP $3; if (!(k in n)) order[++nk] = k; n[k]++
    u[k] += $(c["t_update_ms"]); a[k] += $(c["t_step1_ms"]); b[k] += $(c["t_step2_ms"]); d[k] += $(c["t_step3_ms"]) }
END { for (i = 1; i <= nk; i++) { k = order[i]; T = u[k] + a[k] + b[k] + d[k]; split(k, kk, SUBSEP)
    printf "%s\t%s\t%s\t%d\t%.1f\t%.1f\t%.1f\t%.1f\t%.1f\n", kk[1], kk[2], kk[3], n[k], 100 * u[k] / T, 100 * a[k] / T, 100 * b[k] / T, 100 * d[k] / T, T } }
