// Line charts for the reports of the ceilnav program, drawn by gnuplot
// (Debian package gnuplot-nox): the numbers go to a data file beside the PNG,
// and a gnuplot script beside both draws the PNG from it, so every chart can
// be redrawn or restyled by hand.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ceilnav::app {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;       // equal lengths; non-finite points are left out
  cv::Scalar colour{200, 80, 0};  // BGR, as elsewhere in the program
};

struct PlotPanel {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool y_from_zero = true;  // the y axis starts at 0 when all values are >= 0
};

// Draws `panels` one under the other into `png` (pngcairo terminal, `width` x
// panels * `panel_height` pixels) and leaves beside it `<stem>.dat` (one block
// per series: "x y" lines, blocks separated by two blank lines, each headed by
// a comment naming its panel and series) and `<stem>.gp` (the script).
// Throws std::runtime_error when gnuplot cannot be run (the message names the
// package gnuplot-nox) or fails. `gnuplot` is the program to run.
void write_plots(const std::filesystem::path& png, const std::vector<PlotPanel>& panels,
                 int width = 960, int panel_height = 360, const std::string& gnuplot = "gnuplot");

}  // namespace ceilnav::app
