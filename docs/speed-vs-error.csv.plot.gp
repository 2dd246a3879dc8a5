set terminal pngcairo size 900,600 font 'sans,11'
set output 'docs/speed-vs-error.png'
set title 'rt64k: ms per 800x600 frame against error vs every-pixel trace (256 frames, 2 threads)'
set xlabel 'median ms per frame (log scale)'
set ylabel 'PSNR against full trace, dB (99 = identical)'
set logscale x
set grid
set key bottom right
set arrow from graph 0, first 40 to graph 1, first 40 nohead dt 2 lc rgb '#c00000'
plot 'docs/speed-vs-error.csv.plot.dat' using 2:4:1 with labels offset 0,1 notitle, \
     '' using 2:4 with points pt 7 ps 1.5 title 'median PSNR', \
     '' using 2:3 with points pt 5 ps 1.2 title 'min PSNR'
