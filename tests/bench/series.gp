# series.gp: one or more x-y series, one file each (tab-separated; header "x<TAB>title": the
# second column's header is the series title). SVG and PNG.
# Variables: files (space-separated paths), out (output prefix), and optionally ttl, xl, yl,
# logx, logy (1 for a log axis), style ("linespoints", "points", "lines", "steps"),
# keypos (e.g. "top left", "outside right"), yr / xr (e.g. "[1:*]").
set datafile separator tab
if (!exists("ttl")) ttl = ""
if (!exists("xl")) xl = "x"
if (!exists("yl")) yl = "y"
if (!exists("style")) style = "linespoints"
if (!exists("keypos")) keypos = "top right"
if (exists("logx") && logx) set logscale x
if (exists("logy") && logy) set logscale y; set format y "10^{%L}"
if (exists("yr")) eval("set yrange ".yr)
if (exists("xr")) eval("set xrange ".xr)
set title ttl noenhanced
set xlabel xl noenhanced
set ylabel yl noenhanced
eval("set key ".keypos." noenhanced")
set grid
n = words(files)
set terminal svg size 860,540 dynamic enhanced font "Helvetica,12"
set output out.".svg"
plot for [i=1:n] word(files, i) using 1:2 with @style lw 1.5 pt (i % 13) + 1 ps 0.8 title columnhead(2)
set terminal pngcairo size 860,540 font "Helvetica,10"
set output out.".png"
replot
