# The plot of the engine benchmark. Run by ./lab bench engine as
#   gnuplot -e "dir='build/engine'; ext='png'; stem='engine'; what='spheres'" bench/engine.gp
# (and ext='svg'; stem='engine-boxes', what='cubes' for --shape box). It reads STEM-scaling.dat (N,
# this engine's and Bullet's median ms per step) and writes STEM-scaling.EXT beside it: ms per step
# against N on log-log axes, with N^1 for reference.
if (!exists("dir")) dir = 'build/engine'
if (!exists("ext")) ext = 'png'
if (!exists("stem")) stem = 'engine'
if (!exists("what")) what = 'spheres'
load system('dirname "'.ARG0.'"').'/style.gp'
if (ext eq 'svg') { set terminal svg size 800,560 dynamic font 'sans,12' } else { set terminal pngcairo size 800,560 font 'sans,10' }
set output dir.'/'.stem.'-scaling.'.ext
data = dir.'/'.stem.'-scaling.dat'
set title 'A heap of N '.what.' dropped on a plane: wall time per step (median), one run'
set xlabel 'number of '.what.' N'
set ylabel 'wall time per step, median (ms)'
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set grid
set key maxrows 1
# One column at a time: stats on two columns fits a line and warns when there are only two sizes.
stats data using 1 nooutput
first_n = STATS_min
if (STATS_max == STATS_min) set xrange [first_n / 2 : first_n * 2]  # one size: an x range around it
stats data using 2 nooutput
first_ms = STATS_min
plot data using 1:2 with linespoints lw 2 lc 2 pt 7 ps 1.3 dt solid title 'this engine', \
     data using 1:3 with linespoints lw 2 lc 1 pt 5 ps 1.2 dt (8,4) title 'Bullet', \
     first_ms * x / first_n with lines lw 1.5 lc 7 dt (2,3) title 'proportional to N'
