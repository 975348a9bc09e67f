// run_scanner: per row, the runs of mask = 1 pixels with the intensity sums
// of the run plus one margin pixel each side (sub-pixel centre sum_xw/sum_w),
// through a FIFO onto an AXI4-Stream master, with one trailer beat per frame.
// Cycle model: stream/run_scanner.{hpp,cpp}; spec: docs/blocks/run_scanner.md.
//
// Inputs are assumed legal as frame_check/thresh_lut make them (the C++ model
// throws otherwise): pix.x/pix.y equal the block's own position counters, and
// a beat carrying both abort and a pixel is an SOF (early SOF). Both are
// checked by simulation assertions.
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
  input  ceilnav_pkg::pixel_t  s_lut_grey_i,
  input  ceilnav_pkg::coord_t  s_lut_x_i,
  input  ceilnav_pkg::coord_t  s_lut_y_i,
  input  logic                 s_lut_sof_i,
  input  logic                 s_lut_eol_i,
  input  logic                 s_lut_eof_i,
  input  logic                 s_lut_abort_i,
  input  ceilnav_pkg::pixel_t  s_lut_remap_i,
  input  logic                 s_lut_mask_i,

  // Active configuration, latched at the SOF pixel.
  input  ceilnav_pkg::pixel_t     cfg_background_level_i,
  input  ceilnav_pkg::run_field_t cfg_min_run_length_i,
  input  ceilnav_pkg::run_field_t cfg_max_runs_per_row_i,

  output logic                 m_axis_runs_tvalid_o,
  input  logic                 m_axis_runs_tready_i,
  output logic                 m_axis_runs_tlast_o,
  output logic [ceilnav_pkg::RunBeatBits-1:0] m_axis_runs_tdata_o,  // ceilnav_pkg::run_beat_t

  output logic                 done_o,  // one-cycle pulse: the stats were just updated
  output ceilnav_pkg::word_t   runs_emitted_o,
  output ceilnav_pkg::word_t   runs_dropped_row_limit_o,
  output ceilnav_pkg::word_t   runs_dropped_overflow_o,
  output ceilnav_pkg::word_t   fifo_high_water_o,
  output logic [CountBits-1:0] fifo_occupancy_o,
  output ceilnav_pkg::word_t   trailers_lost_o
);

  // Widths from fixedpoint/datapath.hpp (namespace run_scanner), generated
  // into ceilnav_widths_pkg.
  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned PixelBits = ceilnav_pkg::PixelBits;
  localparam int unsigned WordBits = ceilnav_pkg::WordBits;
  localparam int unsigned FieldBits = ceilnav_pkg::RunFieldBits;  // row, x_start, x_end, config
  localparam int unsigned WrBits = ceilnav_pkg::FifoWrBits;  // writes per edge, 0 .. 3
  localparam int unsigned SumWBits = ceilnav_pkg::SumWBits;    // 255 W: a run plus margins is clipped to the line
  localparam int unsigned SumXwBits = ceilnav_pkg::SumXwBits;  // 255 W (W-1) / 2
  localparam int unsigned RowRunBits = ceilnav_widths_pkg::RowRunBits;  // ceil(W/2) runs per row
  localparam int unsigned RunLenBits = ceilnav_widths_pkg::RunLenBits;  // W pixels
  localparam int unsigned FrameRunBits = ceilnav_widths_pkg::FrameRunBits;  // H ceil(W/2) runs per frame
  // FIFO entry (ceilnav_pkg::run_entry_t): {impl_t, tlast, sum_w, x_end,
  // x_start, row} and, one edge later, sum_xw. row is 16 bits (trailer: the
  // run count); x_start holds the trailer flags. impl_t: a run followed by the
  // constant trailer {row 1, flags 0} (see "FIFO" below).
  localparam int unsigned EntryBits = 2 + SumWBits + 2 * CoordBits + FieldBits;
  localparam logic [CountBits-1:0] Depth = CountBits'(FifoDepth);

  if (FifoDepth < 8 || (FifoDepth & (FifoDepth - 1)) != 0) begin : g_bad_depth
    $fatal(1, "run_scanner: FifoDepth must be a power of two >= 8");
  end

  // ---------------------------------------------------------------------------
  // Configuration: latched at the SOF pixel, which already runs with the port
  // value. The comparisons the run logic needs against it are kept as flags.
  ceilnav_pkg::pixel_t     cfg_bg_q, cfg_bg;
  ceilnav_pkg::run_field_t cfg_min_len_q, cfg_max_runs_q;
  logic        min_le1_q, min_le2_q, max_nz_q, max_le1_q;
  logic        min_le1, min_le2, max_nz, max_le1;
  logic        sof;
  assign sof     = s_lut_sof_i;
  assign cfg_bg  = sof ? cfg_background_level_i : cfg_bg_q;
  // (Small constants: written as zero tests, which Yosys maps onto LUTs, not
  // onto a carry chain.)
  logic min_hi_zero, max_hi_zero;
  assign min_hi_zero = cfg_min_run_length_i[FieldBits-1:2] == '0;
  assign max_hi_zero = cfg_max_runs_per_row_i[FieldBits-1:1] == '0;
  assign min_le1 = sof ? min_hi_zero & ~cfg_min_run_length_i[1] : min_le1_q;
  assign min_le2 = sof ? min_hi_zero & ~(&cfg_min_run_length_i[1:0]) : min_le2_q;
  assign max_nz  = sof ? ~max_hi_zero | cfg_max_runs_per_row_i[0] : max_nz_q;
  assign max_le1 = sof ? max_hi_zero : max_le1_q;

  // ---------------------------------------------------------------------------
  // Row / run state.
  logic                  frame_open_q, frame_open_d, take;
  logic                  row_start_q;  // the last pixel taken was an EOL: x = 0 now
  ceilnav_pkg::pixel_t   prev_w_q;     // w of the previous pixel on the row
  logic                  in_run_q;
  logic [CoordBits-1:0]  run_start_q;
  logic [SumWBits-1:0]   run_sum_w_q;
  // sum_xw runs one pixel behind: the product of the pixel taken last is in
  // xw_q, and the run's sum_xw through that pixel is xw_base_q + xw_q.
  logic [CoordBits+PixelBits-1:0] xw_q;
  logic [SumXwBits-1:0]  xw_base_q, xw_base_d, sum_xw_last;
  logic [RunLenBits-1:0] run_len_q;    // pixels of the open run so far
  logic                  len_ge_q;     // run_len_q >= min_run_length
  logic                  len1_ge_q;    // run_len_q + 1 >= min_run_length
  logic [RowRunBits-1:0] row_runs_q;
  logic                  row_full_q;   // row_runs_q >= max_runs_per_row

  assign take = s_lut_valid_i & (sof | frame_open_q);

  ceilnav_pkg::coord_t  x, y;
  logic                 row_start, in_run, starts;
  ceilnav_pkg::pixel_t  w, prev_w;
  assign x         = s_lut_x_i;  // == the position counters (asserted below)
  assign y         = s_lut_y_i;
  assign row_start = sof | row_start_q;
  assign in_run    = ~row_start & in_run_q;  // SOF/EOL leave no run open
  assign starts    = s_lut_mask_i & ~in_run;  // the previous pixel is the left margin
  // w = max(0, remap - bg): one subtraction, its borrow clamps.
  logic [PixelBits:0]  w_diff, w_diff_q;
  ceilnav_pkg::pixel_t w_q;  // w against the latched background level
  assign w_diff    = {1'b0, s_lut_remap_i} - {1'b0, cfg_bg};
  assign w         = w_diff[PixelBits] ? '0 : w_diff[PixelBits-1:0];
  assign w_diff_q  = {1'b0, s_lut_remap_i} - {1'b0, cfg_bg_q};
  assign w_q       = w_diff_q[PixelBits] ? '0 : w_diff_q[PixelBits-1:0];
  assign prev_w    = row_start ? '0 : prev_w_q;  // left margin clipped at x = 0

  // Run sums including this pixel (as a run pixel or as the right margin):
  // one 11x8 multiplier, registered (xw_q); sum_xw is completed in the next
  // cycle and reaches the FIFO one edge late (run_fifo's late field). The
  // (x-1) prev_w of a run that starts is the previous pixel's product, xw_q.
  logic [CoordBits+PixelBits-1:0] xw;
  ceilnav_pkg::coord_t  start, run_end;
  logic [SumWBits-1:0]  sum_w;
  logic                 end_run, long_enough;
  // x = 0 on the SOF pixel, the only one that uses the port's background
  // level: the product can take w_q, off the SOF multiplexer.
  assign xw      = (CoordBits + PixelBits)'(x) * (CoordBits + PixelBits)'(w_q);
  assign start   = starts ? x : run_start_q;
  assign sum_w   = (starts ? SumWBits'(prev_w) : run_sum_w_q) + SumWBits'(w);
  assign sum_xw_last = xw_base_q + SumXwBits'(xw_q);
  assign xw_base_d   = ~starts ? sum_xw_last : row_start ? '0 : SumXwBits'(xw_q);
  // The run ends at the EOL (mask 1: this pixel is its last) or at this mask-0
  // pixel, its right margin.
  assign end_run = s_lut_mask_i ? s_lut_eol_i : in_run;
  assign run_end = s_lut_mask_i ? x : x - CoordBits'(1);
  // Its length: run_len_q (right margin), run_len_q + 1 or 1 (ends at the EOL).
  assign long_enough = ~s_lut_mask_i ? len_ge_q : in_run ? len1_ge_q : min_le1;

  // Row limit: runs emitted on this row so far < max_runs_per_row.
  logic row_below_max;
  assign row_below_max = row_start ? max_nz : ~row_full_q;

  // Next run length and its comparisons, from registers only.
  logic [RunLenBits-1:0] run_len_inc;
  logic                  len2_ge_min, row_inc_full;
  assign run_len_inc  = run_len_q + RunLenBits'(1);
  assign len2_ge_min  = FieldBits'(run_len_q) + FieldBits'(2) >= cfg_min_len_q;
  assign row_inc_full = FieldBits'(row_runs_q) + FieldBits'(1) >= cfg_max_runs_q;

  // ---------------------------------------------------------------------------
  // Admission and frame counters. Writes per edge: aborted-frame trailer (A),
  // run (R), end-of-frame trailer (T), in that order, admitted against the
  // pre-edge occupancy n: A if n < depth, R if n + A + 1 < depth (one entry
  // stays free for the trailer), T if n + A + R < depth.
  logic [CountBits-1:0]    count_q, count_d;  // FIFO beats, not counting the output register
  logic                    n_lt_d, n_lt_dm1, n_lt_dm2;
  logic                    a_req, a_en, r_ok, r_en, t_req, t_en, drop_limit, drop_ovf, sof_take;
  logic [RowRunBits-1:0]   row_runs_d;
  logic                    row_full_d;

  // count_q <= Depth, a power of two: the comparisons are bit tests.
  assign n_lt_d   = ~count_q[CountBits-1];
  assign n_lt_dm1 = n_lt_d & ~(&count_q[CountBits-2:0]);
  assign n_lt_dm2 = n_lt_d & ~(&count_q[CountBits-2:1]);
  assign sof_take = take & sof;
  assign a_req    = s_lut_abort_i & frame_open_q;
  assign t_req    = take & s_lut_eof_i;
  assign a_en     = a_req & n_lt_d;
  assign r_ok     = take & end_run & long_enough & row_below_max;
  assign r_en     = r_ok & (a_en ? n_lt_dm2 : n_lt_dm1);
  assign t_en     = t_req & (a_en & r_en ? n_lt_dm2 : a_en | r_en ? n_lt_dm1 : n_lt_d);
  assign drop_limit = take & end_run & long_enough & ~row_below_max;
  assign drop_ovf   = r_ok & ~r_en;
  assign row_runs_d = (row_start ? '0 : row_runs_q) + RowRunBits'(r_ok);
  assign row_full_d = row_start ? (r_ok ? max_le1 : ~max_nz) : (r_ok ? row_inc_full : row_full_q);

  logic [FrameRunBits-1:0] emitted_q, emitted_d, emitted_base;
  logic [FrameRunBits-1:0] drop_limit_q, drop_limit_d;
  logic [FrameRunBits-1:0] drop_ovf_q, drop_ovf_d;
  logic                    limit_nz_q, ovf_nz_q, limit_nz_d, ovf_nz_d;  // counter != 0
  logic                    sticky_q, sticky_a, sticky_d;
  logic [CountBits-1:0]    high_water_q, high_water_d;
  ceilnav_pkg::word_t      trailers_lost_q, trailers_lost_d;

  assign emitted_base = sof_take ? '0 : emitted_q;
  assign emitted_d    = emitted_base + FrameRunBits'(r_en);
  assign drop_limit_d = (sof_take ? '0 : drop_limit_q) + FrameRunBits'(drop_limit);
  assign drop_ovf_d   = (sof_take ? '0 : drop_ovf_q) + FrameRunBits'(drop_ovf);
  assign limit_nz_d   = (~sof_take & limit_nz_q) | drop_limit;
  assign ovf_nz_d     = (~sof_take & ovf_nz_q) | drop_ovf;
  assign sticky_a     = a_req ? ~a_en : sticky_q;
  assign sticky_d     = t_req ? ~t_en : sticky_a;

  // Trailer rows: runs emitted, saturated to the 16-bit row field.
  localparam ceilnav_pkg::run_field_t RowMax = {FieldBits{1'b1}};
  function automatic ceilnav_pkg::run_field_t sat_row(logic [FrameRunBits-1:0] v);
    sat_row = v > FrameRunBits'(RowMax) ? RowMax : v[FieldBits-1:0];
  endfunction
  ceilnav_pkg::run_field_t a_row, t_row;
  ceilnav_pkg::run_flags_t a_flags, t_flags;
  // Both candidates from the register, the SOF and run choices last.
  ceilnav_pkg::run_field_t row_inc;
  assign a_row   = sat_row(emitted_q);
  assign row_inc = sat_row(emitted_q + FrameRunBits'(1));
  assign t_row   = sof_take ? FieldBits'(r_en) : r_en ? row_inc : a_row;
  assign a_flags.aborted   = 1'b1;
  assign a_flags.overflow  = ovf_nz_q | sticky_q;
  assign a_flags.row_limit = limit_nz_q;
  assign t_flags.aborted   = 1'b0;
  assign t_flags.overflow  = ovf_nz_d | sticky_a;
  assign t_flags.row_limit = limit_nz_d;

  // Saturating trailers_lost += lost (0..2). lost comes late: it is added to
  // the two low bits only, and their carry selects the upper 30 bits + 1,
  // which is computed from the register alone.
  logic        a_lost, t_lost;
  localparam int unsigned LoBits = 2;  // the low bits that take lost
  logic [LoBits-1:0]          lost;
  logic [LoBits:0]            lost_lo;
  logic [WordBits-1:LoBits]   lost_hi_inc;
  logic                       lost_hi_full;
  assign a_lost       = a_req & ~a_en;
  assign t_lost       = t_req & ~t_en;
  assign lost         = LoBits'(a_lost) + LoBits'(t_lost);
  assign lost_lo      = {1'b0, trailers_lost_q[LoBits-1:0]} + {1'b0, lost};
  assign lost_hi_inc  = trailers_lost_q[WordBits-1:LoBits] + (WordBits - LoBits)'(1);
  assign lost_hi_full = &trailers_lost_q[WordBits-1:LoBits];
  always_comb begin
    trailers_lost_d = {trailers_lost_q[WordBits-1:LoBits], lost_lo[LoBits-1:0]};
    if (lost_lo[LoBits]) begin
      trailers_lost_d = lost_hi_full ? {WordBits{1'b1}} : {lost_hi_inc, lost_lo[LoBits-1:0]};
    end
  end

  // ---------------------------------------------------------------------------
  // FIFO. Entries written on one edge go to consecutive addresses; A, R and T
  // all on one edge happen only for an early SOF whose pixel is a whole 1x1
  // frame with a run, and then T is the constant {row 1, flags 0} (the new
  // frame emitted its one run, dropped nothing, and A cleared the sticky
  // flag). That T is not stored: R carries impl_t and the output produces
  // the trailer after it. So at most two entries per edge: run_fifo's two
  // banks. The occupancy count_q counts beats (impl_t counts one).
  ceilnav_pkg::run_entry_t a_entry, r_entry, t_entry, slot0, slot1;
  logic [WrBits-1:0]       wr_count;
  logic [WrBits-1:0]       n_writes;
  logic                    three;
  assign three = a_en & r_en & t_en;
  // The trailers' don't-care fields repeat the run's, so that Yosys folds the
  // bank write muxes of those bits; the output zeroes them (tlast).
  // (Concatenations in field order: Yosys 0.23 reads no assignment patterns.)
  assign r_entry = {three, 1'b0, sum_w, run_end, start, FieldBits'(y)};
  assign a_entry = {2'b01, sum_w, run_end, CoordBits'(a_flags), a_row};
  assign t_entry = {2'b01, sum_w, run_end, CoordBits'(t_flags), t_row};
  assign slot0 = a_en ? a_entry : r_en ? r_entry : t_entry;
  assign slot1 = a_en & r_en ? r_entry : t_entry;
  assign n_writes = WrBits'(a_en) + WrBits'(r_en) + WrBits'(t_en);
  assign wr_count = n_writes - WrBits'(three);

  // Output: the read register of run_fifo is m_axis's data register; syn_q
  // marks the synthetic trailer after an impl_t run.
  logic                 out_valid_q, syn_q, out_load, pop, rd, syn_next;
  ceilnav_pkg::run_entry_t head;
  logic [SumXwBits-1:0] head_sum_xw;
  logic                 head_impl, head_last;
  assign out_load = ~out_valid_q | m_axis_runs_tready_i;
  assign pop      = out_load & (count_q != '0);
  assign syn_next = out_valid_q & ~syn_q & head_impl;  // the next beat is the synthetic trailer
  assign rd       = pop & ~syn_next;
  assign count_d  = count_q - CountBits'(pop) + CountBits'(n_writes);

  run_fifo #(
    .Depth(FifoDepth),
    .Width(EntryBits),
    .LateWidth(SumXwBits)
  ) u_fifo (
    .clk_i,
    .rst_ni,
    .wr_count_i(wr_count),
    .wr_data_i ({slot1, slot0}),
    .late_en_i (r_en),
    .late_slot_i(a_en),  // R is write 1 after an A, else write 0
    .late_data_i(sum_xw_last),
    .rd_i      (rd),
    .rdata_o   (head),
    .rdata_late_o(head_sum_xw)
  );

  // Largest occupancy after any edge from the SOF edge to the EOF edge. In an
  // open frame high_water_q >= count_q (between taken pixels the occupancy
  // only falls), so count_d > high_water_q iff the change of this edge,
  // n_writes - pop in -1 .. 3, exceeds the slack high_water_q - count_q: the
  // comparison needs only flags of the slack, computed from registers.
  logic [CountBits-1:0] hw_slack;
  logic                 slack_0, slack_le1, slack_le2, hw_rises;
  assign hw_slack  = high_water_q - count_q;
  assign slack_0   = hw_slack == '0;
  assign slack_le1 = hw_slack[CountBits-1:1] == '0;
  assign slack_le2 = slack_le1 || hw_slack == CountBits'(2);
  always_comb begin
    unique case ({n_writes, pop})
      3'b010, 3'b101: hw_rises = slack_0;    // +1
      3'b100, 3'b111: hw_rises = slack_le1;  // +2
      3'b110:         hw_rises = slack_le2;  // +3
      default:        hw_rises = 1'b0;       // -1, 0
    endcase
  end
  always_comb begin
    high_water_d = high_water_q;
    if (take && (sof || hw_rises)) high_water_d = count_d;
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

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      cfg_bg_q <= '0;  // RunScanConfig{} (unused until an SOF latches the port)
      cfg_min_len_q <= FieldBits'(1);
      cfg_max_runs_q <= FieldBits'(8);
      min_le1_q <= 1'b1;
      min_le2_q <= 1'b1;
      max_nz_q <= 1'b1;
      max_le1_q <= 1'b0;
      frame_open_q <= 1'b0;
      row_start_q <= 1'b1;
      prev_w_q <= '0;
      in_run_q <= 1'b0;
      run_start_q <= '0;
      run_sum_w_q <= '0;
      xw_q <= '0;
      xw_base_q <= '0;
      run_len_q <= '0;
      len_ge_q <= 1'b0;
      len1_ge_q <= 1'b0;
      row_runs_q <= '0;
      row_full_q <= 1'b0;
      emitted_q <= '0;
      drop_limit_q <= '0;
      drop_ovf_q <= '0;
      limit_nz_q <= 1'b0;
      ovf_nz_q <= 1'b0;
      high_water_q <= '0;
      stat_emitted_q <= '0;
      stat_drop_limit_q <= '0;
      stat_drop_ovf_q <= '0;
      stat_high_water_q <= '0;
      done_q <= 1'b0;
      sticky_q <= 1'b0;
      trailers_lost_q <= '0;
      count_q <= '0;
      out_valid_q <= 1'b0;
      syn_q <= 1'b0;
    end else begin
      frame_open_q <= frame_open_d;
      if (sof_take) begin
        cfg_bg_q <= cfg_background_level_i;
        cfg_min_len_q <= cfg_min_run_length_i;
        cfg_max_runs_q <= cfg_max_runs_per_row_i;
        min_le1_q <= min_le1;
        min_le2_q <= min_le2;
        max_nz_q <= max_nz;
        max_le1_q <= max_le1;
      end
      if (take) begin
        row_start_q <= s_lut_eol_i;
        in_run_q <= s_lut_mask_i & ~s_lut_eol_i;
        run_start_q <= start;
        run_sum_w_q <= sum_w;
        xw_q <= xw;
        xw_base_q <= xw_base_d;
        prev_w_q <= w;
        // Only read while the run goes on (in_run_q), so the run_len_q + 1 /
        // 1 choice need not look at the mask.
        run_len_q <= in_run ? run_len_inc : RunLenBits'(1);
        len_ge_q <= in_run ? len1_ge_q : min_le1;
        len1_ge_q <= in_run ? len2_ge_min : min_le2;
        row_runs_q <= row_runs_d;
        row_full_q <= row_full_d;
        emitted_q <= emitted_d;
        drop_limit_q <= drop_limit_d;
        drop_ovf_q <= drop_ovf_d;
        limit_nz_q <= limit_nz_d;
        ovf_nz_q <= ovf_nz_d;
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
      count_q <= count_d;
      if (out_load) begin
        out_valid_q <= pop;
        syn_q <= pop & syn_next;
      end
    end
  end

  // ---------------------------------------------------------------------------
  // Outputs. The entry fields a trailer does not use read as 0.
  logic                    head_ok, head_run;
  logic [SumWBits-1:0]     head_sum_w;
  ceilnav_pkg::coord_t     head_x_end, head_x_start;
  ceilnav_pkg::run_field_t head_row;
  assign head_impl    = head.impl_t;
  assign head_last    = head.last;
  assign head_sum_w   = head.sum_w;
  assign head_x_end   = head.x_end;
  assign head_x_start = head.x_start;
  assign head_row     = head.row;
  assign head_ok  = out_valid_q & ~syn_q;  // the beat is the entry read from run_fifo
  assign head_run = head_ok & ~head_last;

  assign m_axis_runs_tvalid_o = out_valid_q;
  assign m_axis_runs_tlast_o  = out_valid_q & (syn_q | head_last);
  logic [SumXwBits-1:0] out_sum_xw;
  logic [SumWBits-1:0]  out_sum_w;
  ceilnav_pkg::coord_t  out_x_end, out_x_start;
  ceilnav_pkg::run_field_t out_row;
  logic                 out_syn;
  ceilnav_pkg::run_beat_t out_beat;
  assign out_sum_xw  = head_sum_xw & {SumXwBits{head_run}};
  assign out_sum_w   = head_sum_w & {SumWBits{head_run}};
  assign out_x_end   = head_x_end & {CoordBits{head_run}};
  assign out_x_start = head_x_start & {CoordBits{head_ok}};
  assign out_syn     = out_valid_q & syn_q;
  assign out_row     = (head_row & {FieldBits{head_ok}}) | FieldBits'(out_syn);
  assign out_beat.x_end   = FieldBits'(out_x_end);
  assign out_beat.sum_xw  = WordBits'(out_sum_xw);
  assign out_beat.sum_w   = WordBits'(out_sum_w);
  assign out_beat.x_start = FieldBits'(out_x_start);
  assign out_beat.row     = out_row;
  assign m_axis_runs_tdata_o = out_beat;
  assign done_o                   = done_q;
  assign runs_emitted_o           = WordBits'(stat_emitted_q);
  assign runs_dropped_row_limit_o = WordBits'(stat_drop_limit_q);
  assign runs_dropped_overflow_o  = WordBits'(stat_drop_ovf_q);
  assign fifo_high_water_o        = WordBits'(stat_high_water_q);
  assign fifo_occupancy_o         = count_q;
  assign trailers_lost_o          = trailers_lost_q;

  // The camera pixel itself is not used: runs are of the LUT output.
  logic unused_grey;
  assign unused_grey = ^s_lut_grey_i;

`ifndef SYNTHESIS
  // Position counters, for the assertion only: the RTL uses pix.x/pix.y.
  ceilnav_pkg::coord_t  x_q, y_q;
  ceilnav_pkg::coord_t  x_cnt, y_cnt;
  ceilnav_pkg::run_beat_t tdata_q;
  logic                 tlast_q, stalled_q;
  assign x_cnt = sof ? '0 : x_q;
  assign y_cnt = sof ? '0 : y_q;
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      x_q <= '0;
      y_q <= '0;
      stalled_q <= 1'b0;
    end else begin
      if (take) begin
        x_q <= s_lut_eol_i ? '0 : x_cnt + CoordBits'(1);
        y_q <= s_lut_eol_i ? y_cnt + CoordBits'(1) : y_cnt;
      end
      stalled_q <= m_axis_runs_tvalid_o & ~m_axis_runs_tready_i;
      tdata_q <= m_axis_runs_tdata_o;
      tlast_q <= m_axis_runs_tlast_o;
    end
  end
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      // frame_check guarantees the pixel position; the counters must agree.
      if (take) begin
        assert (s_lut_x_i == x_cnt && s_lut_y_i == y_cnt)
        else $error("run_scanner: pixel (%0d, %0d) but counters (%0d, %0d)",
                    s_lut_x_i, s_lut_y_i, x_cnt, y_cnt);
        assert (row_start == (x_cnt == '0))
        else $error("run_scanner: row start flag wrong");
      end
      // Only frame_check's early SOF carries an abort and a pixel.
      assert (!(s_lut_abort_i && s_lut_valid_i) || sof)
      else $error("run_scanner: abort on a pixel that is not an SOF");
      // Three writes only with the constant trailer (see "FIFO" above).
      if (a_en && r_en && t_en) begin
        assert (t_row == FieldBits'(1) && t_flags == '0)
        else $error("run_scanner: three writes with a non-constant trailer");
      end
      assert ({1'b0, count_q} + (CountBits + 1)'(n_writes) <= (CountBits + 1)'(Depth))
      else $error("run_scanner: FIFO overflow");
    end
  end
  always_ff @(posedge clk_i) begin
    // AXI4-Stream: a beat that is not taken holds.
    if (rst_ni && stalled_q) begin
      assert (m_axis_runs_tvalid_o && m_axis_runs_tdata_o == tdata_q &&
              m_axis_runs_tlast_o == tlast_q)
      else $error("run_scanner: m_axis_runs changed while stalled");
    end
  end
`endif

endmodule
