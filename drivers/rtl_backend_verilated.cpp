// The Verilated RTL top (rtl_model/ceilnav_top.sv) as a SimDevice, so the one
// Driver runs on it through SimBus exactly as on the C++ model (ModelBus): the
// full configuration (Vceilnav_top) or the tape one (Vceilnav_top_tape, built
// with the configuration's parameters), as SimBusOptions::device_config says.
#include <cstdint>
#include <memory>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include "Vceilnav_top.h"
#include "Vceilnav_top_tape.h"
#include "verilated.h"
#pragma GCC diagnostic pop

#include <cstring>
#include <stdexcept>
#include <string>

#include "ceilnav/regs.hpp"
#include "drivers/rtl_backend.hpp"
#include "stream/run_scanner.hpp"

namespace ceilnav::drivers {

namespace {

template <class Top>
class RtlDevice : public SimDevice {
 public:
  explicit RtlDevice(uint64_t seed) : ctx_(std::make_unique<VerilatedContext>()) {
    ctx_->randReset(2);  // registers without reset start random, as in silicon
    ctx_->randSeed(static_cast<int>(seed & 0x7FFFFFFF));
    top_ = std::make_unique<Top>(ctx_.get(), "ceilnav_top");
    top_->clk_i = 0;
    reset();
  }
  ~RtlDevice() override { top_->final(); }
  RtlDevice(const RtlDevice&) = delete;
  RtlDevice& operator=(const RtlDevice&) = delete;

  // The flops reset synchronously: rst_ni low across one rising edge.
  void reset() override {
    top_->clk_i = 0;
    top_->rst_ni = 0;
    top_->eval();
    top_->clk_i = 1;
    top_->eval();
    top_->clk_i = 0;
    top_->rst_ni = 1;
    top_->eval();
  }

  SimOutputs outputs() const override {
    SimOutputs o;
    o.s_axil.awready = top_->s_axil_awready_o;
    o.s_axil.wready = top_->s_axil_wready_o;
    o.s_axil.bvalid = top_->s_axil_bvalid_o;
    o.s_axil.bresp = static_cast<uint8_t>(top_->s_axil_bresp_o);
    o.s_axil.arready = top_->s_axil_arready_o;
    o.s_axil.rvalid = top_->s_axil_rvalid_o;
    o.s_axil.rdata = top_->s_axil_rdata_o;
    o.s_axil.rresp = static_cast<uint8_t>(top_->s_axil_rresp_o);
    o.m_axis_runs.tvalid = top_->m_axis_runs_tvalid_o;
    o.m_axis_runs.tlast = top_->m_axis_runs_tlast_o;
    stream::RunBeatWords w{};
    for (size_t i = 0; i < w.size(); ++i) w[i] = top_->m_axis_runs_tdata_o[i];
    o.m_axis_runs.tdata = stream::unpack_run_beat(w);
    o.irq = top_->irq_o;
    o.s_axis_video_tready = top_->s_axis_video_tready_o;
    return o;
  }

  void clock(const SimInputs& in) override {
    top_->s_axis_video_tdata_i = in.s_axis_video.tdata;
    top_->s_axis_video_tvalid_i = in.s_axis_video.tvalid;
    top_->s_axis_video_tuser_i = in.s_axis_video.tuser;
    top_->s_axis_video_tlast_i = in.s_axis_video.tlast;
    top_->s_axil_awaddr_i = in.s_axil.awaddr;
    top_->s_axil_awvalid_i = in.s_axil.awvalid;
    top_->s_axil_wdata_i = in.s_axil.wdata;
    top_->s_axil_wstrb_i = in.s_axil.wstrb & 0xFu;
    top_->s_axil_wvalid_i = in.s_axil.wvalid;
    top_->s_axil_bready_i = in.s_axil.bready;
    top_->s_axil_araddr_i = in.s_axil.araddr;
    top_->s_axil_arvalid_i = in.s_axil.arvalid;
    top_->s_axil_rready_i = in.s_axil.rready;
    top_->m_axis_runs_tready_i = in.m_axis_runs_tready;
    top_->eval();  // inputs settle with the clock low
    top_->clk_i = 1;
    top_->eval();
    top_->clk_i = 0;
    top_->eval();
  }

 private:
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<Top> top_;
};

}  // namespace

BusFactory rtl_bus_factory() {
  return [](const SimBusOptions& options) -> std::unique_ptr<SimBus> {
    const regs::Config& c = options.device_config;
    if (c.has_class_moments == regs::kConfigFull.has_class_moments) {
      return std::make_unique<SimBus>(std::make_unique<RtlDevice<Vceilnav_top>>(options.seed),
                                      options);
    }
    if (c.has_class_moments == regs::kConfigTape.has_class_moments) {
      return std::make_unique<SimBus>(std::make_unique<RtlDevice<Vceilnav_top_tape>>(options.seed),
                                      options);
    }
    throw std::runtime_error(std::string("no Verilated top for configuration ") + c.name);
  };
}

}  // namespace ceilnav::drivers
