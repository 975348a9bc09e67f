// edge_detect: the edge block of seed 002 eq. 17 (`edge` is a SystemVerilog
// keyword, hence the module name). A pixel of the LUT remap stream is an
// edge point if its horizontal difference |p(x,y) - p(x-1,y)|, its vertical
// difference |p(x,y) - p(x,y-1)| or its 3x3 Sobel magnitude |gx| + |gy|
// (interior window centres) exceeds a threshold; every edge point becomes
// one beat of m_axis_edges through a FIFO (run_fifo), with one trailer beat
// per frame. The edge test's result is staged for one edge before the FIFO
// admission (the event stage: the Sobel magnitude and the admission in
// separate cycles). Cycle model: stream/edge.{hpp,cpp}; spec: docs/blocks/edge.md.
//
// Inputs are assumed legal as frame_check/thresh_lut make them (the C++ model
// throws otherwise): pix.x/pix.y equal the block's own position counters, and
// a beat carrying both abort and a pixel is an SOF (early SOF). Both are
// checked by simulation assertions.
//
// m_axis_edges_tdata (pack_edge_beat() / pack_edge_trailer() in
// common/edge_record.hpp):
//   edge:    [15:0] x  [31:16] y  [43:32] magnitude  [44] polarity  [46:45] kind
//   trailer: [31:0] edges emitted  [32] overflow  [33] aborted  [63:48] dropped (sat.)

