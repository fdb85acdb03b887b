# paper-tables-3.awk: from scripts/bench/paper.sh (paper_tables)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
$(c["step"]) + 0 >= 1 && $(c["status"]) == "ok" {
    k = $1 SUBSEP $2 SUBSEP $3; if (!(k in seen)) { seen[k] = 1; order[++nk] = k; nodes[k] = $4 }
    if ($(c["method"]) == "augmented") { na[k]++; ta[k, na[k]] = $(c["t_total_ms"]) }
    if ($(c["method"]) == "refactor") { nr[k]++; tr[k, nr[k]] = $(c["t_total_ms"]) }
}
END { print "exp", "model", "size", "nodes", "refactor_ms_median", "steps", "crossover_step", "aug_cumulative_ms"
    for (q = 1; q <= nk; q++) { k = order[q]; if (!na[k] || !nr[k]) continue
        n = nr[k]; for (i = 1; i <= n; i++) x[i] = tr[k, i]
        for (i = 2; i <= n; i++) { y = x[i]; for (j = i - 1; j >= 1 && x[j] > y; j--) x[j + 1] = x[j]; x[j + 1] = y }
        f = x[int((n + 1) / 2)]; cum = 0; cs = ""
        for (i = 1; i <= na[k]; i++) { cum += ta[k, i]; if (cs == "" && cum >= f) cs = i }
        split(k, kk, SUBSEP)
        print kk[1], kk[2], kk[3], nodes[k], sprintf("%.1f", f), na[k], (cs == "" ? ">" na[k] : cs), sprintf("%.1f", cum) } }
