// ceilnav_board: the device as it goes onto an iCE40 board, the top that is
// placed and routed into a bitstream (scripts/synth_report, docs/performance.md).
// ceilnav_top with the ports a board wires to pins:
// * the camera stream (AXI4-Stream video, never back-pressured);
// * the host's register port (AXI4-Lite) with the register map's address bits
//   only (ceilnav_reg_pkg::CeilnavAddrWidth; the register block ignores the
//   others), driven by the board's bus bridge (SPI or a parallel MCU bus);
// * the interrupt.
// The board has no DMA for the run stream: m_axis_runs is not on pins and its
// tready is low, so runs are read through the run window registers
// (CONTROL.RUN_SINK = 1; docs/registers.md). Parameters as ceilnav_top
// (the device configuration).
module ceilnav_board #(
  parameter bit          HasClassMoments = 1'b1,
  parameter bit          HasCorridor     = 1'b1,
  parameter int unsigned HoughLanes      = 4,
  parameter int unsigned HoughThetaStep  = 4,
  parameter int unsigned HoughRhoBits    = 6,
  parameter int unsigned HoughAccBits    = 16,
  localparam int unsigned AddrBits = ceilnav_reg_pkg::CeilnavAddrWidth
) (
  input  logic                clk_i,
  input  logic                rst_ni,

  // Camera: AXI4-Stream video (tuser = SOF, tlast = EOL)
  input  ceilnav_pkg::pixel_t s_axis_video_tdata_i,
  input  logic                s_axis_video_tvalid_i,
  output logic                s_axis_video_tready_o,
  input  logic                s_axis_video_tuser_i,
  input  logic                s_axis_video_tlast_i,

  // Host: AXI4-Lite, register-map address bits
  input  logic [AddrBits-1:0] s_axil_awaddr_i,
  input  logic                s_axil_awvalid_i,
  output logic                s_axil_awready_o,
  input  ceilnav_pkg::word_t  s_axil_wdata_i,
  input  logic [ceilnav_pkg::AxilStrbBits-1:0] s_axil_wstrb_i,
  input  logic                s_axil_wvalid_i,
  output logic                s_axil_wready_o,
  output logic [ceilnav_pkg::AxiRespBits-1:0] s_axil_bresp_o,
  output logic                s_axil_bvalid_o,
  input  logic                s_axil_bready_i,
  input  logic [AddrBits-1:0] s_axil_araddr_i,
  input  logic                s_axil_arvalid_i,
  output logic                s_axil_arready_o,
  output ceilnav_pkg::word_t  s_axil_rdata_o,
  output logic [ceilnav_pkg::AxiRespBits-1:0] s_axil_rresp_o,
  output logic                s_axil_rvalid_o,
  input  logic                s_axil_rready_i,

  output logic                irq_o
);

  logic                                unused_runs_tvalid, unused_runs_tlast;
  logic [ceilnav_pkg::RunBeatBits-1:0] unused_runs_tdata;
  logic         unused_runs;
  assign unused_runs = ^{unused_runs_tvalid, unused_runs_tlast, unused_runs_tdata};

  ceilnav_top #(
    .HasClassMoments(HasClassMoments),
    .HasCorridor    (HasCorridor),
    .HoughLanes     (HoughLanes),
    .HoughThetaStep (HoughThetaStep),
    .HoughRhoBits   (HoughRhoBits),
    .HoughAccBits   (HoughAccBits)
  ) u_top (
    .clk_i,
    .rst_ni,
    .s_axis_video_tdata_i,
    .s_axis_video_tvalid_i,
    .s_axis_video_tready_o,
    .s_axis_video_tuser_i,
    .s_axis_video_tlast_i,
    .s_axil_awaddr_i     (ceilnav_pkg::AxilAddrBits'(s_axil_awaddr_i)),
    .s_axil_awvalid_i,
    .s_axil_awready_o,
    .s_axil_wdata_i,
    .s_axil_wstrb_i,
    .s_axil_wvalid_i,
    .s_axil_wready_o,
    .s_axil_bresp_o,
    .s_axil_bvalid_o,
    .s_axil_bready_i,
    .s_axil_araddr_i     (ceilnav_pkg::AxilAddrBits'(s_axil_araddr_i)),
    .s_axil_arvalid_i,
    .s_axil_arready_o,
    .s_axil_rdata_o,
    .s_axil_rresp_o,
    .s_axil_rvalid_o,
    .s_axil_rready_i,
    .m_axis_runs_tvalid_o(unused_runs_tvalid),
    .m_axis_runs_tready_i(1'b0),
    .m_axis_runs_tlast_o (unused_runs_tlast),
    .m_axis_runs_tdata_o (unused_runs_tdata),
    .irq_o
  );

endmodule
