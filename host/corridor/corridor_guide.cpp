#include "host/corridor/corridor_guide.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ceilnav::host::corridor {

const char* to_string(GuideStatus s) {
  switch (s) {
    case GuideStatus::ok:
      return "ok";
    case GuideStatus::pan_only:
      return "pan_only";
    case GuideStatus::not_found:
      return "not_found";
  }
  return "?";
}

CorridorGuide::CorridorGuide(const CameraConfig& camera, const GuideParams& params,
                             const CorridorModel* model)
    : camera_(camera),
      model_camera_(camera),
      params_(params),
      model_(model),
      predicted_pan_rad_(params.initial_pan_rad),
      last_shift_m_(params.initial_shift_m),
      last_sigma_m_(params.initial_shift_sigma_m) {}

GuideFrame CorridorGuide::process(const Accumulator& acc, std::optional<double> travelled_m) {
  GuideFrame f;
  f.raw_lines = extract_lines(acc, params_.lines);
  for (const HoughLine& h : f.raw_lines) {
    ImageLine u;
    if (undistort_line(h.line, model_camera_, camera_.image_width, camera_.image_height, u)) {
      f.lines.push_back(u);
    }
  }
  VanishingParams vp = params_.vanishing;
  if (!tracking_pan_)
    vp.pan_window_rad = std::max(vp.pan_window_rad, params_.acquire_pan_window_rad);
  f.pan = estimate_pan(f.lines, camera_, params_.mount, predicted_pan_rad_, vp);
  tracking_pan_ = f.pan.status != PanStatus::not_found;
  if (f.pan.status == PanStatus::not_found) {
    ++frames_since_shift_;
    // Blind: the heading is the last one measured.
    if (travelled_m && last_delta_phi_rad_)
      moved_m_ += *travelled_m * std::sin(*last_delta_phi_rad_);
    // Lost: the next frame searches around the path's own pan again (the
    // window around a stale prediction could miss the corridor for good).
    predicted_pan_rad_ = params_.initial_pan_rad;
    return f;
  }
  predicted_pan_rad_ = f.pan.pan_rad;
  const int n = ++frames_since_shift_;
  if (travelled_m) {
    // The heading over the step: the mean of the last and this frame's.
    const double phi =
        last_delta_phi_rad_ ? 0.5 * (*last_delta_phi_rad_ + f.pan.heading_rad) : f.pan.heading_rad;
    moved_m_ += *travelled_m * std::sin(phi);
  }
  last_delta_phi_rad_ = f.pan.heading_rad;
  f.delta_phi_rad = f.pan.heading_rad;
  f.status = GuideStatus::pan_only;
  if (model_ == nullptr) return f;
  // The prediction: the last shift moved on by the lateral motion since;
  // its sigma (the last frame's, then the options') and gate grow as sqrt(n)
  // with the n frames since the last shift.
  ShiftOptions so = params_.shift;
  if (last_shift_m_) {
    const double widen = std::sqrt(static_cast<double>(n));
    so.prior_m = *last_shift_m_ + moved_m_;
    so.prior_sigma_m = last_sigma_m_ * widen;
    so.prior_gate_m *= std::max(1.0, last_sigma_m_ / params_.shift.prior_sigma_m) * widen;
  }
  // The shift uses the lines through the axis vanishing point only (the
  // model's lines are along the axis).
  std::vector<ImageLine> axis_lines;
  for (int i : f.pan.axis.inliers) axis_lines.push_back(f.lines[static_cast<size_t>(i)]);
  f.shift = lateral_shift(axis_lines, f.pan.pan_rad, *model_, so);
  if (!f.shift.valid) return f;
  last_shift_m_ = f.shift.shift_m;
  last_sigma_m_ = params_.shift.prior_sigma_m;
  frames_since_shift_ = 0;
  moved_m_ = 0.0;
  f.turn_rad = wheel_turn(f.delta_phi_rad, f.shift.shift_m, params_.turn);
  f.status = GuideStatus::ok;
  return f;
}

std::optional<LearningImage> learning_image(const GuideFrame& frame) {
  if (frame.pan.status == PanStatus::not_found) return std::nullopt;
  LearningImage li;
  li.pan_rad = frame.pan.pan_rad;
  for (int i : frame.pan.axis.inliers) li.lines.push_back(frame.lines[static_cast<size_t>(i)]);
  return li;
}

uint16_t edge_threshold(const cv::Mat& grey, stream::EdgeMode mode) {
  std::vector<int> d;
  d.reserve(static_cast<size_t>(grey.rows) * static_cast<size_t>(grey.cols));
  for (int y = 0; y < grey.rows; ++y) {
    const auto* row = grey.ptr<uint8_t>(y);
    for (int x = 1; x < grey.cols; ++x) d.push_back(std::abs(row[x] - row[x - 1]));
  }
  if (d.empty()) return 4;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  const int t = std::max(4, 4 * d[d.size() / 2]);
  return static_cast<uint16_t>(mode == stream::EdgeMode::kSobel ? 4 * t : t);
}

uint8_t CorridorGuide::next_weight_shift(const Accumulator& acc, uint32_t saturated_votes) {
  const uint8_t ws = acc.config.weight_shift;
  if (saturated_votes > 0) return static_cast<uint8_t>(std::min(15, ws + 1));
  const uint64_t max =
      acc.cells.empty() ? 0 : *std::max_element(acc.cells.begin(), acc.cells.end());
  if (ws > 0 && 4 * max <= acc.shape.acc_max()) return static_cast<uint8_t>(ws - 1);
  return ws;
}

}  // namespace ceilnav::host::corridor
