# uncertainty-summary.awk: uncertainty/runs.tsv -> uncertainty.tsv: per case and output set,
# the mean wall and CPU seconds without and with --uncertainty, the CPU ratio (the target of
# issue 21: at most 1.25), and the derivatives' own seconds (means of the --uncertainty runs).
NR == 1 { next }
{
    k = $1 "\t" $2
    if (!(k in seen)) { seen[k] = 1; order[++n] = k }
    nr[k, $3]++
    w[k, $3] += $4; c[k, $3] += $5; mb[k, $3] = $6 > mb[k, $3] ? $6 : mb[k, $3]
    if ($3 == "uncertainty") { pre[k] += $7; mat[k] += $8; stp[k] += $9 }
    if ($3 == "plain") prep[k] += $7
}
END {
    print "case\toutput\twall_plain_s\twall_unc_s\tcpu_plain_s\tcpu_unc_s\tcpu_ratio\tpeak_mb_plain\tpeak_mb_unc\tprestress_plain_s\tprestress_unc_s\tderiv_matrices_s\tderiv_steps_s"
    for (i = 1; i <= n; i++) {
        k = order[i]; p = nr[k, "plain"]; u = nr[k, "uncertainty"]
        if (!p || !u) continue
        printf "%s\t%.1f\t%.1f\t%.1f\t%.1f\t%.3f\t%d\t%d\t%.1f\t%.1f\t%.1f\t%.1f\n", k, w[k, "plain"] / p,
            w[k, "uncertainty"] / u, c[k, "plain"] / p, c[k, "uncertainty"] / u,
            (c[k, "uncertainty"] / u) / (c[k, "plain"] / p), mb[k, "plain"], mb[k, "uncertainty"],
            prep[k] / p, pre[k] / u, mat[k] / u, stp[k] / u
    }
}
