#include "drivers/model_bus.hpp"

#include <memory>

namespace ceilnav::drivers {

namespace {

class ModelDevice : public SimDevice {
 public:
  ModelDevice(uint32_t run_fifo_depth, const regs::Config& config) : top_(run_fifo_depth, config) {}
  void reset() override { top_.reset(); }
  SimOutputs outputs() const override {
    SimOutputs o;
    o.s_axil = top_.s_axil_out();
    o.m_axis_runs = top_.m_axis_runs();
    o.irq = top_.irq();
    o.s_axis_video_tready = true;  // CeilnavTop::clock: s_axis_video_tready is always 1
    return o;
  }
  void clock(const SimInputs& in) override {
    top_.clock(in.s_axis_video, in.s_axil, in.m_axis_runs_tready);
  }
  const stream::CeilnavTop& top() const { return top_; }

 private:
  stream::CeilnavTop top_;
};

}  // namespace

ModelBus::ModelBus(const SimBusOptions& options, uint32_t run_fifo_depth)
    : SimBus(std::make_unique<ModelDevice>(run_fifo_depth, options.device_config), options),
      top_(&static_cast<ModelDevice&>(device()).top()) {}

}  // namespace ceilnav::drivers
