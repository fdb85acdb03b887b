# paper-tables.awk: from scripts/bench/paper.sh (paper_tables)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
function key() { return $1 SUBSEP $2 SUBSEP $3 }
($1 == "cut" && $2 == "beam" && $3 == hb) || ($1 == "cut" && $2 == "bunny") || ($1 == "lri" && $2 == "eye") {
    k = key(); st = $(c["step"]) + 0; meth = $(c["method"])
    if (!(k in seen)) { seen[k] = 1; order[++nk] = k; nodes[k] = $4 }
    t[k, meth, st] = $(c["t_total_ms"]); ok[k, meth, st] = $(c["status"])
    if (st > maxst[k]) maxst[k] = st
    if (meth == AL) {
        if (st == 0) { nnz[k] = $(c["nnz_L"]); tf[k] = $(c["t_factor_ms"]); ndof[k] = $(c["n_dofs"]) }
        if ($(c["m"]) + 0 > mm[k]) mm[k] = $(c["m"]) + 0
        if ($(c["iters"]) + 0 > it[k]) it[k] = $(c["iters"]) + 0
        if ($(c["closure_max"]) + 0 > cl[k]) cl[k] = $(c["closure_max"]) + 0
        if ($(c["rel_residual"]) + 0 > rr[k]) rr[k] = $(c["rel_residual"]) + 0
    }
}
function sortv(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } }
END {
    if (hdr) print "case", "variant", "nodes", "dofs", "nnz_L", "factor_ms", "steps_total", "steps_aug_ok", "aug_ms_median", "aug_ms_max",
          "refactor_ms_median", "refactor_metis_ms_median", "pcg_ms_median", "refactor_over_aug_median", "refactor_over_aug_min",
          "refactor_metis_over_aug_median",
          "pcg_over_aug_median", "pcg_over_aug_min", "pcg_steps_failed", "pcg_steps_faster_than_aug",
          "m_max", "refinement_iters_max", "closure_max", "aug_rel_residual_max"
    for (q = 1; q <= nk; q++) {
        k = order[q]; split(k, kk, SUBSEP); na = nr = np = nra = npa = nm = nma = 0; pf = 0; pw = 0; lb = ""
        for (st = 1; st <= maxst[k]; st++) {
            # the baselines over all their steps; the ratios on the steps both completed
            if (ok[k, "refactor", st] == "ok") Rr[++nr] = t[k, "refactor", st]
            if (ok[k, "refactor+metis", st] == "ok") Mr[++nm] = t[k, "refactor+metis", st]
            if (ok[k, "pcg-jacobi", st] == "ok") P[++np] = t[k, "pcg-jacobi", st]
            else if ((k SUBSEP "pcg-jacobi" SUBSEP st) in ok) pf++
            if (ok[k, AL, st] != "ok") continue
            a = t[k, AL, st]; A[++na] = a
            if (ok[k, "refactor", st] == "ok") RA[++nra] = t[k, "refactor", st] / a
            if (ok[k, "refactor+metis", st] == "ok") MA[++nma] = t[k, "refactor+metis", st] / a
            if (ok[k, "pcg-jacobi", st] == "ok") { PA[++npa] = t[k, "pcg-jacobi", st] / a; if (t[k, "pcg-jacobi", st] < a) pw++ }
            else if (ok[k, "pcg-jacobi", st] == "fail") { PA[++npa] = t[k, "pcg-jacobi", st] / a; lb = ">" }
        }
        sortv(A, na); sortv(Rr, nr); sortv(P, np); sortv(RA, nra); sortv(PA, npa); sortv(Mr, nm); sortv(MA, nma)
        if (!((k SUBSEP AL SUBSEP 0) in ok)) continue
        printf "%s-%s-%s\t%s\t%s\t%s\t%.0f\t%.1f\t%d\t%d\t", kk[1], kk[2], kk[3], AL, nodes[k], ndof[k], nnz[k], tf[k], maxst[k], na
        printf "%s\t%s\t%s\t%s\t%s\t", na ? sprintf("%.2f", A[int((na + 1) / 2)]) : "NaN", na ? sprintf("%.2f", A[na]) : "NaN", nr ? sprintf("%.2f", Rr[int((nr + 1) / 2)]) : "NaN", nm ? sprintf("%.2f", Mr[int((nm + 1) / 2)]) : "NaN", np ? sprintf("%.2f", P[int((np + 1) / 2)]) : "NaN"
        printf "%s\t%s\t%s\t", nra ? sprintf("%.1f", RA[int((nra + 1) / 2)]) : "NaN", nra ? sprintf("%.1f", RA[1]) : "NaN", nma ? sprintf("%.2f", MA[int((nma + 1) / 2)]) : "NaN"
        printf "%s\t%s\t%d\t%d\t", npa ? lb sprintf("%.1f", PA[int((npa + 1) / 2)]) : "NaN", npa ? sprintf("%.2f", PA[1]) : "NaN", pf, pw
        printf "%d\t%d\t%d\t%.1e\n", mm[k], it[k], cl[k], rr[k]
        delete A; delete Rr; delete P; delete RA; delete PA; delete Mr; delete MA
    }
}
