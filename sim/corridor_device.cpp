#include "sim/corridor_device.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "host/corridor/corridor_guide.hpp"

namespace ceilnav::sim {

stream::HoughShape corridor_hough_shape() {
  stream::HoughShape s;
  s.lanes = 8;
  s.theta_step = 1;
  s.rho_bits = 9;
  s.acc_bits = 12;
  return s;
}

uint8_t initial_weight_shift(int image_height, const stream::HoughShape& shape) {
  const uint64_t h = static_cast<uint64_t>(std::max(image_height, 0));
  const uint64_t worst = h * (h + 1) / 2;
  uint8_t s = 0;
  while (s < 15 && (worst >> s) > shape.acc_max()) ++s;
  return s;
}

CorridorDevice::CorridorDevice(const stream::HoughShape& shape, int image_width, int image_height)
    : shape_(shape),
      width_(image_width),
      height_(image_height),
      fast_(shape),
      weight_shift_(initial_weight_shift(image_height, shape)) {
  if (image_width < 2 || image_height < 2 || image_width > 2048 || image_height > 2048) {
    throw std::invalid_argument("CorridorDevice: image size must be 2 .. 2048 on each side");
  }
  // The rho bins cover [-W, diagonal].
  const double span = image_width + std::hypot(image_width, image_height);
  while (static_cast<double>(shape.rho_bins()) * (1u << rho_shift_) < span) ++rho_shift_;
}

const CorridorDeviceFrame& CorridorDevice::process(const cv::Mat& grey) {
  if (grey.type() != CV_8UC1 || grey.cols != width_ || grey.rows != height_) {
    throw std::invalid_argument(
        "CorridorDevice: the frame must be 8-bit grey of the configured size");
  }
  stream::EdgeConfig ec;
  ec.enable = true;
  ec.mode = stream::EdgeMode::kHorizontal;
  ec.threshold = host::corridor::edge_threshold(grey);
  stream::HoughConfig hc;
  hc.width = static_cast<uint16_t>(width_);
  hc.rho_shift = rho_shift_;
  hc.weight_shift = weight_shift_;
  const std::span<const uint64_t> cells =
      fast_.run(ec, hc, grey.ptr<uint8_t>(0), static_cast<uint32_t>(width_),
                static_cast<uint32_t>(height_), grey.step[0]);
  CorridorDeviceFrame& f = frame_;
  f.acc.shape = shape_;
  f.acc.config = hc;
  f.acc.cells.resize(cells.size());
  f.clipped_cells = 0;
  const uint64_t max = shape_.acc_max();
  for (size_t i = 0; i < cells.size(); ++i) {
    f.clipped_cells += cells[i] > max ? 1u : 0u;
    f.acc.cells[i] = std::min(cells[i], max);
  }
  f.edges = static_cast<uint32_t>(fast_.edges().size());
  f.threshold = ec.threshold;
  weight_shift_ = host::corridor::CorridorGuide::next_weight_shift(f.acc, f.clipped_cells);
  return f;
}

}  // namespace ceilnav::sim
