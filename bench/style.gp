# The look the studies' plots share (bench/*.gp load it first). Colours are the Okabe-Ito palette,
# which readers with any common colour-vision deficiency tell apart; each line type adds a dash type
# and a point type of its own, so that a grey print tells the lines apart as well. Line types, in
# order: vermillion, blue, bluish green, orange, reddish purple, sky blue, black; the palette's
# yellow is left out (too pale on white). Keys go outside the plot, where they cover no data.
set linetype 1 lc rgb '#D55E00' lw 2 dt solid           pt 9  ps 1.3  # vermillion, filled triangle
set linetype 2 lc rgb '#0072B2' lw 2 dt (10,4)          pt 5  ps 1.1  # blue, filled square
set linetype 3 lc rgb '#009E73' lw 2 dt solid           pt 6  ps 1.8  # bluish green, open circle
set linetype 4 lc rgb '#E69F00' lw 2 dt (4,4)           pt 7  ps 0.8  # orange, filled circle
set linetype 5 lc rgb '#CC79A7' lw 2 dt (12,4,3,4)      pt 13 ps 1.4  # reddish purple, filled diamond
set linetype 6 lc rgb '#56B4E9' lw 2 dt (3,3)           pt 11 ps 1.3  # sky blue, filled triangle down
set linetype 7 lc rgb '#000000' lw 2 dt (12,4,3,4,3,4)  pt 4  ps 1.1  # black, open square
set linetype cycle 7
set key outside below center horizontal samplen 4 height 1.5
set grid lc rgb '#C8C8C8' lw 1 dt (2,4)
