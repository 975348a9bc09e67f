// Port groups of the Verilated tops, one copy each: drive an input group from
// the C++ beat type, or read an output group into it. The functions are
// templates on the Verilated class, so they serve every top that has the
// ports (the names are the RTL's, docs/rtl_style.md): the RTL backend
// (drivers/rtl_backend_verilated.cpp), the co-simulations (testbench/) and the
// RTL benchmark.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/run_scanner.hpp"

namespace ceilnav::drivers {

// s_axis_video_*: the camera stream into frame_check and the device top.
template <class Top>
void drive_s_axis_video(Top& d, const stream::VideoBeat& b) {
  d.s_axis_video_tdata_i = b.tdata;
  d.s_axis_video_tvalid_i = b.tvalid;
  d.s_axis_video_tuser_i = b.tuser;
  d.s_axis_video_tlast_i = b.tlast;
}

// s_lut_*: thresh_lut's output beat into the blocks behind it (the class
// port only where the block has one).
template <class Top>
void drive_s_lut(Top& d, const stream::LutBeat& in) {
  d.s_lut_valid_i = in.pix.valid;
  d.s_lut_grey_i = in.pix.grey;
  d.s_lut_x_i = in.pix.x;
  d.s_lut_y_i = in.pix.y;
  d.s_lut_sof_i = in.pix.sof;
  d.s_lut_eol_i = in.pix.eol;
  d.s_lut_eof_i = in.pix.eof;
  d.s_lut_abort_i = in.pix.abort;
  d.s_lut_remap_i = in.remap;
  d.s_lut_mask_i = in.mask;
  if constexpr (requires { d.s_lut_class_i; }) {
    d.s_lut_class_i = in.cls & 3u;
  }
}

// s_axil_* inputs: the AXI4-Lite master's side of the register bus.
template <class Top>
void drive_s_axil(Top& d, const stream::AxiLiteIn& in) {
  d.s_axil_awaddr_i = in.awaddr;
  d.s_axil_awvalid_i = in.awvalid;
  d.s_axil_wdata_i = in.wdata;
  d.s_axil_wstrb_i = in.wstrb & 0xFu;
  d.s_axil_wvalid_i = in.wvalid;
  d.s_axil_bready_i = in.bready;
  d.s_axil_araddr_i = in.araddr;
  d.s_axil_arvalid_i = in.arvalid;
  d.s_axil_rready_i = in.rready;
}

// s_axil_* outputs: the slave's side.
template <class Top>
stream::AxiLiteOut read_s_axil(const Top& d) {
  stream::AxiLiteOut o;
  o.awready = d.s_axil_awready_o;
  o.wready = d.s_axil_wready_o;
  o.bvalid = d.s_axil_bvalid_o;
  o.bresp = static_cast<uint8_t>(d.s_axil_bresp_o);
  o.arready = d.s_axil_arready_o;
  o.rvalid = d.s_axil_rvalid_o;
  o.rdata = d.s_axil_rdata_o;
  o.rresp = static_cast<uint8_t>(d.s_axil_rresp_o);
  return o;
}

// m_axis_runs_* outputs as a RunBeat (tdata unpacked from its four words).
template <class Top>
stream::RunBeat read_m_axis_runs(const Top& d) {
  stream::RunBeatWords words{};
  for (size_t i = 0; i < words.size(); ++i) words[i] = d.m_axis_runs_tdata_o[i];
  stream::RunBeat b;
  b.tvalid = d.m_axis_runs_tvalid_o;
  b.tlast = d.m_axis_runs_tlast_o;
  b.tdata = stream::unpack_run_beat(words);
  return b;
}

}  // namespace ceilnav::drivers
