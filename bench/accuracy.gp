# Plots of the accuracy study. Run by ./lab bench accuracy as
#   gnuplot -e "dir='build/accuracy'; ext='png'" bench/accuracy.gp   (and ext='svg')
# It reads the data files the study wrote to dir and writes error-*.EXT, work-precision-*.EXT
# and energy-*.EXT beside them. A data file holds one block per integrator measured, in the order
# of methods.gp: an integrator whose hook is not written has no curve, the others keep their line types.
if (!exists("dir")) dir = 'build/accuracy'
if (!exists("ext")) ext = 'png'
load system('dirname "'.ARG0.'"').'/style.gp'
if (ext eq 'svg') { set terminal svg size 800,600 dynamic font 'sans,12' } else { set terminal pngcairo size 800,600 font 'sans,10' }
load dir.'/anchors.gp'
load dir.'/methods.gp'

names = "explicit-Euler semi-implicit-Euler position-Verlet velocity-Verlet RK4"
method(k) = word(measured, k) + 1  # the integrator of the k-th block: word(names, method(k)), line type method(k)
# Position and velocity Verlet are one method written two ways: their errors lie on each other.
# Position Verlet is drawn with rings, velocity Verlet with dots, and the title says what a dot in
# a ring means.
both_verlets = strstrt(' '.measured.' ', ' 2 ') > 0 && strstrt(' '.measured.' ', ' 3 ') > 0
verlets = both_verlets ? "\n{/*0.85 where velocity-Verlet's dots sit in position-Verlet's rings, the two give the same error}" : ''
set key maxrows 2
set logscale xy
set format x '10^{%L}'
set format y '10^{%L}'
set grid

do for [problem in "oscillator kepler pendulum-large"] {
    id = problem eq 'pendulum-large' ? 'pendulum_large' : problem
    c1 = value('c1_'.id); c2 = value('c2_'.id); c4 = value('c4_'.id); unit = value('unit_'.id)
    data = dir.'/sweep-'.problem.'.dat'

    # The reference lines C h^p start left of the smallest step measured and are named there, where
    # their different slopes have taken them apart.
    stats data using 1 nooutput
    h_min = STATS_min; h_max = STATS_max
    set xrange [h_min / 8 : h_max * 1.5]
    set output dir.'/error-'.problem.'.'.ext
    set title 'Global error at the end time against the time step: '.problem.verlets
    set xlabel 'time step h (s)'
    set ylabel 'state error at the end time ('.unit.')'
    unset label
    h_label = h_min / 1.6
    if (c1 > 0) { set label 1 'slope 1' at h_label, c1 * h_label right offset -0.5, 0 tc rgb '#555555' }
    if (c2 > 0) { set label 2 'slope 2' at h_label, c2 * h_label**2 right offset -0.5, 0 tc rgb '#555555' }
    if (c4 > 0) { set label 4 'slope 4' at h_label, c4 * h_label**4 right offset -0.5, 0 tc rgb '#555555' }
    plot for [k=1:words(measured)] data index k-1 using 1:2 with linespoints lt method(k) title word(names, method(k)), \
         (c1 > 0 && x > h_label ? c1*x : 1/0) with lines lw 1.5 lc rgb '#555555' dt (6,4) notitle, \
         (c2 > 0 && x > h_label ? c2*x**2 : 1/0) with lines lw 1.5 lc rgb '#555555' dt (2,3) notitle, \
         (c4 > 0 && x > h_label ? c4*x**4 : 1/0) with lines lw 1.5 lc rgb '#555555' dt (10,3,2,3) notitle
    unset label
    set autoscale x

    set output dir.'/work-precision-'.problem.'.'.ext
    set title 'Work against precision: '.problem.verlets
    set xlabel 'force evaluations over the whole run (a count)'
    plot for [k=1:words(measured)] data index k-1 using 3:2 with linespoints lt method(k) title word(names, method(k))
}

do for [problem in "oscillator kepler"] {
    set output dir.'/energy-'.problem.'.'.ext
    set title 'Relative energy error over time: '.problem
    set logscale y
    unset logscale x
    set format x '%g'
    set xlabel 'time t (s)'
    set ylabel '|E - E_0| / |E_0|  (a ratio, no unit)'
    plot for [k=1:words(measured)] dir.'/energy-'.problem.'.dat' index k-1 using 1:2 with lines lt method(k) \
         title word(names, method(k))
    set logscale x
    set format x '10^{%L}'
}
unset output
