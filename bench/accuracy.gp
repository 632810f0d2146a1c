# Plots of the accuracy study. Run by ./lab bench accuracy as
#   gnuplot -e "dir='build/accuracy'; ext='png'" bench/accuracy.gp   (and ext='svg')
# It reads the data files the study wrote to dir and writes error-*.EXT, work-precision-*.EXT
# and energy-*.EXT beside them. A data file holds one block per integrator measured, in the order
# of methods.gp: an integrator whose hook is not written has no curve, the others keep their line types.
if (!exists("dir")) dir = 'build/accuracy'
if (!exists("ext")) ext = 'png'
if (ext eq 'svg') { set terminal svg size 800,560 dynamic font 'sans,12' } else { set terminal png size 800,560 }
load dir.'/anchors.gp'
load dir.'/methods.gp'

names = "explicit-Euler semi-implicit-Euler position-Verlet velocity-Verlet RK4"
method(k) = word(measured, k) + 1  # the integrator of the k-th block: word(names, method(k)), line type method(k)
set key left top
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set grid

do for [problem in "oscillator kepler pendulum-large"] {
    id = problem eq 'pendulum-large' ? 'pendulum_large' : problem
    c1 = value('c1_'.id); c2 = value('c2_'.id); c4 = value('c4_'.id)
    data = dir.'/sweep-'.problem.'.dat'

    set output dir.'/error-'.problem.'.'.ext
    set title 'Global error at the end time vs time step: '.problem
    set xlabel 'time step h (s)'
    set ylabel 'state error'
    # A reference line through no measured method (its anchor 0) is left out of the key.
    plot for [k=1:words(measured)] data index k-1 using 1:2 with linespoints lt method(k) title word(names, method(k)), \
         c1*x dashtype 2 lc rgb 'gray40' title (c1 > 0 ? 'slope 1' : ''), \
         c2*x**2 dashtype 3 lc rgb 'gray40' title (c2 > 0 ? 'slope 2' : ''), \
         c4*x**4 dashtype 4 lc rgb 'gray40' title (c4 > 0 ? 'slope 4' : '')

    set output dir.'/work-precision-'.problem.'.'.ext
    set title 'Work vs precision: '.problem
    set key right top
    set xlabel 'force evaluations for the whole run'
    plot for [k=1:words(measured)] data index k-1 using 3:2 with linespoints lt method(k) title word(names, method(k))
    set key left top
}

do for [problem in "oscillator kepler"] {
    set output dir.'/energy-'.problem.'.'.ext
    set title 'Relative energy error over time: '.problem
    set logscale y
    unset logscale x
    set format x '%g'
    set xlabel 'time (s)'
    set ylabel '|E - E_0| / |E_0|'
    set key right bottom
    plot for [k=1:words(measured)] dir.'/energy-'.problem.'.dat' index k-1 using 1:2 with lines lt method(k) \
         title word(names, method(k))
    set logscale x
    set format x '10^{%L}'
    set key left top
}
unset output
