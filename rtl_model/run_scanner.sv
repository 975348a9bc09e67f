// run_scanner: per row, the runs of mask = 1 pixels with the intensity sums
// of the run plus one margin pixel each side (sub-pixel centre sum_xw/sum_w),
// through a FIFO onto an AXI4-Stream master, with one trailer beat per frame.
// Cycle model: stream/run_scanner.{hpp,cpp}; spec: docs/blocks/run_scanner.md.
//
// m_axis_runs_tdata layout (pack_run_beat() in stream/run_scanner.hpp): no
// field crosses a 32-bit word.
//   [15:0] row (trailer: runs emitted, saturated)  [31:16] x_start (trailer: flags)
//   [63:32] sum_w   [95:64] sum_xw   [111:96] x_end

module run_scanner #(
  parameter int unsigned FifoDepth = 1024,  // run FIFO entries, power of two, >= 8
  localparam int unsigned CountBits = $clog2(FifoDepth) + 1
) (
  input  logic                 clk_i,
  input  logic                 rst_ni,

  // s_lut: pixel beat from thresh_lut (LutBeat).
  input  logic                 s_lut_valid_i,
  input  logic [7:0]           s_lut_grey_i,
  input  logic [10:0]          s_lut_x_i,
  input  logic [10:0]          s_lut_y_i,
  input  logic                 s_lut_sof_i,
  input  logic                 s_lut_eol_i,
  input  logic                 s_lut_eof_i,
  input  logic                 s_lut_abort_i,
  input  logic [7:0]           s_lut_remap_i,
  input  logic                 s_lut_mask_i,

  // Active configuration, latched at the SOF pixel.
  input  logic [7:0]           cfg_background_level_i,
  input  logic [15:0]          cfg_min_run_length_i,
  input  logic [15:0]          cfg_max_runs_per_row_i,

  output logic                 m_axis_runs_tvalid_o,
  input  logic                 m_axis_runs_tready_i,
  output logic                 m_axis_runs_tlast_o,
  output logic [111:0]         m_axis_runs_tdata_o,

  output logic                 done_o,  // one-cycle pulse: the stats were just updated
  output logic [31:0]          runs_emitted_o,
  output logic [31:0]          runs_dropped_row_limit_o,
  output logic [31:0]          runs_dropped_overflow_o,
  output logic [31:0]          fifo_high_water_o,
  output logic [CountBits-1:0] fifo_occupancy_o,
  output logic [31:0]          trailers_lost_o
);

  localparam int unsigned CoordBits = 11;
  localparam int unsigned SumWBits = 19;    // 255 W: a run plus margins is clipped to the line
  localparam int unsigned SumXwBits = 29;   // 255 W (W-1) / 2
  localparam int unsigned RowRunBits = 11;  // ceil(W/2) runs per row
  localparam int unsigned FrameRunBits = 22;  // H ceil(W/2) runs per frame
  // FIFO entry: {tlast, sum_xw, sum_w, x_end, x_start, row}. row is 16 bits
  // (trailer: the run count); x_start holds the trailer flags.
  localparam int unsigned EntryBits = 1 + SumXwBits + SumWBits + 2 * CoordBits + 16;
  localparam logic [15:0] FlagRowLimit = 16'h0001;
  localparam logic [15:0] FlagOverflow = 16'h0002;
  localparam logic [15:0] FlagAborted = 16'h0004;
  localparam logic [CountBits-1:0] Depth = CountBits'(FifoDepth);

  if (FifoDepth < 8 || (FifoDepth & (FifoDepth - 1)) != 0) begin : g_bad_depth
    $fatal(1, "run_scanner: FifoDepth must be a power of two >= 8");
  end

  // ---------------------------------------------------------------------------
  // Row / run state.
  logic [7:0]             cfg_bg_q;
  logic [15:0]            cfg_min_len_q, cfg_max_runs_q;
  logic [7:0]             cfg_bg;
  logic [15:0]            cfg_min_len, cfg_max_runs;
  logic                   frame_open_q, frame_open_d;
  logic [CoordBits-1:0]   x_q, y_q;
  logic [7:0]             prev_w_q;
  logic                   in_run_q;
  logic [CoordBits-1:0]   run_start_q;
  logic [SumWBits-1:0]    run_sum_w_q;
  logic [SumXwBits-1:0]   run_sum_xw_q;
  logic [RowRunBits-1:0]  row_runs_q;

  logic take;
  assign take = s_lut_valid_i & (s_lut_sof_i | frame_open_q);

  // The SOF pixel already runs with the configuration it latches.
  assign cfg_bg       = s_lut_sof_i ? cfg_background_level_i : cfg_bg_q;
  assign cfg_min_len  = s_lut_sof_i ? cfg_min_run_length_i : cfg_min_len_q;
  assign cfg_max_runs = s_lut_sof_i ? cfg_max_runs_per_row_i : cfg_max_runs_q;

  logic [CoordBits-1:0]  x, y, x_m1;
  logic                  row_start, in_run;
  logic [RowRunBits-1:0] row_runs;
  logic [7:0]            w, prev_w;
  assign x         = s_lut_sof_i ? '0 : x_q;
  assign y         = s_lut_sof_i ? '0 : y_q;
  assign x_m1      = x - 11'd1;
  assign row_start = x == '0;
  assign in_run    = ~row_start & in_run_q;  // SOF/EOL leave no run open
  assign row_runs  = row_start ? '0 : row_runs_q;
  assign w         = s_lut_remap_i > cfg_bg ? s_lut_remap_i - cfg_bg : 8'd0;
  assign prev_w    = row_start ? 8'd0 : prev_w_q;  // left margin clipped at x = 0

  // Run sums including this pixel (as a run pixel or as the right margin).
  // x w is the one 11x8 multiplier; (x-1) prev_w is only needed when a run
  // starts, and then it equals the x w of the previous pixel, so a register
  // holds it.
  logic [CoordBits+7:0]  xw;
  logic [CoordBits+7:0]  prev_xw_q;  // (x-1) prev_w of the previous pixel on the row
  logic [CoordBits-1:0]  start;
  logic [SumWBits-1:0]   sum_w;
  logic [SumXwBits-1:0]  sum_xw;
  logic                  end_run;
  logic [CoordBits-1:0]  run_end;
  logic [CoordBits:0]    run_len;
  logic                  run_long_enough;
  assign xw = (CoordBits + 8)'(x) * (CoordBits + 8)'(w);

  always_comb begin
    start = run_start_q;
    sum_w = run_sum_w_q + SumWBits'(w);
    sum_xw = run_sum_xw_q + SumXwBits'(xw);
    if (s_lut_mask_i && !in_run) begin  // run starts here; the previous pixel is its left margin
      start = x;
      sum_w = SumWBits'(prev_w) + SumWBits'(w);
      sum_xw = (row_start ? '0 : SumXwBits'(prev_xw_q)) + SumXwBits'(xw);
    end
    end_run = 1'b0;
    run_end = '0;
    if (s_lut_mask_i && s_lut_eol_i) begin  // the run reaches the end of the line
      end_run = 1'b1;
      run_end = x;
    end else if (!s_lut_mask_i && in_run) begin  // this mask-0 pixel is the right margin
      end_run = 1'b1;
      run_end = x_m1;
    end
  end
  assign run_len = {1'b0, run_end} - {1'b0, start} + 12'd1;
  assign run_long_enough = 16'(run_len) >= cfg_min_len;

  // ---------------------------------------------------------------------------
  // Frame counters and FIFO writes: aborted-frame trailer (A), run (R),
  // end-of-frame trailer (T), in that order, at tail, tail+1, ...
  logic [FrameRunBits-1:0] emitted_q, emitted_d, emitted_base;
  logic [FrameRunBits-1:0] drop_limit_q, drop_limit_d, drop_limit_base;
  logic [FrameRunBits-1:0] drop_ovf_q, drop_ovf_d, drop_ovf_base;
  logic [CountBits-1:0]    high_water_q, high_water_d;
  logic                    sticky_q, sticky_a, sticky_d;
  logic [31:0]             trailers_lost_q, trailers_lost_d;
  logic [CountBits-1:0]    fifo_count;  // pre-edge occupancy
  logic [CountBits-1:0]    fifo_count_next;
  logic [CountBits+1:0]    count_wide;

  logic        a_req, a_en, r_en, t_req, t_en;
  logic [15:0] a_flags, t_flags;
  logic        row_run_ok;
  logic [RowRunBits-1:0] row_runs_d;
  logic [1:0]  lost;

  assign count_wide = (CountBits + 2)'(fifo_count);
  assign a_req = s_lut_abort_i & frame_open_q;
  assign t_req = take & s_lut_eof_i;
  assign a_en = a_req && count_wide < (CountBits + 2)'(Depth);
  assign row_run_ok = take & end_run & run_long_enough & (16'(row_runs) < cfg_max_runs);
  // One entry stays free for the trailer.
  assign r_en = row_run_ok && count_wide + (CountBits + 2)'(a_en) + (CountBits + 2)'(1) <
                              (CountBits + 2)'(Depth);

  // The counters that the trailer of this edge's frame sees (after SOF reset).
  assign emitted_base    = take & s_lut_sof_i ? '0 : emitted_q;
  assign drop_limit_base = take & s_lut_sof_i ? '0 : drop_limit_q;
  assign drop_ovf_base   = take & s_lut_sof_i ? '0 : drop_ovf_q;
  assign emitted_d    = emitted_base + FrameRunBits'(r_en);
  logic drop_limit, drop_ovf;
  assign drop_limit   = take & end_run & run_long_enough & ~row_run_ok;
  assign drop_ovf     = row_run_ok & ~r_en;
  assign drop_limit_d = drop_limit_base + FrameRunBits'(drop_limit);
  assign drop_ovf_d   = drop_ovf_base + FrameRunBits'(drop_ovf);
  assign row_runs_d   = row_runs + RowRunBits'(row_run_ok);

  always_comb begin
    a_flags = FlagAborted;
    if (drop_limit_q != '0) a_flags |= FlagRowLimit;
    if (drop_ovf_q != '0) a_flags |= FlagOverflow;
    if (sticky_q) a_flags |= FlagOverflow;
    t_flags = 16'd0;
    if (drop_limit_d != '0) t_flags |= FlagRowLimit;
    if (drop_ovf_d != '0) t_flags |= FlagOverflow;
    if (sticky_a) t_flags |= FlagOverflow;
  end
  assign sticky_a = a_req ? ~a_en : sticky_q;
  assign t_en = t_req && count_wide + (CountBits + 2)'(a_en) + (CountBits + 2)'(r_en) <
                         (CountBits + 2)'(Depth);
  assign sticky_d = t_req ? ~t_en : sticky_a;
  logic a_lost, t_lost;
  assign a_lost = a_req & ~a_en;
  assign t_lost = t_req & ~t_en;
  assign lost = 2'(a_lost) + 2'(t_lost);

  always_comb begin
    trailers_lost_d = trailers_lost_q;
    if (lost != 2'd0) begin
      if (trailers_lost_q >= 32'hFFFF_FFFF - 32'(lost)) trailers_lost_d = 32'hFFFF_FFFF;
      else trailers_lost_d = trailers_lost_q + 32'(lost);
    end
  end

  // Trailer row: runs emitted, saturated to 16 bits.
  logic [15:0] a_row, t_row;
  assign a_row = emitted_q > FrameRunBits'(16'hFFFF) ? 16'hFFFF : emitted_q[15:0];
  assign t_row = emitted_d > FrameRunBits'(16'hFFFF) ? 16'hFFFF : emitted_d[15:0];

  logic [EntryBits-1:0] a_entry, r_entry, t_entry;
  assign a_entry = {1'b1, SumXwBits'(0), SumWBits'(0), CoordBits'(0), a_flags[CoordBits-1:0],
                    a_row};
  assign r_entry = {1'b0, sum_xw, sum_w, run_end, start, 5'd0, y};
  assign t_entry = {1'b1, SumXwBits'(0), SumWBits'(0), CoordBits'(0), t_flags[CoordBits-1:0],
                    t_row};

  // Compact the writes: A, R, T in order into slots 0, 1, 2.
  logic [1:0]             wr_count;
  logic [3*EntryBits-1:0] wr_data;
  assign wr_count = 2'(a_en) + 2'(r_en) + 2'(t_en);
  assign wr_data[0 +: EntryBits] = a_en ? a_entry : r_en ? r_entry : t_entry;
  assign wr_data[EntryBits +: EntryBits] = a_en && r_en ? r_entry : t_entry;
  assign wr_data[2*EntryBits +: EntryBits] = t_entry;

  // ---------------------------------------------------------------------------
  // FIFO and output register (m_axis): takes the head when empty or
  // transferring.
  logic                 out_load, pop;
  logic                 out_valid_q, out_valid_d;
  logic [EntryBits-1:0] out_q, out_d, fifo_head;

  assign out_load = ~out_valid_q | m_axis_runs_tready_i;
  assign pop = out_load & (fifo_count != '0);
  assign out_valid_d = out_load ? pop : out_valid_q;
  assign out_d = out_load ? (pop ? fifo_head : '0) : out_q;

  run_fifo #(
    .Depth(FifoDepth),
    .Width(EntryBits)
  ) u_fifo (
    .clk_i,
    .rst_ni,
    .wr_count_i(wr_count),
    .wr_data_i (wr_data),
    .rd_i      (pop),
    .count_o   (fifo_count),
    .head_o    (fifo_head)
  );

  assign fifo_count_next = fifo_count - CountBits'(pop) + CountBits'(wr_count);
  // Largest occupancy after any edge from the SOF edge to the EOF edge.
  always_comb begin
    high_water_d = high_water_q;
    if (take) begin
      if (s_lut_sof_i || fifo_count_next > high_water_q) high_water_d = fifo_count_next;
    end
  end

  always_comb begin
    frame_open_d = frame_open_q;
    if (take) frame_open_d = ~s_lut_eof_i;
    else if (s_lut_abort_i) frame_open_d = 1'b0;
  end

  // ---------------------------------------------------------------------------
  // Registers.
  logic [FrameRunBits-1:0] stat_emitted_q, stat_drop_limit_q, stat_drop_ovf_q;
  logic [CountBits-1:0]    stat_high_water_q;
  logic                    done_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      cfg_bg_q <= 8'd0;  // RunScanConfig{} (unused until an SOF latches the port)
      cfg_min_len_q <= 16'd1;
      cfg_max_runs_q <= 16'd8;
      frame_open_q <= 1'b0;
      x_q <= '0;
      y_q <= '0;
      prev_w_q <= '0;
      prev_xw_q <= '0;
      in_run_q <= 1'b0;
      run_start_q <= '0;
      run_sum_w_q <= '0;
      run_sum_xw_q <= '0;
      row_runs_q <= '0;
      emitted_q <= '0;
      drop_limit_q <= '0;
      drop_ovf_q <= '0;
      high_water_q <= '0;
      stat_emitted_q <= '0;
      stat_drop_limit_q <= '0;
      stat_drop_ovf_q <= '0;
      stat_high_water_q <= '0;
      done_q <= 1'b0;
      sticky_q <= 1'b0;
      trailers_lost_q <= '0;
      out_valid_q <= 1'b0;
      out_q <= '0;
    end else begin
      frame_open_q <= frame_open_d;
      if (take) begin
        if (s_lut_sof_i) begin
          cfg_bg_q <= cfg_background_level_i;
          cfg_min_len_q <= cfg_min_run_length_i;
          cfg_max_runs_q <= cfg_max_runs_per_row_i;
        end
        in_run_q <= s_lut_mask_i & ~s_lut_eol_i;
        run_start_q <= start;
        run_sum_w_q <= sum_w;
        run_sum_xw_q <= sum_xw;
        prev_w_q <= w;
        prev_xw_q <= xw;
        row_runs_q <= row_runs_d;
        x_q <= s_lut_eol_i ? '0 : x + 11'd1;
        y_q <= s_lut_eol_i ? y + 11'd1 : y;
        emitted_q <= emitted_d;
        drop_limit_q <= drop_limit_d;
        drop_ovf_q <= drop_ovf_d;
      end
      high_water_q <= high_water_d;
      if (t_req) begin
        stat_emitted_q <= emitted_d;
        stat_drop_limit_q <= drop_limit_d;
        stat_drop_ovf_q <= drop_ovf_d;
        stat_high_water_q <= high_water_d;
      end
      done_q <= t_req;
      sticky_q <= sticky_d;
      trailers_lost_q <= trailers_lost_d;
      out_valid_q <= out_valid_d;
      out_q <= out_d;
    end
  end

  // ---------------------------------------------------------------------------
  // Outputs.
  logic                 out_last;
  logic [SumXwBits-1:0] out_sum_xw;
  logic [SumWBits-1:0]  out_sum_w;
  logic [CoordBits-1:0] out_x_end, out_x_start;
  logic [15:0]          out_row;
  assign {out_last, out_sum_xw, out_sum_w, out_x_end, out_x_start, out_row} = out_q;

  assign m_axis_runs_tvalid_o = out_valid_q;
  assign m_axis_runs_tlast_o  = out_last;
  assign m_axis_runs_tdata_o  = {16'(out_x_end), 32'(out_sum_xw), 32'(out_sum_w),
                                 16'(out_x_start), out_row};
  assign done_o                   = done_q;
  assign runs_emitted_o           = 32'(stat_emitted_q);
  assign runs_dropped_row_limit_o = 32'(stat_drop_limit_q);
  assign runs_dropped_overflow_o  = 32'(stat_drop_ovf_q);
  assign fifo_high_water_o        = 32'(stat_high_water_q);
  assign fifo_occupancy_o         = fifo_count;
  assign trailers_lost_o          = trailers_lost_q;

  // The camera pixel itself is not used: runs are of the LUT output.
  logic unused_grey;
  assign unused_grey = ^s_lut_grey_i;

`ifndef SYNTHESIS
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      // frame_check guarantees the pixel position; the counters must agree.
      if (take) begin
        assert (s_lut_x_i == x && s_lut_y_i == y)
        else $error("run_scanner: pixel (%0d, %0d) but counters (%0d, %0d)",
                    s_lut_x_i, s_lut_y_i, x, y);
      end
      // AXI4-Stream: a beat that is not taken holds.
      if (out_valid_q && !m_axis_runs_tready_i) begin
        assert (out_valid_d && out_d == out_q)
        else $error("run_scanner: m_axis_runs changed while stalled");
      end
    end
  end
`else
  logic unused_pos;
  assign unused_pos = ^{s_lut_x_i, s_lut_y_i};
`endif

endmodule
