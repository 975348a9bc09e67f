// ceilnav_top: the device. pipeline + AXI4-Lite register file (addresses and
// fields from the generated ceilnav_regs.svh, source rtl_model/regmap.json),
// interrupt, cycle counters, video gate and the run FIFO register window.
// Cycle-exact twin of stream/ceilnav_top.cpp (stream::CeilnavTop); timing in
// docs/blocks/ceilnav_top.md, registers in docs/registers.md.
//
// The configuration (docs/registers.md "Configurations", from regmap.json) is
// a parameter per optional block: HasClassMoments = 0 is the `tape` device,
// without class_moments; its registers (CLASS_WIN_*, CLASS_MOM_*) then answer
// SLVERR like unmapped addresses.
module ceilnav_top #(
  parameter bit HasClassMoments = 1'b1
) (
  input  logic         clk_i,
  input  logic         rst_ni,

  // AXI4-Stream video (tuser = SOF, tlast = EOL); never back-pressured
  input  logic [7:0]   s_axis_video_tdata_i,
  input  logic         s_axis_video_tvalid_i,
  output logic         s_axis_video_tready_o,
  input  logic         s_axis_video_tuser_i,
  input  logic         s_axis_video_tlast_i,

  // AXI4-Lite slave
  input  logic [31:0]  s_axil_awaddr_i,
  input  logic         s_axil_awvalid_i,
  output logic         s_axil_awready_o,
  input  logic [31:0]  s_axil_wdata_i,
  input  logic [3:0]   s_axil_wstrb_i,
  input  logic         s_axil_wvalid_i,
  output logic         s_axil_wready_o,
  output logic [1:0]   s_axil_bresp_o,
  output logic         s_axil_bvalid_o,
  input  logic         s_axil_bready_i,
  input  logic [31:0]  s_axil_araddr_i,
  input  logic         s_axil_arvalid_i,
  output logic         s_axil_arready_o,
  output logic [31:0]  s_axil_rdata_o,
  output logic [1:0]   s_axil_rresp_o,
  output logic         s_axil_rvalid_o,
  input  logic         s_axil_rready_i,

  // AXI4-Stream runs (pack_run_beat layout, see run_scanner.sv)
  output logic         m_axis_runs_tvalid_o,
  input  logic         m_axis_runs_tready_i,
  output logic         m_axis_runs_tlast_o,
  output logic [111:0] m_axis_runs_tdata_o,

  output logic         irq_o
);

  `include "ceilnav_regs.svh"

  localparam int unsigned AddrBits = CeilnavAddrWidth;
  localparam int unsigned FifoCountBits = $clog2(RunFifoDepth) + 1;
  localparam logic [1:0] RespOkay = 2'b00;
  localparam logic [1:0] RespSlvErr = 2'b10;
  localparam int unsigned IntrBits = 3;

  // Field value v (low `width` bits) at bit `lsb` of a register word.
  function automatic logic [31:0] put(logic [31:0] v, int unsigned lsb, int unsigned width);
    logic [31:0] mask;
    mask = (width >= 32) ? 32'hFFFF_FFFF : ((32'd1 << width) - 32'd1);
    put = (v & mask) << lsb;
  endfunction

  // Word index of a byte offset.
  function automatic logic [AddrBits-3:0] widx(logic [AddrBits-1:0] offset);
    widx = (AddrBits-2)'(offset >> 2);
  endfunction

  // Address of element i of a register array.
  function automatic logic [AddrBits-1:0] elem(logic [AddrBits-1:0] base, int unsigned i,
                                               int unsigned stride);
    elem = AddrBits'(32'(base) + i * stride);
  endfunction

  // ---------------------------------------------------------------------------
  // Registers
  logic                 enable_q, run_sink_q;
  logic [IntrBits-1:0]  intr_state_q, intr_enable_q;
  logic [3:0]           err_cause_q;
  logic [11:0]          width_q, height_q, min_run_q, max_runs_q;
  logic [7:0]           background_q;
  logic                 hist_src_q;
  logic [11:0]          win_x0_q, win_x1_q, win_y0_q, win_y1_q;  // CLASS_WIN_X / _Y
  logic [7:0]           lut_index_q, hist_index_q;
  logic                 lut_wr_en_q;  // LUT write port, one edge after the bus write
  logic [7:0]           lut_wr_index_q;
  logic [10:0]          lut_wr_data_q;
  logic                 lut_pending_q;  // copy of thresh_lut's pending flag (STATUS)
  logic                 gate_open_q, in_frame_q;
  logic                 soft_rst_q;     // datapath held in reset
  logic [5:0]           err_lsb_prev_q;  // bit 0 of each frame_check counter, one edge old
  logic [31:0]          trailers_lost_prev_q;
  logic [31:0]          cycle_q, frame_count_q, eof_edge_q, eof_to_irq_q;

  logic                 awready_q, bvalid_q, arready_q, rvalid_q;
  logic [1:0]           bresp_q, rresp_q, rd_resp_q;
  logic [1:0]           rd_stage_q;  // 0 idle, 1 sample on this edge, 2 respond, 3 rvalid
  logic [AddrBits-1:0]  rd_addr_q;
  logic [31:0]          rd_data_q, rdata_q;
  logic                 rd_hist_q;  // the response is the histogram port's data
  localparam int unsigned RdWords = 1 << (AddrBits - 2);
  logic [RdWords-1:0]   rd_sel_q;   // one-hot word of rd_addr_q (none if misaligned)

  // ---------------------------------------------------------------------------
  // Datapath
  logic                     dp_rst_n;
  logic                     pass, video_sof;
  logic                     pipe_tvalid, pipe_tlast, runs_tready;
  logic [111:0]             pipe_tdata;
  logic                     hist_rd_en;
  logic [22:0]              hist_rd_data;
  logic                     frame_done, res_valid;
  logic [31:0]              res_frame_index, res_cycles, res_emitted, res_row_limit;
  logic [31:0]              res_overflow, res_high_water;
  logic [6*32-1:0]          res_errors, errors;
  logic [6*64-1:0]          res_grey, res_mask;
  logic [18*64-1:0]         res_class;
  logic [31:0]              frames_overrun, trailers_lost;
  logic [FifoCountBits-1:0] fifo_occupancy;

  // The soft reset comes from a flop: glitch-free, released on a clock edge.
  assign dp_rst_n  = rst_ni & ~soft_rst_q;
  assign video_sof = s_axis_video_tvalid_i & s_axis_video_tuser_i;
  assign pass      = s_axis_video_tvalid_i & (s_axis_video_tuser_i ? enable_q : gate_open_q);

  pipeline #(
    .RunFifoDepth   (RunFifoDepth),
    .HasClassMoments(HasClassMoments)
  ) u_pipeline (
    .clk_i,
    .rst_ni                      (dp_rst_n),
    .s_axis_video_tdata_i        (pass ? s_axis_video_tdata_i : 8'd0),
    .s_axis_video_tvalid_i       (pass),
    .s_axis_video_tuser_i        (pass & s_axis_video_tuser_i),
    .s_axis_video_tlast_i        (pass & s_axis_video_tlast_i),
    .cfg_width_i                 (width_q),
    .cfg_height_i                (height_q),
    .cfg_background_level_i      (background_q),
    .cfg_min_run_length_i        (16'(min_run_q)),
    .cfg_max_runs_per_row_i      (16'(max_runs_q)),
    .cfg_hist_source_remap_i     (hist_src_q),
    .cfg_class_win_x0_i          (win_x0_q),
    .cfg_class_win_x1_i          (win_x1_q),
    .cfg_class_win_y0_i          (win_y0_q),
    .cfg_class_win_y1_i          (win_y1_q),
    .lut_wr_en_i                 (lut_wr_en_q),
    .lut_wr_index_i              (lut_wr_index_q),
    .lut_wr_data_i               (lut_wr_data_q),
    .m_axis_runs_tvalid_o        (pipe_tvalid),
    .m_axis_runs_tready_i        (runs_tready),
    .m_axis_runs_tlast_o         (pipe_tlast),
    .m_axis_runs_tdata_o         (pipe_tdata),
    .hist_rd_en_i                (hist_rd_en),
    .hist_rd_bin_i               (hist_index_q),
    .hist_rd_data_o              (hist_rd_data),
    .frame_done_o                (frame_done),
    .res_valid_o                 (res_valid),
    .res_frame_index_o           (res_frame_index),
    .res_cycles_in_frame_o       (res_cycles),
    .res_runs_emitted_o          (res_emitted),
    .res_runs_dropped_row_limit_o(res_row_limit),
    .res_runs_dropped_overflow_o (res_overflow),
    .res_fifo_high_water_o       (res_high_water),
    .res_errors_o                (res_errors),
    .res_mom_grey_o              (res_grey),
    .res_mom_mask_o              (res_mask),
    .res_class_mom_o             (res_class),
    .errors_o                    (errors),
    .frames_overrun_o            (frames_overrun),
    .run_trailers_lost_o         (trailers_lost),
    .run_fifo_occupancy_o        (fifo_occupancy)
  );

  // ---------------------------------------------------------------------------
  // Bus handshakes against the registered outputs (wready == awready).
  logic                aw_hs, b_hs, ar_hs, r_hs;
  logic [AddrBits-1:0] wr_addr;

  assign aw_hs   = awready_q & s_axil_awvalid_i & s_axil_wvalid_i;
  assign b_hs    = bvalid_q & s_axil_bready_i;
  assign ar_hs   = arready_q & s_axil_arvalid_i;
  assign r_hs    = rvalid_q & s_axil_rready_i;
  assign wr_addr = s_axil_awaddr_i[AddrBits-1:0];

  // ---------------------------------------------------------------------------
  // Read sample (edge after the AR handshake): the register before this edge.
  logic        rd_sample, run_pop, rd_ok;
  logic [31:0] rd_value;
  logic [1:0]  rd_resp;
  logic [31:0] head_w0, head_w1, head_w2, head_w3;

  assign rd_sample = rd_stage_q == 2'd1;
  assign head_w0 = pipe_tdata[31:0];    // {x_start, row}
  assign head_w1 = pipe_tdata[63:32];   // sum_w
  assign head_w2 = pipe_tdata[95:64];   // sum_xw
  assign head_w3 = {16'd0, pipe_tdata[111:96]};  // x_end

  // The read multiplexer: an AND-OR over a one-hot word select registered
  // with the AR handshake (rd_sel_q, none for a misaligned address), on iCE40
  // LUT4s about 2/3 of a binary mux tree over ~50 wide words. A word that is
  // no register selects nothing: 0 with SLVERR. Evaluated only on the sample
  // edge (the gate is free in hardware, rd_data_q loads only then, and keeps
  // the Verilated model from forming every word on every cycle).
  localparam int unsigned MomWords = CEILNAV_MOM_GREY_LO_COUNT;
  logic [MomWords-1:0] sel_grey_lo, sel_grey_hi, sel_mask_lo, sel_mask_hi;
  for (genvar i = 0; i < MomWords; i++) begin : g_mom_sel
    assign sel_grey_lo[i] =
        rd_sel_q[widx(elem(CEILNAV_MOM_GREY_LO_OFFSET, i, CEILNAV_MOM_GREY_LO_STRIDE))];
    assign sel_grey_hi[i] =
        rd_sel_q[widx(elem(CEILNAV_MOM_GREY_HI_OFFSET, i, CEILNAV_MOM_GREY_HI_STRIDE))];
    assign sel_mask_lo[i] =
        rd_sel_q[widx(elem(CEILNAV_MOM_MASK_LO_OFFSET, i, CEILNAV_MOM_MASK_LO_STRIDE))];
    assign sel_mask_hi[i] =
        rd_sel_q[widx(elem(CEILNAV_MOM_MASK_HI_OFFSET, i, CEILNAV_MOM_MASK_HI_STRIDE))];
  end

  localparam int unsigned ClassMomWords = CEILNAV_CLASS_MOM_LO_COUNT;
  logic [ClassMomWords-1:0] sel_class_lo, sel_class_hi;
  for (genvar i = 0; i < ClassMomWords; i++) begin : g_class_sel
    // Absent block (HasClassMoments = 0): no word selects, SLVERR.
    assign sel_class_lo[i] = HasClassMoments &
        rd_sel_q[widx(elem(CEILNAV_CLASS_MOM_LO_OFFSET, i, CEILNAV_CLASS_MOM_LO_STRIDE))];
    assign sel_class_hi[i] = HasClassMoments &
        rd_sel_q[widx(elem(CEILNAV_CLASS_MOM_HI_OFFSET, i, CEILNAV_CLASS_MOM_HI_STRIDE))];
  end

  function automatic logic [31:0] pick(logic sel, logic [31:0] v);
    pick = {32{sel}} & v;
  endfunction

  always_comb begin
    rd_value = 32'd0;
    rd_ok    = 1'b0;
    if (rd_sample) begin
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_ID_OFFSET)],
          CEILNAV_ID_RESVAL);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_ID_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_VERSION_OFFSET)],
          CEILNAV_VERSION_RESVAL);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_VERSION_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CONTROL_OFFSET)],
          put(32'(enable_q), CEILNAV_CONTROL_ENABLE_LSB, CEILNAV_CONTROL_ENABLE_WIDTH) |
          put(32'(run_sink_q), CEILNAV_CONTROL_RUN_SINK_LSB, CEILNAV_CONTROL_RUN_SINK_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CONTROL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_STATUS_OFFSET)],
          put(32'(in_frame_q), CEILNAV_STATUS_IN_FRAME_LSB, CEILNAV_STATUS_IN_FRAME_WIDTH) |
          put(32'(res_valid), CEILNAV_STATUS_RESULTS_VALID_LSB,
              CEILNAV_STATUS_RESULTS_VALID_WIDTH) |
          put(32'(pipe_tvalid), CEILNAV_STATUS_RUN_AVAIL_LSB, CEILNAV_STATUS_RUN_AVAIL_WIDTH) |
          put(32'(gate_open_q), CEILNAV_STATUS_GATE_OPEN_LSB, CEILNAV_STATUS_GATE_OPEN_WIDTH) |
          put(32'(lut_pending_q), CEILNAV_STATUS_LUT_PENDING_LSB,
              CEILNAV_STATUS_LUT_PENDING_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_STATUS_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_INTR_STATE_OFFSET)],
          32'(intr_state_q));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_INTR_STATE_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_ERROR_CAUSE_OFFSET)],
          32'(err_cause_q));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_ERROR_CAUSE_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_INTR_ENABLE_OFFSET)],
          32'(intr_enable_q));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_INTR_ENABLE_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_INTR_TEST_OFFSET)],
          32'd0);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_INTR_TEST_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_WIDTH_OFFSET)],
          put(32'(width_q), CEILNAV_WIDTH_VALUE_LSB, CEILNAV_WIDTH_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_WIDTH_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_HEIGHT_OFFSET)],
          put(32'(height_q), CEILNAV_HEIGHT_VALUE_LSB, CEILNAV_HEIGHT_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_HEIGHT_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_BACKGROUND_LEVEL_OFFSET)],
          put(32'(background_q), CEILNAV_BACKGROUND_LEVEL_VALUE_LSB,
              CEILNAV_BACKGROUND_LEVEL_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_BACKGROUND_LEVEL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_MIN_RUN_LENGTH_OFFSET)],
          put(32'(min_run_q), CEILNAV_MIN_RUN_LENGTH_VALUE_LSB,
              CEILNAV_MIN_RUN_LENGTH_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_MIN_RUN_LENGTH_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_MAX_RUNS_PER_ROW_OFFSET)],
          put(32'(max_runs_q), CEILNAV_MAX_RUNS_PER_ROW_VALUE_LSB,
              CEILNAV_MAX_RUNS_PER_ROW_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_MAX_RUNS_PER_ROW_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_HIST_SOURCE_OFFSET)],
          put(32'(hist_src_q), CEILNAV_HIST_SOURCE_REMAP_LSB, CEILNAV_HIST_SOURCE_REMAP_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_HIST_SOURCE_OFFSET)];
      rd_value = rd_value | pick(HasClassMoments & rd_sel_q[widx(CEILNAV_CLASS_WIN_X_OFFSET)],
          put(32'(win_x0_q), CEILNAV_CLASS_WIN_X_X0_LSB, CEILNAV_CLASS_WIN_X_X0_WIDTH) |
          put(32'(win_x1_q), CEILNAV_CLASS_WIN_X_X1_LSB, CEILNAV_CLASS_WIN_X_X1_WIDTH));
      rd_ok = rd_ok | (HasClassMoments & rd_sel_q[widx(CEILNAV_CLASS_WIN_X_OFFSET)]);
      rd_value = rd_value | pick(HasClassMoments & rd_sel_q[widx(CEILNAV_CLASS_WIN_Y_OFFSET)],
          put(32'(win_y0_q), CEILNAV_CLASS_WIN_Y_Y0_LSB, CEILNAV_CLASS_WIN_Y_Y0_WIDTH) |
          put(32'(win_y1_q), CEILNAV_CLASS_WIN_Y_Y1_LSB, CEILNAV_CLASS_WIN_Y_Y1_WIDTH));
      rd_ok = rd_ok | (HasClassMoments & rd_sel_q[widx(CEILNAV_CLASS_WIN_Y_OFFSET)]);
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_LUT_INDEX_OFFSET)],
          put(32'(lut_index_q), CEILNAV_LUT_INDEX_VALUE_LSB, CEILNAV_LUT_INDEX_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_LUT_INDEX_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_LUT_DATA_OFFSET)],
          32'd0);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_LUT_DATA_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_HIST_INDEX_OFFSET)],
          put(32'(hist_index_q), CEILNAV_HIST_INDEX_VALUE_LSB, CEILNAV_HIST_INDEX_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_HIST_INDEX_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_HIST_DATA_OFFSET)],
          32'd0);  // from the histogram port, one edge later
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_HIST_DATA_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_FIFO_LEVEL_OFFSET)],
          put(32'(fifo_occupancy) + 32'(pipe_tvalid), CEILNAV_RUN_FIFO_LEVEL_VALUE_LSB,
              CEILNAV_RUN_FIFO_LEVEL_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_FIFO_LEVEL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_FIFO_DEPTH_OFFSET)],
          put(32'(RunFifoDepth), CEILNAV_RUN_FIFO_DEPTH_VALUE_LSB,
              CEILNAV_RUN_FIFO_DEPTH_VALUE_WIDTH));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_FIFO_DEPTH_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_WORD0_OFFSET)],
          {32{pipe_tvalid}} & (put(32'd1, CEILNAV_RUN_WORD0_VALID_LSB,
                                   CEILNAV_RUN_WORD0_VALID_WIDTH) |
          put(32'(pipe_tlast), CEILNAV_RUN_WORD0_LAST_LSB, CEILNAV_RUN_WORD0_LAST_WIDTH) |
          put({16'd0, head_w0[15:0]}, CEILNAV_RUN_WORD0_ROW_LSB, CEILNAV_RUN_WORD0_ROW_WIDTH)));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_WORD0_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_WORD1_OFFSET)],
          {32{pipe_tvalid}} & (put({16'd0, head_w0[31:16]}, CEILNAV_RUN_WORD1_X_START_LSB,
                                   CEILNAV_RUN_WORD1_X_START_WIDTH) |
          put(head_w3, CEILNAV_RUN_WORD1_X_END_LSB, CEILNAV_RUN_WORD1_X_END_WIDTH)));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_WORD1_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_WORD2_OFFSET)],
          {32{pipe_tvalid}} & (put(head_w1, CEILNAV_RUN_WORD2_SUM_W_LSB,
                                   CEILNAV_RUN_WORD2_SUM_W_WIDTH)));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_WORD2_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_WORD3_OFFSET)],
          {32{pipe_tvalid}} & (put(head_w2, CEILNAV_RUN_WORD3_SUM_XW_LSB,
                                   CEILNAV_RUN_WORD3_SUM_XW_WIDTH)));
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_WORD3_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_FRAME_INDEX_OFFSET)],
          res_frame_index);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_FRAME_INDEX_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_FRAME_COUNT_OFFSET)],
          frame_count_q);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_FRAME_COUNT_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CYCLES_PER_FRAME_OFFSET)],
          res_cycles);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CYCLES_PER_FRAME_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_EOF_TO_IRQ_CYCLES_OFFSET)],
          eof_to_irq_q);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_EOF_TO_IRQ_CYCLES_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUNS_EMITTED_OFFSET)],
          res_emitted);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUNS_EMITTED_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUNS_DROPPED_ROW_LIMIT_OFFSET)],
          res_row_limit);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUNS_DROPPED_ROW_LIMIT_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUNS_DROPPED_OVERFLOW_OFFSET)],
          res_overflow);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUNS_DROPPED_OVERFLOW_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_FIFO_HIGH_WATER_OFFSET)],
          res_high_water);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_FIFO_HIGH_WATER_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_EARLY_EOL_OFFSET)],
          res_errors[0*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_EARLY_EOL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_LATE_EOL_OFFSET)],
          res_errors[1*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_LATE_EOL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_EARLY_SOF_OFFSET)],
          res_errors[2*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_EARLY_SOF_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_MISSING_SOF_OFFSET)],
          res_errors[3*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_MISSING_SOF_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_FRAMES_OK_OFFSET)],
          res_errors[4*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_FRAMES_OK_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RES_FRAMES_ABORTED_OFFSET)],
          res_errors[5*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RES_FRAMES_ABORTED_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_EARLY_EOL_OFFSET)],
          errors[0*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_EARLY_EOL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_LATE_EOL_OFFSET)],
          errors[1*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_LATE_EOL_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_EARLY_SOF_OFFSET)],
          errors[2*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_EARLY_SOF_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_MISSING_SOF_OFFSET)],
          errors[3*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_MISSING_SOF_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_FRAMES_OK_OFFSET)],
          errors[4*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_FRAMES_OK_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_CNT_FRAMES_ABORTED_OFFSET)],
          errors[5*32 +: 32]);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_CNT_FRAMES_ABORTED_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_RUN_TRAILERS_LOST_OFFSET)],
          trailers_lost);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_RUN_TRAILERS_LOST_OFFSET)];
      rd_value = rd_value | pick(rd_sel_q[widx(CEILNAV_FRAMES_OVERRUN_OFFSET)],
          frames_overrun);
      rd_ok = rd_ok | rd_sel_q[widx(CEILNAV_FRAMES_OVERRUN_OFFSET)];
      // The moment arrays: MOM_*[i] at OFFSET + i * STRIDE.
      for (int unsigned i = 0; i < MomWords; i++) begin
        rd_value = rd_value | pick(sel_grey_lo[i], res_grey[64*i +: 32]) |
                   pick(sel_grey_hi[i], res_grey[64*i+32 +: 32]) |
                   pick(sel_mask_lo[i], res_mask[64*i +: 32]) |
                   pick(sel_mask_hi[i], res_mask[64*i+32 +: 32]);
        rd_ok = rd_ok | sel_grey_lo[i] | sel_grey_hi[i] | sel_mask_lo[i] | sel_mask_hi[i];
      end
      // CLASS_MOM_*[i] (i = 6 (c - 1) + k) at OFFSET + i * STRIDE.
      for (int unsigned i = 0; i < ClassMomWords; i++) begin
        rd_value = rd_value | pick(sel_class_lo[i], res_class[64*i +: 32]) |
                   pick(sel_class_hi[i], res_class[64*i+32 +: 32]);
        rd_ok = rd_ok | sel_class_lo[i] | sel_class_hi[i];
      end
    end
  end

  assign rd_resp = rd_ok ? RespOkay : RespSlvErr;

  // Read side effects on the sample edge (only for an OKAY read).
  assign hist_rd_en  = rd_sample & (rd_addr_q == CEILNAV_HIST_DATA_OFFSET);
  assign run_pop     = rd_sample & (rd_addr_q == CEILNAV_RUN_WORD3_OFFSET) & run_sink_q;
  assign runs_tready = run_sink_q ? run_pop : m_axis_runs_tready_i;

  // ---------------------------------------------------------------------------
  // Write decode: the register file's part of a write handshake.
  logic                wr_err, wr_control, wr_lut_data, wr_hist_index;
  logic [IntrBits-1:0] intr_clear, intr_test;
  logic [3:0]          err_cause_clear;
  logic [31:0]         wdata;

  assign wdata = s_axil_wdata_i;

  always_comb begin
    wr_err        = 1'b0;
    wr_control    = 1'b0;
    wr_lut_data   = 1'b0;
    wr_hist_index = 1'b0;
    intr_clear    = '0;
    intr_test     = '0;
    err_cause_clear = '0;
    if (aw_hs) begin
      unique case (wr_addr)
        CEILNAV_CONTROL_OFFSET:          wr_control = 1'b1;
        CEILNAV_INTR_STATE_OFFSET:
          intr_clear = IntrBits'(wdata & CEILNAV_INTR_STATE_W1C_MASK);
        CEILNAV_INTR_TEST_OFFSET:
          intr_test = IntrBits'(wdata & CEILNAV_INTR_TEST_WO_MASK);
        CEILNAV_ERROR_CAUSE_OFFSET:
          err_cause_clear = 4'(wdata & CEILNAV_ERROR_CAUSE_W1C_MASK);
        CEILNAV_LUT_DATA_OFFSET:         wr_lut_data = 1'b1;
        CEILNAV_HIST_INDEX_OFFSET:       wr_hist_index = 1'b1;
        CEILNAV_INTR_ENABLE_OFFSET, CEILNAV_WIDTH_OFFSET, CEILNAV_HEIGHT_OFFSET,
        CEILNAV_BACKGROUND_LEVEL_OFFSET, CEILNAV_MIN_RUN_LENGTH_OFFSET,
        CEILNAV_MAX_RUNS_PER_ROW_OFFSET, CEILNAV_HIST_SOURCE_OFFSET,
        CEILNAV_LUT_INDEX_OFFSET: ;
        CEILNAV_CLASS_WIN_X_OFFSET, CEILNAV_CLASS_WIN_Y_OFFSET:
          wr_err = ~HasClassMoments;
        default: wr_err = 1'b1;  // no register, misaligned, or no writable field
      endcase
      if (s_axil_wstrb_i != 4'b1111) begin
        wr_err = 1'b1;
      end
      if (wr_err) begin
        wr_control    = 1'b0;
        wr_lut_data   = 1'b0;
        wr_hist_index = 1'b0;
        intr_clear    = '0;
        intr_test     = '0;
        err_cause_clear = '0;
      end
    end
  end

  logic wr_ok, soft_reset;
  assign wr_ok      = aw_hs & ~wr_err;
  assign soft_reset = wr_control & wdata[CEILNAV_CONTROL_SOFT_RESET_LSB];

  // ---------------------------------------------------------------------------
  // Events from the pipeline's registered outputs against one-edge-old copies.
  logic                events_frame_error, eof_seen, frame_closed, events_run_overflow;
  logic [IntrBits-1:0] events, intr_state_d, intr_enable_d;
  logic                enable_d, irq_before, irq_after;

  // The frame_check counters move by +1 or not at all (saturating) on an edge,
  // or go to 0 with the datapath reset, which also clears err_lsb_prev_q:
  // a counter changed on the last edge iff its bit 0 did.
  logic [5:0] err_lsb, err_changed;
  for (genvar i = 0; i < 6; i++) begin : g_err_lsb
    assign err_lsb[i] = errors[i*32];
  end
  assign err_changed = err_lsb ^ err_lsb_prev_q;

  assign events_frame_error = (|err_changed[3:0]) | err_changed[5];
  assign eof_seen = err_changed[4];
  // An early SOF aborts a frame and opens the next one on the same beat; an
  // EOL error always leaves frame_check discarding (the frame aborted, or its
  // SOF pixel rejected before it opened).
  assign frame_closed = eof_seen | (err_changed[5] & ~err_changed[2]) | (|err_changed[1:0]);
  assign events_run_overflow = (frame_done & (res_overflow != 32'd0)) |
                               (trailers_lost != trailers_lost_prev_q);
  assign events = IntrBits'(
      put(32'(frame_done), CEILNAV_INTR_STATE_FRAME_DONE_LSB, 1) |
      put(32'(events_run_overflow), CEILNAV_INTR_STATE_RUN_OVERFLOW_LSB, 1) |
      put(32'(events_frame_error), CEILNAV_INTR_STATE_FRAME_ERROR_LSB, 1));

  // A hardware set wins over a clear on the same edge.
  assign intr_state_d  = (intr_state_q & ~intr_clear) | events | intr_test;
  assign intr_enable_d = (wr_ok && wr_addr == CEILNAV_INTR_ENABLE_OFFSET) ?
                         IntrBits'(wdata & CEILNAV_INTR_ENABLE_RW_MASK) : intr_enable_q;
  assign enable_d      = wr_control ? wdata[CEILNAV_CONTROL_ENABLE_LSB] : enable_q;
  // The C++ model compares irq before/after with the enable of after the edge.
  assign irq_before    = |(intr_state_q & intr_enable_d);
  assign irq_after     = |(intr_state_d & intr_enable_d);

  // ---------------------------------------------------------------------------
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      enable_q             <= 1'b0;
      run_sink_q           <= 1'b0;
      intr_state_q         <= '0;
      intr_enable_q        <= '0;
      err_cause_q          <= '0;
      width_q              <= 12'(CEILNAV_WIDTH_VALUE_RESVAL);
      height_q             <= 12'(CEILNAV_HEIGHT_VALUE_RESVAL);
      background_q         <= 8'(CEILNAV_BACKGROUND_LEVEL_VALUE_RESVAL);
      min_run_q            <= 12'(CEILNAV_MIN_RUN_LENGTH_VALUE_RESVAL);
      max_runs_q           <= 12'(CEILNAV_MAX_RUNS_PER_ROW_VALUE_RESVAL);
      hist_src_q           <= CEILNAV_HIST_SOURCE_REMAP_RESVAL;
      win_x0_q             <= CEILNAV_CLASS_WIN_X_X0_RESVAL;
      win_x1_q             <= CEILNAV_CLASS_WIN_X_X1_RESVAL;
      win_y0_q             <= CEILNAV_CLASS_WIN_Y_Y0_RESVAL;
      win_y1_q             <= CEILNAV_CLASS_WIN_Y_Y1_RESVAL;
      lut_index_q          <= '0;
      hist_index_q         <= '0;
      lut_wr_en_q          <= 1'b0;
      lut_wr_index_q       <= '0;
      lut_wr_data_q        <= '0;
      lut_pending_q        <= 1'b0;
      gate_open_q          <= 1'b0;
      in_frame_q           <= 1'b0;
      soft_rst_q           <= 1'b0;
      err_lsb_prev_q       <= '0;
      trailers_lost_prev_q <= '0;
      cycle_q              <= '0;
      frame_count_q        <= '0;
      eof_edge_q           <= '0;
      eof_to_irq_q         <= '0;
    end else begin
      // Register file
      enable_q      <= enable_d;
      intr_enable_q <= intr_enable_d;
      intr_state_q  <= intr_state_d;
      // ERROR_CAUSE: {MISSING_SOF, EARLY_SOF, LATE_EOL, EARLY_EOL} = err_changed[3:0].
      err_cause_q   <= (err_cause_q & ~err_cause_clear) | err_changed[3:0];
      if (wr_control) begin
        run_sink_q <= wdata[CEILNAV_CONTROL_RUN_SINK_LSB];
      end
      if (wr_ok) begin
        unique case (wr_addr)
          CEILNAV_WIDTH_OFFSET:  width_q <= wdata[CEILNAV_WIDTH_VALUE_LSB +: 12];
          CEILNAV_HEIGHT_OFFSET: height_q <= wdata[CEILNAV_HEIGHT_VALUE_LSB +: 12];
          CEILNAV_BACKGROUND_LEVEL_OFFSET:
            background_q <= wdata[CEILNAV_BACKGROUND_LEVEL_VALUE_LSB +: 8];
          CEILNAV_MIN_RUN_LENGTH_OFFSET:
            min_run_q <= wdata[CEILNAV_MIN_RUN_LENGTH_VALUE_LSB +: 12];
          CEILNAV_MAX_RUNS_PER_ROW_OFFSET:
            max_runs_q <= wdata[CEILNAV_MAX_RUNS_PER_ROW_VALUE_LSB +: 12];
          CEILNAV_HIST_SOURCE_OFFSET: hist_src_q <= wdata[CEILNAV_HIST_SOURCE_REMAP_LSB];
          CEILNAV_CLASS_WIN_X_OFFSET: begin
            win_x0_q <= wdata[CEILNAV_CLASS_WIN_X_X0_LSB +: 12];
            win_x1_q <= wdata[CEILNAV_CLASS_WIN_X_X1_LSB +: 12];
          end
          CEILNAV_CLASS_WIN_Y_OFFSET: begin
            win_y0_q <= wdata[CEILNAV_CLASS_WIN_Y_Y0_LSB +: 12];
            win_y1_q <= wdata[CEILNAV_CLASS_WIN_Y_Y1_LSB +: 12];
          end
          default: ;
        endcase
      end
      if (wr_ok && wr_addr == CEILNAV_LUT_INDEX_OFFSET) begin
        lut_index_q <= wdata[CEILNAV_LUT_INDEX_VALUE_LSB +: 8];
      end else if (wr_lut_data) begin
        lut_index_q <= lut_index_q + 8'd1;
      end
      if (wr_hist_index) begin
        hist_index_q <= wdata[CEILNAV_HIST_INDEX_VALUE_LSB +: 8];
      end else if (hist_rd_en) begin
        hist_index_q <= hist_index_q + 8'd1;
      end
      lut_wr_en_q <= wr_lut_data;
      if (wr_lut_data) begin
        lut_wr_index_q <= lut_index_q;
        lut_wr_data_q  <= {wdata[CEILNAV_LUT_DATA_CLASS_LSB +: 2],
                           wdata[CEILNAV_LUT_DATA_MASK_LSB],
                           wdata[CEILNAV_LUT_DATA_REMAP_LSB +: 8]};
      end

      // Status and counters
      if (irq_after && !irq_before) begin
        eof_to_irq_q <= cycle_q - eof_edge_q;
      end
      if (frame_done) begin
        frame_count_q <= frame_count_q + 32'd1;
      end
      if (eof_seen) begin
        eof_edge_q <= cycle_q - 32'd1;
      end
      if (pass && s_axis_video_tuser_i && !soft_rst_q) begin
        in_frame_q <= 1'b1;
      end else if (frame_closed) begin
        in_frame_q <= 1'b0;
      end
      if (video_sof) begin
        gate_open_q <= enable_d;
      end
      // thresh_lut swaps on a passed SOF beat; a LUT_DATA write sets the flag after it.
      if (wr_lut_data) begin
        lut_pending_q <= 1'b1;
      end else if (pass && s_axis_video_tuser_i && !soft_rst_q) begin
        lut_pending_q <= 1'b0;
      end
      err_lsb_prev_q       <= err_lsb;
      trailers_lost_prev_q <= trailers_lost;
      cycle_q              <= cycle_q + 32'd1;
      soft_rst_q           <= soft_reset;

      // A soft reset clears what the datapath reset clears on the top level.
      if (soft_reset) begin
        lut_pending_q        <= 1'b0;
        in_frame_q           <= 1'b0;
        err_lsb_prev_q       <= '0;
        trailers_lost_prev_q <= '0;
        frame_count_q        <= '0;
        eof_edge_q           <= '0;
        eof_to_irq_q         <= '0;
      end
    end
  end

  // ---------------------------------------------------------------------------
  // AXI4-Lite channels
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      awready_q  <= 1'b0;
      bvalid_q   <= 1'b0;
      bresp_q    <= RespOkay;
      arready_q  <= 1'b1;
      rvalid_q   <= 1'b0;
      rdata_q    <= '0;
      rresp_q    <= RespOkay;
      rd_stage_q <= 2'd0;
      rd_addr_q  <= '0;
      rd_sel_q   <= '0;
      rd_data_q  <= '0;
      rd_resp_q  <= RespOkay;
      rd_hist_q  <= 1'b0;
    end else begin
      // Write: AW and W are taken together, one write at a time.
      if (aw_hs) begin
        awready_q <= 1'b0;
        bvalid_q  <= 1'b1;
        bresp_q   <= wr_err ? RespSlvErr : RespOkay;
      end else if (!awready_q && !bvalid_q && s_axil_awvalid_i && s_axil_wvalid_i) begin
        awready_q <= 1'b1;
      end
      if (b_hs) begin
        bvalid_q <= 1'b0;
        bresp_q  <= RespOkay;
      end

      // Read: one in flight, sample on the edge after AR, respond on the next.
      if (rd_sample) begin
        rd_data_q  <= rd_value;
        rd_resp_q  <= rd_resp;
        rd_hist_q  <= hist_rd_en;
        rd_stage_q <= 2'd2;
      end else if (rd_stage_q == 2'd2) begin
        rvalid_q   <= 1'b1;
        rdata_q    <= rd_hist_q ? 32'(hist_rd_data) : rd_data_q;
        rresp_q    <= rd_resp_q;
        rd_stage_q <= 2'd3;
      end
      if (r_hs) begin
        rvalid_q   <= 1'b0;
        rdata_q    <= '0;
        rresp_q    <= RespOkay;
        arready_q  <= 1'b1;
        rd_stage_q <= 2'd0;
      end
      if (ar_hs) begin
        arready_q  <= 1'b0;
        rd_addr_q  <= s_axil_araddr_i[AddrBits-1:0];
        rd_sel_q   <= (s_axil_araddr_i[1:0] == 2'b00) ?
                      (RdWords'(1) << s_axil_araddr_i[AddrBits-1:2]) : '0;
        rd_stage_q <= 2'd1;
      end
    end
  end

  assign s_axis_video_tready_o = 1'b1;
  assign s_axil_awready_o      = awready_q;
  assign s_axil_wready_o       = awready_q;
  assign s_axil_bvalid_o       = bvalid_q;
  assign s_axil_bresp_o        = bresp_q;
  assign s_axil_arready_o      = arready_q;
  assign s_axil_rvalid_o       = rvalid_q;
  assign s_axil_rdata_o        = rdata_q;
  assign s_axil_rresp_o        = rresp_q;
  assign m_axis_runs_tvalid_o  = ~run_sink_q & pipe_tvalid;
  assign m_axis_runs_tlast_o   = ~run_sink_q & pipe_tlast;
  assign m_axis_runs_tdata_o   = run_sink_q ? 112'd0 : pipe_tdata;
  assign irq_o                 = |(intr_state_q & intr_enable_q);

  logic unused;
  assign unused = ^{s_axil_awaddr_i[31:AddrBits], s_axil_araddr_i[31:AddrBits], wdata};

endmodule
