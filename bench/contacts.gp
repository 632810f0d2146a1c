# Plots of the contacts study. Run by ./lab bench contacts as
#   gnuplot -e "dir='build/contacts'; ext='png'" bench/contacts.gp   (and ext='svg')
# It reads the data files the study wrote to dir and writes pile-iterations.EXT, tunnelling.EXT,
# resting-column.EXT and mass-ratio.EXT beside them. A figure whose data file is missing (its
# experiment was skipped because a hook is not written yet) is left out.
if (!exists("dir")) dir = 'build/contacts'
if (!exists("ext")) ext = 'png'
load system('dirname "'.ARG0.'"').'/style.gp'
have(name) = system('test -s "'.dir.'/'.name.'" && echo 1 || echo 0') eq '1'
terminal(width, height) = ext eq 'svg' ? sprintf("svg size %d,%d dynamic font 'sans,12'", width, height) \
                                       : sprintf("pngcairo size %d,%d font 'sans,10'", width, height)
set grid
set logscale x 2

# 1. Residual overlap and cost against the contact iterations on the pile.
if (have('pile-iterations.dat')) {
    eval 'set terminal '.terminal(800, 680)
    set output dir.'/pile-iterations.'.ext
    data = dir.'/pile-iterations.dat'
    set title "Contact iterations on a pile (balls-in-a-box): overlap left after the step, and cost\n" \
              ."{/*0.85 a marker inside another: the two overlaps are the same}"
    set xlabel 'contact iterations (sweeps per stage)'
    set ylabel 'overlap after the step (mm)'
    set logscale y
    set format y '10^{%L}'
    set yrange [*:*]
    set y2label 'wall time per step (µs)'
    set y2range [0:*]
    set y2tics
    set ytics nomirror
    set key maxrows 4
    plot data index 0 using 1:3 with linespoints lw 2 lc 1 pt 7 dt solid title 'positions: mean of the contacts', \
         data index 0 using 1:4 with linespoints lw 1.5 lc 1 pt 6 dt (8,4) title 'positions: largest contact', \
         data index 0 using 1:5 with linespoints lw 2 lc 1 pt 8 ps 1 dt (2,3) title 'positions: largest of any pair', \
         data index 1 using 1:3 with linespoints lw 2 lc 2 pt 5 dt solid title 'impulses: mean of the contacts', \
         data index 1 using 1:4 with linespoints lw 1.5 lc 2 pt 4 dt (8,4) title 'impulses: largest contact', \
         data index 1 using 1:5 with linespoints lw 2 lc 2 pt 10 ps 1 dt (2,3) title 'impulses: largest of any pair', \
         data index 0 using 1:8 axes x1y2 with linespoints lw 1 lc 7 pt 1 dt solid title 'positions: µs per step (right axis)', \
         data index 1 using 1:8 axes x1y2 with linespoints lw 1 lc 7 pt 2 dt (8,4) title 'impulses: µs per step (right axis)'
    unset y2label
    unset y2tics
    set ytics mirror
    unset yrange
    set key maxrows auto
}

