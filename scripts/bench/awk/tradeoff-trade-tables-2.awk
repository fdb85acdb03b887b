# tradeoff-trade-tables-2.awk: from scripts/bench/tradeoff.sh (trade_tables)
{ d = $2 - $4; if (d < 0) d = -d; if (d > fe) fe = d
                       if ($3 != "NaN" && $5 != "NaN") { d = $3 - $5; if (d < 0) d = -d; if (d > ce) ce = d } }
                     END { printf "%.4f\t%.4f", fe, ce }
