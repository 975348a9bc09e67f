#include "host/navigator.hpp"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include "host/model_bus.hpp"

namespace ceilnav::host {

Navigator::Navigator(const CameraConfig& camera, const NavigatorOptions& options)
    : camera_(camera), model_(camera), options_(options), pipeline_(options.fifo_depth) {
  if (options_.backend == Backend::fast) return;
  SimBusOptions bus_opt;
  bus_opt.seed = options_.seed;
  bus_opt.run_tready_low_probability = options_.backpressure_probability;
  bus_opt.axi_timing.valid_delay_probability = options_.backpressure_probability > 0 ? 0.2 : 0.0;
  bus_opt.axi_timing.ready_low_probability = options_.backpressure_probability > 0 ? 0.2 : 0.0;
  if (options_.bus_factory) {
    bus_ = options_.bus_factory(bus_opt);
  } else if (options_.backend == Backend::model) {
    bus_ = std::make_unique<ModelBus>(bus_opt, options_.fifo_depth);
  } else {
    throw std::invalid_argument("navigator: the rtl backend needs a bus factory");
  }
  driver_ = std::make_unique<Driver>(*bus_);
  driver_->identify();
}

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

  if (options_.backend == Backend::fast) {
    return pipeline_.process_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], &runs);
  }
  // Through the registers: configure between frames, stream the frame in,
  // wait for the interrupt, read results and runs.
  driver_->configure(cfg);
  const uint64_t start = bus_->cycles();
  FrameFeed feed;
  feed.gap_probability = options_.gap_probability;
  feed.blanking_cycles = 16;
  bus_->queue_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], feed);
  FrameReadout r = driver_->read_frame();
  if (!r.trailer_seen || !r.consistent) {
    throw std::runtime_error("navigator: the device lost the frame's run trailer or results");
  }
  runs = std::move(r.runs);
  cycles = bus_->cycles() - start;
  return r.results;
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
  ThresholdSettings fresh;  // from this frame's histogram (of the camera grey: same every pass)
  for (int pass = 1; pass <= 2; ++pass) {
    out.results = run_pipeline(grey, settings, out.runs, out.cycles);
    out.settings = settings;
    out.passes = pass;
    fresh = choose_threshold(out.results.histogram, options_.threshold);
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
  // Saturated frame: the background (median grey) is at full scale, so no
  // threshold can rise above it and the mask is the background itself.
  if (fresh.threshold <= fresh.background_grey) {
    out.pose.status = Status::no_tape;
    return out;
  }
  out.pose = estimate_tape_pose(out.runs, model_, camera_, options_.pose);
  if (camera_.camera_pitch_deg >= 89.999) {
    out.zenith = zenith_pose_from_moments(out.results.moments, model_, camera_);
  }
  return out;
}

}  // namespace ceilnav::host
