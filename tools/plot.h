// plot.h - the bench's plot (ms per frame against PSNR), drawn by gnuplot
// with no shell and no user string in anything gnuplot reads.
//
// gnuplot is started with an argument vector ("gnuplot", nothing else) by
// posix_spawn; its script comes on stdin from an anonymous memory file
// (memfd), the points are inline in the script (a datablock), and the PNG
// comes out on its stdout, another memory file. Only a complete PNG (signature
// first, IEND last) is then written to the output, whole or not at all
// (output.h), every write checked. So no path, quote, semicolon or newline the
// user gave reaches gnuplot, gnuplot's special names ('<cmd', '|cmd') are
// never used, and gnuplot never touches the output.
#pragma once
#include <string>
#include <vector>

struct PlotPoint {
  std::string label; // a bench mode name: letters and digits only
  double medianMs, minPsnr, medianPsnr, p95Ms;
};

struct PlotTitle {
  int width, height, frames, threads;
};

// gnuplot's path: the first executable regular file named gnuplot in a folder
// of PATH (or the system's default path when PATH is unset). False with a
// one-line `error` when there is none.
bool find_gnuplot(std::string& gnuplot, std::string& error);

// The gnuplot script for `points` (what draw_plot feeds gnuplot); false if a
// label holds anything but letters, digits, '-' and '_'.
bool plot_script(const std::vector<PlotPoint>& points, const PlotTitle& title, std::string& script);

// Runs `gnuplot` on the script and writes its PNG to `path`, whole or not at
// all. False with a one-line `error`: gnuplot's own last error line, the
// signal that ended it, or the write that failed.
bool draw_plot(const std::string& gnuplot, const std::string& path,
               const std::vector<PlotPoint>& points, const PlotTitle& title, std::string& error);
