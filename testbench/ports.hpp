// Scoreboard checks of the Verilated tops' output groups against the model
// (Sim: Cosim<Top>), and the drive and read helpers of drivers/verilated_ports.hpp
// under the testbench's names.
#pragma once

#include <cstddef>
#include <cstdint>

#include "drivers/verilated_ports.hpp"
#include "stream/axi_lite.hpp"
#include "stream/beat.hpp"
#include "stream/run_scanner.hpp"

namespace ceilnav::testbench {

using drivers::drive_s_axil;
using drivers::drive_s_axis_video;
using drivers::drive_s_lut;
using drivers::read_m_axis_runs;
using drivers::read_s_axil;

// Every s_axil_* output against the model's (Sim: Cosim<Top>).
template <class Sim, class Top>
bool check_s_axil(Sim& sim, const Top& d, const stream::AxiLiteOut& a) {
  bool ok = sim.check("s_axil_awready_o", d.s_axil_awready_o, a.awready);
  ok = sim.check("s_axil_wready_o", d.s_axil_wready_o, a.wready) && ok;
  ok = sim.check("s_axil_bvalid_o", d.s_axil_bvalid_o, a.bvalid) && ok;
  ok = sim.check("s_axil_bresp_o", d.s_axil_bresp_o, a.bresp) && ok;
  ok = sim.check("s_axil_arready_o", d.s_axil_arready_o, a.arready) && ok;
  ok = sim.check("s_axil_rvalid_o", d.s_axil_rvalid_o, a.rvalid) && ok;
  ok = sim.check("s_axil_rdata_o", d.s_axil_rdata_o, a.rdata) && ok;
  ok = sim.check("s_axil_rresp_o", d.s_axil_rresp_o, a.rresp) && ok;
  return ok;
}

// Every m_axis_runs_* output against the model's beat; tdata word by word
// (the packing of stream::pack_run_beat).
template <class Sim, class Top>
bool check_m_axis_runs(Sim& sim, const Top& d, const stream::RunBeat& runs) {
  const stream::RunBeatWords words = stream::pack_run_beat(runs.tdata);
  bool ok = sim.check("m_axis_runs_tvalid_o", d.m_axis_runs_tvalid_o, runs.tvalid);
  ok = sim.check("m_axis_runs_tlast_o", d.m_axis_runs_tlast_o, runs.tlast) && ok;
  static const char* const kWordNames[4] = {
      "m_axis_runs_tdata_o[31:0]", "m_axis_runs_tdata_o[63:32]", "m_axis_runs_tdata_o[95:64]",
      "m_axis_runs_tdata_o[111:96]"};
  for (size_t i = 0; i < 4; ++i) {
    ok = sim.check(kWordNames[i], d.m_axis_runs_tdata_o[i], words[i]) && ok;
  }
  return ok;
}

}  // namespace ceilnav::testbench
