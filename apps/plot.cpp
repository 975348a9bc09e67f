#include "apps/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace ceilnav::app {

namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickFontScale = 0.45;
constexpr double kLabelFontScale = 0.55;
const cv::Scalar kBlack{0, 0, 0};
const cv::Scalar kGrid{225, 225, 225};

// Tick step of 1, 2 or 5 times a power of ten giving about `target` ticks.
double nice_step(double span, int target) {
  const double raw = span / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

struct Range {
  double lo, hi;
};

Range data_range(const std::vector<PlotSeries>& series, bool x_axis) {
  Range r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const auto& s : series) {
    for (double v : x_axis ? s.x : s.y) {
      if (!std::isfinite(v)) continue;
      r.lo = std::min(r.lo, v);
      r.hi = std::max(r.hi, v);
    }
  }
  if (!(r.lo <= r.hi)) r = {0.0, 1.0};
  return r;
}

bool all_integers(const std::vector<PlotSeries>& series, bool x_axis) {
  for (const auto& s : series) {
    for (double v : x_axis ? s.x : s.y) {
      if (std::isfinite(v) && v != std::round(v)) return false;
    }
  }
  return true;
}

// Widens a range to tick multiples (and a non-empty span).
Range padded(Range r, bool from_zero, bool integer_ticks, double& step) {
  if (from_zero && r.lo >= 0.0) r.lo = 0.0;
  if (r.hi - r.lo < 1e-12) {
    const double half = std::max(std::abs(r.hi) * 0.1, 1.0);
    r = {from_zero && r.lo >= 0.0 ? 0.0 : r.lo - half, r.hi + half};
  }
  step = nice_step(r.hi - r.lo, 6);
  if (integer_ticks) step = std::max(step, 1.0);
  return {std::floor(r.lo / step) * step, std::ceil(r.hi / step) * step};
}

std::string tick_text(double v, double step) {
  char buf[32];
  if (std::abs(v) < step * 1e-6) v = 0.0;
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step)));
  if (std::abs(v) >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.3g", v);
  } else {
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  }
  return buf;
}

void put_text(cv::Mat& img, const std::string& text, cv::Point at, double scale,
              const cv::Scalar& colour = kBlack, int thickness = 1) {
  cv::putText(img, text, at, kFont, scale, colour, thickness, cv::LINE_AA);
}

cv::Size text_size(const std::string& text, double scale, int thickness = 1) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, thickness, &baseline);
}

}  // namespace

cv::Mat draw_plot(const PlotPanel& panel, int width, int height) {
  cv::Mat img(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  // The legend has a row of its own between the title and the axes.
  const int left = 90, right = 20, top = 62, bottom = 60;
  const cv::Rect area(left, top, width - left - right, height - top - bottom);

  double xstep = 1.0, ystep = 1.0;
  const Range xr =
      padded(data_range(panel.series, true), false, all_integers(panel.series, true), xstep);
  const Range yr = padded(data_range(panel.series, false), panel.y_from_zero,
                          all_integers(panel.series, false), ystep);
  const auto px = [&](double x) {
    return area.x + static_cast<int>(std::lround((x - xr.lo) / (xr.hi - xr.lo) * area.width));
  };
  const auto py = [&](double y) {
    return area.y + area.height -
           static_cast<int>(std::lround((y - yr.lo) / (yr.hi - yr.lo) * area.height));
  };

  // Grid, ticks and tick labels.
  for (double v = yr.lo; v <= yr.hi + ystep * 1e-9; v += ystep) {
    const int y = py(v);
    cv::line(img, {area.x, y}, {area.x + area.width, y}, kGrid, 1);
    cv::line(img, {area.x - 5, y}, {area.x, y}, kBlack, 1);
    const std::string t = tick_text(v, ystep);
    const cv::Size ts = text_size(t, kTickFontScale);
    put_text(img, t, {area.x - 8 - ts.width, y + ts.height / 2}, kTickFontScale);
  }
  for (double v = xr.lo; v <= xr.hi + xstep * 1e-9; v += xstep) {
    const int x = px(v);
    cv::line(img, {x, area.y}, {x, area.y + area.height}, kGrid, 1);
    cv::line(img, {x, area.y + area.height}, {x, area.y + area.height + 5}, kBlack, 1);
    const std::string t = tick_text(v, xstep);
    const cv::Size ts = text_size(t, kTickFontScale);
    put_text(img, t, {x - ts.width / 2, area.y + area.height + 10 + ts.height}, kTickFontScale);
  }
  cv::rectangle(img, area, kBlack, 1);

  // Axis labels and title.
  const cv::Size xs = text_size(panel.x_label, kLabelFontScale);
  put_text(img, panel.x_label, {area.x + (area.width - xs.width) / 2, height - 12},
           kLabelFontScale);
  const cv::Size ys = text_size(panel.y_label, kLabelFontScale);
  cv::Mat ylab(ys.height + 8, ys.width + 4, CV_8UC3, cv::Scalar(255, 255, 255));
  put_text(ylab, panel.y_label, {2, ys.height + 2}, kLabelFontScale);
  cv::rotate(ylab, ylab, cv::ROTATE_90_COUNTERCLOCKWISE);
  const int ly = std::max(0, area.y + (area.height - ylab.rows) / 2);
  if (ly + ylab.rows <= height && ylab.cols + 6 <= left) {
    ylab.copyTo(img(cv::Rect(6, ly, ylab.cols, ylab.rows)));
  }
  const cv::Size tsz = text_size(panel.title, kLabelFontScale, 2);
  put_text(img, panel.title, {(width - tsz.width) / 2, 26}, kLabelFontScale, kBlack, 2);

  // Series: lines with point markers; earlier series wider, so that equal
  // series stay visible. Legend entries left to right above the axes.
  int legend_x = area.x;
  for (size_t k = 0; k < panel.series.size(); ++k) {
    const PlotSeries& s = panel.series[k];
    const int thickness = k == 0 && panel.series.size() > 1 ? 4 : 2;
    const int radius = k == 0 && panel.series.size() > 1 ? 6 : 3;
    const size_t n = std::min(s.x.size(), s.y.size());
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      const cv::Point p(px(s.x[i]), py(s.y[i]));
      cv::circle(img, p, radius, s.colour, cv::FILLED, cv::LINE_AA);
      if (i > 0 && std::isfinite(s.x[i - 1]) && std::isfinite(s.y[i - 1])) {
        cv::line(img, {px(s.x[i - 1]), py(s.y[i - 1])}, p, s.colour, thickness, cv::LINE_AA);
      }
    }
    if (!s.label.empty()) {
      const cv::Size ls = text_size(s.label, kTickFontScale);
      const int ly2 = top - 12;
      cv::line(img, {legend_x, ly2 - ls.height / 2}, {legend_x + 22, ly2 - ls.height / 2}, s.colour,
               thickness, cv::LINE_AA);
      put_text(img, s.label, {legend_x + 28, ly2}, kTickFontScale);
      legend_x += 28 + ls.width + 24;
    }
  }
  return img;
}

cv::Mat stack_plots(const std::vector<cv::Mat>& panels) {
  cv::Mat out;
  cv::vconcat(panels, out);
  return out;
}

std::vector<unsigned char> encode_png(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) throw std::runtime_error("cannot encode a PNG plot");
  return bytes;
}

}  // namespace ceilnav::app
