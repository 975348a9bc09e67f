#include "drivers/device.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "drivers/model_bus.hpp"

namespace ceilnav::drivers {

Device::Device(const DeviceOptions& options)
    : options_(options),
      pipeline_(options.fifo_depth, options.device_config.has_class_moments,
                options.device_config.has_corridor, stream::HoughShape{},
                stream::EdgeDetector::kDefaultFifoDepth, options.device_config.has_orientation) {
  if (options_.backend == Backend::fast) return;
  SimBusOptions bus_opt;
  bus_opt.device_config = options_.device_config;
  bus_opt.seed = options_.seed;
  bus_opt.run_tready_low_probability = options_.backpressure_probability;
  bus_opt.axi_timing.valid_delay_probability = options_.backpressure_probability > 0 ? 0.2 : 0.0;
  bus_opt.axi_timing.ready_low_probability = options_.backpressure_probability > 0 ? 0.2 : 0.0;
  if (options_.bus_factory) {
    bus_ = options_.bus_factory(bus_opt);
  } else if (options_.backend == Backend::model) {
    bus_ = std::make_unique<ModelBus>(bus_opt, options_.fifo_depth);
  } else {
    throw std::invalid_argument("device: the rtl backend needs a bus factory");
  }
  driver_ = std::make_unique<host::Driver>(*bus_);
  driver_->identify();
}

void Device::set_corridor(const stream::EdgeConfig& edge, const stream::HoughConfig& hough) {
  if (options_.backend == Backend::fast) {
    if (!pipeline_.has_corridor()) throw std::runtime_error("device: no corridor blocks");
    pipeline_.set_corridor_config(edge, hough);
  } else {
    driver_->configure_corridor(edge, hough);
  }
  corridor_on_ = true;
  edge_cfg_ = edge;
  hough_cfg_ = hough;
}

stream::CorridorReadout Device::fast_corridor() const {
  const stream::Hough& h = pipeline_.hough();
  stream::CorridorReadout c;
  c.valid = h.results_valid();
  c.shape = h.shape();
  c.edge = edge_cfg_;
  c.config = hough_cfg_;
  c.frame_count = fast_hough_frames_;
  c.cells = h.results();
  if (!c.valid) std::fill(c.cells.begin(), c.cells.end(), 0u);  // the read port reads 0
  c.counters = h.counters();
  c.edge_trailers_lost = pipeline_.edge().trailers_lost();
  return c;
}

void Device::set_orientation(const host::OrientationControl& ori) {
  if (options_.backend == Backend::fast) {
    if (!pipeline_.has_orientation()) {
      throw std::runtime_error("device: the device has no orientation block");
    }
    pipeline_.set_orientation_config({ori.enable, ori.threshold});
  } else {
    driver_->configure_orientation(ori);
  }
  orientation_on_ = true;
  ori_cfg_ = ori;
}

host::OrientationReadout Device::fast_orientation() const {
  const stream::Orientation& o = pipeline_.orientation();
  host::OrientationReadout r;
  r.valid = o.results_valid();
  r.frames = o.frames();
  r.skipped = o.frames_skipped();
  r.votes = o.frame_votes();
  r.bins = o.results();
  return r;
}

stream::FrameResults Device::process(const cv::Mat& grey, const stream::PipelineConfig& cfg,
                                     std::vector<stream::RunRecord>& runs, uint64_t& cycles) {
  if (grey.type() != CV_8UC1 || grey.cols != cfg.width || grey.rows != cfg.height) {
    throw std::invalid_argument("device: frame must be 8-bit grey " + std::to_string(cfg.width) +
                                "x" + std::to_string(cfg.height));
  }
  runs.clear();
  cycles = 0;
  if (options_.backend == Backend::fast) {
    pipeline_.set_config(cfg);
    const stream::FrameResults res =
        pipeline_.process_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], &runs);
    if (corridor_on_) {
      if (edge_cfg_.enable && hough_cfg_.enable) ++fast_hough_frames_;
      corridor_ = fast_corridor();
    }
    if (orientation_on_) orientation_ = fast_orientation();
    return res;
  }
  // Through the registers: configure between frames, stream the frame in,
  // wait for the interrupt, read results and runs.
  driver_->configure(cfg);
  if (corridor_on_) driver_->configure_corridor(edge_cfg_, hough_cfg_);
  if (orientation_on_) driver_->configure_orientation(ori_cfg_);
  const uint64_t start = bus_->cycles();
  FrameFeed feed;
  feed.gap_probability = options_.gap_probability;
  feed.blanking_cycles = 16;
  bus_->queue_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], feed);
  host::FrameReadout r = driver_->read_frame();
  if (!r.trailer_seen || !r.consistent) {
    throw std::runtime_error("device: the device lost the frame's run trailer or results");
  }
  runs = std::move(r.runs);
  if (corridor_on_) {
    corridor_ = driver_->read_corridor();
    if (!corridor_.consistent) {
      throw std::runtime_error("device: the hough block published a frame during the readout");
    }
  }
  if (orientation_on_) {
    orientation_ = driver_->read_orientation();
    if (!orientation_.consistent) {
      throw std::runtime_error(
          "device: the orientation block published a frame during the readout");
    }
  }
  cycles = bus_->cycles() - start;
  return r.results;
}

std::unique_ptr<host::FrameProcessor> make_device(const DeviceOptions& options) {
  return std::make_unique<Device>(options);
}

}  // namespace ceilnav::drivers