module edge_detect #(
  parameter int unsigned FifoDepth = 1024,  // edge FIFO entries, power of two, >= 8
  localparam int unsigned CountBits = $clog2(FifoDepth) + 1,
  localparam int unsigned ModeBits = 2,
  localparam int unsigned ThreshBits = 12,
  localparam int unsigned TdataBits = 2 * ceilnav_pkg::WordBits
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

  // Configuration (EDGE_CONTROL), latched at the SOF pixel.
  input  logic                  cfg_enable_i,
  input  logic [ModeBits-1:0]   cfg_mode_i,       // 0 horizontal, 1 vertical, 2 Sobel, 3 none
  input  logic [ThreshBits-1:0] cfg_threshold_i,  // edge: magnitude > threshold

  output logic                 m_axis_edges_tvalid_o,
  input  logic                 m_axis_edges_tready_i,
  output logic                 m_axis_edges_tlast_o,
  output logic [TdataBits-1:0] m_axis_edges_tdata_o,

  output logic                 done_o,  // one-cycle pulse: the stats were just updated
  output logic                 pending_o,  // an edge point or a trailer staged for the FIFO
  output ceilnav_pkg::word_t   edges_emitted_o,  // last completed frame
  output ceilnav_pkg::word_t   edges_dropped_o,
  output logic [CountBits-1:0] fifo_occupancy_o,
  output ceilnav_pkg::word_t   trailers_lost_o
);

  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned PixelBits = ceilnav_pkg::PixelBits;
  localparam int unsigned WordBits  = ceilnav_pkg::WordBits;
  localparam int unsigned WrBits    = ceilnav_pkg::FifoWrBits;
  // Widths from fixedpoint/datapath.hpp (namespace edge).
  localparam int unsigned GBits    = ceilnav_widths_pkg::EdgeGBits;      // Sobel gx, gy, signed
  localparam int unsigned SMagBits = ceilnav_widths_pkg::EdgeMagBits;    // |gx| + |gy| <= 2040
  localparam int unsigned CntBits  = ceilnav_widths_pkg::EdgeCountBits;  // edges per frame
  localparam int unsigned SumBits  = GBits - 1;       // a 1 2 1 weighted sum, <= 1020
  localparam int unsigned DiffBits = PixelBits + 1;   // p - q, signed
  localparam int unsigned FieldBits = ceilnav_pkg::RunFieldBits;  // x, y, dropped: 16 bits
  localparam int unsigned MagField = 12;   // beat magnitude[11:0]
  localparam int unsigned KindBits = 2;
  localparam int unsigned FlagBits = 2;    // trailer flags: overflow, aborted
  // FIFO entry {last, a, b}: edge a = {0, y, x}, b = {0, kind, polarity,
  // magnitude}; trailer a = edges emitted, b = {dropped (saturated), flags}.
  localparam int unsigned ABits = CntBits;
  localparam int unsigned BBits = FieldBits + FlagBits;
  localparam int unsigned EntryBits = 1 + ABits + BBits;

  localparam logic [ModeBits-1:0] ModeH = ModeBits'(0);
  localparam logic [ModeBits-1:0] ModeV = ModeBits'(1);
  localparam logic [ModeBits-1:0] ModeS = ModeBits'(2);

  if (FifoDepth < 8 || (FifoDepth & (FifoDepth - 1)) != 0) begin : g_bad_depth
    $fatal(1, "edge_detect: FifoDepth must be a power of two >= 8");
  end

  // ---------------------------------------------------------------------------
  // Frame and configuration. A frame is taken from an SOF pixel with
  // cfg_enable_i = 1 to its EOF pixel or an abort (line_window).
  logic                  frame_open_q, take, sof_take;
  logic [ModeBits-1:0]   mode_q, mode;
  logic [ThreshBits-1:0] thresh_q, thresh;
  assign mode     = s_lut_sof_i ? cfg_mode_i : mode_q;
  assign thresh   = s_lut_sof_i ? cfg_threshold_i : thresh_q;

  ceilnav_pkg::coord_t x, y;
  ceilnav_pkg::pixel_t p;
  assign x = s_lut_x_i;  // == the position counters (asserted in line_window)
  assign y = s_lut_y_i;
  assign p = s_lut_remap_i;

  // The taken frame and the line buffer (line_window): r1, r2 = p(x,y-1),
  // p(x,y-2) of this pixel's column; sr1, sr2 the same without the bypass of
  // one-pixel-wide frames.
  ceilnav_pkg::pixel_t r1, r2, sr1, sr2;
  line_window u_window (
    .clk_i,
    .rst_ni,
    .s_valid_i   (s_lut_valid_i),
    .s_x_i       (s_lut_x_i),
    .s_y_i       (s_lut_y_i),
    .s_sof_i     (s_lut_sof_i),
    .s_eol_i     (s_lut_eol_i),
    .s_eof_i     (s_lut_eof_i),
    .s_abort_i   (s_lut_abort_i),
    .s_remap_i   (s_lut_remap_i),
    .enable_i    (cfg_enable_i),
    .take_o      (take),
    .sof_take_o  (sof_take),
    .frame_open_o(frame_open_q),
    .r1_o        (r1),
    .r2_o        (r2),
    .sr1_o       (sr1),
    .sr2_o       (sr2)
  );

  // 3x3 window. Of columns x-2 and x-1 the block keeps what this pixel's
  // tests need, summed ahead on the edges that took those columns; the column
  // of this pixel is {r2, r1, p} (rows y-2, y-1, y):
  //   w1_top_q, w1_bot_q  p(x-1, y-2), p(x-1, y) (the horizontal difference's left pixel)
  //   s1_q, s2_q          t + 2 m + b of columns x-1, x-2
  //   dy_q                (b0 + 2 b1) - (t0 + 2 t1) of columns x-2 (0), x-1 (1)
  ceilnav_pkg::pixel_t w1_top_q, w1_bot_q;
  logic [SumBits-1:0]  s1_q, s2_q;
  logic [GBits-1:0]    dy_q, dy_d;

  // ---------------------------------------------------------------------------
  // Differences. Horizontal / vertical: d = p - left / p - up.
  logic [DiffBits-1:0]  diff;
  ceilnav_pkg::pixel_t  diff_mag;
  logic                 diff_rises;
  assign diff       = {1'b0, p} - {1'b0, mode == ModeV ? r1 : w1_bot_q};
  assign diff_mag   = diff[DiffBits-1] ? PixelBits'(-diff) : diff[PixelBits-1:0];
  assign diff_rises = ~diff[DiffBits-1] & (diff != '0);

  // Sobel on the window centred at (x-1, y-1), columns 0 (x-2), 1, 2 (x):
  //   gx = (t2 + 2 m2 + b2) - (t0 + 2 m0 + b0) = (r2 + 2 r1) + (p - s2_q),
  //   gy = (b0 + 2 b1 + b2) - (t0 + 2 t1 + t2) = (dy_q + p) - r2.
  // The line buffer's read data (the slow BRAM output) meets two adders for
  // gx and one for gy; p - s2_q and dy_q + p are formed alongside. They take
  // the read register itself, not the bypass: only a one-pixel-wide frame
  // reads through the bypass, and it has no Sobel centre.
  function automatic logic [SumBits-1:0] sum121(ceilnav_pkg::pixel_t a, ceilnav_pkg::pixel_t b,
                                                ceilnav_pkg::pixel_t c);
    sum121 = SumBits'(a) + SumBits'({b, 1'b0}) + SumBits'(c);
  endfunction
  logic [GBits-1:0]    gx, gy, gx_early, gy_early;
  logic [SMagBits-1:0] sobel_mag;
  logic                sobel_rises;
  assign gx_early    = GBits'(p) - GBits'(s2_q);
  assign gy_early    = dy_q + GBits'(p);
  assign gx          = GBits'(sr2) + GBits'({sr1, 1'b0}) + gx_early;
  assign gy          = gy_early - GBits'(sr2);
  // |gx|, |gy|: -gx, -gy are formed beside gx, gy from the same operands and
  // the sign picks one (a mux after the adders instead of a negation).
  logic [SumBits-1:0]  ngx, ngy, agx, agy;
  assign ngx         = SumBits'((GBits'(0) - gx_early) - (GBits'(sr2) + GBits'({sr1, 1'b0})));
  assign ngy         = SumBits'(GBits'(sr2) - gy_early);
  assign agx         = gx[GBits-1] ? ngx : gx[SumBits-1:0];
  assign agy         = gy[GBits-1] ? ngy : gy[SumBits-1:0];
  assign sobel_mag   = SMagBits'(agx) + SMagBits'(agy);
  assign sobel_rises = ~gx[GBits-1] & (gx != '0);
  // The next pixel's dy_q: this column is its column 1, column x-1 its column 0.
  assign dy_d = GBits'(w1_bot_q) + GBits'({p, 1'b0}) - GBits'(w1_top_q) - GBits'({r2, 1'b0});

  // The edge test. Sobel centres need x, y >= 2 (interior of the frame).
  logic                 in_range, is_sobel, hit;
  logic [MagField-1:0]  mag;
  logic                 rises;
  logic [KindBits-1:0]  kind;
  ceilnav_pkg::coord_t  ex, ey;
  assign is_sobel = mode == ModeS;
  always_comb begin
    unique case (mode)
      ModeH:   in_range = x != '0;
      ModeV:   in_range = y != '0;
      ModeS:   in_range = (x[CoordBits-1:1] != '0) & (y[CoordBits-1:1] != '0);
      default: in_range = 1'b0;  // reserved: no edges
    endcase
  end
  assign mag   = is_sobel ? MagField'(sobel_mag) : MagField'(diff_mag);
  assign rises = is_sobel ? sobel_rises : diff_rises;
  assign kind  = is_sobel ? KindBits'(2) : KindBits'(mode == ModeV);
  assign ex    = is_sobel ? x - CoordBits'(1) : x;
  assign ey    = is_sobel ? y - CoordBits'(1) : y;
  // The threshold compare before the mode's choice (one compare per source).
  assign hit   = take & in_range &
                 (is_sobel ? ThreshBits'(sobel_mag) > thresh : ThreshBits'(diff_mag) > thresh);

  // ---------------------------------------------------------------------------
  // Event stage: what the pixel (or abort) sampled on edge n asks of the FIFO
  // is registered on edge n and admitted on edge n + 1 (the Sobel magnitude
  // and the threshold compare in one cycle, the admission and the counters
  // in the next). The stage is never stalled: it holds the events of the
  // last edge only, and the admission below is that of the events' own edge,
  // one edge later.
  logic                 ev_a_req_q, ev_hit_q, ev_t_req_q, ev_sof_q;
  logic [MagField-1:0]  ev_mag_q;
  logic                 ev_rises_q;
  logic [KindBits-1:0]  ev_kind_q;
  ceilnav_pkg::coord_t  ev_x_q, ev_y_q;
  // The staged edge point's fields: a data pipeline qualified by ev_hit_q.
  always_ff @(posedge clk_i) begin
    ev_mag_q   <= mag;
    ev_rises_q <= rises;
    ev_kind_q  <= kind;
    ev_x_q     <= ex;
    ev_y_q     <= ey;
  end

  // ---------------------------------------------------------------------------
  // Admission of the staged events. Writes per edge: aborted-frame trailer
  // (A) or edge (E) -- never both: A comes only with no pixel or an SOF
  // pixel, which is no edge -- then the end-of-frame trailer (T); against the
  // pre-edge occupancy n: A if n < depth, E if n + 1 < depth (one entry stays
  // free for the trailer), T if n + A + E < depth.
  logic [CountBits-1:0] count_q, count_d;  // FIFO entries, not counting the output register
  logic                 n_lt_d, n_lt_dm1;
  logic                 a_req, a_en, e_en, t_req, t_en, drop;
  assign n_lt_d   = ~count_q[CountBits-1];
  assign n_lt_dm1 = n_lt_d & ~(&count_q[CountBits-2:0]);
  assign a_req    = ev_a_req_q;
  assign a_en     = a_req & n_lt_d;
  assign e_en     = ev_hit_q & n_lt_dm1;
  assign drop     = ev_hit_q & ~n_lt_dm1;
  assign t_req    = ev_t_req_q;
  assign t_en     = t_req & (a_en | e_en ? n_lt_dm1 : n_lt_d);

  logic [CntBits-1:0] emitted_q, emitted_d, dropped_q, dropped_d;
  logic               sticky_q, sticky_a, sticky_d;
  assign emitted_d = (ev_sof_q ? '0 : emitted_q) + CntBits'(e_en);
  assign dropped_d = (ev_sof_q ? '0 : dropped_q) + CntBits'(drop);
  assign sticky_a  = a_req ? ~a_en : sticky_q;
  assign sticky_d  = t_req ? ~t_en : sticky_a;

  // v saturated to 16 bits (an OR of the high bits, not a compare: the
  // dropped count's path into the trailer is the admission's longest).
  function automatic logic [FieldBits-1:0] sat16(logic [CntBits-1:0] v);
    sat16 = |v[CntBits-1:FieldBits] ? {FieldBits{1'b1}} : v[FieldBits-1:0];
  endfunction
  logic [EntryBits-1:0] a_entry, e_entry, t_entry, slot0;
  assign a_entry = {1'b1, emitted_q, sat16(dropped_q), 1'b1, (dropped_q != '0) | sticky_q};
  assign t_entry = {1'b1, emitted_d, sat16(dropped_d), 1'b0, (dropped_d != '0) | sticky_a};
  assign e_entry = {1'b0, 1'b0, ev_y_q, ev_x_q, (BBits - MagField - 1 - KindBits)'(0), ev_kind_q,
                    ev_rises_q, ev_mag_q};
  assign slot0   = a_en ? a_entry : e_en ? e_entry : t_entry;

  logic [WrBits-1:0] n_writes;
  assign n_writes = WrBits'(a_en) + WrBits'(e_en) + WrBits'(t_en);

  // Saturating trailers_lost += lost (0 .. 2).
  ceilnav_pkg::word_t trailers_lost_q;
  logic [WordBits:0]  lost_sum;
  logic               a_lost, t_lost;
  assign a_lost   = a_req & ~a_en;
  assign t_lost   = t_req & ~t_en;
  assign lost_sum = {1'b0, trailers_lost_q} + (WordBits + 1)'(a_lost) + (WordBits + 1)'(t_lost);

  // ---------------------------------------------------------------------------
  // FIFO (run_fifo, no late field): its read register is the output register.
  logic                 out_valid_q, out_load, pop;
  logic [EntryBits-1:0] head;
  logic                 late_unused;
  assign out_load = ~out_valid_q | m_axis_edges_tready_i;
  assign pop      = out_load & (count_q != '0);
  assign count_d  = count_q - CountBits'(pop) + CountBits'(n_writes);

  run_fifo #(
    .Depth(FifoDepth),
    .Width(EntryBits),
    .LateWidth(1)
  ) u_fifo (
    .clk_i,
    .rst_ni,
    .wr_count_i  (n_writes),
    .wr_data_i   ({t_entry, slot0}),
    .late_en_i   (1'b0),
    .late_slot_i (1'b0),
    .late_data_i (1'b0),
    .rd_i        (pop),
    .rdata_o     (head),
    .rdata_late_o(late_unused)
  );

  // ---------------------------------------------------------------------------
  // Registers.
  logic [CntBits-1:0] stat_emitted_q, stat_dropped_q;
  logic               done_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      mode_q <= ModeH;  // EdgeConfig{} (unused until an SOF latches the port)
      thresh_q <= ThreshBits'(32);
      w1_top_q <= '0;
      w1_bot_q <= '0;
      s1_q <= '0;
      s2_q <= '0;
      dy_q <= '0;
      ev_a_req_q <= 1'b0;
      ev_hit_q <= 1'b0;
      ev_t_req_q <= 1'b0;
      ev_sof_q <= 1'b0;
      emitted_q <= '0;
      dropped_q <= '0;
      sticky_q <= 1'b0;
      trailers_lost_q <= '0;
      stat_emitted_q <= '0;
      stat_dropped_q <= '0;
      done_q <= 1'b0;
      count_q <= '0;
      out_valid_q <= 1'b0;
    end else begin
      if (sof_take) begin
        mode_q <= cfg_mode_i;
        thresh_q <= cfg_threshold_i;
      end
      if (take) begin
        w1_top_q <= r2;
        w1_bot_q <= p;
        s2_q <= s1_q;
        s1_q <= sum121(r2, r1, p);
        dy_q <= dy_d;
      end
      ev_a_req_q <= s_lut_abort_i & frame_open_q;
      ev_hit_q <= hit;
      ev_t_req_q <= take & s_lut_eof_i;
      ev_sof_q <= sof_take;
      emitted_q <= emitted_d;  // changes only with a staged edge or SOF
      dropped_q <= dropped_d;
      sticky_q <= sticky_d;
      trailers_lost_q <= lost_sum[WordBits] ? {WordBits{1'b1}} : lost_sum[WordBits-1:0];
      if (t_req) begin
        stat_emitted_q <= emitted_d;
        stat_dropped_q <= dropped_d;
      end
      done_q <= t_req;
      count_q <= count_d;
      if (out_load) out_valid_q <= pop;
    end
  end

  // ---------------------------------------------------------------------------
  // Outputs: the entry laid out as the beat; 0 while no beat is valid.
  logic                 head_last;
  logic [ABits-1:0]     head_a;
  logic [BBits-1:0]     head_b;
  logic [WordBits-1:0]  word0, word1;
  assign {head_last, head_a, head_b} = head;
  always_comb begin
    if (head_last) begin
      word0 = WordBits'(head_a);
      word1 = {head_b[BBits-1:FlagBits], (WordBits - FieldBits - FlagBits)'(0),
               head_b[FlagBits-1:0]};
    end else begin
      word0 = {(FieldBits - CoordBits)'(0), head_a[2*CoordBits-1:CoordBits],
               (FieldBits - CoordBits)'(0), head_a[CoordBits-1:0]};
      word1 = WordBits'(head_b[MagField+KindBits:0]);
    end
  end
  assign m_axis_edges_tvalid_o = out_valid_q;
  assign m_axis_edges_tlast_o  = out_valid_q & head_last;
  assign m_axis_edges_tdata_o  = {word1, word0} & {TdataBits{out_valid_q}};
  assign done_o           = done_q;
  assign pending_o        = ev_a_req_q | ev_hit_q | ev_t_req_q;
  assign edges_emitted_o  = WordBits'(stat_emitted_q);
  assign edges_dropped_o  = WordBits'(stat_dropped_q);
  assign fifo_occupancy_o = count_q;
  assign trailers_lost_o  = trailers_lost_q;

  // Edges are of the LUT remap: the camera pixel and the mask are not used;
  // run_fifo's late field is not used.
  logic unused;
  assign unused = ^{s_lut_grey_i, s_lut_mask_i, late_unused};

`ifndef SYNTHESIS
  // (The pixel position and the line buffer's read are checked in line_window.)
  logic [TdataBits-1:0] tdata_q;
  logic                 tlast_q, stalled_q;
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      stalled_q <= 1'b0;
    end else begin
      stalled_q <= m_axis_edges_tvalid_o & ~m_axis_edges_tready_i;
      tdata_q <= m_axis_edges_tdata_o;
      tlast_q <= m_axis_edges_tlast_o;
    end
  end
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      // Only frame_check's early SOF carries an abort and a pixel.
      assert (!(s_lut_abort_i && s_lut_valid_i) || s_lut_sof_i)
      else $error("edge_detect: abort on a pixel that is not an SOF");
      assert (!(a_en && e_en))
      else $error("edge_detect: an aborted-frame trailer and an edge on one edge");
      assert ({1'b0, count_q} + (CountBits + 1)'(n_writes) <= (CountBits + 1)'(FifoDepth))
      else $error("edge_detect: FIFO overflow");
    end
  end
  always_ff @(posedge clk_i) begin
    // AXI4-Stream: a beat that is not taken holds.
    if (rst_ni && stalled_q) begin
      assert (m_axis_edges_tvalid_o && m_axis_edges_tdata_o == tdata_q &&
              m_axis_edges_tlast_o == tlast_q)
      else $error("edge_detect: m_axis_edges changed while stalled");
    end
  end
`endif

endmodule
