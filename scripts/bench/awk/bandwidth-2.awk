# bandwidth-2.awk: from scripts/bench/bandwidth.sh (part_bandwidth)
function med(key,   n, i, j, t, a) { n = cnt[key]; for (i = 1; i <= n; i++) a[i] = v[key, i]
    for (i = 2; i <= n; i++) { t = a[i]; for (j = i - 1; j >= 1 && a[j] > t; j--) a[j + 1] = a[j]; a[j + 1] = t }
    return n ? a[int((n + 1) / 2)] : "NaN" }
NR == 1 { next }
{ k = $1 SUBSEP $2; cnt[k]++; v[k, cnt[k]] = $9; cl[k, cnt[k]] = $4; tm[k, cnt[k]] = $7
  if (!($1 in seen)) { seen[$1] = 1; order[++no] = $1 } n[$1] = ($2 == "full-super") ? $4 : n[$1]
  if ($2 == "full-super") { fs[$1] = $7; fsr[$1] = $9 } if ($2 == "full-simpl") { fp[$1] = $7; fpr[$1] = $9 }
  if ($2 ~ /closure/) { ct[$2 SUBSEP $1] += $7; cc[$2 SUBSEP $1] += $4; cn[$2 SUBSEP $1]++ } }
END {
    print "tag", "n_dofs", "full_super_ms", "full_super_x_bound", "full_simpl_ms", "full_simpl_x_bound",
          "set_closure_mean_dofs", "set_closure_ms_mean", "set_closure_x_bound_median",
          "spread_closure_mean_dofs", "spread_closure_ms_mean", "spread_closure_x_bound_median"
    for (i = 1; i <= no; i++) { t = order[i]; s = "closure-set" SUBSEP t; p = "closure-spread" SUBSEP t
        printf "%s\t%s\t%.3f\t%s\t%.3f\t%s\t", t, n[t], fs[t], fsr[t], fp[t], fpr[t]
        if (cn[s]) printf "%.0f\t%.4f\t%s\t", cc[s] / cn[s], ct[s] / cn[s], med(t SUBSEP "closure-set"); else printf "NaN\tNaN\tNaN\t"
        if (cn[p]) printf "%.0f\t%.4f\t%s\n", cc[p] / cn[p], ct[p] / cn[p], med(t SUBSEP "closure-spread"); else printf "NaN\tNaN\tNaN\n" }
}
