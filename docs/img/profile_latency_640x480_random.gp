set terminal pngcairo noenhanced size 960,720 font 'sans,10'
set output 'profile_latency_640x480_random.png'
set multiplot layout 2,1
set grid lc rgb '#e1e1e1'
set key top right opaque box spacing 1.4
set title 'Frame end (EOF pixel accepted) to irq rise'
set xlabel 'frame'
set ylabel 'cycles'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.26, graph 0.00
plot 'profile_latency_640x480_random.dat' index 0 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#145ac8' title 'at the ports', \
     'profile_latency_640x480_random.dat' index 1 using 1:2 with linespoints lw 2 dt 2 pt 7 ps 0.6 lc rgb '#d22828' title 'EOF_TO_IRQ_CYCLES'
set title 'Host readout: irq rise to the driver''s last transaction'
set xlabel 'frame'
set ylabel 'cycles'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.18, graph 0.00
plot 'profile_latency_640x480_random.dat' index 2 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#289628' title 'readout'
unset multiplot
