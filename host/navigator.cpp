#include "host/navigator.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace ceilnav::host {

namespace {

// splitmix64: a small, fully specified generator so that a seed gives the same
// gap/back-pressure pattern on every platform.
uint64_t next_random(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

bool chance(uint64_t& state, double p) {
  if (p <= 0.0) return false;
  return static_cast<double>(next_random(state) >> 11) * 0x1.0p-53 < p;
}

}  // namespace

Navigator::Navigator(const CameraConfig& camera, const NavigatorOptions& options)
    : camera_(camera),
      model_(camera),
      options_(options),
      pipeline_(options.fifo_depth),
      rng_state_(options.seed) {}

stream::FrameResults Navigator::run_pipeline(const cv::Mat& grey, const ThresholdSettings& s,
                                             std::vector<stream::RunRecord>& runs,
                                             uint64_t& cycles) {
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(grey.cols);
  cfg.height = static_cast<uint16_t>(grey.rows);
  cfg.min_run_length = options_.min_run_length;
  cfg.max_runs_per_row = options_.max_runs_per_row;
  cfg.hist_source_remap = false;
  cfg = apply_threshold(cfg, s);
  pipeline_.set_config(cfg);
  runs.clear();
  cycles = 0;

  if (!options_.clocked) {
    return pipeline_.process_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], &runs);
  }

  // Cycle-level: one beat per clock, random tvalid gaps on the video input and
  // random tready on the run stream; runs until frame_done and the trailer.
  bool done = false, trailer = false;
  int x = 0, y = 0;
  const uint64_t limit = 64ull * static_cast<uint64_t>(grey.total()) + 100000ull;
  while (!(done && trailer)) {
    if (cycles > limit) throw std::runtime_error("navigator: the pipeline did not finish a frame");
    stream::VideoBeat beat;
    if (y < grey.rows && !chance(rng_state_, options_.gap_probability)) {
      beat.tvalid = true;
      beat.tdata = grey.at<uint8_t>(y, x);
      beat.tuser = x == 0 && y == 0;
      beat.tlast = x == grey.cols - 1;
      if (++x == grey.cols) {
        x = 0;
        ++y;
      }
    }
    const bool tready = !chance(rng_state_, options_.backpressure_probability);
    const stream::RunBeat out = pipeline_.m_axis_runs();
    if (out.tvalid && tready) {
      if (out.tlast) {
        trailer = true;
      } else {
        runs.push_back(out.tdata);
      }
    }
    pipeline_.clock(beat, tready);
    ++cycles;
    if (pipeline_.frame_done()) done = true;
  }
  return pipeline_.results();
}

FrameOutcome Navigator::process(const cv::Mat& grey) {
  if (grey.type() != CV_8UC1 || grey.cols != camera_.image_width ||
      grey.rows != camera_.image_height) {
    throw std::invalid_argument("navigator: frame must be 8-bit grey " +
                                std::to_string(camera_.image_width) + "x" +
                                std::to_string(camera_.image_height));
  }
  FrameOutcome out;
  ThresholdSettings settings = previous_.value_or(ThresholdSettings{});
  for (int pass = 1; pass <= 2; ++pass) {
    out.results = run_pipeline(grey, settings, out.runs, out.cycles);
    out.settings = settings;
    out.passes = pass;
    const ThresholdSettings fresh = choose_threshold(out.results.histogram, options_.threshold);
    const bool stale = !previous_.has_value() ||
                       std::abs(static_cast<int>(fresh.threshold) - settings.threshold) >
                           options_.threshold_tolerance_grey ||
                       std::abs(static_cast<int>(fresh.background_level) -
                                settings.background_level) > options_.threshold_tolerance_grey;
    previous_ = fresh;
    if (!stale || pass == 2) break;
    settings = fresh;
  }

  if (!out.results.valid) {
    out.pose.status = Status::frame_invalid;
    return out;
  }
  out.pose = estimate_tape_pose(out.runs, model_, camera_, options_.pose);
  if (camera_.camera_pitch_deg >= 89.999) {
    out.zenith = zenith_pose_from_moments(out.results.moments, model_, camera_);
  }
  return out;
}

}  // namespace ceilnav::host
