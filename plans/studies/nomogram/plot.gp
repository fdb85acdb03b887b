# plot.gp: SIA against arc, three panels (per incision count, per depth, per age), the
# simulated series as lines with points and the clinical anchors (anchors.tsv) as open symbols.
# Called by summarize.sh with: term (png|svg), out, dir (by-count.dat, by-depth.dat,
# by-age.dat: blocks of "arc sia" headed by a quoted title), anchors, nc, nd, na (block counts).
if (term eq 'png') { set terminal pngcairo size 1800,600 font ',10' } else { set terminal svg size 1800,600 font 'sans,10' }
set output out
set datafile separator whitespace
set key top left box opaque font ',8' spacing 0.9
set grid
set xlabel 'arc per incision (deg)'
set ylabel 'SIA (D)'
set xrange [0:100]
set yrange [0:*]
set multiplot layout 1,3 title 'keratome nomogram study: surgically induced astigmatism against arc'
anch = "< awk -F'\t' '$1 == \"wallace\" && $3 == %d { print $4, $5 }' ".anchors
anch60 = "< awk -F'\t' '$1 == \"wallace\" && $2 == \"60-70\" && $3 == %d { print $4, $5 }' ".anchors
wang = "< awk -F'\t' '$1 == \"wang2003\" && $3 == %d { print $4, $5 }' ".anchors
set title 'per incision count (reference eye, depth 0.9)'
plot for [i=0:(nc > 0 ? nc - 1 : 0)] dir.'/by-count.dat' index i using 1:2 with linespoints lw 2 pt 7 title columnheader(1), \
     sprintf(anch60, 1) using 1:2 with points pt 6 ps 1.5 lc rgb 'black' title 'Wallace 60-70 y, one incision (band midpoints)', \
     sprintf(anch60, 2) using 1:2 with points pt 4 ps 1.5 lc rgb 'black' title 'Wallace 60-70 y, a pair (band midpoints)', \
     sprintf(wang, 1) using 1:2 with points pt 8 ps 2 lc rgb 'red' title 'Wang 2003, one 6 mm incision', \
     sprintf(wang, 2) using 1:2 with points pt 10 ps 2 lc rgb 'red' title 'Wang 2003, a pair'
set title 'per depth (reference eye, paired)'
plot for [i=0:(nd > 0 ? nd - 1 : 0)] dir.'/by-depth.dat' index i using 1:2 with linespoints lw 2 pt 7 title columnheader(1), \
     sprintf(anch60, 2) using 1:2 with points pt 4 ps 1.5 lc rgb 'black' title 'Wallace 60-70 y, a pair (band midpoints)', \
     sprintf(wang, 2) using 1:2 with points pt 10 ps 2 lc rgb 'red' title 'Wang 2003, a pair'
set title 'per age (depth 0.9)'
plot for [i=0:(na > 0 ? na - 1 : 0)] dir.'/by-age.dat' index i using 1:2 with linespoints lw 2 pt 7 title columnheader(1), \
     sprintf(anch, 1) using 1:2 with points pt 6 ps 1.5 lc rgb 'black' title 'Wallace 40-50, 60-70, 80+ y, one incision', \
     sprintf(anch, 2) using 1:2 with points pt 4 ps 1.5 lc rgb 'black' title 'Wallace 40-50, 60-70, 80+ y, a pair'
unset multiplot
