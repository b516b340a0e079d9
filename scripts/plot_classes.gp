# rgvc_bench_classes' plot: per scene class, (a) the median cull time of the culler's variants beside
# Masked Occlusion Culling's figure from issue #10, (b) where the default core's and view-frustum
# culling's time goes, (c) how tight their PVS is.
#
#   gnuplot -e "csv='classes.csv'; out='scenes/figures/classes.png'" scripts/plot_classes.gp
#   (rgvc_bench_classes --csv FILE --plot FILE.png runs this after writing its CSV)
#
# Columns of the CSV (apps/bench/BenchClasses.cpp, writeCsv): 1 scene, 2 scene_no, 3 dim, 4 variant,
# 5 median_ms, 6 p90_ms, 7 update_ms, 8 walk_ms, 9 buffer_ms, 10 voxels, 11 nodes, 12 bricks, 13 pvs,
# 14 pvs_over_visible (-1: no frame counted), 15 misses, 16 moc_ms (-1: none), 17 runs, 18 vfc_ms (the
# scene's vfc median; -1: none).
# Variants drawn: new (the default: brick tree + occlusion image), vfc (occlusion off), and the paper's
# per-voxel traversals (old in 3D, rings in 2D); the others stay in the CSV.
if (!exists("csv")) csv = 'classes.csv'
if (!exists("out")) out = 'classes.png'
set datafile separator ','
set datafile commentschars '#'
n = int(system("tail -n +2 '".csv."' | cut -d, -f2 | sort -n | tail -1")) + 1
set terminal pngcairo size (n < 8 ? 900 : 110 * n + 160), 1250 font 'DejaVu Sans,9'
set output out
set multiplot layout 3, 1 title "rgvc\\_bench\\_classes: the culler per scene class (one thread)" font ',12'
set xrange [-0.6 : n - 0.4]
# The scenes' names at their ordinals: ("room-1k" 0, "room-10k" 1, ...).
tics = system("tail -n +2 '".csv."' | cut -d, -f1,2 | uniq | awk -F, '{printf \"%s\\\"%s\\\" %s\", (NR > 1 ? \", \" : \"\"), $1, $2}'")
eval "set xtics (".tics.")"
set xtics rotate by -30 left nomirror font ',9'
set grid ytics mytics lc rgb '#dddddd'
set style fill solid 0.85 noborder
set boxwidth 0.22
set key top left font ',8' box opaque
is(v) = strcol(4) eq v
paper(x) = (strcol(4) eq 'old' || strcol(4) eq 'rings')

set title '(a) median cull time per frame (log scale); Masked Occlusion Culling: the issue''s figures'
set logscale y
set ylabel 'ms'
plot csv skip 1 using ($2 - 0.24):(is('new') ? $5 : NaN) with boxes lc rgb '#1a73e8' title 'new (default)', \
     '' skip 1 using ($2):(is('vfc') ? $5 : NaN) with boxes lc rgb '#9aa0a6' title 'vfc (occlusion off)', \
     '' skip 1 using ($2 + 0.24):(paper(0) ? $5 : NaN) with boxes lc rgb '#e8710a' title 'the paper''s traversal (old 3D, rings 2D)', \
     '' skip 1 using ($2 - 0.24):((is('new') && $16 > 0) ? $16 : NaN) with points pt 9 ps 1.6 lc rgb '#000000' title 'Masked Occlusion Culling'

set title "(b) where the time goes, in units of vfc's median frame (above 1: slower than --no-occlusion): update, walk, buffer pass (left new, right vfc)"
unset logscale y
set ylabel "median ms / vfc's median frame ms (stacked)"
set boxwidth 0.34
set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead dt 2 lc rgb '#5f6368' front
u(x) = ($18 > 0) ? x / $18 : NaN
plot csv skip 1 using ($2 - 0.19):(is('new') ? u($7 + $8 + $9) : NaN) with boxes lc rgb '#fbbc04' title 'buffer pass', \
     '' skip 1 using ($2 - 0.19):(is('new') ? u($7 + $8) : NaN) with boxes lc rgb '#1a73e8' title 'walk', \
     '' skip 1 using ($2 - 0.19):(is('new') ? u($7) : NaN) with boxes lc rgb '#34a853' title 'update (placements, O, I, T)', \
     '' skip 1 using ($2 + 0.19):(is('vfc') ? u($7 + $8 + $9) : NaN) with boxes lc rgb '#fbbc04' notitle, \
     '' skip 1 using ($2 + 0.19):(is('vfc') ? u($7 + $8) : NaN) with boxes lc rgb '#1a73e8' notitle, \
     '' skip 1 using ($2 + 0.19):(is('vfc') ? u($7) : NaN) with boxes lc rgb '#34a853' notitle
unset arrow 1

set title '(c) |PVS| / |exactly visible| (mean over the checked frames; log scale)'
set logscale y
set ylabel 'ratio'
set yrange [0.8 : *]
set boxwidth 0.22
plot csv skip 1 using ($2 - 0.24):((is('new') && $14 > 0) ? $14 : NaN) with boxes lc rgb '#1a73e8' title 'new', \
     '' skip 1 using ($2):((is('vfc') && $14 > 0) ? $14 : NaN) with boxes lc rgb '#9aa0a6' title 'vfc', \
     '' skip 1 using ($2 + 0.24):((paper(0) && $14 > 0) ? $14 : NaN) with boxes lc rgb '#e8710a' title 'the paper''s traversal'
unset multiplot
