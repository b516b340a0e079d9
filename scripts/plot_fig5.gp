# Plots of rgvc_bench3d --figure (seed 004 §6, Figure 5) from its CSVs:
#   gnuplot -e "dir='OUT'; m5a='zb vfc ...'; mwalk='zb vfc ...'" scripts/plot_fig5.gp
# dir: the --out folder; m5a, mwalk: the method labels of figure (a) and of the walk, as the program
# passes them. Writes OUT/fig5a.png from fig5a-median.csv, OUT/fig5b.png and OUT/fig5c.png from
# fig5bc.csv; a missing CSV skips its plot. Rows are filtered by the method column (strcol(2) of the
# medians, strcol(2) of the walk), so the CSV headers and `#` lines are never plotted.
if (!exists("dir")) dir = "fig5"
if (!exists("m5a")) m5a = "zb vfc rgvc-50x30x50 rgvc-100x60x100"
if (!exists("mwalk")) mwalk = "zb vfc rgvc-50x30x50 rgvc-100x60x100 rgvc+chc-50x30x50 rgvc+chc-100x60x100 chc ideal"

set datafile separator ","
set terminal pngcairo size 1100,460 font "sans,10" noenhanced
set grid lc rgb "#dddddd"
set key top left
exists_file(f) = system("test -f '" . f . "' && echo 1 || echo 0") eq "1"

# (a) median frame time against hidden movers: 0-10,000 (the paper's range) and the whole range.
f = dir . "/fig5a-median.csv"
if (exists_file(f)) {
    set output dir . "/fig5a.png"
    set multiplot layout 1,2 title "Figure 5a: frame time (cull + draw + glFinish) against hidden moving spheres (median per point)"
    set xlabel "hidden moving spheres"
    set ylabel "ms per frame"
    set xrange [0:*]
    set title "0 to 10,000"
    plot for [m in m5a] f using ($1 <= 10000 ? $1 : 1/0):(strcol(2) eq m ? $3 : 1/0) with linespoints lw 2 pt 7 title m
    set xrange [0:*]
    set title "the whole range (spheres of fewer triangles above --lod-above, see the CSV)"
    set logscale y
    plot for [m in m5a] f using 1:(strcol(2) eq m ? $3 : 1/0) with linespoints lw 2 pt 7 title m
    unset logscale y
    unset multiplot
    unset title
}

# (b), (c) per frame of the walk.
f = dir . "/fig5bc.csv"
if (exists_file(f)) {
    set terminal pngcairo size 1000,500 font "sans,10" noenhanced
    set output dir . "/fig5b.png"
    set title "Figure 5b: the walkthrough, frame time per frame (cull + draw + glFinish)"
    set xlabel "frame"
    set ylabel "ms per frame"
    set xrange [*:*]
    set logscale y
    set key outside right
    plot for [m in mwalk] f using 1:(strcol(2) eq m ? $3 : 1/0) with lines lw 1.5 title m
    unset logscale y

    # |PVS| per frame: the grid's set for rgvc-* (candidates, column 7), what is drawn for rgvc+chc-*
    # and vfc (column 6), and the exact visible count (column 8, the same on every method's rows).
    set output dir . "/fig5c.png"
    set title "Figure 5c: potentially visible objects per frame against the exactly visible (item buffer)"
    set ylabel "objects"
    set logscale y
    plot for [m in "rgvc-50x30x50 rgvc-100x60x100"] f using 1:(strcol(2) eq m ? $7 : 1/0) with lines lw 1.5 title m, \
         for [m in "rgvc+chc-50x30x50 rgvc+chc-100x60x100 vfc"] f using 1:(strcol(2) eq m ? $6 : 1/0) with lines lw 1.5 title m, \
         f using 1:(strcol(2) eq "zb" ? $8 : 1/0) with lines lw 2.5 lc rgb "black" title "exact (item buffer)"
    unset logscale y
}
