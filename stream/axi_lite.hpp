// AXI4-Lite port bundles (s_axil_*) of the register top. Timing of the
// slave: docs/blocks/ceilnav_top.md. The master that drives them in
// simulation is drivers::AxiLiteMaster (drivers/axi_lite_master.hpp).
#pragma once

#include <cstdint>

namespace ceilnav::stream {

// Master -> slave.
struct AxiLiteIn {
  uint32_t awaddr = 0;
  bool awvalid = false;
  uint32_t wdata = 0;
  uint8_t wstrb = 0xF;
  bool wvalid = false;
  bool bready = false;
  uint32_t araddr = 0;
  bool arvalid = false;
  bool rready = false;
  friend bool operator==(const AxiLiteIn&, const AxiLiteIn&) = default;
};

// Slave -> master (all registered in the device).
struct AxiLiteOut {
  bool awready = false;
  bool wready = false;
  bool bvalid = false;
  uint8_t bresp = 0;  // 0 OKAY, 2 SLVERR
  bool arready = false;
  bool rvalid = false;
  uint32_t rdata = 0;
  uint8_t rresp = 0;
  friend bool operator==(const AxiLiteOut&, const AxiLiteOut&) = default;
};

}  // namespace ceilnav::stream
