# paper-tables-2.awk: from scripts/bench/paper.sh (paper_tables)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
($1 == "cut" && $2 == "beam" && $3 == hb) || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
    k = $1 "-" $2 "-" $3; st = $(c["step"]); if (!((k, st) in s)) { s[k, st] = 1; rows[++n] = k SUBSEP st }
    t[k, st, $(c["method"])] = $(c["t_total_ms"]) ($(c["status"]) == "ok" ? "" : "(" $(c["status"]) ")")
    if ($(c["method"]) == "augmented") { mm[k, st] = $(c["m"]); it[k, st] = $(c["iters"]); cl[k, st] = $(c["closure_max"]) }
}
END { print "case", "step", "m", "refinement_iters", "closure_max", "augmented_ms", "refactor_ms", "refactor_metis_ms", "pcg_jacobi_ms", "cg_ms"
    for (i = 1; i <= n; i++) { split(rows[i], r, SUBSEP); k = r[1]; st = r[2]
        print k, st, mm[k, st], it[k, st], cl[k, st], t[k, st, "augmented"], t[k, st, "refactor"], t[k, st, "refactor+metis"], t[k, st, "pcg-jacobi"], t[k, st, "cg"] } }
