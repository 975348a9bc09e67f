// orientation: the major-orientation histogram of seed 004's FindOrientation.
// Every interior pixel's 3x3 Sobel gradient of the LUT remap stream votes
// its weight (alpha-max-beta-min) into the bin of its angle folded modulo
// 90 degrees, found by a quadrant and an octant fold, a 9-bit restoring
// division min / max and an arctangent table (fixedpoint/orientation.hpp,
// through ceilnav_widths_pkg). Two BRAM banks: one accumulates the open
// frame (read-modify-write with forwarding), the other holds the published
// histogram for the read port; a publication swaps them and the new
// accumulating bank is cleared by a sweep of one bin per clock. A vote that
// meets the sweep is dropped and its frame is not published (skipped).
// Cycle model: stream/orientation.{hpp,cpp}; spec: docs/blocks/orientation.md.
//
// Inputs are assumed legal as frame_check/thresh_lut make them (the C++ model
// throws otherwise): pix.x/pix.y equal the block's own position counters
// (asserted in line_window, the taken frame and the line buffer shared with
// edge_detect), and a beat carrying both abort and a pixel is an SOF (early
// SOF; asserted here).
//
// Pipeline (one pixel per clock, never stalled), registers after the edge
// that takes the pixel: A gradient, F fold, B weight + threshold, C1..C3
// the division (3 quotient bits each), D table read, E bin; the read stage
// reads the accumulating bank at E's bin, the write stage (W) writes the sum
// on the next edge and publishes the frame at its EOF: done_o rises 9 edges
// after the EOF pixel's.

