#include "drivers/device.hpp"

#include <stdexcept>
#include <string>

#include "drivers/model_bus.hpp"

namespace ceilnav::drivers {

Device::Device(const DeviceOptions& options) : options_(options), pipeline_(options.fifo_depth) {
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
    throw std::invalid_argument("device: the rtl backend needs a bus factory");
  }
  driver_ = std::make_unique<host::Driver>(*bus_);
  driver_->identify();
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
  host::FrameReadout r = driver_->read_frame();
  if (!r.trailer_seen || !r.consistent) {
    throw std::runtime_error("device: the device lost the frame's run trailer or results");
  }
  runs = std::move(r.runs);
  cycles = bus_->cycles() - start;
  return r.results;
}

std::unique_ptr<host::FrameProcessor> make_device(const DeviceOptions& options) {
  return std::make_unique<Device>(options);
}

}  // namespace ceilnav::drivers
