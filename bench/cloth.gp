# Plots of the cloth study. Run by ./lab bench cloth as
#   gnuplot -e "dir='build/cloth'; ext='png'" bench/cloth.gp   (and ext='svg')
# It reads the data files the study wrote to dir and writes cloth-stretch.EXT (the hanging cloth's
# settled stretch against iterations and against the time step) and cloth-speed.EXT (the cost of a
# step and of a projection against the cloth's size, and the drop on a sphere beside Bullet) beside
# them. A figure whose data is missing (its part was not run) is left out.
if (!exists("dir")) dir = 'build/cloth'
if (!exists("ext")) ext = 'png'
load system('dirname "'.ARG0.'"').'/style.gp'
have(name) = system('test -s "'.dir.'/'.name.'" && echo 1 || echo 0') eq '1'
terminal(width, height) = ext eq 'svg' ? sprintf("svg size %d,%d dynamic font 'sans,12'", width, height) \
                                       : sprintf("pngcairo size %d,%d font 'sans,10'", width, height)
set grid
# Each method's largest stretch is column 2k of a sweep's file (its mean 2k + 1), k = 1..4: PBD k=1,
# PBD k=0.5, XPBD a=0, XPBD soft; the theory of the soft XPBD cloth is the last column. XPBD with
# compliance 0 is PBD with stiffness 1: its markers lie on PBD's line, drawn large and open.
methods = 4
theory = 2 * methods + 2
stretchPlot = "plot data using 1:2 with linespoints lt 1 title columnheader(2), " \
            . "data using 1:4 with linespoints lt 2 title columnheader(4), " \
            . "data using 1:6 with points lt 3 ps 2.2 title columnheader(6), " \
            . "data using 1:8 with linespoints lt 4 ps 1.2 title columnheader(8), " \
            . "data using 1:(column(theory)) with lines lt 7 lw 1.5 title columnheader(theory)"

# 1. The settled stretch against iterations and against the time step.
if (have('cloth-iterations.dat') && have('cloth-timestep.dat')) {
    eval 'set terminal '.terminal(1100, 560)
    set output dir.'/cloth-stretch.'.ext
    set multiplot layout 1,2 title "A hanging cloth's settled stretch: PBD's is the solver's, XPBD's the material's\n" \
                                   ."{/*0.85 largest relative stretch of a stretch link; XPBD a=0 (open markers) is PBD k=1}"
    set bmargin 8
    set logscale xy
    set format y '10^{%L}'
    set ylabel 'largest relative stretch'
    set key maxrows 3

    data = dir.'/cloth-iterations.dat'
    set title 'against the projection iterations (h = 1/60 s)'
    set xlabel 'iterations n'
    set logscale x 2
    set format x '%g'
    eval stretchPlot

    data = dir.'/cloth-timestep.dat'
    set title 'against the time step (16 iterations)'
    set xlabel 'time step h (s)'
    set logscale x 10
    set format x '10^{%L}'
    eval stretchPlot
    unset multiplot
    unset logscale
}

# 2. What a step costs, and the drop beside Bullet.
if (have('cloth-cost.dat') || have('cloth-bullet.dat')) {
    # A panel for each part that was run, side by side.
    panels = have('cloth-cost.dat') + have('cloth-bullet.dat')
    eval 'set terminal '.terminal(550 * panels, 520)
    set output dir.'/cloth-speed.'.ext
    eval sprintf("set multiplot layout 1,%d title 'What a cloth step costs'", panels)
    set bmargin 6
    unset logscale
    set format x '%g'
    set format y '%g'
    if (have('cloth-cost.dat')) {
        data = dir.'/cloth-cost.dat'
        set title 'hanging cloths, XPBD, 10 iterations'
        set xlabel 'particles'
        set logscale x 2
        set format x '%g'
        set ylabel 'ns per constraint projection (CPU time)'
        set yrange [0:*]
        set y2label 'µs per step'
        set logscale y2
        set format y2 '10^{%L}'
        set y2tics
        set ytics nomirror
        plot data using 1:2 with linespoints lc 1 lt 1 title columnheader(2), \
             data using 1:3 axes x1y2 with linespoints lc 2 lt 2 title columnheader(3).' (right axis)'
        unset y2label
        unset y2tics
        unset logscale
        set ytics mirror
        unset yrange
    }
    if (have('cloth-bullet.dat')) {
        data = dir.'/cloth-bullet.dat'
        set title 'the cloth dropped on a sphere: median wall time per step'
        set xlabel 'particles along a side'
        set ylabel 'ms per step'
        set yrange [0:*]
        set style data histograms
        set style histogram clustered gap 1
        set style fill solid 0.85 border -1
        set boxwidth 0.9
        set format x '%g'
        # Bullet, then this engine on each thread count the study ran.
        plot for [c=2:*] data using c:xtic(1) lc (c - 1) fs pattern (2 * c - 1) title columnheader(c)
    }
    unset multiplot
}
