# Plots of the fluids study. Run by ./lab bench fluids as
#   gnuplot -e "dir='build/fluids'; ext='png'" bench/fluids.gp   (and ext='svg')
# It reads the data files the study wrote to dir and writes beside them fluids-density.EXT (PBF's
# density error against the iterations and the time step), fluids-stability.EXT (WCSPH's largest
# stable time step against the speed of sound, beside the CFL bound), fluids-cost.EXT (the cost per
# particle and step against N, and each part beside the bare neighbour loop) and fluids-dambreak.EXT
# (both methods' surge front beside Martin and Moyce's measurements). A figure whose data is
# missing (its part was not run) is left out.
if (!exists("dir")) dir = 'build/fluids'
if (!exists("ext")) ext = 'png'
load system('dirname "'.ARG0.'"').'/style.gp'
have(name) = system('test -s "'.dir.'/'.name.'" && echo 1 || echo 0') eq '1'
fields(name) = int(system("awk 'NR == 2 { print NF; exit }' \"".dir.'/'.name.'"'))
terminal(width, height) = ext eq 'svg' ? sprintf("svg size %d,%d dynamic font 'sans,12'", width, height) \
                                       : sprintf("pngcairo size %d,%d font 'sans,10'", width, height)
set grid

# 1. PBF's density error against the iterations (a line per time step) and against the time step
# (a line per iteration count).
if (have('fluids-iterations.dat') && have('fluids-timestep.dat')) {
    eval 'set terminal '.terminal(1100, 560)
    set output dir.'/fluids-density.'.ext
    set multiplot layout 1,2 title "PBF: a column released at rest, its mean density error at the end of the run\n" \
                                   ."{/*0.85 mean over the particles of max(ρ/ρ_0 - 1, 0); the rest lattice alone reads 0.98 %}"
    set bmargin 8
    set logscale y
    set format y '%g %%'
    set ylabel 'mean density error'
    set key maxrows 3

    data = dir.'/fluids-iterations.dat'
    steps = (fields('fluids-iterations.dat') - 1) / 2
    set title 'against the solver iterations (a line per time step)'
    set xlabel 'iterations per step'
    set logscale x 2
    set format x '%g'
    plot for [k = 1:steps] data using 1:(100 * column(2 * k)) with linespoints lt k title columnheader(2 * k)

    data = dir.'/fluids-timestep.dat'
    counts = fields('fluids-timestep.dat') - 1
    set title 'against the time step (a line per iteration count)'
    set xlabel 'time step h (s)'
    set logscale x 2
    set format x '1/%.0f'
    plot for [k = 1:counts] data using (1 / $1):(100 * column(k + 1)) with linespoints lt k title columnheader(k + 1)
    unset multiplot
    unset logscale
}

# 2. WCSPH's largest stable time step against the speed of sound, beside the CFL bound.
if (have('fluids-stiffness.dat')) {
    eval 'set terminal '.terminal(700, 520)
    set output dir.'/fluids-stability.'.ext
    set title "WCSPH: the largest stable time step of a column at rest\n" \
             ."{/*0.85 one substep a step; bisected to 2 %; Tait's stiffness B = ρ_0 c^2 / 7}"
    set bmargin 6
    set logscale xy
    set format x '%g'
    set format y '10^{%L}'
    set xlabel 'speed of sound c (m/s)'
    set ylabel 'time step h (s)'
    set autoscale xfix
    set offsets graph 0.05, graph 0.05, 0, 0
    set xtics (2.5, 5, 10, 20, 40, 80, 160, 320)
    data = dir.'/fluids-stiffness.dat'
    plot data using 1:2 with linespoints lt 1 title columnheader(2), \
         data using 1:3 with lines lt 7 title columnheader(3)
    unset logscale
    set autoscale x
    set offsets 0, 0, 0, 0
    set xtics autofreq
}

# 3 and 4. The cost per particle and step against N, and each part beside the bare loop.
if (have('fluids-cost.dat') || have('fluids-limit.dat')) {
    eval 'set terminal '.terminal(1100, 560)
    set output dir.'/fluids-cost.'.ext
    set multiplot layout 1,2 title 'What a fluid step costs (CPU time of one thread)'
    set bmargin 8
    unset title
    set format x '%g'
    set format y '%g'
    if (have('fluids-cost.dat')) {
        data = dir.'/fluids-cost.dat'
        set title 'per particle against the particles'
        set xlabel 'particles N'
        set logscale xy
        set format x '10^{%L}'
        set format y '%g'
        set ylabel 'ns per particle'
        set key maxrows 3
        set autoscale xfix
        set offsets graph 0.05, graph 0.05, 0, 0
        plot for [k = 2:6] data using 1:k with linespoints lt (k - 1) title columnheader(k)
        unset logscale
        set autoscale x
        set offsets 0, 0, 0, 0
    }
    if (have('fluids-limit.dat')) {
        data = dir.'/fluids-limit.dat'
        set title 'beside the bare loop: poly6 summed over the same neighbours'
        set xlabel ''
        set format x '%g'
        set ylabel 'ns per particle'
        set yrange [0:*]
        set style data histograms
        set style histogram clustered gap 1
        set style fill solid 0.85 border -1
        set boxwidth 0.8
        set xtics rotate by -20
        stats data using 2 nooutput  # the bars: 4, or 5 with an instructor's bare PBF iteration
        set xrange [0.4:STATS_records + 0.6]  # the header is record 0, the bars records 1 to STATS_records
        plot data using 2:xtic(1) lc 2 fs pattern 3 notitle, \
             '' using 0:2:(sprintf('%.0f', $2)) with labels offset 0,0.8 notitle
        unset yrange
        set autoscale x
        set xtics norotate
    }
    unset multiplot
}

# 5. The dam break's surge front beside Martin and Moyce's measurements.
if (have('fluids-dambreak-pbf.dat') && have('fluids-dambreak-measured.dat')) {
    eval 'set terminal '.terminal(760, 560)
    set output dir.'/fluids-dambreak.'.ext
    set title "The dam break: the surge front against Martin and Moyce (1952)\n" \
             ."{/*0.85 a column a = 0.25 m wide, 2a tall; Z = z / a, T = t (2 g / a)^{1/2}}"
    set bmargin 6
    set style data lines
    set style fill empty
    set xtics norotate
    set xlabel 'T'
    set ylabel 'surge front Z'
    set xrange [0:*]
    set yrange [1:*]
    set format x '%g'
    set format y '%g'
    plot dir.'/fluids-dambreak-pbf.dat' using 1:2 with lines lt 1 title columnheader(2), \
         dir.'/fluids-dambreak-wcsph.dat' using 1:2 with lines lt 2 title columnheader(2), \
         dir.'/fluids-dambreak-measured.dat' using 1:2 with points lt 7 ps 1.6 title columnheader(2)
}
