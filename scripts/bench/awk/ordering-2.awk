# ordering-2.awk: from scripts/bench/ordering.sh (part_ordering)
NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
$1 == "ordering" && $2 == mo && $3 == o && $(c["step"]) + 0 >= 1 {
    if ($(c["status"]) != "ok") { st = $(c["status"]); next }
    n++; t[n] = $(c["t_total_ms"]); cl[n] = $(c["closure_max"]); if ($(c["iters"]) + 0 > it) it = $(c["iters"]) + 0 }
function med(a, n,   i, j, x) { for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x } return a[int((n + 1) / 2)] }
END { if (!n) { printf "0\tNaN\tNaN\tNaN\tNaN\t%s", st ? st : "none"; exit }
      mx = 0; for (i = 1; i <= n; i++) if (t[i] > mx) mx = t[i]
      printf "%d\t%.2f\t%.2f\t%s\t%d\t%s", n, med(t, n), mx, med(cl, n), it, st ? st : "ok" }
