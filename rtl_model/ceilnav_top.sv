// ceilnav_top: the device. pipeline + the generated register block
// (ceilnav_regblock: AXI4-Lite decode, storage, read multiplexer, interrupt;
// source rtl_model/regmap.json), the hardware side of the registers (events,
// cycle counters, video gate, LUT write port, run FIFO register window).
// Cycle-exact twin of stream/ceilnav_top.cpp (stream::CeilnavTop); timing in
// docs/blocks/ceilnav_top.md, registers in docs/registers.md.
//
// The configuration (docs/registers.md "Configurations", from regmap.json) is
// a parameter per optional block: HasClassMoments = 0 leaves out
// class_moments (its registers CLASS_WIN_*, CLASS_MOM_* then answer SLVERR
// like unmapped addresses), HasCorridor = 0 the edge and hough blocks
// (EDGE_*, HOUGH_*): `tape` has neither, `corridor` only the corridor blocks,
// `full` both; HasOrientation = 0 leaves out the orientation block (ORI_*):
// only `homing` has it. Hough*: the hough block's compile-time shape
// (HOUGH_SHAPE); OriBins: the orientation block's bins (ORI_STATUS.NUM_BINS).
module ceilnav_top #(
  parameter bit          HasClassMoments = 1'b1,
  parameter bit          HasCorridor     = 1'b1,
  parameter int unsigned HoughLanes      = 4,
  parameter int unsigned HoughThetaStep  = 4,
  parameter int unsigned HoughRhoBits    = 6,
  parameter int unsigned HoughAccBits    = 16,
  parameter bit          HasOrientation  = 1'b0,
  parameter int unsigned OriBins         = 90
) (
  input  logic                                 clk_i,
  input  logic                                 rst_ni,

  // AXI4-Stream video (tuser = SOF, tlast = EOL); never back-pressured
  input  ceilnav_pkg::pixel_t                  s_axis_video_tdata_i,
  input  logic                                 s_axis_video_tvalid_i,
  output logic                                 s_axis_video_tready_o,
  input  logic                                 s_axis_video_tuser_i,
  input  logic                                 s_axis_video_tlast_i,

  // AXI4-Lite slave
  input  logic [ceilnav_pkg::AxilAddrBits-1:0] s_axil_awaddr_i,
  input  logic                                 s_axil_awvalid_i,
  output logic                                 s_axil_awready_o,
  input  logic [ceilnav_pkg::AxilDataBits-1:0] s_axil_wdata_i,
  input  logic [ceilnav_pkg::AxilStrbBits-1:0] s_axil_wstrb_i,
  input  logic                                 s_axil_wvalid_i,
  output logic                                 s_axil_wready_o,
  output logic [ceilnav_pkg::AxiRespBits-1:0]  s_axil_bresp_o,
  output logic                                 s_axil_bvalid_o,
  input  logic                                 s_axil_bready_i,
  input  logic [ceilnav_pkg::AxilAddrBits-1:0] s_axil_araddr_i,
  input  logic                                 s_axil_arvalid_i,
  output logic                                 s_axil_arready_o,
  output logic [ceilnav_pkg::AxilDataBits-1:0] s_axil_rdata_o,
  output logic [ceilnav_pkg::AxiRespBits-1:0]  s_axil_rresp_o,
  output logic                                 s_axil_rvalid_o,
  input  logic                                 s_axil_rready_i,

  // AXI4-Stream runs (ceilnav_pkg::run_beat_t, pack_run_beat layout)
  output logic                                 m_axis_runs_tvalid_o,
  input  logic                                 m_axis_runs_tready_i,
  output logic                                 m_axis_runs_tlast_o,
  output logic [ceilnav_pkg::RunBeatBits-1:0]  m_axis_runs_tdata_o,

  output logic                                 irq_o
);

  localparam int unsigned WordBits = ceilnav_pkg::WordBits;
  localparam int unsigned ErrCount = ceilnav_pkg::ErrCount;
  localparam int unsigned ClassWords = ceilnav_pkg::MaxClasses * ceilnav_pkg::MomentCount;
  localparam int unsigned MomBits = ceilnav_pkg::MomentBits;

  localparam int unsigned RunFifoDepth = ceilnav_reg_pkg::RunFifoDepth;
  localparam int unsigned FifoCountBits = $clog2(RunFifoDepth) + 1;
  localparam int unsigned EdgeFifoDepth = ceilnav_reg_pkg::EdgeFifoDepth;
  localparam int unsigned EdgeCountBits = $clog2(EdgeFifoDepth) + 1;
  localparam int unsigned HoughIndexBits = $clog2(180 / HoughThetaStep) + HoughRhoBits;

  // ---------------------------------------------------------------------------
  // Register block (generated from rtl_model/regmap.json)
  ceilnav_reg_pkg::ceilnav_reg2hw_t reg2hw;
  ceilnav_reg_pkg::ceilnav_hw2reg_t hw2reg;
  logic irq_rise;

  ceilnav_regblock #(
    .HasClassMoments(HasClassMoments),
    .HasCorridor    (HasCorridor),
    .HasOrientation (HasOrientation)
  ) u_regblock (
    .clk_i,
    .rst_ni,
    .s_axil_awaddr_i,
    .s_axil_awvalid_i,
    .s_axil_awready_o,
    .s_axil_wdata_i,
    .s_axil_wstrb_i,
    .s_axil_wvalid_i,
    .s_axil_wready_o,
    .s_axil_bresp_o,
    .s_axil_bvalid_o,
    .s_axil_bready_i,
    .s_axil_araddr_i,
    .s_axil_arvalid_i,
    .s_axil_arready_o,
    .s_axil_rdata_o,
    .s_axil_rresp_o,
    .s_axil_rvalid_o,
    .s_axil_rready_i,
    .reg2hw_o  (reg2hw),
    .hw2reg_i  (hw2reg),
    .irq_o,
    .irq_rise_o(irq_rise)
  );

  // ---------------------------------------------------------------------------
  // Hardware side of the registers
  logic                 lut_wr_en_q;  // LUT write port, one edge after the bus write
  ceilnav_pkg::pixel_t  lut_wr_index_q;
  ceilnav_pkg::lut_entry_t lut_wr_data_q;
  logic                 lut_pending_q;  // copy of thresh_lut's pending flag (STATUS)
  logic                 gate_open_q, in_frame_q;
  logic                 soft_rst_q;     // datapath held in reset
  logic [ErrCount-1:0]  err_lsb_prev_q;  // bit 0 of each frame_check counter, one edge old
  ceilnav_pkg::word_t   trailers_lost_prev_q;
  ceilnav_pkg::word_t   frame_count_q, eof_to_irq_q;
  ceilnav_pkg::word_t   eof_age_q;  // EOF_TO_IRQ_CYCLES if irq rose on the next edge

  // ---------------------------------------------------------------------------
  // Datapath
  logic                     dp_rst_n;
  logic                     pass, video_sof;
  logic                     pipe_tvalid, pipe_tlast, runs_tready;
  ceilnav_pkg::run_beat_t   pipe_tdata;
  logic [ceilnav_pkg::BinBits-1:0] hist_rd_data;
  logic                     frame_done, res_valid;
  ceilnav_pkg::frame_errors_t errors;
  logic                     res_wr_valid, res_bank, res_overflow_nonzero;
  logic [ceilnav_pkg::StoreAddrBits-1:0] res_wr_addr;
  ceilnav_pkg::word_t       res_wr_data;
  logic                     mom_wr_valid;
  logic [ClassWords*MomBits-1:0] res_class;
  ceilnav_pkg::word_t       frames_overrun, trailers_lost;
  logic [FifoCountBits-1:0] fifo_occupancy;
  logic                     soft_reset, wr_lut_data, hist_rd_en, run_pop;
  logic [HoughAccBits-1:0]  hough_rd_data;
  logic                     hough_done, hough_res_valid, corridor_pending;
  logic [1:0]               hough_state;
  ceilnav_pkg::word_t       hough_edges, hough_bad_edges, hough_votes, hough_dropped;
  ceilnav_pkg::word_t       hough_saturated, hough_trailer_edges, hough_trailer_flags;
  ceilnav_pkg::word_t       edge_count, edge_dropped, edge_trailers_lost, hough_stalls;
  logic [EdgeCountBits:0]   edge_fifo_level;
  ceilnav_pkg::word_t       hough_frame_count_q;
  ceilnav_pkg::word_t       ori_rd_data, ori_votes, ori_frames, ori_skipped;
  logic                     ori_done, ori_res_valid, ori_clearing;

  // Synchronous datapath reset: low on the edge that accepts the soft-reset
  // strobe and on the next one (soft_rst_q), so the datapath leaves the same
  // two edges in reset as the former asynchronous rst_ni & ~soft_rst_q did.
  assign dp_rst_n   = rst_ni & ~soft_reset & ~soft_rst_q;
  assign video_sof = s_axis_video_tvalid_i & s_axis_video_tuser_i;
  // The gate passes whole frames: CONTROL.ENABLE as it is before the SOF beat's edge.
  assign pass      = s_axis_video_tvalid_i &
                     (s_axis_video_tuser_i ? reg2hw.control.enable : gate_open_q);

  pipeline #(
    .RunFifoDepth   (RunFifoDepth),
    .HasClassMoments(HasClassMoments),
    .HasCorridor    (HasCorridor),
    .EdgeFifoDepth  (EdgeFifoDepth),
    .HoughLanes     (HoughLanes),
    .HoughThetaStep (HoughThetaStep),
    .HoughRhoBits   (HoughRhoBits),
    .HoughAccBits   (HoughAccBits),
    .HasOrientation (HasOrientation),
    .OriBins        (OriBins)
  ) u_pipeline (
    .clk_i,
    .rst_ni                      (dp_rst_n),
    .s_axis_video_tdata_i        (pass ? s_axis_video_tdata_i : '0),
    .s_axis_video_tvalid_i       (pass),
    .s_axis_video_tuser_i        (pass & s_axis_video_tuser_i),
    .s_axis_video_tlast_i        (pass & s_axis_video_tlast_i),
    .cfg_width_i                 (reg2hw.width.value),
    .cfg_height_i                (reg2hw.height.value),
    .cfg_background_level_i      (reg2hw.background_level.value),
    .cfg_min_run_length_i        (ceilnav_pkg::RunFieldBits'(reg2hw.min_run_length.value)),
    .cfg_max_runs_per_row_i      (ceilnav_pkg::RunFieldBits'(reg2hw.max_runs_per_row.value)),
    .cfg_hist_source_remap_i     (reg2hw.hist_source.remap),
    .cfg_class_win_x0_i          (reg2hw.class_win_x.x0),
    .cfg_class_win_x1_i          (reg2hw.class_win_x.x1),
    .cfg_class_win_y0_i          (reg2hw.class_win_y.y0),
    .cfg_class_win_y1_i          (reg2hw.class_win_y.y1),
    .cfg_edge_enable_i           (reg2hw.edge_control.enable),
    .cfg_edge_mode_i             (reg2hw.edge_control.mode),
    .cfg_edge_threshold_i        (reg2hw.edge_control.threshold),
    .cfg_hough_enable_i          (reg2hw.hough_control.enable),
    .cfg_hough_unit_weight_i     (reg2hw.hough_control.unit_weight),
    .cfg_hough_weight_shift_i    (reg2hw.hough_control.weight_shift),
    .cfg_hough_rho_shift_i       (reg2hw.hough_control.rho_shift),
    .cfg_hough_theta_first_i     (reg2hw.hough_control.theta_first),
    .cfg_hough_theta_count_i     (reg2hw.hough_control.theta_count),
    .cfg_hough_width_i           (reg2hw.hough_geometry.width),
    .cfg_ori_enable_i            (reg2hw.ori_control.enable),
    .cfg_ori_threshold_i         (reg2hw.ori_control.threshold),
    .lut_wr_en_i                 (lut_wr_en_q),
    .lut_wr_index_i              (lut_wr_index_q),
    .lut_wr_data_i               (lut_wr_data_q),
    .m_axis_runs_tvalid_o        (pipe_tvalid),
    .m_axis_runs_tready_i        (runs_tready),
    .m_axis_runs_tlast_o         (pipe_tlast),
    .m_axis_runs_tdata_o         (pipe_tdata),
    .hist_rd_en_i                (hist_rd_en),
    .hist_rd_bin_i               (reg2hw.hist_index.value),
    .hist_rd_data_o              (hist_rd_data),
    .hough_rd_en_i               (reg2hw.hough_data.re),
    .hough_rd_index_i            (reg2hw.hough_index.value[HoughIndexBits-1:0]),
    .hough_rd_data_o             (hough_rd_data),
    .ori_rd_en_i                 (reg2hw.ori_data.re),
    .ori_rd_bin_i                (reg2hw.ori_index.value),
    .ori_rd_data_o               (ori_rd_data),
    .frame_done_o                (frame_done),
    .res_valid_o                 (res_valid),
    .res_wr_valid_o              (res_wr_valid),
    .res_wr_addr_o               (res_wr_addr),
    .res_wr_data_o               (res_wr_data),
    .res_bank_o                  (res_bank),
    .res_overflow_nonzero_o      (res_overflow_nonzero),
    .mom_wr_valid_o              (mom_wr_valid),
    .res_class_mom_o             (res_class),
    .errors_o                    (errors),
    .frames_overrun_o            (frames_overrun),
    .run_trailers_lost_o         (trailers_lost),
    .run_fifo_occupancy_o        (fifo_occupancy),
    .hough_done_o                (hough_done),
    .hough_results_valid_o       (hough_res_valid),
    .hough_state_o               (hough_state),
    .hough_edges_o               (hough_edges),
    .hough_bad_edges_o           (hough_bad_edges),
    .hough_votes_o               (hough_votes),
    .hough_dropped_o             (hough_dropped),
    .hough_saturated_o           (hough_saturated),
    .hough_trailer_edges_o       (hough_trailer_edges),
    .hough_trailer_flags_o       (hough_trailer_flags),
    .edge_count_o                (edge_count),
    .edge_dropped_o              (edge_dropped),
    .edge_fifo_level_o           (edge_fifo_level),
    .edge_trailers_lost_o        (edge_trailers_lost),
    .corridor_pending_o          (corridor_pending),
    .hough_stalls_o              (hough_stalls),
    .ori_done_o                  (ori_done),
    .ori_results_valid_o         (ori_res_valid),
    .ori_clearing_o              (ori_clearing),
    .ori_votes_o                 (ori_votes),
    .ori_frames_o                (ori_frames),
    .ori_skipped_o               (ori_skipped)
  );

  // ---------------------------------------------------------------------------
  // Register strobes.
  assign soft_reset  = reg2hw.control.we & reg2hw.control.soft_reset;
  assign wr_lut_data = reg2hw.lut_data.we;
  assign hist_rd_en  = reg2hw.hist_data.re;
  assign run_pop     = reg2hw.run_word3.re & reg2hw.control.run_sink;
  assign runs_tready = reg2hw.control.run_sink ? run_pop : m_axis_runs_tready_i;

  // ---------------------------------------------------------------------------
  // Events from the pipeline's registered outputs against one-edge-old copies.
  logic events_frame_error, eof_seen, frame_closed, events_run_overflow;

  // The frame_check counters move by +1 or not at all (saturating) on an edge,
  // or go to 0 with the datapath reset, which also clears err_lsb_prev_q:
  // a counter changed on the last edge iff its bit 0 did.
  // err_lsb, err_changed: {frames_aborted, frames_ok, missing_sof, early_sof, late_eol,
  // early_eol}, the order of ceilnav_pkg::frame_errors_t.
  logic [ErrCount-1:0] err_lsb, err_changed;
  assign err_lsb = {errors.frames_aborted[0], errors.frames_ok[0], errors.missing_sof[0],
                    errors.early_sof[0], errors.late_eol[0], errors.early_eol[0]};
  assign err_changed = err_lsb ^ err_lsb_prev_q;

  assign events_frame_error = (|err_changed[3:0]) | err_changed[5];
  assign eof_seen = err_changed[4];
  // An early SOF aborts a frame and opens the next one on the same beat; an
  // EOL error always leaves frame_check discarding (the frame aborted, or its
  // SOF pixel rejected before it opened).
  assign frame_closed = eof_seen | (err_changed[5] & ~err_changed[2]) | (|err_changed[1:0]);
  assign events_run_overflow = (frame_done & res_overflow_nonzero) |
                               (trailers_lost != trailers_lost_prev_q);

  // ---------------------------------------------------------------------------
  // Result store: the published set's moments and frame meta as register words
  // in one BRAM pair, written by the pipeline (docs/blocks/pipeline.md, "Result
  // store"): the moments in the 24 cycles after each publication (the register
  // block holds a read of MOM_* meanwhile: hw2reg.moments.ready), the meta into
  // the unpublished bank before the publication flips it. Before the first
  // publication (and after a soft reset) the set reads 0: the word read is
  // masked with RESULTS_VALID as it was on the read edge.
  localparam int unsigned StoreAddrBits = ceilnav_pkg::StoreAddrBits;
  localparam int unsigned StoreWords = 1 << StoreAddrBits;  // one iCE40 BRAM pair (256 x 32)
  localparam logic [StoreAddrBits-1:0] StoreMetaBase = StoreAddrBits'(32);
  logic [WordBits-1:0] res_store [StoreWords];
  ceilnav_pkg::word_t  store_rd_q;
  logic                store_rd_valid_q, store_re;
  logic [StoreAddrBits-1:0] store_rd_addr;

  assign store_re      = reg2hw.moments.re | reg2hw.meta.re;
  // Meta bank b at StoreMetaBase + 16 b.
  assign store_rd_addr = reg2hw.meta.re ? StoreMetaBase + StoreAddrBits'({res_bank,
                                                                          reg2hw.meta.index})
                                        : StoreAddrBits'(reg2hw.moments.index);

  // No write on an edge in which the pipeline, which drives the write port, is
  // in reset (rst_ni or a soft reset; docs/rtl_style.md, "Reset").
  logic store_we;
  assign store_we = dp_rst_n & res_wr_valid;

  always_ff @(posedge clk_i) begin
    if (store_we) begin
      res_store[res_wr_addr] <= res_wr_data;
    end
    if (store_re) begin
      store_rd_q <= res_store[store_rd_addr];
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      store_rd_valid_q <= 1'b0;
    end else if (store_re) begin
      store_rd_valid_q <= res_valid;
    end
  end

  // ---------------------------------------------------------------------------
  // hw2reg: what the registers read, and the interrupt / error-cause events.
  always_comb begin
    hw2reg = '0;
    hw2reg.status.in_frame        = in_frame_q;
    hw2reg.status.results_valid   = res_valid;
    hw2reg.status.run_avail       = pipe_tvalid;
    hw2reg.status.gate_open       = gate_open_q;
    hw2reg.status.lut_pending     = lut_pending_q;
    hw2reg.status.hough_pending   = corridor_pending;
    hw2reg.intr_state.frame_done   = frame_done;
    hw2reg.intr_state.run_overflow = events_run_overflow;
    hw2reg.intr_state.frame_error  = events_frame_error;
    hw2reg.intr_state.hough_done   = hough_done;
    hw2reg.error_cause.early_eol   = err_changed[0];
    hw2reg.error_cause.late_eol    = err_changed[1];
    hw2reg.error_cause.early_sof   = err_changed[2];
    hw2reg.error_cause.missing_sof = err_changed[3];
    hw2reg.hist_data.count        = hist_rd_data;
    hw2reg.run_fifo_level.value   = ceilnav_pkg::RunFieldBits'(fifo_occupancy) +
                                    ceilnav_pkg::RunFieldBits'(pipe_tvalid);
    hw2reg.run_fifo_depth.value   = ceilnav_pkg::RunFieldBits'(RunFifoDepth);
    hw2reg.features.class_moments = HasClassMoments;
    hw2reg.features.corridor      = HasCorridor;
    hw2reg.features.orientation   = HasOrientation;
    // The run window: the head entry of the run FIFO (pack_run_beat layout; the
    // run scanner drives tdata and tlast to 0 without tvalid).
    hw2reg.run_word0.valid        = pipe_tvalid;
    hw2reg.run_word0.last         = pipe_tlast;
    hw2reg.run_word0.row          = pipe_tdata.row;
    hw2reg.run_word1.x_start      = pipe_tdata.x_start;
    hw2reg.run_word1.x_end        = pipe_tdata.x_end;
    hw2reg.run_word2.sum_w        = pipe_tdata.sum_w[ceilnav_pkg::SumWBits-1:0];
    hw2reg.run_word3.sum_xw       = pipe_tdata.sum_xw[ceilnav_pkg::SumXwBits-1:0];
    hw2reg.frame_count.value      = frame_count_q;
    hw2reg.eof_to_irq_cycles.value = eof_to_irq_q;
    hw2reg.cnt_early_eol.value      = errors.early_eol;
    hw2reg.cnt_late_eol.value       = errors.late_eol;
    hw2reg.cnt_early_sof.value      = errors.early_sof;
    hw2reg.cnt_missing_sof.value    = errors.missing_sof;
    hw2reg.cnt_frames_ok.value      = errors.frames_ok;
    hw2reg.cnt_frames_aborted.value = errors.frames_aborted;
    hw2reg.run_trailers_lost.value  = trailers_lost;
    hw2reg.frames_overrun.value     = frames_overrun;
    // The corridor blocks (the pipeline drives 0 without them).
    hw2reg.edge_count.value          = edge_count;
    hw2reg.edge_dropped.value        = edge_dropped;
    hw2reg.edge_fifo_level.value     = 16'(edge_fifo_level);
    hw2reg.edge_trailers_lost.value  = edge_trailers_lost;
    hw2reg.hough_status.results_valid = hough_res_valid;
    hw2reg.hough_status.state        = hough_state;
    hw2reg.hough_data.count          = WordBits'(hough_rd_data);
    hw2reg.hough_edges.value         = hough_edges;
    hw2reg.hough_bad_edges.value     = hough_bad_edges;
    hw2reg.hough_votes.value         = hough_votes;
    hw2reg.hough_dropped.value       = hough_dropped;
    hw2reg.hough_saturated.value     = hough_saturated;
    hw2reg.hough_trailer_edges.value = hough_trailer_edges;
    hw2reg.hough_trailer_flags.value = hough_trailer_flags;
    hw2reg.hough_shape.lanes         = HasCorridor ? 8'(HoughLanes) : 8'd0;
    hw2reg.hough_shape.theta_step    = HasCorridor ? 8'(HoughThetaStep) : 8'd0;
    hw2reg.hough_shape.rho_bits      = HasCorridor ? 8'(HoughRhoBits) : 8'd0;
    hw2reg.hough_shape.acc_bits      = HasCorridor ? 8'(HoughAccBits) : 8'd0;
    hw2reg.hough_frame_count.value   = hough_frame_count_q;
    hw2reg.hough_stalls.value        = hough_stalls;
    // The orientation block (the pipeline drives 0 without it).
    hw2reg.ori_status.results_valid  = ori_res_valid;
    hw2reg.ori_status.clearing       = ori_clearing;
    hw2reg.ori_status.num_bins       = HasOrientation ? 9'(OriBins) : 9'd0;
    hw2reg.ori_data.count            = ori_rd_data;
    hw2reg.ori_frames.value          = ori_frames;
    hw2reg.ori_skipped.value         = ori_skipped;
    hw2reg.ori_votes.value           = ori_votes;
    // MOM_*: the result store (below); CLASS_MOM_*[i] (i = 6 (c - 1) + k): the
    // 64-bit moments in two words.
    hw2reg.moments.data  = store_rd_q & {WordBits{store_rd_valid_q}};
    hw2reg.moments.ready = ~mom_wr_valid;
    hw2reg.meta.data     = store_rd_q & {WordBits{store_rd_valid_q}};
    for (int unsigned i = 0; i < ClassWords; i++) begin
      hw2reg.class_mom_lo.value[i] = res_class[MomBits*i +: WordBits];
      hw2reg.class_mom_hi.value[i] = res_class[MomBits*i+WordBits +: WordBits];
    end
  end

  // ---------------------------------------------------------------------------
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      lut_wr_en_q          <= 1'b0;
      lut_wr_index_q       <= '0;
      lut_wr_data_q        <= '0;
      lut_pending_q        <= 1'b0;
      gate_open_q          <= 1'b0;
      in_frame_q           <= 1'b0;
      soft_rst_q           <= 1'b0;
      err_lsb_prev_q       <= '0;
      trailers_lost_prev_q <= '0;
      frame_count_q        <= '0;
      hough_frame_count_q  <= '0;
      eof_age_q            <= '0;
      eof_to_irq_q         <= '0;
    end else begin
      // LUT write port: the entry LUT_INDEX pointed at before the write.
      lut_wr_en_q <= wr_lut_data;
      if (wr_lut_data) begin
        lut_wr_index_q <= reg2hw.lut_index.value;
        lut_wr_data_q  <= {reg2hw.lut_data.class_, reg2hw.lut_data.mask,
                           reg2hw.lut_data.remap};
      end

      // Status and counters
      if (irq_rise) begin
        eof_to_irq_q <= eof_age_q;
      end
      if (frame_done) begin
        frame_count_q <= frame_count_q + WordBits'(1);
      end
      if (hough_done) begin
        hough_frame_count_q <= hough_frame_count_q + WordBits'(1);
      end
      // Edges from the one that accepted the last good EOF pixel (eof_seen is
      // one edge later), or from the last reset.
      eof_age_q <= eof_seen ? WordBits'(2) : eof_age_q + WordBits'(1);
      if (pass && s_axis_video_tuser_i && !soft_rst_q) begin
        in_frame_q <= 1'b1;
      end else if (frame_closed) begin
        in_frame_q <= 1'b0;
      end
      if (video_sof) begin
        gate_open_q <= reg2hw.control.enable;
      end
      // thresh_lut swaps on a passed SOF beat; a LUT_DATA write sets the flag after it.
      if (wr_lut_data) begin
        lut_pending_q <= 1'b1;
      end else if (pass && s_axis_video_tuser_i && !soft_rst_q) begin
        lut_pending_q <= 1'b0;
      end
      err_lsb_prev_q       <= err_lsb;
      trailers_lost_prev_q <= trailers_lost;
      soft_rst_q           <= soft_reset;

      // A soft reset clears what the datapath reset clears on the top level.
      if (soft_reset) begin
        lut_pending_q        <= 1'b0;
        in_frame_q           <= 1'b0;
        err_lsb_prev_q       <= '0;
        trailers_lost_prev_q <= '0;
        frame_count_q        <= '0;
        hough_frame_count_q  <= '0;
        eof_age_q            <= '0;
        eof_to_irq_q         <= '0;
      end
    end
  end

  assign s_axis_video_tready_o = 1'b1;
  assign m_axis_runs_tvalid_o  = ~reg2hw.control.run_sink & pipe_tvalid;
  assign m_axis_runs_tlast_o   = ~reg2hw.control.run_sink & pipe_tlast;
  assign m_axis_runs_tdata_o   = reg2hw.control.run_sink ? '0 : pipe_tdata;

  // The run words use the SumWBits / SumXwBits low bits of sum_w / sum_xw
  // (pack_run_beat); HOUGH_INDEX's bits above the read index are not used.
  logic unused;
  // (ORI_FRAMES counts the orientation block's publications: its done pulse
  // is not used.)
  assign unused = ^{ori_done, pipe_tdata.sum_xw[WordBits-1:ceilnav_pkg::SumXwBits],
                    pipe_tdata.sum_w[WordBits-1:ceilnav_pkg::SumWBits],
                    reg2hw.hough_index.value[19:HoughIndexBits]};

endmodule
