# rgvc_sweep's plot: time against overestimation, one panel per scene, the Pareto front marked.
#
#   gnuplot -e "csv='rgvc_sweep.csv'; out='scenes/figures/sweep.png'" scripts/plot_sweep.gp
#   (rgvc_sweep --plot FILE.png runs this after writing its CSV)
#
# Columns of the CSV (rgvc_sweep, apps/bench/SweepReport.cpp): 1 scene, 3 setting, 5 approximate,
# 20 overestimation (|answer|/|visible|, -1 when no frame was counted), 21 misses, 24 pareto, 25 time_ms
# (median frame ms with drawing, or cull ms without). Conservative settings are filled circles, the base
# setting a square, approximate ones (CHC++ with n_vp > 0) open triangles; the front (conservative, 0 misses,
# no other setting faster and tighter) is the line, its settings named.
if (!exists("csv")) csv = 'rgvc_sweep.csv'
if (!exists("out")) out = 'sweep.png'
set datafile separator ','
set datafile commentschars '#'
scenes = system("grep -v '^#' '".csv."' | tail -n +2 | cut -d, -f1 | uniq | tr '\\n' ' '")
n = words(scenes)
cols = (n > 4) ? 4 : n
rows = int((n + cols - 1) / cols)
set terminal pngcairo size 520*cols, 420*rows font 'DejaVu Sans,9'
set output out
set multiplot layout rows, cols title "rgvc\\_sweep: time against overestimation (front: conservative settings, 0 misses)" font ',12'
set logscale xy
set grid xtics ytics mytics lc rgb '#dddddd'
set xlabel '|answer| / |exact visible| (mean over checked frames)'
set ylabel 'median frame ms (cull + draw)'
set offsets graph 0.05, graph 0.3, graph 0.1, graph 0.1
do for [i=1:n] {
    s = word(scenes, i)
    set title s font ',11'
    if (i == 1) { set key top left font ',8' box opaque } else { unset key }
    plot csv skip 1 using ((strcol(1) eq s && $5 == 0 && $20 >= 0) ? $20 : NaN):25 with points pt 7 ps 0.8 lc rgb '#9aa0a6' title 'conservative', \
         '' skip 1 using ((strcol(1) eq s && $5 == 1 && $20 >= 0) ? $20 : NaN):25 with points pt 8 ps 1.1 lc rgb '#e8710a' title 'approximate (n_vp > 0)', \
         '' skip 1 using ((strcol(1) eq s && $5 == 0 && $21 > 0) ? $20 : NaN):25 with points pt 2 ps 1.5 lc rgb '#d93025' title 'MISSED', \
         '' skip 1 using ((strcol(1) eq s && strcol(3) eq 'base') ? $20 : NaN):25 with points pt 5 ps 1.1 lc rgb '#188038' title 'base', \
         '' skip 1 using ((strcol(1) eq s && $24 == 1) ? $20 : NaN):25 smooth unique with linespoints pt 7 ps 0.9 lw 2 lc rgb '#1a73e8' title 'Pareto front', \
         '' skip 1 using ((strcol(1) eq s && $24 == 1) ? $20 : NaN):25:3 with labels left offset 0.6, 0.4 font ',7' tc rgb '#1a73e8' notitle
}
unset multiplot
