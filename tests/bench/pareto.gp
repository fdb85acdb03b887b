# pareto.gp: time per step against the dioptre error each setting causes (tradeoff part).
# Variables: in (columns step_ms, flattening_err_D, setting), out. The dashed line is 0.05 D.
set datafile separator tab
set logscale xy
set format y "10^{%L}"
set xlabel "median time per step (ms)"
set ylabel "largest error in meridian flattening (D)"
set title "Eye LRI plan: speed against accuracy (errors below 1e-6 D drawn at 1e-6)"
set key top right
set grid
set terminal svg size 900,600 dynamic enhanced font "Helvetica,12"
set output out.".svg"
plot in using 1:2 with points pt 7 ps 1 title "setting", \
     in using 1:2:3 with labels offset 0.8,0.5 left font ",9" noenhanced notitle, \
     0.05 with lines dt 2 lc rgb "black" title "0.05 D"
set terminal pngcairo size 900,600 font "Helvetica,10"
set output out.".png"
replot
