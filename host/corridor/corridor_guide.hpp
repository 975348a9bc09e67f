// Seed 002's guidance, frame by frame, from the Hough accumulator the device
// publishes: the lines (steps 3-8 of the matching stage, hough_lines.hpp),
// the pan (eq. 10-16, vanishing.hpp), the lateral shift against a learnt
// model (eq. 21-25, lateral_shift.hpp) and the wheel turn (eq. 26-28,
// turn_law.hpp), with what a frame carries to the next: the predicted pan,
// the predicted shift as the matching's prior (the last shift moved on by
// the distance travelled at the measured heading, when odometry gives the
// distance; the prior widening with every frame without a shift), and
// the Hough weight shift the host programs for the next frame.
// docs/corridor.md, "Guidance".
#pragma once

#include <cstdint>
#include <numbers>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "common/edge_record.hpp"
#include "host/camera_model.hpp"
#include "host/corridor/corridor_model.hpp"
#include "host/corridor/hough_lines.hpp"
#include "host/corridor/lateral_shift.hpp"
#include "host/corridor/turn_law.hpp"
#include "host/corridor/vanishing.hpp"

namespace ceilnav::host::corridor {

struct GuideParams {
  LineExtractionParams lines;
  VanishingParams vanishing;
  ShiftOptions shift;
  TurnLaw turn = design_turn_law();
  CameraMount mount;             // tilt, swing, pan on the vehicle (calibration)
  double initial_pan_rad = 0.0;  // the first frame's prediction, and after a frame without one
  // The pan window (VanishingParams::pan_window_rad) of a frame without a
  // prediction (the first, and after a frame without a pan): the vehicle
  // may be turned well away from the path's pan then; the tracking window
  // (10 deg) applies once a pan was found.
  double acquire_pan_window_rad = 30.0 * std::numbers::pi / 180.0;
  // The first frame's prior on the lateral shift (the matching's, lateral_shift.hpp):
  // a guided drive starts near where the learnt path does (0), within
  // about initial_shift_sigma_m; nullopt: none.
  std::optional<double> initial_shift_m = 0.0;
  double initial_shift_sigma_m = 0.3;
};

enum class GuideStatus {
  ok,         // pan and lateral shift
  pan_only,   // a pan, no shift (no model, or no line matched)
  not_found,  // no corridor: no pan
};
const char* to_string(GuideStatus s);

struct GuideFrame {
  GuideStatus status = GuideStatus::not_found;
  std::vector<HoughLine> raw_lines;  // on the voted (distorted) image
  std::vector<ImageLine> lines;      // undistorted (the raw lines that undistort)
  PanEstimate pan;
  double delta_phi_rad = 0.0;  // eq. 16: the vehicle's heading to the corridor
  LateralShift shift;          // valid when status ok
  double turn_rad = 0.0;       // eq. 26 (0 unless ok)
};

// A learning drive's image (seed section 4.1) from a frame: the lines through
// the axis vanishing point at the frame's pan; nullopt without a pan.
std::optional<LearningImage> learning_image(const GuideFrame& frame);

// The eq. 17 threshold the host programs from a frame: 4 x the median
// |p(x) - p(x-1)| over the frame (the noise's scale: most horizontal
// neighbours see no edge), at least 4 grey levels; x4 for Sobel magnitudes.
uint16_t edge_threshold(const cv::Mat& grey, stream::EdgeMode mode = stream::EdgeMode::kHorizontal);

class CorridorGuide {
 public:
  // model: nullptr for the learning drive (pan only).
  CorridorGuide(const CameraConfig& camera, const GuideParams& params,
                const CorridorModel* model = nullptr);
  // travelled_m: the distance the vehicle moved since the previous frame
  // (odometry), which moves the predicted shift on by travelled sin(Delta-phi);
  // nullopt: the prediction is the last shift.
  GuideFrame process(const Accumulator& acc, std::optional<double> travelled_m = std::nullopt);
  // The Hough weight shift for the next frame: raised while cells saturate,
  // lowered when the largest cell would still fit at the lower shift with a
  // factor 2 to spare (votes weigh (y + 1) >> shift, eq. 18).
  static uint8_t next_weight_shift(const Accumulator& acc, uint32_t saturated_votes);

 private:
  CameraConfig camera_;
  CameraModel model_camera_;
  GuideParams params_;
  const CorridorModel* model_;
  double predicted_pan_rad_;
  bool tracking_pan_ = false;  // the last frame had a pan
  std::optional<double> last_shift_m_;
  double last_sigma_m_;  // the prior sigma of the next frame with one frame since
  int frames_since_shift_ = 0;
  double moved_m_ = 0.0;  // lateral motion since the last shift (odometry x heading)
  std::optional<double> last_delta_phi_rad_;
};

}  // namespace ceilnav::host::corridor
