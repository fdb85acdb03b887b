# bandwidth.gp: measured solve time against the bytes the solve streams (tests/bench/solves.c).
# Variables: in (solves-bound.tsv), out (prefix of the .svg and .png), bw (GB/s, STREAM triad).
# The line is the streaming bound bytes / bandwidth; points above it are slower than memory.
set datafile separator tab
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "bytes streamed (model: 2 x 12 B per L entry simplicial, 2 x 8 B supernodal)"
set ylabel "time (ms)"
set title sprintf("Solves against the memory bandwidth (STREAM triad %.2f GB/s)", bw)
set key top left
set grid
sel(k) = (strcol(2) eq k) ? column(7) : NaN
bound(x) = x / (bw * 1e9) * 1e3
set terminal svg size 860,560 dynamic enhanced font "Helvetica,12"
set output out.".svg"
plot in using 6:(sel("full-super")) with points pt 7 ps 1.2 title "full solve, supernodal LL^T", \
     in using 6:(sel("full-simpl")) with points pt 5 ps 1.2 title "full solve, simplicial", \
     in using 6:(sel("closure-set")) with points pt 6 ps 0.6 title "closure solve, node of the cut set", \
     in using 6:(sel("closure-spread")) with points pt 4 ps 0.6 title "closure solve, node spread over the mesh", \
     bound(x) with lines lw 2 lc rgb "black" title "bytes / bandwidth"
set terminal pngcairo size 860,560 font "Helvetica,10"
set output out.".png"
replot
