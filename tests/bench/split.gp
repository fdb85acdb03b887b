# split.gp: the split of each step's time between the edit update and the augmented method's
# three solution steps (the paper's Fig. 10b), as stacked bars.
# Variables: in (columns step, update, step1, step2, step3 in ms, with a header), out, ttl.
set datafile separator tab
if (!exists("ttl")) ttl = "Split of step time"
set title ttl noenhanced
set style data histograms
set style histogram rowstacked
set style fill solid 0.8 border -1
set boxwidth 0.8
set xlabel "step"
set ylabel "time (ms)"
set key top left
set grid y
set xtics rotate by 0
set terminal svg size 860,540 dynamic enhanced font "Helvetica,12"
set output out.".svg"
plot in using 2:xtic(1) title "update (edits, Lset, J)", '' using 3 title "step 1: rhs = H R^{-1} f", \
     '' using 4 title "step 2: GMRES on H R^{-1} J", '' using 5 title "step 3: a_1 = R^{-1}(f - J a_2)"
set terminal pngcairo size 860,540 font "Helvetica,10"
set output out.".png"
replot
