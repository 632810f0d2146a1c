# The plot of the solvers benchmark. Run by ./lab bench solvers as
#   gnuplot -e "dir='build/solvers'; ext='png'" bench/solvers.gp   (and ext='svg')
# It reads solvers-drift.dat, solvers-speed.dat and solvers-ms.dat (a row per scene, a column per
# solver, Bullet last) and writes solvers.EXT beside them: three panels of bars per scene, each
# solver a colour (the first solid, the others hatched each its own way, for a grey print), on log
# scales; the dashed lines are what standing allows (1 cm, 1 mm/s).
if (!exists("dir")) dir = 'build/solvers'
if (!exists("ext")) ext = 'png'
load system('dirname "'.ARG0.'"').'/style.gp'
if (ext eq 'svg') { set terminal svg size 1100,1000 dynamic font 'sans,12' } else { set terminal pngcairo size 1100,1000 font 'sans,10' }
set output dir.'/solvers.'.ext
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
fill(c) = c == 2 ? 3 : c + 2  # fill pattern 3 is solid; 5, 6, ... are hatchings
set boxwidth 0.9
set logscale y
set format y '10^{%L}'
set grid ytics
set key outside top center horizontal autotitle columnheader
set xtics rotate by -35 left nomirror
columns = system('sed -n 2p "'.dir.'/solvers-drift.dat" | wc -w') + 0  # scene and one per solver
atleast(x, low) = x < low ? low : x
set multiplot layout 3,1 title 'The contact solvers'' test scenes, one run each'
set lmargin 12
set ylabel 'top body''s drift (m)'
set yrange [1e-6:*]
unset xtics
set xtics format '' rotate by -35 left nomirror
plot for [c=2:columns] dir.'/solvers-drift.dat' using (atleast(column(c), 1e-6)):xtic('') lc c-1 dt solid fs pattern fill(c), \
     0.01 with lines lw 1.5 dt (6,4) lc 7 title 'what standing allows'
unset key
set ylabel 'fastest point, last second (m/s)'
set yrange [1e-6:*]
plot for [c=2:columns] dir.'/solvers-speed.dat' using (atleast(column(c), 1e-6)):xtic('') lc c-1 dt solid fs pattern fill(c), \
     0.001 with lines lw 1.5 dt (6,4) lc 7 notitle
set ylabel 'wall time per step (ms)'
set yrange [1e-3:*]
set xtics format '% g'
plot for [c=2:columns] dir.'/solvers-ms.dat' using (atleast(column(c), 1e-3)):xtic(1) lc c-1 dt solid fs pattern fill(c)
unset multiplot
