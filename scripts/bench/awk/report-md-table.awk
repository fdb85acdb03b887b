# report-md-table.awk: from scripts/bench/report.sh (md_table)
NR == 1 { s = "|"; t = "|"; for (i = 1; i <= NF; i++) { s = s " " $i " |"; t = t "---|" } print s; print t; next }
        { s = "|"; for (i = 1; i <= NF; i++) s = s " " $i " |"; print s }