module orientation #(
  parameter int unsigned Bins = 90,  // 2 .. 256 bins over [0, 90) degrees
  localparam int unsigned BinIdxBits = 8,
  localparam int unsigned ThreshBits = ceilnav_widths_pkg::OriThreshBits,
  localparam int unsigned BinBits = ceilnav_widths_pkg::OriBinBits
) (
  input  logic                  clk_i,
  input  logic                  rst_ni,

  // s_lut: pixel beat from thresh_lut (LutBeat).
  input  logic                  s_lut_valid_i,
  input  ceilnav_pkg::pixel_t   s_lut_grey_i,
  input  ceilnav_pkg::coord_t   s_lut_x_i,
  input  ceilnav_pkg::coord_t   s_lut_y_i,
  input  logic                  s_lut_sof_i,
  input  logic                  s_lut_eol_i,
  input  logic                  s_lut_eof_i,
  input  logic                  s_lut_abort_i,
  input  ceilnav_pkg::pixel_t   s_lut_remap_i,
  input  logic                  s_lut_mask_i,

  // Configuration, latched at the SOF pixel.
  input  logic                  cfg_enable_i,
  input  logic [ThreshBits-1:0] cfg_threshold_i,  // a gradient votes if its weight > threshold

  // Read port of the published histogram (BRAM style: data after the edge).
  input  logic                  hist_rd_en_i,
  input  logic [BinIdxBits-1:0] hist_rd_bin_i,
  output logic [BinBits-1:0]    hist_rd_data_o,  // 0 after an edge without a read

  output logic                  done_o,           // one-cycle pulse: a frame was published
  output logic                  results_valid_o,  // a frame was published since reset
  output logic                  clearing_o,       // the accumulating bank is being swept
  output ceilnav_pkg::word_t    frame_votes_o,    // votes of the last published frame
  output ceilnav_pkg::word_t    frames_o,         // published since reset (saturating)
  output ceilnav_pkg::word_t    frames_skipped_o  // ended unpublished (saturating)
);

  localparam int unsigned CoordBits  = ceilnav_pkg::CoordBits;
  localparam int unsigned WordBits   = ceilnav_pkg::WordBits;
  // Widths from fixedpoint/orientation.hpp.
  localparam int unsigned GBits      = ceilnav_widths_pkg::OriGradBits;    // gx, gy, signed
  localparam int unsigned AbsBits    = ceilnav_widths_pkg::OriAbsBits;     // |gx|, |gy| <= 1020
  localparam int unsigned DivBits    = ceilnav_widths_pkg::OriDivBits;     // quotient bits after 1
  localparam int unsigned AngleFrac  = ceilnav_widths_pkg::OriAngleFrac;   // phi: u0.12 of 90 deg
  localparam int unsigned AtanBits   = ceilnav_widths_pkg::OriAtanBits;
  localparam int unsigned AtanEntries = ceilnav_widths_pkg::OriAtanEntries;
  localparam int unsigned WeightBits = ceilnav_widths_pkg::OriWeightBits;
  localparam int unsigned SumBits    = GBits - 1;          // a 1 2 1 weighted sum, <= 1020
  localparam int unsigned RemBits    = AbsBits + 1;        // 2 x remainder < 2040
  localparam int unsigned QBits      = DivBits + 1;        // floor(m 2^9 / M) <= 512
  localparam int unsigned QrBits     = QBits - 1;          // round(m 2^8 / M) <= 256
  localparam int unsigned AtanAddrBits = $clog2(AtanEntries);
  localparam int unsigned PhiBits    = AngleFrac + 1;      // phi <= 4096
  localparam int unsigned W8Bits     = AbsBits + 4;        // 7 M + 4 m + 4 <= 11224
  localparam int unsigned ProdBits   = PhiBits + BinIdxBits + 1;  // phi Bins + 2048
  localparam int unsigned KBits      = ProdBits - AngleFrac;
  localparam int unsigned DivStages  = 3;
  localparam int unsigned StepsPerStage = DivBits / DivStages;
  localparam logic [BinIdxBits-1:0] LastBin = BinIdxBits'(Bins - 1);
  localparam int unsigned MemAddrBits = $clog2(Bins);  // bank addresses

  if (Bins < 2 || Bins > (1 << BinIdxBits)) begin : g_bad_bins
    $fatal(1, "orientation: Bins must be 2 .. 256");
  end
  if (StepsPerStage * DivStages != DivBits) begin : g_bad_div
    $fatal(1, "orientation: the division's bits must split evenly over its stages");
  end

  // ---------------------------------------------------------------------------
  // Frame and configuration. A frame is taken from an SOF pixel with
  // cfg_enable_i = 1 to its EOF pixel or an abort (line_window).
  logic                  frame_open_q, take, sof_take;
  logic [ThreshBits-1:0] thresh_q;

  ceilnav_pkg::coord_t x, y;
  ceilnav_pkg::pixel_t p;
  assign x = s_lut_x_i;  // == the position counters (asserted in line_window)
  assign y = s_lut_y_i;
  assign p = s_lut_remap_i;

  // The taken frame and the line buffer, as edge_detect's (line_window):
  // r1, r2 = p(x,y-1), p(x,y-2) of this pixel's column.
  ceilnav_pkg::pixel_t r1, r2, sr1_unused, sr2_unused;
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
    .sr1_o       (sr1_unused),
    .sr2_o       (sr2_unused)
  );

  // 3x3 window: columns x-2 (0), x-1 (1) registered, column x = {r2, r1, p}.
  ceilnav_pkg::pixel_t t0_q, m0_q, b0_q, t1_q, m1_q, b1_q;
  logic [GBits-1:0]    gx, gy;
  logic                interior;
  function automatic logic [SumBits-1:0] sum121(ceilnav_pkg::pixel_t a, ceilnav_pkg::pixel_t b,
                                                ceilnav_pkg::pixel_t c);
    sum121 = SumBits'(a) + SumBits'({b, 1'b0}) + SumBits'(c);
  endfunction
  assign gx = GBits'(sum121(r2, r1, p)) - GBits'(sum121(t0_q, m0_q, b0_q));
  assign gy = GBits'(sum121(b0_q, b1_q, p)) - GBits'(sum121(t0_q, t1_q, r2));
  assign interior = (x > CoordBits'(1)) & (y > CoordBits'(1));

  // ---------------------------------------------------------------------------
  // Stage A: the gradient and the pixel's frame events.
  logic             a_int_q, a_sof_q, a_eof_q, a_abort_q;
  logic [GBits-1:0] a_gx_q, a_gy_q;

  // Stage F: quadrant fold (u, v) = (|gx|, |gy|) in quadrants 1 and 3, else
  // (|gy|, |gx|); octant fold M = max, m = min, upper = v > u. The threshold
  // of the pixel's frame travels with it from here (thresh_q is the next
  // frame's from the edge after its SOF pixel).
  logic                  gx_neg, gy_neg, gx_zero, gy_zero, same, upper, ibit;
  logic [AbsBits-1:0]    ax, ay, u, v, gmax, gmin;  // M = gmax, m = gmin
  logic [W8Bits-1:0]     w8, w7, wsum;
  logic [WeightBits-1:0] weight;
  assign gx_neg  = a_gx_q[GBits-1];
  assign gy_neg  = a_gy_q[GBits-1];
  assign gx_zero = a_gx_q == '0;
  assign gy_zero = a_gy_q == '0;
  assign ax      = gx_neg ? AbsBits'(-a_gx_q) : a_gx_q[AbsBits-1:0];
  assign ay      = gy_neg ? AbsBits'(-a_gy_q) : a_gy_q[AbsBits-1:0];
  assign same    = (~gx_neg & ~gx_zero & ~gy_neg) | (gx_neg & (gy_neg | gy_zero));
  assign u       = same ? ax : ay;
  assign v       = same ? ay : ax;
  assign upper   = v > u;
  assign gmax    = upper ? v : u;
  assign gmin    = upper ? u : v;

  logic                  f_int_q, f_sof_q, f_eof_q, f_abort_q, f_upper_q;
  logic [AbsBits-1:0]    f_max_q, f_min_q;
  logic [ThreshBits-1:0] f_thresh_q;

  // Stage B: the weight (max(8 M, 7 M + 4 m) + 4) >> 3 and the threshold; the
  // division's integer bit (m == M: then the remainder and every further bit
  // are 0).
  assign w8      = {1'b0, f_max_q, 3'b000};
  assign w7      = W8Bits'(f_max_q) * W8Bits'(7) + {2'b00, f_min_q, 2'b00};
  assign wsum    = (w8 > w7 ? w8 : w7) + W8Bits'(4);
  assign weight  = wsum[W8Bits-1:3];
  assign ibit    = f_min_q == f_max_q;

  // The sideband of a vote through stages B..E: {vote, weight, upper, sof,
  // eof, aborted}.
  localparam int unsigned SideBits = WeightBits + 5;
  typedef struct packed {
    logic                  vote;
    logic [WeightBits-1:0] weight;
    logic                  upper;
    logic                  sof;
    logic                  eof;
    logic                  aborted;
  } side_t;

  side_t              b_side_q;
  logic [AbsBits-1:0] b_big_q;
  logic [RemBits-1:0] b_rem_q;
  logic               b_q_q;

  // Stages C1..C3: the restoring division, StepsPerStage bits each:
  // rem = 2 rem; if rem >= M: rem -= M, bit 1. Stage s at [s W +: W].
  logic [DivStages*SideBits-1:0] c_side_q, c_side_in;
  logic [DivStages*AbsBits-1:0]  c_big_q, c_big_in;
  logic [DivStages*RemBits-1:0]  c_rem_q, c_rem_in, c_rem_out;
  logic [DivStages*QBits-1:0]    c_q_q, c_q_in, c_q_out;
  logic [SideBits-1:0]           c_side_last;
  logic [QBits-1:0]              c_q_last;

  assign c_side_in = {c_side_q[(DivStages-1)*SideBits-1:0], b_side_q};
  assign c_big_in  = {c_big_q[(DivStages-1)*AbsBits-1:0], b_big_q};
  assign c_rem_in  = {c_rem_q[(DivStages-1)*RemBits-1:0], b_rem_q};
  assign c_q_in    = {c_q_q[(DivStages-1)*QBits-1:0], QBits'(b_q_q)};
  assign c_side_last = c_side_q[(DivStages-1)*SideBits +: SideBits];
  assign c_q_last    = c_q_q[(DivStages-1)*QBits +: QBits];

  for (genvar s = 0; s < DivStages; s++) begin : g_div
    logic [AbsBits-1:0] m_big;
    assign m_big = c_big_in[s*AbsBits +: AbsBits];
    always_comb begin : div_step
      logic [RemBits-1:0] r, twice;
      logic [QBits-1:0]   q;
      r = c_rem_in[s*RemBits +: RemBits];
      q = c_q_in[s*QBits +: QBits];
      for (int i = 0; i < StepsPerStage; i++) begin
        twice = {r[RemBits-2:0], 1'b0};
        if (twice >= RemBits'(m_big)) begin
          r = twice - RemBits'(m_big);
          q = {q[QBits-2:0], 1'b1};
        end else begin
          r = twice;
          q = {q[QBits-2:0], 1'b0};
        end
      end
      c_rem_out[s*RemBits +: RemBits] = r;
      c_q_out[s*QBits +: QBits] = q;
    end
  end

  // Stage D: q = (Q + 1) >> 1 (round to nearest), the table read (BRAM/ROM);
  // q = 256 is 45 degrees, not in the table.
  logic [QBits-1:0]        q_inc;
  logic [QrBits-1:0]       q_round;
  logic [AtanBits-1:0]     atan_rom [AtanEntries];
  logic [AtanBits-1:0]     d_atan_q;
  logic                    d_half_q;
  side_t                   d_side_q;
  initial begin
    for (int i = 0; i < AtanEntries; i++) begin
      atan_rom[i] = ceilnav_widths_pkg::OriAtan[AtanBits*i +: AtanBits];
    end
  end
  assign q_inc   = c_q_last + QBits'(1);
  assign q_round = q_inc[QBits-1:1];
  always_ff @(posedge clk_i) begin
    d_atan_q <= atan_rom[q_round[AtanAddrBits-1:0]];
  end

  // Stage E: phi = t or 4096 - t (upper octant), bin = round(phi Bins / 4096)
  // mod Bins.
  logic [PhiBits-1:0]    t, phi;
  logic [ProdBits-1:0]   prod;
  logic [KBits-1:0]      k;
  logic [BinIdxBits-1:0] bin;
  assign t    = d_half_q ? PhiBits'(1 << (AngleFrac - 1)) : PhiBits'(d_atan_q);
  assign phi  = d_side_q.upper ? PhiBits'(1 << AngleFrac) - t : t;
  assign prod = ProdBits'(phi) * ProdBits'(Bins) + ProdBits'(1 << (AngleFrac - 1));
  assign k    = prod[ProdBits-1:AngleFrac];
  assign bin  = k == KBits'(Bins) ? '0 : k[BinIdxBits-1:0];

  side_t                 e_side_q;
  logic [BinIdxBits-1:0] e_bin_q;

  // ---------------------------------------------------------------------------
  // Histogram. Read stage (E): the vote is read from the accumulating bank,
  // or dropped while the sweep clears it. Write stage (W): the saturating sum
  // (forwarded when the last vote wrote the same bin), and the frame's
  // publication at its EOF: the banks swap, the new accumulating bank is
  // swept; a frame with a dropped vote, one that ends while the sweep runs
  // and an aborted one are not published and their bank is swept.
  logic                  acc_q, res_valid_q, sweep_busy_q;
  logic [BinIdxBits-1:0] sweep_ptr_q;
  logic                  p_accept, p_drop;
  logic                  w_vote_q, w_eof_q, w_abort_q, w_bank_q;
  logic [BinIdxBits-1:0] w_bin_q;
  logic [WeightBits-1:0] w_weight_q;
  logic                  fwd_q;
  logic [BinBits-1:0]    fwd_data_q, w_base, w_new;
  logic [BinBits:0]      w_sum;
  logic                  publish, skip, sweep_start;
  logic [2*BinBits-1:0]  bank_rd_q;  // bank b at [b BinBits +: BinBits]
  logic                  rd_valid_q, rd_bank_q, rd_in_range;
  logic [MemAddrBits-1:0] rd_addr;

  assign p_accept    = e_side_q.vote & ~sweep_busy_q;
  assign p_drop      = e_side_q.vote & sweep_busy_q;
  assign w_base      = fwd_q ? fwd_data_q : bank_rd_q[32'(w_bank_q) * BinBits +: BinBits];
  assign w_sum       = {1'b0, w_base} + (BinBits + 1)'(w_weight_q);
  assign w_new       = w_sum[BinBits] ? {BinBits{1'b1}} : w_sum[BinBits-1:0];
  assign publish     = w_eof_q & ~w_abort_q & ~sweep_busy_q & ~dropped_q;
  assign skip        = w_eof_q & ~publish;
  assign sweep_start = w_abort_q | w_eof_q;
  assign rd_in_range = {1'b0, hist_rd_bin_i} < (BinIdxBits + 1)'(Bins);
  assign rd_addr     = rd_in_range ? MemAddrBits'(hist_rd_bin_i) : '0;

  for (genvar b = 0; b < 2; b++) begin : g_bank
    (* ram_style = "block" *) logic [BinBits-1:0] mem [Bins];
    // Configuration contents: zeros (as the C++ model's banks).
    initial begin
      for (int i = 0; i < Bins; i++) begin
        mem[i] = '0;
      end
    end
    logic                  is_acc, rd_en, wr_en;
    logic [MemAddrBits-1:0] raddr, waddr;
    assign is_acc = acc_q == 1'(b);
    assign rd_en  = is_acc ? p_accept : hist_rd_en_i;
    assign raddr  = is_acc ? MemAddrBits'(e_bin_q) : rd_addr;
    // No write on an edge in reset (the registers may hold anything there).
    assign wr_en  = rst_ni && is_acc && (w_vote_q || sweep_busy_q);
    assign waddr  = MemAddrBits'(w_vote_q ? w_bin_q : sweep_ptr_q);
    always_ff @(posedge clk_i) begin
      if (wr_en) begin
        mem[waddr] <= w_vote_q ? w_new : '0;
      end
      if (rd_en) begin
        bank_rd_q[b*BinBits +: BinBits] <= mem[raddr];
      end
    end
  end

  // Frame counters at the read stage: accepted votes, a dropped vote.
  ceilnav_pkg::word_t votes_q, votes_d, stat_votes_q, frames_q, skipped_q;
  logic               dropped_q, dropped_d;
  logic               done_q;
  assign votes_d   = (e_side_q.sof ? '0 : votes_q) + WordBits'(p_accept);
  assign dropped_d = (e_side_q.sof ? 1'b0 : dropped_q) | p_drop;

  function automatic ceilnav_pkg::word_t sat_inc(ceilnav_pkg::word_t c);
    sat_inc = &c ? c : c + WordBits'(1);
  endfunction

  // ---------------------------------------------------------------------------
  // Registers.
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      thresh_q <= ThreshBits'(16);  // OrientationConfig{} (unused until an SOF latches the port)
      a_int_q <= 1'b0;
      a_sof_q <= 1'b0;
      a_eof_q <= 1'b0;
      a_abort_q <= 1'b0;
      f_int_q <= 1'b0;
      f_sof_q <= 1'b0;
      f_eof_q <= 1'b0;
      f_abort_q <= 1'b0;
      b_side_q <= '0;
      c_side_q <= '0;
      d_side_q <= '0;
      e_side_q <= '0;
      w_vote_q <= 1'b0;
      w_eof_q <= 1'b0;
      w_abort_q <= 1'b0;
      fwd_q <= 1'b0;
      acc_q <= 1'b0;
      res_valid_q <= 1'b0;
      sweep_busy_q <= 1'b1;  // the accumulating bank may hold a partial frame
      sweep_ptr_q <= '0;
      votes_q <= '0;
      dropped_q <= 1'b0;
      stat_votes_q <= '0;
      frames_q <= '0;
      skipped_q <= '0;
      done_q <= 1'b0;
      rd_valid_q <= 1'b0;
    end else begin
      if (sof_take) thresh_q <= cfg_threshold_i;
      // A
      a_int_q <= take & interior;
      a_sof_q <= sof_take;
      a_eof_q <= take & s_lut_eof_i;
      a_abort_q <= s_lut_abort_i & frame_open_q;
      // F
      f_int_q <= a_int_q;
      f_sof_q <= a_sof_q;
      f_eof_q <= a_eof_q;
      f_abort_q <= a_abort_q;
      // B
      b_side_q.vote <= f_int_q & (ThreshBits'(weight) > f_thresh_q);
      b_side_q.weight <= weight;
      b_side_q.upper <= f_upper_q;
      b_side_q.sof <= f_sof_q;
      b_side_q.eof <= f_eof_q;
      b_side_q.aborted <= f_abort_q;
      // C1..C3, D, E
      c_side_q <= c_side_in;
      d_side_q <= c_side_last;
      e_side_q <= d_side_q;
      // Read and write stages.
      w_vote_q <= p_accept;
      w_eof_q <= e_side_q.eof;
      w_abort_q <= e_side_q.aborted;
      fwd_q <= p_accept & w_vote_q & (e_bin_q == w_bin_q);
      votes_q <= votes_d;
      dropped_q <= dropped_d;
      acc_q <= acc_q ^ publish;
      if (publish) begin
        res_valid_q <= 1'b1;
        stat_votes_q <= votes_q;
        frames_q <= sat_inc(frames_q);
      end
      if (skip) skipped_q <= sat_inc(skipped_q);
      done_q <= publish;
      if (sweep_start) begin
        sweep_busy_q <= 1'b1;
        sweep_ptr_q <= '0;
      end else if (sweep_busy_q) begin
        sweep_busy_q <= sweep_ptr_q != LastBin;
        sweep_ptr_q <= sweep_ptr_q + BinIdxBits'(1);
      end
      rd_valid_q <= hist_rd_en_i & res_valid_q & rd_in_range;
    end
  end

  // Data registers: qualified by the valid and event bits above.
  always_ff @(posedge clk_i) begin
    if (take) begin
      t0_q <= t1_q;
      m0_q <= m1_q;
      b0_q <= b1_q;
      t1_q <= r2;
      m1_q <= r1;
      b1_q <= p;
    end
    a_gx_q <= gx;
    a_gy_q <= gy;
    f_upper_q <= upper;
    f_max_q <= gmax;
    f_min_q <= gmin;
    f_thresh_q <= thresh_q;
    b_big_q <= f_max_q;
    b_rem_q <= ibit ? '0 : RemBits'(f_min_q);
    b_q_q <= ibit;
    c_big_q <= c_big_in;
    c_rem_q <= c_rem_out;
    c_q_q <= c_q_out;
    d_half_q <= q_round[QrBits-1];
    e_bin_q <= bin;
    w_bin_q <= e_bin_q;
    w_weight_q <= e_side_q.weight;
    w_bank_q <= acc_q;
    fwd_data_q <= w_new;
    rd_bank_q <= ~acc_q;
  end

  // ---------------------------------------------------------------------------
  // Outputs.
  assign hist_rd_data_o   = rd_valid_q ? bank_rd_q[32'(rd_bank_q) * BinBits +: BinBits] : '0;
  assign done_o           = done_q;
  assign results_valid_o  = res_valid_q;
  assign clearing_o       = sweep_busy_q;
  assign frame_votes_o    = stat_votes_q;
  assign frames_o         = frames_q;
  assign frames_skipped_o = skipped_q;

  // The camera pixel and the mask are not used.
  logic unused;
  // Of the last division stage only the quotient, of the sums only the kept
  // bits, and the octant at stage E only through the bin are used.
  assign unused = ^{s_lut_grey_i, s_lut_mask_i, sr1_unused, sr2_unused, c_rem_q[(DivStages-1)*RemBits +: RemBits],
                    c_big_q[(DivStages-1)*AbsBits +: AbsBits],
                    q_inc[0], wsum[2:0], prod[AngleFrac-1:0], e_side_q.upper};

`ifndef SYNTHESIS
  // (The pixel position and the line buffer's read are checked in line_window.)
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      assert (!(s_lut_abort_i && s_lut_valid_i) || s_lut_sof_i)
      else $error("orientation: abort on a pixel that is not an SOF");
      // A vote is read and written in the bank it was counted in: no
      // accepted vote on an edge that changes the banks' roles.
      assert (!(p_accept && (publish || sweep_start)))
      else $error("orientation: a vote on the edge its bank changes role");
      assert (!(w_vote_q && sweep_busy_q))
      else $error("orientation: a vote write during the sweep");
    end
  end
`endif

endmodule
