// pipeline: frame_check -> thresh_lut -> {histogram, moment_gen, class_moments,
// run_scanner, edge_detect -> hough, orientation},
// the configuration that travels with the SOF, and the double-buffered frame
// result registers. Cycle-exact twin of stream/pipeline.cpp (Pipeline::clock
// with the histogram read port); see docs/blocks/pipeline.md, section "RTL".
//
// Publication: if moment_gen takes the stage-3 EOF beat sampled on edge T
// (eof_accept_o), the frame meta is staged on edge T and the run stats on
// edge T+1, and the whole set is published on the edge on which moment_gen
// raises done_o (its done_next_o is high before it; edge
// T+MomentGen::kCombineCycles). The moments leave moment_gen as 24 register
// words in the 24 cycles after that edge (mom_wr_*), into the device's result
// store, which holds reads of them until the last word is written. class_moments takes the same EOF
// (its eof_keep_i is moment_gen's eof_accept_o), shows it on edge T+2 and
// keeps it until the next taken EOF (>= T+kCombineCycles): its outputs are
// copied into the published set on the publication edge. At most one staged set waits:
// moment_gen takes the next EOF no earlier than that edge (on it, the old set
// is published while the new meta is staged).
// The histogram is read through the histogram block's port; its result bank
// switches on edge T+1 (Pipeline::kHistSwitchCycles after the video EOF).
// The corridor blocks (HasCorridor): edge_detect samples thresh_lut's output
// (the LUT remap) like the stage-3 blocks, with EDGE_CONTROL travelling with
// the SOF; its m_axis_edges feeds hough's s_axis_edges. The hough publishes
// a frame when it votes the frame's trailer, on its own schedule (hough_done_o),
// and is read through its port like the histogram.
// The orientation block (HasOrientation) samples thresh_lut's output like
// edge_detect, with ORI_CONTROL travelling with the SOF the same way; it
// publishes a frame's histogram on its own schedule (Orientation::
// kDoneLatencyCycles after the EOF pixel) and is read through its port.
module pipeline #(
  parameter int unsigned RunFifoDepth = 1024,  // run FIFO entries, power of two, >= 8
  // 0: no class_moments and no published copy of its results; res_class_mom_o = 0
  // (C++: Pipeline(depth, /*has_class_moments=*/false)).
  parameter bit          HasClassMoments = 1'b1,
  // 0: no edge_detect and no hough; their outputs are 0
  // (C++: Pipeline(depth, has_class_moments, /*has_corridor=*/false)).
  parameter bit          HasCorridor = 1'b1,
  parameter int unsigned EdgeFifoDepth = 1024,  // edge FIFO entries, power of two, >= 8
  // hough's compile-time shape (stream::HoughShape)
  parameter int unsigned HoughLanes     = 4,
  parameter int unsigned HoughThetaStep = 4,
  parameter int unsigned HoughRhoBits   = 6,
  parameter int unsigned HoughAccBits   = 16,
  // 0: no orientation block; its outputs are 0
  // (C++: Pipeline(..., /*has_orientation=*/false)).
  parameter bit          HasOrientation = 1'b0,
  parameter int unsigned OriBins        = 90,  // orientation bins, 2 .. 256
  localparam int unsigned FifoCountBits = $clog2(RunFifoDepth) + 1,
  localparam int unsigned EdgeCountBits = $clog2(EdgeFifoDepth) + 1,
  localparam int unsigned HoughIndexBits = $clog2(180 / HoughThetaStep) + HoughRhoBits,
  // Published class moments: class c, MomentIndex k at [MomentBits*(6*(c-1)+k) +: MomentBits].
  localparam int unsigned ClassMomBits = ceilnav_pkg::MaxClasses * ceilnav_pkg::MomentCount *
                                         ceilnav_pkg::MomentBits
) (
  input  logic                     clk_i,
  input  logic                     rst_ni,       // synchronous, active low

  // Video (tready = 1)
  input  ceilnav_pkg::pixel_t      s_axis_video_tdata_i,
  input  logic                     s_axis_video_tvalid_i,
  input  logic                     s_axis_video_tuser_i,
  input  logic                     s_axis_video_tlast_i,

  // Shadow configuration (PipelineConfig), active from the next SOF beat
  input  ceilnav_pkg::geom_t       cfg_width_i,
  input  ceilnav_pkg::geom_t       cfg_height_i,
  input  ceilnav_pkg::pixel_t      cfg_background_level_i,
  input  ceilnav_pkg::run_field_t  cfg_min_run_length_i,
  input  ceilnav_pkg::run_field_t  cfg_max_runs_per_row_i,
  input  logic                     cfg_hist_source_remap_i,
  input  ceilnav_pkg::win_t        cfg_class_win_x0_i,  // class_moments window [x0, x1) x [y0, y1)
  input  ceilnav_pkg::win_t        cfg_class_win_x1_i,
  input  ceilnav_pkg::win_t        cfg_class_win_y0_i,
  input  ceilnav_pkg::win_t        cfg_class_win_y1_i,
  input  logic                     cfg_edge_enable_i,     // EDGE_CONTROL (shadow)
  input  logic [1:0]               cfg_edge_mode_i,
  input  logic [11:0]              cfg_edge_threshold_i,
  // HOUGH_CONTROL, HOUGH_GEOMETRY: hough samples them with a frame's first edge beat
  input  logic                     cfg_hough_enable_i,
  input  logic                     cfg_hough_unit_weight_i,
  input  logic [3:0]               cfg_hough_weight_shift_i,
  input  logic [2:0]               cfg_hough_rho_shift_i,
  input  logic [7:0]               cfg_hough_theta_first_i,
  input  logic [7:0]               cfg_hough_theta_count_i,
  input  logic [11:0]              cfg_hough_width_i,
  input  logic                     cfg_ori_enable_i,     // ORI_CONTROL (shadow)
  input  logic [11:0]              cfg_ori_threshold_i,
  // LUT write port (shadow bank)
  input  logic                     lut_wr_en_i,
  input  ceilnav_pkg::pixel_t      lut_wr_index_i,
  input  ceilnav_pkg::lut_entry_t  lut_wr_data_i,

  // Runs
  output logic                     m_axis_runs_tvalid_o,
  input  logic                     m_axis_runs_tready_i,
  output logic                     m_axis_runs_tlast_o,
  output ceilnav_pkg::run_beat_t   m_axis_runs_tdata_o,

  // Histogram read port (result bank, one cycle)
  input  logic                     hist_rd_en_i,
  input  ceilnav_pkg::pixel_t      hist_rd_bin_i,
  output logic [ceilnav_pkg::BinBits-1:0] hist_rd_data_o,

  // hough read port (published bank, one cycle): index = j << HoughRhoBits | rho
  input  logic                     hough_rd_en_i,
  input  logic [HoughIndexBits-1:0] hough_rd_index_i,
  output logic [HoughAccBits-1:0]  hough_rd_data_o,
  // orientation read port (published bank, one cycle; 0 after an edge without a read)
  input  logic                     ori_rd_en_i,
  input  ceilnav_pkg::pixel_t      ori_rd_bin_i,
  output ceilnav_pkg::word_t       ori_rd_data_o,
  // Published results (FrameResults); frame_done_o: one-cycle pulse, high in
  // the first cycle that shows a new set.
  output logic                     frame_done_o,
  output logic                     res_valid_o,
  // The published set lives in the device's result store (a 256 x 32 RAM),
  // written through this port: the moments at 0..23 (register word order,
  // MomentGen::kMomentWords) in the 24 cycles after each publication edge,
  // the frame meta (12 words, register order of RES_FRAME_INDEX ..
  // RES_FRAMES_ABORTED without the live counters) into bank 1 - res_bank_o
  // at ResMetaBase + 16 * bank while the frame's moments combine; the bank
  // becomes res_bank_o on the publication edge.
  output logic                     res_wr_valid_o,
  output logic [ceilnav_pkg::StoreAddrBits-1:0] res_wr_addr_o,
  output ceilnav_pkg::word_t       res_wr_data_o,
  output logic                     res_bank_o,
  output logic                     res_overflow_nonzero_o,  // published RUNS_DROPPED_OVERFLOW != 0
  output logic                     mom_wr_valid_o,  // moments being written: reads of them wait
  output logic [ClassMomBits-1:0]  res_class_mom_o,

  // Live status
  output ceilnav_pkg::frame_errors_t errors_o,  // frame_check's counters
  output ceilnav_pkg::word_t       frames_overrun_o,
  output ceilnav_pkg::word_t       run_trailers_lost_o,
  output logic [FifoCountBits-1:0] run_fifo_occupancy_o,

  // Corridor (0 without HasCorridor)
  output logic                     hough_done_o,  // one-cycle pulse: hough published a frame
  output logic                     hough_results_valid_o,
  output logic [1:0]               hough_state_o,
  output ceilnav_pkg::word_t       hough_edges_o,  // the published hough frame's counters
  output ceilnav_pkg::word_t       hough_bad_edges_o,
  output ceilnav_pkg::word_t       hough_votes_o,
  output ceilnav_pkg::word_t       hough_dropped_o,
  output ceilnav_pkg::word_t       hough_saturated_o,
  output ceilnav_pkg::word_t       hough_trailer_edges_o,
  output ceilnav_pkg::word_t       hough_trailer_flags_o,
  output ceilnav_pkg::word_t       edge_count_o,  // edge_detect's last completed frame
  output ceilnav_pkg::word_t       edge_dropped_o,
  output logic [EdgeCountBits:0]   edge_fifo_level_o,  // FIFO memory + output register
  output ceilnav_pkg::word_t       edge_trailers_lost_o,
  output logic                     corridor_pending_o,  // STATUS.HOUGH_PENDING
  output ceilnav_pkg::word_t       hough_stalls_o,  // edge beat offered, not taken (saturating)

  // Orientation (0 without HasOrientation)
  output logic                     ori_done_o,           // one-cycle pulse: a frame was published
  output logic                     ori_results_valid_o,
  output logic                     ori_clearing_o,
  output ceilnav_pkg::word_t       ori_votes_o,          // votes of the published frame
  output ceilnav_pkg::word_t       ori_frames_o,         // published since reset (saturating)
  output ceilnav_pkg::word_t       ori_skipped_o         // ended unpublished (saturating)
);

  localparam int unsigned WordBits = ceilnav_pkg::WordBits;

  // ---------------------------------------------------------------------------
  // Stage 1: frame_check; the stage configuration is latched with the SOF beat.
  logic                          video_sof;
  ceilnav_pkg::pix_beat_t        fc;  // PixelBeat
  ceilnav_pkg::frame_errors_t    fc_errors;
  logic                          unused_fc_tready;

  assign video_sof = s_axis_video_tvalid_i & s_axis_video_tuser_i;

  frame_check u_frame_check (
    .clk_i,
    .rst_ni,
    .s_axis_video_tdata_i,
    .s_axis_video_tvalid_i,
    .s_axis_video_tready_o(unused_fc_tready),
    .s_axis_video_tuser_i,
    .s_axis_video_tlast_i,
    .cfg_width_i,
    .cfg_height_i,
    .m_pix_valid_o   (fc.valid),
    .m_pix_grey_o    (fc.grey),
    .m_pix_x_o       (fc.x),
    .m_pix_y_o       (fc.y),
    .m_pix_sof_o     (fc.sof),
    .m_pix_eol_o     (fc.eol),
    .m_pix_eof_o     (fc.eof),
    .m_pix_abort_o   (fc.abort_frame),
    .early_eol_o     (fc_errors.early_eol),
    .late_eol_o      (fc_errors.late_eol),
    .early_sof_o     (fc_errors.early_sof),
    .missing_sof_o   (fc_errors.missing_sof),
    .frames_ok_o     (fc_errors.frames_ok),
    .frames_aborted_o(fc_errors.frames_aborted)
  );

  // StageConfig: the configuration that travels with the SOF.
  ceilnav_pkg::stage_cfg_t cfg_shadow, cfg_fc_q, cfg_lut_q;
  assign cfg_shadow = {cfg_class_win_y1_i, cfg_class_win_y0_i, cfg_class_win_x1_i,
                       cfg_class_win_x0_i, cfg_hist_source_remap_i, cfg_max_runs_per_row_i,
                       cfg_min_run_length_i, cfg_background_level_i};

  // ---------------------------------------------------------------------------
  // Stage 2: thresh_lut (bank swap on frame_check's SOF edge).
  ceilnav_pkg::lut_beat_t lut;  // LutBeat

  thresh_lut u_thresh_lut (
    .clk_i,
    .rst_ni,
    .s_pix_valid_i (fc.valid),
    .s_pix_grey_i  (fc.grey),
    .s_pix_x_i     (fc.x),
    .s_pix_y_i     (fc.y),
    .s_pix_sof_i   (fc.sof),
    .s_pix_eol_i   (fc.eol),
    .s_pix_eof_i   (fc.eof),
    .s_pix_abort_i (fc.abort_frame),
    .frame_start_i (video_sof),
    .lut_wr_en_i,
    .lut_wr_index_i,
    .lut_wr_data_i,
    .m_lut_valid_o (lut.pix.valid),
    .m_lut_grey_o  (lut.pix.grey),
    .m_lut_x_o     (lut.pix.x),
    .m_lut_y_o     (lut.pix.y),
    .m_lut_sof_o   (lut.pix.sof),
    .m_lut_eol_o   (lut.pix.eol),
    .m_lut_eof_o   (lut.pix.eof),
    .m_lut_abort_o (lut.pix.abort_frame),
    .m_lut_remap_o (lut.lut.remap),
    .m_lut_mask_o  (lut.lut.mask),
    .m_lut_class_o (lut.lut.cls)
  );

  // Frame meta of the EOF pixel leaving frame_check (FrameMeta):
  // {cycles_in_frame, errors, frame_index}.
  // frame_index = frames_ok - 1 of the same snapshot: formed at the output.
  ceilnav_pkg::word_t       frame_cycles_q;  // cycles since the SOF pixel left frame_check, saturating
  ceilnav_pkg::word_t       frame_cycles;    // SOF pixel to this pixel, inclusive
  ceilnav_pkg::frame_meta_t meta_fc, meta_lut_q;

  assign frame_cycles = (fc.valid && fc.sof) ? WordBits'(1) : frame_cycles_q;
  assign meta_fc = {frame_cycles, fc_errors};

  // ---------------------------------------------------------------------------
  // Stage 3: histogram, moment_gen, run_scanner (all sample thresh_lut's output).
  ceilnav_pkg::word_t mom_overrun;
  logic        mom_done, mom_done_next, mom_accept, unused_mom_busy;
  logic        mom_wr_valid;
  logic [ceilnav_pkg::MomIndexBits-1:0] mom_wr_index;
  ceilnav_pkg::word_t mom_wr_data;
  logic        unused_hist_done, hist_count_ok;

  // A frame the histogram cannot count (no cleared bank at its SOF) is dropped
  // at its EOF by moment_gen (eof_drop_i); the histogram keeps (publishes)
  // exactly the frames moment_gen takes.
  histogram u_histogram (
    .clk_i,
    .rst_ni,
    .s_lut_valid_i (lut.pix.valid),
    .s_lut_grey_i  (lut.pix.grey),
    .s_lut_x_i     (lut.pix.x),
    .s_lut_y_i     (lut.pix.y),
    .s_lut_sof_i   (lut.pix.sof),
    .s_lut_eol_i   (lut.pix.eol),
    .s_lut_eof_i   (lut.pix.eof),
    .s_lut_abort_i (lut.pix.abort_frame),
    .s_lut_remap_i (lut.lut.remap),
    .s_lut_mask_i  (lut.lut.mask),
    .source_remap_i(cfg_lut_q.hist_source_remap),
    .count_ok_o    (hist_count_ok),
    .keep_i        (mom_accept),
    .done_o        (unused_hist_done),
    .hist_rd_en_i,
    .hist_rd_bin_i,
    .hist_rd_data_o
  );

  moment_gen u_moment_gen (
    .clk_i,
    .rst_ni,
    .s_lut_valid_i  (lut.pix.valid),
    .s_lut_grey_i   (lut.pix.grey),
    .s_lut_x_i      (lut.pix.x),
    .s_lut_y_i      (lut.pix.y),
    .s_lut_sof_i    (lut.pix.sof),
    .s_lut_eol_i    (lut.pix.eol),
    .s_lut_eof_i    (lut.pix.eof),
    .s_lut_abort_i  (lut.pix.abort_frame),
    .s_lut_remap_i  (lut.lut.remap),
    .s_lut_mask_i   (lut.lut.mask),
    .eof_drop_i     (~hist_count_ok),
    .done_o         (mom_done),
    .done_next_o    (mom_done_next),
    .eof_accept_o   (mom_accept),
    .mom_wr_valid_o (mom_wr_valid),
    .mom_wr_index_o (mom_wr_index),
    .mom_wr_data_o  (mom_wr_data),
    .combine_busy_o (unused_mom_busy),
    .overrun_count_o(mom_overrun)
  );

  ceilnav_pkg::run_stats_t rs;  // the frame's RunStats, final after its EOF edge
  logic                    unused_rs_done;

  run_scanner #(
    .FifoDepth(RunFifoDepth)
  ) u_run_scanner (
    .clk_i,
    .rst_ni,
    .s_lut_valid_i           (lut.pix.valid),
    .s_lut_grey_i            (lut.pix.grey),
    .s_lut_x_i               (lut.pix.x),
    .s_lut_y_i               (lut.pix.y),
    .s_lut_sof_i             (lut.pix.sof),
    .s_lut_eol_i             (lut.pix.eol),
    .s_lut_eof_i             (lut.pix.eof),
    .s_lut_abort_i           (lut.pix.abort_frame),
    .s_lut_remap_i           (lut.lut.remap),
    .s_lut_mask_i            (lut.lut.mask),
    .cfg_background_level_i  (cfg_lut_q.background_level),
    .cfg_min_run_length_i    (cfg_lut_q.min_run_length),
    .cfg_max_runs_per_row_i  (cfg_lut_q.max_runs_per_row),
    .m_axis_runs_tvalid_o,
    .m_axis_runs_tready_i,
    .m_axis_runs_tlast_o,
    .m_axis_runs_tdata_o,
    .done_o                  (unused_rs_done),
    .runs_emitted_o          (rs.emitted),
    .runs_dropped_row_limit_o(rs.dropped_row_limit),
    .runs_dropped_overflow_o (rs.dropped_overflow),
    .fifo_high_water_o       (rs.high_water),
    .fifo_occupancy_o        (run_fifo_occupancy_o),
    .trailers_lost_o         (run_trailers_lost_o)
  );

  // ---------------------------------------------------------------------------
  // Staging and publication. An EOF that moment_gen drops (overrun_count
  // moves on its edge) is neither staged nor published. (C++ decides by
  // comparing overrun_count before and after the edge: the same, except once
  // the counter has saturated at 2^32 - 1.)
  // The staged set is a chain of 11 words in write order: FRAMES_OK (written
  // twice: as frames_ok - 1 for RES_FRAME_INDEX without a shift, then as
  // itself), CYCLES, the error counters, then the four run statistics
  // (narrow, last: the chain shifts towards slot 0 and a slot is only as wide
  // as what can reach it). It loads on the accept edge (meta) and the next
  // (run stats) and is written into the unpublished bank while the moments
  // combine, after the previous set's moment words (which have the write port
  // first): done by accept + 2 + 24 + 12 < accept + kCombineCycles.
  localparam int unsigned MetaWords = 12;  // writes
  localparam int unsigned MetaSlots = 11;
  localparam int unsigned AddrBits = ceilnav_pkg::StoreAddrBits;
  localparam int unsigned StepBits = 4;  // meta write step and port index, 0 .. MetaWords - 1
  localparam logic [AddrBits-1:0] ResMetaBase = AddrBits'(32);
  // Port index (RES_FRAME_INDEX, CYCLES_PER_FRAME, RUNS_EMITTED .. RUN_FIFO_HIGH_WATER,
  // RES_EARLY_EOL .. RES_FRAMES_ABORTED) written by step k, at [StepBits*k +: StepBits]
  // (entries StepBits = 4 bits wide).
  localparam logic [MetaWords*StepBits-1:0] MetaOrder = {
    4'd5, 4'd4, 4'd3, 4'd2, 4'd11, 4'd9, 4'd8, 4'd7, 4'd6, 4'd1, 4'd10, 4'd0};
  logic                     accept;       // moment_gen takes the stage-3 EOF on this edge
  logic                     runs_pend_q;  // ... it did on the last edge: stage the run stats
  logic [MetaSlots*WordBits-1:0] meta_chain_q;  // slot k at [WordBits*k +: WordBits]
  logic                     meta_pend_q;   // the chain waits for / is in its writes
  logic [StepBits-1:0]      meta_step_q;
  logic                     meta_wr;
  logic                     res_valid_q, res_bank_q;
  logic                     staged_ovf_q, res_ovf_q;

  assign accept  = lut.pix.valid & lut.pix.eof & mom_accept;
  assign meta_wr = meta_pend_q & ~runs_pend_q & ~mom_wr_valid;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      cfg_fc_q       <= '0;
      cfg_lut_q      <= '0;
      frame_cycles_q <= '0;
      meta_lut_q     <= '0;
      runs_pend_q    <= 1'b0;
      meta_chain_q   <= '0;
      meta_pend_q    <= 1'b0;
      meta_step_q    <= '0;
      res_valid_q    <= 1'b0;
      res_bank_q     <= 1'b0;
      staged_ovf_q   <= 1'b0;
      res_ovf_q      <= 1'b0;
    end else begin
      if (video_sof) begin
        cfg_fc_q <= cfg_shadow;
      end
      if (fc.valid && fc.sof) begin
        cfg_lut_q <= cfg_fc_q;
      end
      frame_cycles_q <= (frame_cycles == {WordBits{1'b1}}) ? frame_cycles
                                                           : frame_cycles + WordBits'(1);
      if (fc.valid && fc.eof) begin
        meta_lut_q <= meta_fc;
      end
      // The meta of the EOF pixel is staged on the edge moment_gen takes it;
      // run_scanner's stats of that frame are final after the same edge.
      runs_pend_q <= accept;
      if (accept) begin
        // {aborted, missing_sof .. early_eol, cycles, frames_ok}
        meta_chain_q[0 +: 7*WordBits] <= {meta_lut_q.errors.frames_aborted,
                                          meta_lut_q.errors.missing_sof,
                                          meta_lut_q.errors.early_sof,
                                          meta_lut_q.errors.late_eol,
                                          meta_lut_q.errors.early_eol, meta_lut_q.cycles,
                                          meta_lut_q.errors.frames_ok};
        meta_pend_q <= 1'b1;
        meta_step_q <= '0;
      end else if (meta_wr) begin
        if (meta_step_q != 4'd0) begin
          meta_chain_q <= {WordBits'(0), meta_chain_q[MetaSlots*WordBits-1:WordBits]};
        end
        meta_step_q  <= meta_step_q + StepBits'(1);
        meta_pend_q  <= meta_step_q != StepBits'(MetaWords - 1);
      end
      if (runs_pend_q) begin
        meta_chain_q[7*WordBits +: 4*WordBits] <= rs;
        staged_ovf_q <= rs.dropped_overflow != '0;
      end
      if (mom_done_next) begin
        res_bank_q  <= ~res_bank_q;
        res_ovf_q   <= staged_ovf_q;
        res_valid_q <= 1'b1;
      end
    end
  end

  // The write port: moment words first, then the meta chain's head.
  logic [StepBits-1:0] meta_index;  // MetaOrder entry of meta_step_q (< MetaWords while writing)
  assign meta_index = MetaOrder[StepBits*meta_step_q +: StepBits];
  assign res_wr_valid_o = mom_wr_valid | meta_wr;
  // Meta bank b at ResMetaBase + 16 b.
  assign res_wr_addr_o  = mom_wr_valid ? AddrBits'(mom_wr_index)
                                       : ResMetaBase + AddrBits'({~res_bank_q, meta_index});
  assign res_wr_data_o  = mom_wr_valid ? mom_wr_data
                        : meta_chain_q[WordBits-1:0] - WordBits'(meta_step_q == '0);

  assign frame_done_o           = mom_done;
  assign res_valid_o            = res_valid_q;
  assign res_bank_o             = res_bank_q;
  assign res_overflow_nonzero_o = res_ovf_q;
  assign mom_wr_valid_o         = mom_wr_valid;
  // class_moments (HasClassMoments): the block and its published copy
  // res_class_q, loaded on the publication edge like the rest of the set.
  if (HasClassMoments) begin : g_class
    // The moments of the class masks 1..3 in the class window.
    localparam int unsigned Classes = ceilnav_pkg::MaxClasses;
    localparam int unsigned C00 = ceilnav_pkg::M00Bits, C10 = ceilnav_pkg::M10Bits;
    localparam int unsigned C20 = ceilnav_pkg::M20Bits, C11 = ceilnav_pkg::M11Bits;
    localparam int unsigned MomBits = ceilnav_pkg::MomentBits;
    localparam int unsigned ClassResBits = Classes * (C00 + 2 * C10 + 2 * C20 + C11);
    logic                      cls_done;
    logic [Classes*C00-1:0]    c00;
    logic [Classes*C10-1:0]    c10, c01;
    logic [Classes*C20-1:0]    c20, c02;
    logic [Classes*C11-1:0]    c11;

    class_moments #(
      .NumClasses(Classes)
    ) u_class_moments (
      .clk_i,
      .rst_ni,
      .s_lut_valid_i (lut.pix.valid),
      .s_lut_grey_i  (lut.pix.grey),
      .s_lut_x_i     (lut.pix.x),
      .s_lut_y_i     (lut.pix.y),
      .s_lut_sof_i   (lut.pix.sof),
      .s_lut_eol_i   (lut.pix.eol),
      .s_lut_eof_i   (lut.pix.eof),
      .s_lut_abort_i (lut.pix.abort_frame),
      .s_lut_remap_i (lut.lut.remap),
      .s_lut_mask_i  (lut.lut.mask),
      .s_lut_class_i (lut.lut.cls),
      .win_x0_i      (cfg_lut_q.win_x0),
      .win_x1_i      (cfg_lut_q.win_x1),
      .win_y0_i      (cfg_lut_q.win_y0),
      .win_y1_i      (cfg_lut_q.win_y1),
      .eof_keep_i    (mom_accept),
      .done_o        (cls_done),
      .m00_o         (c00),
      .m10_o         (c10),
      .m01_o         (c01),
      .m20_o         (c20),
      .m11_o         (c11),
      .m02_o         (c02)
    );

    logic [ClassResBits-1:0] res_class_q;
    always_ff @(posedge clk_i) begin
      if (!rst_ni)            res_class_q <= '0;
      else if (mom_done_next) res_class_q <= {c02, c11, c20, c01, c10, c00};
    end

    // res_class_q = {c02, c11, c20, c01, c10, c00}, each Classes x width.
    localparam int unsigned OffC00 = 0;
    localparam int unsigned OffC10 = OffC00 + Classes * C00;
    localparam int unsigned OffC01 = OffC10 + Classes * C10;
    localparam int unsigned OffC20 = OffC01 + Classes * C10;
    localparam int unsigned OffC11 = OffC20 + Classes * C20;
    localparam int unsigned OffC02 = OffC11 + Classes * C11;
    for (genvar c = 0; c < Classes; c++) begin : g_res_class
      assign res_class_mom_o[MomBits*(6*c+0) +: MomBits] = MomBits'(res_class_q[OffC00 + c*C00 +: C00]);
      assign res_class_mom_o[MomBits*(6*c+1) +: MomBits] = MomBits'(res_class_q[OffC10 + c*C10 +: C10]);
      assign res_class_mom_o[MomBits*(6*c+2) +: MomBits] = MomBits'(res_class_q[OffC01 + c*C10 +: C10]);
      assign res_class_mom_o[MomBits*(6*c+3) +: MomBits] = MomBits'(res_class_q[OffC20 + c*C20 +: C20]);
      assign res_class_mom_o[MomBits*(6*c+4) +: MomBits] = MomBits'(res_class_q[OffC11 + c*C11 +: C11]);
      assign res_class_mom_o[MomBits*(6*c+5) +: MomBits] = MomBits'(res_class_q[OffC02 + c*C20 +: C20]);
    end
    logic unused_cls;
    assign unused_cls = cls_done;
  end else begin : g_no_class
    assign res_class_mom_o = '0;
    // The class index and the class window are not used in this configuration.
    logic unused_cls;
    assign unused_cls = ^{lut.lut.cls, cfg_lut_q.win_x0, cfg_lut_q.win_x1, cfg_lut_q.win_y0,
                          cfg_lut_q.win_y1};
  end

  // Corridor (HasCorridor): edge_detect -> hough. EDGE_CONTROL travels with
  // the SOF like the stage configuration (edge_cfg_fc_q, edge_cfg_lut_q);
  // edge_detect latches it at the SOF pixel.
  if (HasCorridor) begin : g_corridor
    localparam int unsigned EdgeCfgBits = 1 + 2 + 12;
    logic [EdgeCfgBits-1:0] edge_cfg_shadow, edge_cfg_fc_q, edge_cfg_lut_q;
    logic                   edge_tvalid, edge_tlast, hough_tready, edge_done, edge_pending;
    logic [63:0]            edge_tdata;
    logic [EdgeCountBits-1:0] edge_occupancy;
    ceilnav_pkg::word_t     stalls_q;

    assign edge_cfg_shadow = {cfg_edge_threshold_i, cfg_edge_mode_i, cfg_edge_enable_i};

    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        edge_cfg_fc_q  <= '0;
        edge_cfg_lut_q <= '0;
        stalls_q       <= '0;
      end else begin
        if (video_sof) begin
          edge_cfg_fc_q <= edge_cfg_shadow;
        end
        if (fc.valid && fc.sof) begin
          edge_cfg_lut_q <= edge_cfg_fc_q;
        end
        if (edge_tvalid && !hough_tready && stalls_q != {WordBits{1'b1}}) begin
          stalls_q <= stalls_q + WordBits'(1);
        end
      end
    end

    edge_detect #(
      .FifoDepth(EdgeFifoDepth)
    ) u_edge (
      .clk_i,
      .rst_ni,
      .s_lut_valid_i        (lut.pix.valid),
      .s_lut_grey_i         (lut.pix.grey),
      .s_lut_x_i            (lut.pix.x),
      .s_lut_y_i            (lut.pix.y),
      .s_lut_sof_i          (lut.pix.sof),
      .s_lut_eol_i          (lut.pix.eol),
      .s_lut_eof_i          (lut.pix.eof),
      .s_lut_abort_i        (lut.pix.abort_frame),
      .s_lut_remap_i        (lut.lut.remap),
      .s_lut_mask_i         (lut.lut.mask),
      .cfg_enable_i         (edge_cfg_lut_q[0]),
      .cfg_mode_i           (edge_cfg_lut_q[2:1]),
      .cfg_threshold_i      (edge_cfg_lut_q[14:3]),
      .m_axis_edges_tvalid_o(edge_tvalid),
      .m_axis_edges_tready_i(hough_tready),
      .m_axis_edges_tlast_o (edge_tlast),
      .m_axis_edges_tdata_o (edge_tdata),
      .done_o               (edge_done),
      .pending_o            (edge_pending),
      .edges_emitted_o      (edge_count_o),
      .edges_dropped_o      (edge_dropped_o),
      .fifo_occupancy_o     (edge_occupancy),
      .trailers_lost_o      (edge_trailers_lost_o)
    );

    hough #(
      .Lanes    (HoughLanes),
      .ThetaStep(HoughThetaStep),
      .RhoBits  (HoughRhoBits),
      .AccBits  (HoughAccBits)
    ) u_hough (
      .clk_i,
      .rst_ni,
      .s_axis_edges_tvalid_i(edge_tvalid),
      .s_axis_edges_tready_o(hough_tready),
      .s_axis_edges_tdata_i (edge_tdata),
      .s_axis_edges_tlast_i (edge_tlast),
      .cfg_enable_i         (cfg_hough_enable_i),
      .cfg_unit_weight_i    (cfg_hough_unit_weight_i),
      .cfg_weight_shift_i   (cfg_hough_weight_shift_i),
      .cfg_rho_shift_i      (cfg_hough_rho_shift_i),
      .cfg_theta_first_i    (cfg_hough_theta_first_i),
      .cfg_theta_count_i    (cfg_hough_theta_count_i),
      .cfg_width_i          (cfg_hough_width_i),
      .rd_en_i              (hough_rd_en_i),
      .rd_index_i           (hough_rd_index_i),
      .rd_data_o            (hough_rd_data_o),
      .done_o               (hough_done_o),
      .results_valid_o      (hough_results_valid_o),
      .state_o              (hough_state_o),
      .edges_o              (hough_edges_o),
      .bad_edges_o          (hough_bad_edges_o),
      .votes_o              (hough_votes_o),
      .dropped_o            (hough_dropped_o),
      .saturated_o          (hough_saturated_o),
      .trailer_edges_o      (hough_trailer_edges_o),
      .trailer_flags_o      (hough_trailer_flags_o)
    );

    assign edge_fifo_level_o  = (EdgeCountBits + 1)'(edge_occupancy) +
                                (EdgeCountBits + 1)'(edge_tvalid);
    // hough_state_o: 1 vote, 2 swap (ceilnav_pkg-free: hough's encoding)
    assign corridor_pending_o = edge_pending | edge_tvalid | (edge_occupancy != '0) |
                                (hough_state_o == 2'd1) | (hough_state_o == 2'd2);
    assign hough_stalls_o     = stalls_q;

    logic unused_edge;
    assign unused_edge = edge_done;
  end else begin : g_no_corridor
    assign hough_rd_data_o       = '0;
    assign hough_done_o          = 1'b0;
    assign hough_results_valid_o = 1'b0;
    assign hough_state_o         = '0;
    assign hough_edges_o         = '0;
    assign hough_bad_edges_o     = '0;
    assign hough_votes_o         = '0;
    assign hough_dropped_o       = '0;
    assign hough_saturated_o     = '0;
    assign hough_trailer_edges_o = '0;
    assign hough_trailer_flags_o = '0;
    assign edge_count_o          = '0;
    assign edge_dropped_o        = '0;
    assign edge_fifo_level_o     = '0;
    assign edge_trailers_lost_o  = '0;
    assign corridor_pending_o    = 1'b0;
    assign hough_stalls_o        = '0;
    logic unused_corridor;
    assign unused_corridor = ^{cfg_edge_enable_i, cfg_edge_mode_i, cfg_edge_threshold_i,
                               cfg_hough_enable_i, cfg_hough_unit_weight_i,
                               cfg_hough_weight_shift_i, cfg_hough_rho_shift_i,
                               cfg_hough_theta_first_i, cfg_hough_theta_count_i,
                               cfg_hough_width_i, hough_rd_en_i, hough_rd_index_i};
  end

  // Orientation (HasOrientation): ORI_CONTROL travels with the SOF like
  // EDGE_CONTROL (ori_cfg_fc_q, ori_cfg_lut_q); the block latches it at the
  // SOF pixel.
  if (HasOrientation) begin : g_orientation
    localparam int unsigned OriCfgBits = 1 + 12;
    logic [OriCfgBits-1:0] ori_cfg_shadow, ori_cfg_fc_q, ori_cfg_lut_q;

    assign ori_cfg_shadow = {cfg_ori_threshold_i, cfg_ori_enable_i};

    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        ori_cfg_fc_q  <= '0;
        ori_cfg_lut_q <= '0;
      end else begin
        if (video_sof) begin
          ori_cfg_fc_q <= ori_cfg_shadow;
        end
        if (fc.valid && fc.sof) begin
          ori_cfg_lut_q <= ori_cfg_fc_q;
        end
      end
    end

    orientation #(
      .Bins(OriBins)
    ) u_orientation (
      .clk_i,
      .rst_ni,
      .s_lut_valid_i   (lut.pix.valid),
      .s_lut_grey_i    (lut.pix.grey),
      .s_lut_x_i       (lut.pix.x),
      .s_lut_y_i       (lut.pix.y),
      .s_lut_sof_i     (lut.pix.sof),
      .s_lut_eol_i     (lut.pix.eol),
      .s_lut_eof_i     (lut.pix.eof),
      .s_lut_abort_i   (lut.pix.abort_frame),
      .s_lut_remap_i   (lut.lut.remap),
      .s_lut_mask_i    (lut.lut.mask),
      .cfg_enable_i    (ori_cfg_lut_q[0]),
      .cfg_threshold_i (ori_cfg_lut_q[12:1]),
      .hist_rd_en_i    (ori_rd_en_i),
      .hist_rd_bin_i   (ori_rd_bin_i),
      .hist_rd_data_o  (ori_rd_data_o),
      .done_o          (ori_done_o),
      .results_valid_o (ori_results_valid_o),
      .clearing_o      (ori_clearing_o),
      .frame_votes_o   (ori_votes_o),
      .frames_o        (ori_frames_o),
      .frames_skipped_o(ori_skipped_o)
    );
  end else begin : g_no_orientation
    assign ori_rd_data_o       = '0;
    assign ori_done_o          = 1'b0;
    assign ori_results_valid_o = 1'b0;
    assign ori_clearing_o      = 1'b0;
    assign ori_votes_o         = '0;
    assign ori_frames_o        = '0;
    assign ori_skipped_o       = '0;
    logic unused_orientation;
    assign unused_orientation = ^{cfg_ori_enable_i, cfg_ori_threshold_i, ori_rd_en_i,
                                  ori_rd_bin_i};
  end

  assign errors_o                     = fc_errors;
  assign frames_overrun_o             = mom_overrun;

  logic unused;
  assign unused = ^{unused_fc_tready, unused_mom_busy, unused_hist_done, unused_rs_done};

`ifndef SYNTHESIS
  // Every publication has a staged set, and a set is never overwritten before
  // it is published (see the header). Unprovable only once overrun_count saturates.
  logic staged_pending_q;
  always_ff @(posedge clk_i) begin
    if (!rst_ni)            staged_pending_q <= 1'b0;
    else if (accept)        staged_pending_q <= 1'b1;
    else if (mom_done_next) staged_pending_q <= 1'b0;
  end
  MetaWrittenBeforePublish: assert property (@(posedge clk_i) disable iff (!rst_ni)
      mom_done_next |-> !meta_pend_q);
  StagedBeforePublish: assert property (@(posedge clk_i) disable iff (!rst_ni)
      mom_done_next |-> staged_pending_q);
  OneStagedSet: assert property (@(posedge clk_i) disable iff (!rst_ni)
      accept |-> (!staged_pending_q || mom_done_next));
`endif

endmodule