# 2. The largest speed that does not tunnel against the time step, and the fraction of shots that tunnel.
if (have('tunnelling-limit.dat')) {
    eval 'set terminal '.terminal(1100, 560)
    set output dir.'/tunnelling.'.ext
    set multiplot layout 1,2 title 'Tunnelling: a ball shot head-on at a static sphere (64 start phases)'
    set bmargin 11  # room for the longer of the two keys: both plots the same height
    data = dir.'/tunnelling-limit.dat'
    set title 'Largest speed that never tunnels'
    set xlabel 'time step h (s)'
    set ylabel 'largest speed that never tunnels, v_{max} (m/s)'
    set logscale xy 10
    set format x '10^{%L}'
    set format y '10^{%L}'
    set key maxrows 3
    # Each pair of radii: its colour and point type, and its line (r_a + r_b) / h in the same colour.
    pairs = "'r_{a} = r_{b} = 1 cm' 'r_{a} = 1 cm, r_{b} = 10 cm' 'r_{a} = r_{b} = 10 cm' 'r_{a} = 10 cm, r_{b} = 1 m'"
    plot for [i=0:3] data index i using 1:2 with points lt i+1 ps 1.5 title word(pairs, i+1), \
         for [i=0:3] data index i using 1:4 with lines lw 1 dt (6,4) lc i+1 notitle, \
         1/0 with lines lw 1 dt (6,4) lc 7 title 'lines: (r_{a} + r_{b}) / h'
    set title 'Fraction of start phases that tunnel'
    set xlabel 'step over reach, v h / R   (R = r_{a} + r_{b}; a ratio, no unit)'
    set ylabel 'fraction of start phases that tunnel (0 to 1)'
    unset logscale y
    set format y '%g'
    set yrange [-0.05:1.05]
    set ytics 0, 0.2, 1
    set samples 400
    impulses(x) = x > 1 ? 1 - 1/x : 0
    positions(x) = x > 1 ? (2 * (1 - 1/x) < 1 ? 2 * (1 - 1/x) : 1) : 0
    fraction = dir.'/tunnel-fraction.dat'
    plot impulses(x) with lines lw 2 lc 2 dt (10,4) title 'impulses: 1 - R/(v h)', \
         positions(x) with lines lw 2 lc 1 dt solid title 'positions: min(1, 2 (1 - R/(v h)))', \
         fraction index 1 using 1:2 with points pt 5 ps 0.6 lc 2 title 'impulses, R = 10 cm', \
         fraction index 0 using 1:2 with points pt 9 ps 0.7 lc 1 title 'positions, R = 10 cm', \
         dir.'/fast-small.dat' using 1:2 with points pt 6 ps 2 lw 1.5 lc 7 title 'impulses, 1 mm..1 m, 1..1000 m/s'
    unset multiplot
    set bmargin
    unset yrange
    set ytics autofreq
    set key maxrows auto
    set logscale x 2
    unset logscale y
    set format x '%g'
}

# 3. Resting contact: how far the top sphere of a column sinks against the iterations, columns of 2, 3, 5 and 10.
if (have('resting-column.dat')) {
    eval 'set terminal '.terminal(800, 640)
    set output dir.'/resting-column.'.ext
    data = dir.'/resting-column.dat'
    set title "A column of spheres placed at rest on a plane, 10 s: how far the top sphere sinks\n(left out where spheres passed through each other)"
    set xlabel 'contact iterations (sweeps per stage)'
    set ylabel 'sink of the top sphere over the last 5 s (mm)'
    set logscale y
    set format y '10^{%L}'
    set yrange [1e-6:*]
    set key maxrows 3
    # The column's size is the colour and the point's shape; positions are solid lines with filled
    # points, impulses dashed lines with open points of the same shape.
    sizes = "2 3 5 10"
    filled = "9 5 7 13"
    open = "8 4 6 12"
    plot for [i=0:3] data index i using 1:($5 != 0 ? 1/0 : $2) with linespoints lw 2 lc i+1 \
             pt (word(filled, i+1) + 0) ps 1.2 dt solid title 'positions, '.word(sizes, i+1).' spheres', \
         for [i=0:3] data index i+4 using 1:($5 != 0 ? 1/0 : $2) with linespoints lw 1.5 lc i+1 \
             pt (word(open, i+1) + 0) ps 1.6 dt (8,4) title 'impulses, '.word(sizes, i+1).' spheres', \
         9.81e-4 * 1e3 with lines lw 1 lc 7 dt (2,3) title 'g h^{2} (h = 10 ms)'
    unset logscale y
    unset yrange
    set key maxrows auto
}

# 4. Mass ratios: what one stage leaves against its sweeps, with theory rho^k.
if (have('mass-ratio-stage.dat')) {
    eval 'set terminal '.terminal(800, 560)
    set output dir.'/mass-ratio.'.ext
    data = dir.'/mass-ratio-stage.dat'
    set title "A light sphere under a heavy one on a plane: one interpenetration stage\n(the impulse stage leaves the same fraction of the approach speed)"
    set xlabel 'contact iterations k (sweeps per stage)'
    set ylabel 'overlap with the plane: left / at the start (a ratio)'
    set logscale y
    set format y '10^{%L}'
    set yrange [1e-12:10]
    set key maxrows 3
    ratios = "1:1 1:10 1:100 1:1000"
    plot for [i=0:3] data index i using 1:2 with points lt i+1 ps 1.5 title 'bottom:top = '.word(ratios, i+1), \
         for [i=0:3] data index i using 1:3 with lines lw 1 dt (6,4) lc i+1 notitle, \
         1/0 with lines lw 1 dt (6,4) lc 7 title 'lines: theory ρ^k, ρ = m_{top} / (m_{bottom} + m_{top})'
}
unset output
