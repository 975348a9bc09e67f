set terminal pngcairo noenhanced size 960,1080 font 'sans,10'
set output 'profile_throughput_1920x1080.png'
set multiplot layout 3,1
set grid lc rgb '#e1e1e1'
set key top right opaque box spacing 1.4
set title 'Video throughput vs run-stream back-pressure'
set xlabel 'm_axis_runs tready-low duty'
set ylabel 'pixels / tvalid cycle'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.18, graph 0.00
plot 'profile_throughput_1920x1080.dat' index 0 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#145ac8' title 'min over frames'
set title 'Run FIFO vs back-pressure'
set xlabel 'm_axis_runs tready-low duty'
set ylabel 'entries'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.26, graph 0.00
plot 'profile_throughput_1920x1080.dat' index 1 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#145ac8' title 'high-water (max)', \
     'profile_throughput_1920x1080.dat' index 2 using 1:2 with linespoints lw 2 dt 2 pt 7 ps 0.6 lc rgb '#d22828' title 'drops (total)'
set title 'Run stream stalls vs back-pressure'
set xlabel 'm_axis_runs tready-low duty'
set ylabel 'cycles / frame'
set xrange [*:*]
set yrange [0:*]
set offsets 0, 0, graph 0.18, graph 0.00
plot 'profile_throughput_1920x1080.dat' index 3 using 1:2 with linespoints lw 2 dt 1 pt 7 ps 0.6 lc rgb '#289628' title 'tvalid && !tready'
unset multiplot
