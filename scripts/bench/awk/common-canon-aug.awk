# common-canon-aug.awk: from scripts/bench/common.sh (canon_aug)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; n = split(cols, k, " "); next }
{
    line = ""
    for (j = 1; j <= n; j++) {
        if (k[j] == "method") v = meth
        else if (k[j] == "status") v = "ok"
        else if (k[j] == "t_factor_ms") v = (NR == 2 && $(c["t_update_ms"]) != "NaN" && meth == "augmented") ? $(c["t_update_ms"]) : "NaN"
        else v = (k[j] in c) ? $(c[k[j]]) : "NaN"
        line = line (j > 1 ? OFS : "") v
    }
    print line
}
