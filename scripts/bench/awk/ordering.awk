# ordering.awk: from scripts/bench/ordering.sh (part_ordering)
$2 == "factor" { f = $7 } $2 == "full-super" { s = $7 }
                $2 == "closure-set" { c += $7; n++ }
                END { printf "%.1f\t%.2f\t%s", f, s, n ? sprintf("%.3f", c / n) : "NaN" }
