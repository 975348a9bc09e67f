set terminal pngcairo noenhanced size 960,720 font 'sans,10'
set output 'pattern_accuracy.png'
set multiplot layout 2,1
set grid lc rgb '#e1e1e1'
set key top right opaque box spacing 1.4
set title 'theta error vs theta (max over D = 1..5 m)'
set xlabel 'theta (deg)'
set ylabel '|theta error| (deg)'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.58, graph 0.00
plot 'pattern_accuracy.dat' index 0 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#ff8c00' title 'projection', \
     'pattern_accuracy.dat' index 1 using 1:2 with linespoints lw 2 dt 2 pt 7 ps 0.6 lc rgb '#0050c8' title 'moment', \
     'pattern_accuracy.dat' index 2 using 1:2 with linespoints lw 2 dt 3 pt 7 ps 0.6 lc rgb '#00a000' title 'conic', \
     'pattern_accuracy.dat' index 3 using 1:2 with linespoints lw 2 dt 4 pt 7 ps 0.6 lc rgb '#a000a0' title 'conic+bars', \
     'pattern_accuracy.dat' index 4 using 1:2 with linespoints lw 2 dt 5 pt 7 ps 0.6 lc rgb '#c80000' title 'seed Table I (greatest)', \
     'pattern_accuracy.dat' index 5 using 1:2 with linespoints lw 2 dt 6 pt 7 ps 0.6 lc rgb '#787878' title 'seed eq. 55, k = 1, D = 5 m'
set title 'distance error vs D (max over theta = 0..75 deg)'
set xlabel 'D (m)'
set ylabel '|D error| (%)'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.58, graph 0.00
plot 'pattern_accuracy.dat' index 6 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#ff8c00' title 'projection', \
     'pattern_accuracy.dat' index 7 using 1:2 with linespoints lw 2 dt 2 pt 7 ps 0.6 lc rgb '#0050c8' title 'moment', \
     'pattern_accuracy.dat' index 8 using 1:2 with linespoints lw 2 dt 3 pt 7 ps 0.6 lc rgb '#00a000' title 'conic', \
     'pattern_accuracy.dat' index 9 using 1:2 with linespoints lw 2 dt 4 pt 7 ps 0.6 lc rgb '#a000a0' title 'conic+bars', \
     'pattern_accuracy.dat' index 10 using 1:2 with linespoints lw 2 dt 5 pt 7 ps 0.6 lc rgb '#c80000' title 'seed Table II', \
     'pattern_accuracy.dat' index 11 using 1:2 with linespoints lw 2 dt 6 pt 7 ps 0.6 lc rgb '#787878' title 'seed eq. 48, k = 1'
unset multiplot
