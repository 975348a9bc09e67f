// Line charts drawn with OpenCV for the reports of the ceilnav program: axes
// with ticks at 1-2-5 steps, tick labels, axis labels, a title and a legend.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ceilnav::app {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  // equal lengths
  cv::Scalar colour{200, 80, 0};
};

struct PlotPanel {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  bool y_from_zero = true;  // the y axis starts at 0 when all values are >= 0
};

// One panel, width x height pixels, 8-bit BGR on white.
cv::Mat draw_plot(const PlotPanel& panel, int width = 960, int height = 360);

// Panels one under the other (equal widths).
cv::Mat stack_plots(const std::vector<cv::Mat>& panels);

// PNG file bytes of an image (throws std::runtime_error if encoding fails).
std::vector<unsigned char> encode_png(const cv::Mat& image);

}  // namespace ceilnav::app
