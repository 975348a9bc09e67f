// hough: weighted Hough voter (seed 002 step 3, eq. 18). Each edge point
// (x, y) of s_axis_edges votes, for every theta of the configured range, into
// cell (theta, rho index) with weight (y + 1) >> weight_shift (or 1):
// rho index = floor((x C + y S + (W << 14) + 2^(13 + rho_shift)) / 2^(14 +
// rho_shift)) (round to nearest), C, S the
// s1.14 cos/sin table of ceilnav_widths_pkg (fixedpoint/hough_trig.hpp).
// theta cell j of the range goes to lane j mod Lanes, slot j / Lanes; each
// lane has one BRAM per bank of Slots x 2^RhoBits cells, so an edge takes
// ceil(count / Lanes) cycles (tready low meanwhile). Per lane a vote runs
// through a five-stage pipeline: T (the slot: the table words), M (the two
// products), R (their sum with the frame's bias, the shift and the range
// check), B (the BRAM read of the cell) and W (the saturating write), with
// forwarding of the write to the read of the same cell on the same edge.
// Two banks: the trailer publishes the voting bank (state SWAP, held until
// the pipeline has written its last vote and counted its clips), the old
// result bank becomes the voting bank and is cleared by a sweep (CLEAR, one
// word per lane per edge) before the next edge is accepted.
// Cycle-exact twin of stream/hough.cpp; see docs/blocks/hough.md.
// In the device it sits in pipeline (HasCorridor); it also has its own
// co-simulation (cosim_hough_test).
module hough #(
  parameter int unsigned Lanes     = 4,   // parallel theta lanes, a power of two
  parameter int unsigned ThetaStep = 4,   // degrees between thetas; divides 180
  parameter int unsigned RhoBits   = 6,   // 2^RhoBits rho bins
  parameter int unsigned AccBits   = 16   // cell width (saturating), <= 32
) (
  input  logic        clk_i,
  input  logic        rst_ni,

  // AXI4-Stream edges: word0 = x | y << 16, word1 = magnitude | ...; trailer
  // (tlast) word0 = edges, word1 = flags.
  input  logic        s_axis_edges_tvalid_i,
  output logic        s_axis_edges_tready_o,
  input  logic [63:0] s_axis_edges_tdata_i,
  input  logic        s_axis_edges_tlast_i,

  // Configuration (HOUGH_CONTROL, HOUGH_GEOMETRY), sampled with the first beat of a frame
  input  logic        cfg_enable_i,
  input  logic        cfg_unit_weight_i,
  input  logic [3:0]  cfg_weight_shift_i,
  input  logic [2:0]  cfg_rho_shift_i,
  input  logic [7:0]  cfg_theta_first_i,
  input  logic [7:0]  cfg_theta_count_i,
  input  logic [11:0] cfg_width_i,

  // Result read port (BRAM style, one cycle): index = j << RhoBits | rho
  input  logic                             rd_en_i,
  input  logic [$clog2(180 / ThetaStep) + RhoBits - 1:0] rd_index_i,
  output logic [AccBits-1:0]               rd_data_o,

  output logic        done_o,           // one cycle after a publication
  output logic        results_valid_o,  // a frame is published
  output logic [1:0]  state_o,          // 0 idle, 1 vote, 2 swap, 3 clear

  // Published per-frame counters (saturating)
  output logic [31:0] edges_o,
  output logic [31:0] bad_edges_o,
  output logic [31:0] votes_o,
  output logic [31:0] dropped_o,
  output logic [31:0] saturated_o,
  output logic [31:0] trailer_edges_o,
  output logic [31:0] trailer_flags_o
);

  localparam int unsigned NTheta    = 180 / ThetaStep;
  localparam int unsigned JBits     = $clog2(NTheta);  // theta cell index j
  localparam int unsigned IndexBits = JBits + RhoBits;
  localparam int unsigned Slots     = (NTheta + Lanes - 1) / Lanes;
  localparam int unsigned SlotBits  = Slots > 1 ? $clog2(Slots) : 1;
  localparam int unsigned RhoBins   = 1 << RhoBits;
  localparam int unsigned Words     = Slots * RhoBins;  // per lane and bank
  localparam int unsigned AddrBits  = SlotBits + RhoBits;
  localparam int unsigned Frac      = ceilnav_widths_pkg::HoughTrigFrac;
  localparam int unsigned SumBits   = ceilnav_widths_pkg::HoughRhoSumBits;
  localparam int unsigned WBits     = ceilnav_widths_pkg::HoughWeightBits;
  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned ProdBits  = CoordBits + 1 + 16;  // (x or y) x (cos or sin), signed
  localparam int unsigned MaskLo    = Frac + RhoBits;  // < SumBits for RhoBits <= 12
  localparam int unsigned MaskBits  = SumBits - MaskLo;
  localparam int unsigned CntBits   = 32;
  localparam int unsigned CntBits1  = CntBits + 1;
  localparam int unsigned AccBits1  = AccBits + 1;
  localparam int unsigned LaneCnt   = $clog2(Lanes + 1);  // 0 .. Lanes
  localparam int unsigned LaneBits  = $clog2(Lanes);
  // Largest cell value, 2^AccBits - 1 (a difference: Yosys 0.23 reads '1 here as 1)
  localparam logic [AccBits-1:0] AccMax = AccBits'((64'd1 << AccBits) - 64'd1);

  typedef logic [AddrBits-1:0] addr_t;
  typedef logic [1:0] state_t;
  localparam state_t StIdle = 2'd0, StVote = 2'd1, StSwap = 2'd2, StClear = 2'd3;

  // cos (sin_sel 0) or sin (sin_sel 1) of theta cell t (t * ThetaStep degrees), s1.14
  function automatic logic signed [15:0] trig_of(input logic [7:0] t, input logic sin_sel);
    trig_of = '0;
    for (int i = 0; i < NTheta; i++) begin
      if (t == 8'(i)) begin
        trig_of = sin_sel ? ceilnav_widths_pkg::HoughSin[16 * i * ThetaStep +: 16]
                          : ceilnav_widths_pkg::HoughCos[16 * i * ThetaStep +: 16];
      end
    end
  endfunction

  function automatic logic [CntBits-1:0] sat_add(input logic [CntBits-1:0] a,
                                                  input logic [LaneCnt-1:0] n);
    logic [CntBits:0] s;
    s = {1'b0, a} + CntBits1'(n);
    sat_add = s[CntBits] ? '1 : s[CntBits-1:0];
  endfunction

  // ---------------------------------------------------------------------------
  // State
  state_t state_q;
  logic   acc_q, disp_q;  // voting bank, result bank (always different)
  logic   res_valid_q, done_q;
  addr_t  clr_ptr_q;
  logic   frame_open_q, frame_en_q;
  logic   unit_q;
  logic [3:0]  wshift_q;
  logic [2:0]  rshift_q;
  logic [7:0]  first_q, count_q, last_slot_q, slot_q;
  logic [CoordBits-1:0] x_q, y_q;
  // Derived from the configuration when a frame opens: the rho bias
  // (W << 14) + 2^(13 + rho_shift) (W and half a bin, to round to the
  // nearest bin) and the mask of the sum bits at and above 2^(14 + rho_shift
  // + RhoBits) (a sum with any of them set is past the last bin), kept from
  // bit MaskLo = 14 + RhoBits up (the bits below are never in it).
  logic signed [SumBits-1:0] bias_q;
  logic [MaskBits-1:0]       hi_mask_q;

  // The theta range of the configuration inputs (used when a frame opens),
  // from short parallel chains of the inputs: a first past the table is
  // clamped to NTheta - 1 (its range is that one theta); else a count of 0 or
  // past the end (count + first > NTheta) runs to the end. The last slot is
  // (count - 1) / Lanes.
  logic       clamp_in, to_end_in;
  logic [8:0] end_in;
  logic [7:0] first_in, count_in, last_slot_in, avail_in, avail_m1_in, count_m1_in;
  always_comb begin
    clamp_in     = cfg_theta_first_i > 8'(NTheta - 1);
    end_in       = {1'b0, cfg_theta_count_i} + {1'b0, cfg_theta_first_i};
    to_end_in    = cfg_theta_count_i == 8'd0 || end_in > 9'(NTheta);
    avail_in     = 8'(NTheta) - cfg_theta_first_i;
    avail_m1_in  = 8'(NTheta - 1) - cfg_theta_first_i;
    count_m1_in  = cfg_theta_count_i - 8'd1;
    first_in     = clamp_in ? 8'(NTheta - 1) : cfg_theta_first_i;
    count_in     = clamp_in ? 8'd1 : to_end_in ? avail_in : cfg_theta_count_i;
    last_slot_in = clamp_in ? 8'd0 : (to_end_in ? avail_m1_in : count_m1_in) >> LaneBits;
  end
  logic signed [SumBits-1:0] bias_in;
  logic [MaskBits-1:0]       hi_mask_in;
  assign bias_in    = SumBits'({cfg_width_i, Frac'(0)})
                    + (SumBits'(1) << (Frac - 1 + 32'(cfg_rho_shift_i)));
  assign hi_mask_in = MaskBits'(~((64'd1 << cfg_rho_shift_i) - 64'd1));

  logic ready, accept, open_now, en, bad_xy;
  logic [31:0] word0, word1;
  assign ready    = state_q == StIdle || (state_q == StVote && slot_q == last_slot_q);
  assign accept   = ready & s_axis_edges_tvalid_i;
  assign open_now = accept & ~frame_open_q;
  assign en       = frame_open_q ? frame_en_q : cfg_enable_i;
  assign word0    = s_axis_edges_tdata_i[31:0];
  assign word1    = s_axis_edges_tdata_i[63:32];
  assign bad_xy   = |word0[15:CoordBits] | |word0[31:16+CoordBits];

  // ---------------------------------------------------------------------------
  // Stage T (the slot cycle): the votes of slot slot_q of the held edge, one
  // per lane: which lanes are active and their table words. The stages after
  // it carry the slot as data, qualified by the valid bits t_valid_q,
  // m_valid_q, r_valid_q, b_valid_q (the stage holds a slot) and, per lane, the
  // activity / vote bits; the data registers have no reset.
  logic [WBits-1:0] weight;
  assign weight = unit_q ? WBits'(1) : WBits'((WBits'(y_q) + WBits'(1)) >> wshift_q);

  logic                 t_valid_q, m_valid_q, r_valid_q, b_valid_q;
  logic [CoordBits-1:0] t_x_q, t_y_q;
  logic [SlotBits-1:0]  t_slot_q, m_slot_q;
  logic [WBits-1:0]     t_weight_q, m_weight_q, r_weight_q, b_weight_q;

  // Host read
  logic [JBits-1:0]   rd_j;
  logic [RhoBits-1:0] rd_rho;
  logic               rd_ok, rd_en_q, rd_bank_q;
  logic [31:0]        rd_lane, rd_lane_q;
  addr_t              rd_addr;
  assign rd_j    = rd_index_i[IndexBits-1:RhoBits];
  assign rd_rho  = rd_index_i[RhoBits-1:0];
  assign rd_ok   = rd_en_i && res_valid_q && 32'(rd_j) < NTheta;
  assign rd_lane = 32'(rd_j) % Lanes;
  assign rd_addr = AddrBits'({SlotBits'(32'(rd_j) / Lanes), rd_rho});

  // Per lane: stages T, M, R of the vote, two BRAM banks (one write port, one
  // read port each) read in stage B and written in stage W.
  logic [Lanes-1:0] r_vote_q, r_drop_q, b_vote_q, w_sat_q;
  // BRAM read registers: bank b, lane l at [(b Lanes + l) AccBits +: AccBits]
  logic [2*Lanes*AccBits-1:0] bank_rd_q;

  for (genvar l = 0; l < Lanes; l++) begin : g_lane
    // Stage T: cell j of the range, theta index t = first + j; registers the
    // table words (the multipliers' input registers).
    logic [8:0] j;
    logic [7:0] t;
    logic       t_act_q, m_act_q;
    // sin >= 0 on [0, 180) degrees: the y product is unsigned.
    logic signed [15:0] cos_t, t_cos_q;
    logic [15:0]        sin_t, t_sin_q;
    assign j     = 9'(slot_q) * 9'(Lanes) + 9'(l);
    assign t     = 8'(9'(first_q) + j);
    assign cos_t = trig_of(t, 1'b0);
    assign sin_t = trig_of(t, 1'b1);

    // Stage M: the two products (the multipliers' output registers).
    // The product registers have the products' own width (no extension
    // bits: Yosys 0.23 leaves such bits undriven when it packs the register
    // into an SB_MAC16); the sum extends them.
    logic signed [CoordBits:0]  xs;
    logic signed [ProdBits-1:0] m_xc_q;
    logic [ProdBits-2:0]        m_ys_q;
    assign xs = {1'b0, t_x_q};

    // Stage R: the sum with the frame's bias, the rounding shift and the
    // range check (the bits at and above bin 2^RhoBits, the frame's mask).
    logic signed [SumBits-1:0] rho_sum;
    logic [RhoBits-1:0] rho;
    logic in_range;
    addr_t r_addr_q;
    assign rho_sum  = SumBits'(m_xc_q) + $signed(SumBits'(m_ys_q)) + bias_q;
    assign rho      = RhoBits'($unsigned(rho_sum) >> (Frac + 32'(rshift_q)));
    assign in_range = !rho_sum[SumBits-1] && ~|(rho_sum[SumBits-1:MaskLo] & hi_mask_q);

    always_ff @(posedge clk_i) begin
      t_cos_q  <= cos_t;
      t_sin_q  <= sin_t;
      m_xc_q   <= ProdBits'(xs) * ProdBits'(t_cos_q);
      m_ys_q   <= (ProdBits - 1)'(t_y_q) * (ProdBits - 1)'(t_sin_q);
      r_addr_q <= AddrBits'({m_slot_q, rho});
    end

    // Stage W: the cell read in stage B on the previous edge (or the value
    // this lane wrote on that edge, when it wrote the cell read then) + weight.
    logic               b_fwd_q;
    addr_t              b_addr_q;
    logic [AccBits-1:0] last_q, old, new_val;
    logic [AccBits:0]   acc_sum;
    assign old     = b_fwd_q ? last_q
                             : bank_rd_q[(32'(acc_q) * Lanes + l) * AccBits +: AccBits];
    assign acc_sum = {1'b0, old} + AccBits1'(b_weight_q);
    // acc_sum[AccBits] set: acc_sum > AccMax (the cell clips)
    assign new_val = acc_sum[AccBits] ? AccMax : acc_sum[AccBits-1:0];

    for (genvar b = 0; b < 2; b++) begin : g_bank
      (* ram_style = "block" *) logic [AccBits-1:0] mem [Words];
      initial begin
        for (int i = 0; i < Words; i++) begin
          mem[i] = '0;
        end
      end
      logic  is_acc, rd_en, wr_en;
      addr_t raddr, waddr;
      assign is_acc = acc_q == 1'(b);
      assign rd_en  = is_acc ? r_vote_q[l] : (rd_ok && rd_lane == l);
      assign raddr  = is_acc ? r_addr_q : rd_addr;
      // No write on an edge in reset (the registers may hold anything there).
      assign wr_en  = rst_ni && is_acc && (b_vote_q[l] || state_q == StClear);
      assign waddr  = b_vote_q[l] ? b_addr_q : clr_ptr_q;
      always_ff @(posedge clk_i) begin
        if (wr_en) begin
          mem[waddr] <= b_vote_q[l] ? new_val : '0;
        end
        if (rd_en) begin
          bank_rd_q[(b * Lanes + l) * AccBits +: AccBits] <= mem[raddr];
        end
      end
    end

    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        t_act_q     <= 1'b0;
        m_act_q     <= 1'b0;
        r_vote_q[l] <= 1'b0;
        r_drop_q[l] <= 1'b0;
        b_vote_q[l] <= 1'b0;
        w_sat_q[l]  <= 1'b0;
        b_fwd_q     <= 1'b0;
        b_addr_q    <= '0;
        last_q      <= '0;
      end else begin
        t_act_q     <= state_q == StVote && j < {1'b0, count_q};
        m_act_q     <= t_act_q;
        r_vote_q[l] <= m_act_q && in_range;
        r_drop_q[l] <= m_act_q && !in_range;
        b_vote_q[l] <= r_vote_q[l];
        w_sat_q[l]  <= b_vote_q[l] && acc_sum[AccBits];  // counted on the next edge
        b_fwd_q     <= r_vote_q[l] && b_vote_q[l] && b_addr_q == r_addr_q;
        b_addr_q    <= r_addr_q;
        if (b_vote_q[l]) begin
          last_q <= new_val;
        end
      end
    end
  end

  // Shared data of the slot in flight (no reset: qualified by the valid bits).
  always_ff @(posedge clk_i) begin
    t_x_q      <= x_q;
    t_y_q      <= y_q;
    t_slot_q   <= slot_q[SlotBits-1:0];
    m_slot_q   <= t_slot_q;
    t_weight_q <= weight;
    m_weight_q <= t_weight_q;
    r_weight_q <= m_weight_q;
    b_weight_q <= r_weight_q;
  end

  // The pipeline holds a slot whose write or saturation count is still to
  // come after this edge (stage R's drops and stage W's votes are counted on
  // this edge, W's clipped votes on the next): SWAP waits for it.
  logic busy;
  assign busy = t_valid_q | m_valid_q | r_valid_q | b_valid_q;

  // ---------------------------------------------------------------------------
  // Counters of the open frame (next values), published on the SWAP edge.
  logic [CntBits-1:0] c_edges_q, c_bad_q, c_votes_q, c_drop_q, c_sat_q, c_tre_q, c_trf_q;
  logic [CntBits-1:0] c_edges_d, c_bad_d, c_votes_d, c_drop_d, c_sat_d, c_tre_d, c_trf_d;
  logic [CntBits-1:0] p_edges_q, p_bad_q, p_votes_q, p_drop_q, p_sat_q, p_tre_q, p_trf_q;

  function automatic logic [LaneCnt-1:0] popcount(input logic [Lanes-1:0] v);
    popcount = '0;
    for (int i = 0; i < Lanes; i++) begin
      popcount = popcount + LaneCnt'(v[i]);
    end
  endfunction

  logic take_edge, take_bad, take_trailer;
  assign take_trailer = accept && s_axis_edges_tlast_i && en;
  assign take_edge    = accept && !s_axis_edges_tlast_i && en && !bad_xy;
  assign take_bad     = accept && !s_axis_edges_tlast_i && en && bad_xy;

  always_comb begin
    c_votes_d = sat_add(c_votes_q, popcount(b_vote_q));
    c_sat_d   = sat_add(c_sat_q, popcount(w_sat_q));
    c_drop_d  = sat_add(c_drop_q, popcount(r_drop_q));
    c_edges_d = sat_add(c_edges_q, LaneCnt'(take_edge));
    c_bad_d   = sat_add(c_bad_q, LaneCnt'(take_bad));
    c_tre_d   = take_trailer ? word0 : c_tre_q;
    c_trf_d   = take_trailer ? word1 : c_trf_q;
  end

  // ---------------------------------------------------------------------------
  state_t next;
  always_comb begin
    next = state_q;
    case (state_q)
      StClear: if (clr_ptr_q == AddrBits'(Words - 1)) next = StIdle;
      StSwap:  if (!busy) next = StClear;
      StVote:  if (slot_q == last_slot_q) next = StIdle;
      default: ;
    endcase
    if (accept) begin
      next = StIdle;
      if (s_axis_edges_tlast_i) begin
        if (en) next = StSwap;
      end else if (en && !bad_xy) begin
        next = StVote;
      end
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      state_q      <= StClear;
      acc_q        <= 1'b0;
      disp_q       <= 1'b1;
      res_valid_q  <= 1'b0;
      done_q       <= 1'b0;
      clr_ptr_q    <= '0;
      frame_open_q <= 1'b0;
      frame_en_q   <= 1'b0;
      unit_q       <= 1'b0;
      wshift_q     <= '0;
      rshift_q     <= '0;
      first_q      <= '0;
      count_q      <= 8'd1;
      last_slot_q  <= '0;
      slot_q       <= '0;
      x_q          <= '0;
      y_q          <= '0;
      t_valid_q    <= 1'b0;
      m_valid_q    <= 1'b0;
      r_valid_q    <= 1'b0;
      b_valid_q    <= 1'b0;
      bias_q       <= '0;
      hi_mask_q    <= '0;
      rd_en_q      <= 1'b0;
      rd_bank_q    <= 1'b0;
      rd_lane_q    <= '0;
      {c_edges_q, c_bad_q, c_votes_q, c_drop_q, c_sat_q, c_tre_q, c_trf_q} <= '0;
      {p_edges_q, p_bad_q, p_votes_q, p_drop_q, p_sat_q, p_tre_q, p_trf_q} <= '0;
    end else begin
      state_q     <= next;
      done_q      <= 1'b0;
      t_valid_q   <= state_q == StVote;
      m_valid_q   <= t_valid_q;
      r_valid_q   <= m_valid_q;
      b_valid_q   <= r_valid_q;
      rd_en_q     <= rd_ok;
      rd_bank_q   <= disp_q;
      rd_lane_q   <= rd_lane;
      {c_edges_q, c_bad_q, c_votes_q, c_drop_q, c_sat_q, c_tre_q, c_trf_q} <=
          {c_edges_d, c_bad_d, c_votes_d, c_drop_d, c_sat_d, c_tre_d, c_trf_d};
      case (state_q)
        StClear: clr_ptr_q <= clr_ptr_q == AddrBits'(Words - 1) ? '0 : clr_ptr_q + AddrBits'(1);
        StSwap: if (!busy) begin
          {p_edges_q, p_bad_q, p_votes_q, p_drop_q, p_sat_q, p_tre_q, p_trf_q} <=
              {c_edges_d, c_bad_d, c_votes_d, c_drop_d, c_sat_d, c_tre_d, c_trf_d};
          {c_edges_q, c_bad_q, c_votes_q, c_drop_q, c_sat_q, c_tre_q, c_trf_q} <= '0;
          disp_q      <= acc_q;
          acc_q       <= disp_q;
          res_valid_q <= 1'b1;
          done_q      <= 1'b1;
          clr_ptr_q   <= '0;
        end
        StVote: if (slot_q != last_slot_q) slot_q <= slot_q + 8'd1;
        default: ;
      endcase
      if (open_now) begin
        frame_open_q <= 1'b1;
        frame_en_q   <= cfg_enable_i;
        unit_q       <= cfg_unit_weight_i;
        wshift_q     <= cfg_weight_shift_i;
        rshift_q     <= cfg_rho_shift_i;
        bias_q       <= bias_in;
        hi_mask_q    <= hi_mask_in;
        first_q      <= first_in;
        count_q      <= count_in;
        last_slot_q  <= last_slot_in;
      end
      if (accept && s_axis_edges_tlast_i) begin
        frame_open_q <= 1'b0;
      end
      if (take_edge) begin
        x_q    <= word0[CoordBits-1:0];
        y_q    <= word0[16 +: CoordBits];
        slot_q <= '0;
      end
    end
  end

  assign s_axis_edges_tready_o = ready;
  assign rd_data_o       = rd_en_q ? bank_rd_q[(32'(rd_bank_q) * Lanes + rd_lane_q) * AccBits +: AccBits]
                                   : '0;
  assign done_o          = done_q;
  assign results_valid_o = res_valid_q;
  assign state_o         = state_q;
  assign edges_o         = p_edges_q;
  assign bad_edges_o     = p_bad_q;
  assign votes_o         = p_votes_q;
  assign dropped_o       = p_drop_q;
  assign saturated_o     = p_sat_q;
  assign trailer_edges_o = p_tre_q;
  assign trailer_flags_o = p_trf_q;

`ifndef SYNTHESIS
  // The sweep never runs while a vote is written.
  SweepDisjoint: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(state_q == StClear && |b_vote_q));
  // The pipeline is empty when the sweep starts (SWAP waited for it).
  SweepAfterDrain: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(state_q == StClear && busy));
  // The voting and the result banks differ.
  BanksDiffer: assert property (@(posedge clk_i) disable iff (!rst_ni) acc_q != disp_q);
`endif

endmodule
