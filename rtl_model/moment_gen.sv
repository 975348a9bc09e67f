// moment_gen: m00 m10 m01 m20 m11 m02 of the LUT remap value I and of the
// mask, once per frame. Counters and adders, no multiplier on the pixel path:
// cascaded accumulators along the row (A1 += I, A2 += A1, A3 += A2) and down
// the frame (at each row end F00 += A1, F01 += F00, F02 += F01, F10 += A2,
// F11 += F10, F20 += A3) give the sums of I weighted by u = W - x and
// v = H - y. After EOF two bit-serial units, one per image (six serial x
// parallel multipliers by the 12-bit W and H each), form the grey and the mask
// moments in one pass over the widest register.
// Cycle model: stream/moment_gen.{hpp,cpp}; spec: docs/blocks/moment_gen.md.

module moment_gen (
  input  logic        clk_i,
  input  logic        rst_ni,

  // s_lut: pixel beat from thresh_lut (LutBeat).
  input  logic        s_lut_valid_i,
  input  ceilnav_pkg::pixel_t s_lut_grey_i,
  input  ceilnav_pkg::coord_t s_lut_x_i,
  input  ceilnav_pkg::coord_t s_lut_y_i,
  input  logic        s_lut_sof_i,
  input  logic        s_lut_eol_i,
  input  logic        s_lut_eof_i,
  input  logic        s_lut_abort_i,
  input  ceilnav_pkg::pixel_t s_lut_remap_i,
  input  logic        s_lut_mask_i,
  // The EOF beat on the input is dropped (counted as an overrun, no combine):
  // the histogram had no cleared bank for this frame.
  input  logic        eof_drop_i,

  output logic        done_o,          // one-cycle pulse: the moment outputs were just updated
  output logic        done_next_o,     // done_o rises on the next edge (Moore)
  output logic        eof_accept_o,    // the EOF beat on the input is taken (Mealy)
  // The moments as 24 register words, one per edge for 24 edges after the
  // done edge (mom_wr_valid_o is high with done_o and 23 cycles after): word
  // index w = 6 * {grey lo, grey hi, mask lo, mask hi} + MomentIndex, i.e. the
  // MOM_GREY_LO .. MOM_MASK_HI register order. Written into the device's
  // result store (docs/blocks/moment_gen.md, "Result words").
  output logic        mom_wr_valid_o,
  output logic [ceilnav_pkg::MomIndexBits-1:0] mom_wr_index_o,
  output ceilnav_pkg::word_t mom_wr_data_o,
  output logic        combine_busy_o,
  output ceilnav_pkg::word_t overrun_count_o
);

  // Widths for W = H = 2048, derived with their proofs in
  // fixedpoint/datapath.hpp (namespace moment_gen) and generated into
  // ceilnav_widths_pkg (G = grey, K = mask).
  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned WordBits = ceilnav_pkg::WordBits;
  localparam int unsigned Moments = ceilnav_pkg::MomentCount;  // m00 m10 m01 m20 m11 m02
  localparam int unsigned IndexBits = ceilnav_pkg::MomIndexBits;  // result word index
  localparam int unsigned DimBits = ceilnav_widths_pkg::DimBits;  // W, H in 1 .. 2^CoordBits
  // Row accumulators A1, A2, A3.
  localparam int unsigned GA1 = ceilnav_widths_pkg::GA1, GA2 = ceilnav_widths_pkg::GA2,
                          GA3 = ceilnav_widths_pkg::GA3;
  localparam int unsigned KA1 = ceilnav_widths_pkg::KA1, KA2 = ceilnav_widths_pkg::KA2,
                          KA3 = ceilnav_widths_pkg::KA3;
  // Frame accumulators F00 F10 F01 F20 F11 F02.
  localparam int unsigned GF00 = ceilnav_widths_pkg::GF00, GF10 = ceilnav_widths_pkg::GF10,
                          GF01 = ceilnav_widths_pkg::GF01, GF20 = ceilnav_widths_pkg::GF20,
                          GF11 = ceilnav_widths_pkg::GF11, GF02 = ceilnav_widths_pkg::GF02;
  localparam int unsigned KF00 = ceilnav_widths_pkg::KF00, KF10 = ceilnav_widths_pkg::KF10,
                          KF01 = ceilnav_widths_pkg::KF01, KF20 = ceilnav_widths_pkg::KF20,
                          KF11 = ceilnav_widths_pkg::KF11, KF02 = ceilnav_widths_pkg::KF02;
  // Combine shift registers: F_ab on entry, m_ab on exit (the wider of the two).
  localparam int unsigned GR00 = ceilnav_widths_pkg::GR00, GR10 = ceilnav_widths_pkg::GR10,
                          GR01 = ceilnav_widths_pkg::GR01, GR20 = ceilnav_widths_pkg::GR20,
                          GR11 = ceilnav_widths_pkg::GR11, GR02 = ceilnav_widths_pkg::GR02;
  localparam int unsigned KR00 = ceilnav_widths_pkg::KR00, KR10 = ceilnav_widths_pkg::KR10,
                          KR01 = ceilnav_widths_pkg::KR01, KR20 = ceilnav_widths_pkg::KR20,
                          KR11 = ceilnav_widths_pkg::KR11, KR02 = ceilnav_widths_pkg::KR02;
  localparam int unsigned GreyPass = ceilnav_widths_pkg::GreyPass;  // widest grey register
  localparam int unsigned MaskPass = ceilnav_widths_pkg::MaskPass;
  localparam int unsigned PassBits = GreyPass > MaskPass ? GreyPass : MaskPass;

  // Combine schedule, as the value of cnt_q before the edge (cnt_q = 0 after
  // the EOF edge): snapshot loads, then pass bit k of a register of width N
  // is read at k < N and written at 1 <= k <= N (one stream register between).
  // The grey and the mask pass run side by side, from the same edge.
  localparam int unsigned CntBits = 6;
  localparam logic [CntBits-1:0] Load0 = CntBits'(1);  // F00 final after edge EOF+1
  localparam logic [CntBits-1:0] Load1 = CntBits'(2);  // F10, F01
  localparam logic [CntBits-1:0] Load2 = CntBits'(3);  // F20, F11, F02
  localparam int unsigned PassStart = 4;
  localparam logic [CntBits-1:0] DoneCnt = CntBits'(PassStart + PassBits + 1);  // 56

  // ---------------------------------------------------------------------------
  // Stage 0: the pixel. row_start / first_row describe the pixel on the input.
  logic take, eof_take, row_start, first_row;
  logic frame_open_q, row_start_q, first_row_q;

  assign take      = s_lut_valid_i & (s_lut_sof_i | frame_open_q);
  assign eof_take  = take & s_lut_eof_i;
  assign row_start = s_lut_sof_i | row_start_q;
  assign first_row = s_lut_sof_i | first_row_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      frame_open_q <= 1'b0;
      row_start_q  <= 1'b0;
      first_row_q  <= 1'b0;
    end else if (take) begin
      frame_open_q <= ~s_lut_eof_i;
      row_start_q  <= s_lut_eol_i;
      first_row_q  <= first_row & ~s_lut_eol_i;
    end else if (s_lut_abort_i) begin
      frame_open_q <= 1'b0;  // the partial sums are never combined
    end
  end

  // The cascade is skewed: stage k works on the pixel taken k edges before.
  localparam int unsigned Stages = 3;  // A1 / F00, A2 / F10 F01, A3 / F20 F11 F02
  logic [Stages-1:1] val_q, rs_q;  // stage k: valid pixel, first of its row
  logic [Stages:1]   eol_q, fr_q;  // stage k: valid row end, in the frame's first row

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      val_q <= '0;
      rs_q  <= '0;
      eol_q <= '0;
      fr_q  <= '0;
    end else begin
      val_q <= {val_q[1], take};
      rs_q  <= {rs_q[1], row_start};
      eol_q <= {eol_q[Stages-1:1], take & s_lut_eol_i};
      fr_q  <= {fr_q[Stages-1:1], first_row};
    end
  end

  // Row accumulators. `start ? add : acc + add` keeps the start mux behind the
  // adder, where it shares the sum's LUT (iCE40: one LC per bit).
  logic [GA1-1:0] ga1_q;
  logic [GA2-1:0] ga2_q;
  logic [GA3-1:0] ga3_q;
  logic [KA1-1:0] ka1_q;
  logic [KA2-1:0] ka2_q;
  logic [KA3-1:0] ka3_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      ga1_q <= '0;
      ka1_q <= '0;
    end else if (take) begin
      ga1_q <= row_start ? GA1'(s_lut_remap_i) : ga1_q + GA1'(s_lut_remap_i);
      ka1_q <= row_start ? KA1'(s_lut_mask_i) : ka1_q + KA1'(s_lut_mask_i);
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      ga2_q <= '0;
      ka2_q <= '0;
    end else if (val_q[1]) begin
      ga2_q <= rs_q[1] ? GA2'(ga1_q) : ga2_q + GA2'(ga1_q);
      ka2_q <= rs_q[1] ? KA2'(ka1_q) : ka2_q + KA2'(ka1_q);
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      ga3_q <= '0;
      ka3_q <= '0;
    end else if (val_q[2]) begin
      ga3_q <= rs_q[2] ? GA3'(ga2_q) : ga3_q + GA3'(ga2_q);
      ka3_q <= rs_q[2] ? KA3'(ka2_q) : ka3_q + KA3'(ka2_q);
    end
  end

  // Frame accumulators, updated at row ends; the first row starts them.
  logic [GF00-1:0] gf00_q;
  logic [GF10-1:0] gf10_q;
  logic [GF01-1:0] gf01_q;
  logic [GF20-1:0] gf20_q;
  logic [GF11-1:0] gf11_q;
  logic [GF02-1:0] gf02_q;
  logic [KF00-1:0] kf00_q;
  logic [KF10-1:0] kf10_q;
  logic [KF01-1:0] kf01_q;
  logic [KF20-1:0] kf20_q;
  logic [KF11-1:0] kf11_q;
  logic [KF02-1:0] kf02_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gf00_q <= '0;
      kf00_q <= '0;
    end else if (eol_q[1]) begin
      gf00_q <= fr_q[1] ? GF00'(ga1_q) : gf00_q + GF00'(ga1_q);
      kf00_q <= fr_q[1] ? KF00'(ka1_q) : kf00_q + KF00'(ka1_q);
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gf10_q <= '0;
      gf01_q <= '0;
      kf10_q <= '0;
      kf01_q <= '0;
    end else if (eol_q[2]) begin
      gf10_q <= fr_q[2] ? GF10'(ga2_q) : gf10_q + GF10'(ga2_q);
      gf01_q <= fr_q[2] ? GF01'(gf00_q) : gf01_q + GF01'(gf00_q);
      kf10_q <= fr_q[2] ? KF10'(ka2_q) : kf10_q + KF10'(ka2_q);
      kf01_q <= fr_q[2] ? KF01'(kf00_q) : kf01_q + KF01'(kf00_q);
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gf20_q <= '0;
      gf11_q <= '0;
      gf02_q <= '0;
      kf20_q <= '0;
      kf11_q <= '0;
      kf02_q <= '0;
    end else if (eol_q[3]) begin
      gf20_q <= fr_q[3] ? GF20'(ga3_q) : gf20_q + GF20'(ga3_q);
      gf11_q <= fr_q[3] ? GF11'(gf10_q) : gf11_q + GF11'(gf10_q);
      gf02_q <= fr_q[3] ? GF02'(gf01_q) : gf02_q + GF02'(gf01_q);
      kf20_q <= fr_q[3] ? KF20'(ka3_q) : kf20_q + KF20'(ka3_q);
      kf11_q <= fr_q[3] ? KF11'(kf10_q) : kf11_q + KF11'(kf10_q);
      kf02_q <= fr_q[3] ? KF02'(kf01_q) : kf02_q + KF02'(kf01_q);
    end
  end

  // ---------------------------------------------------------------------------
  // Combine control. An EOF is accepted if no combine runs or this is its done
  // edge (kCombineCycles edges after the last accepted EOF), and eof_drop_i is
  // low; otherwise the frame is dropped and counted.
  logic               busy_q;
  logic [CntBits-1:0] cnt_q;
  logic               accept, last_step;
  ceilnav_pkg::word_t overrun_count_q;
  logic [DimBits-1:0] w_q, h_q;

  assign last_step = busy_q & (cnt_q == DoneCnt);
  assign accept    = eof_take & ~eof_drop_i & (~busy_q | last_step);

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      busy_q          <= 1'b0;
      cnt_q           <= '0;
      overrun_count_q <= '0;
      w_q             <= '0;
      h_q             <= '0;
    end else begin
      if (accept) begin
        busy_q <= 1'b1;
        cnt_q  <= '0;
        // Frames are rectangular (frame_check): W, H from the EOF pixel.
        w_q    <= DimBits'(s_lut_x_i) + DimBits'(1);
        h_q    <= DimBits'(s_lut_y_i) + DimBits'(1);
      end else if (last_step) begin
        busy_q <= 1'b0;
      end else if (busy_q) begin
        cnt_q <= cnt_q + CntBits'(1);
      end
      if (eof_take && !accept && overrun_count_q != {WordBits{1'b1}}) begin
        overrun_count_q <= overrun_count_q + WordBits'(1);
      end
    end
  end

  // Pass windows on cnt_q: in_pass(s, n) = s <= cnt < s + n.
  function automatic logic in_win(logic [CntBits-1:0] c, int unsigned s, int unsigned n);
    in_win = (c >= CntBits'(s)) && (c < CntBits'(s + n));
  endfunction

  logic load0, load1, load2, ser_clr;
  assign load0     = busy_q & (cnt_q == Load0);
  assign load1     = busy_q & (cnt_q == Load1);
  assign load2     = busy_q & (cnt_q == Load2);
  // Serial state starts the pass from 0 (carry 1 for subtractors).
  assign ser_clr   = cnt_q == CntBits'(PassStart);

  // ---------------------------------------------------------------------------
  // Combine shift registers (snapshot of F, then m), LSB out, MSB in.
  logic [GR00-1:0] gr00_q;
  logic [GR10-1:0] gr10_q;
  logic [GR01-1:0] gr01_q;
  logic [GR20-1:0] gr20_q;
  logic [GR11-1:0] gr11_q;
  logic [GR02-1:0] gr02_q;
  logic [KR00-1:0] kr00_q;
  logic [KR10-1:0] kr10_q;
  logic [KR01-1:0] kr01_q;
  logic [KR20-1:0] kr20_q;
  logic [KR11-1:0] kr11_q;
  logic [KR02-1:0] kr02_q;

  // Serial result bits m_ab (bit k-1 during pass bit k) of each image, below:
  // {m02, m11, m20, m01, m10, m00}.
  logic [Moments-1:0] gm_s, km_s;

  // Shift enables: pass bits 0 .. N of the register's own pass.
  logic [Moments-1:0] g_sh, k_sh;
  assign g_sh[0] = busy_q & in_win(cnt_q, PassStart, GR00 + 1);
  assign g_sh[1] = busy_q & in_win(cnt_q, PassStart, GR10 + 1);
  assign g_sh[2] = busy_q & in_win(cnt_q, PassStart, GR01 + 1);
  assign g_sh[3] = busy_q & in_win(cnt_q, PassStart, GR20 + 1);
  assign g_sh[4] = busy_q & in_win(cnt_q, PassStart, GR11 + 1);
  assign g_sh[5] = busy_q & in_win(cnt_q, PassStart, GR02 + 1);
  assign k_sh[0] = busy_q & in_win(cnt_q, PassStart, KR00 + 1);
  assign k_sh[1] = busy_q & in_win(cnt_q, PassStart, KR10 + 1);
  assign k_sh[2] = busy_q & in_win(cnt_q, PassStart, KR01 + 1);
  assign k_sh[3] = busy_q & in_win(cnt_q, PassStart, KR20 + 1);
  assign k_sh[4] = busy_q & in_win(cnt_q, PassStart, KR11 + 1);
  assign k_sh[5] = busy_q & in_win(cnt_q, PassStart, KR02 + 1);

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gr00_q <= '0;
      kr00_q <= '0;
    end else begin
      if (load0)         gr00_q <= gf00_q;
      else if (g_sh[0])  gr00_q <= {gm_s[0], gr00_q[GR00-1:1]};
      if (load0)         kr00_q <= kf00_q;
      else if (k_sh[0])  kr00_q <= {km_s[0], kr00_q[KR00-1:1]};
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gr10_q <= '0;
      gr01_q <= '0;
      kr10_q <= '0;
      kr01_q <= '0;
    end else begin
      if (load1)         gr10_q <= gf10_q;
      else if (g_sh[1])  gr10_q <= {gm_s[1], gr10_q[GR10-1:1]};
      if (load1)         gr01_q <= gf01_q;
      else if (g_sh[2])  gr01_q <= {gm_s[2], gr01_q[GR01-1:1]};
      if (load1)         kr10_q <= kf10_q;
      else if (k_sh[1])  kr10_q <= {km_s[1], kr10_q[KR10-1:1]};
      if (load1)         kr01_q <= kf01_q;
      else if (k_sh[2])  kr01_q <= {km_s[2], kr01_q[KR01-1:1]};
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      gr20_q <= '0;
      gr11_q <= '0;
      gr02_q <= '0;
      kr20_q <= '0;
      kr11_q <= '0;
      kr02_q <= '0;
    end else begin
      if (load2)         gr20_q <= GR20'(gf20_q);
      else if (g_sh[3])  gr20_q <= {gm_s[3], gr20_q[GR20-1:1]};
      if (load2)         gr11_q <= gf11_q;
      else if (g_sh[4])  gr11_q <= {gm_s[4], gr11_q[GR11-1:1]};
      if (load2)         gr02_q <= GR02'(gf02_q);
      else if (g_sh[5])  gr02_q <= {gm_s[5], gr02_q[GR02-1:1]};
      if (load2)         kr20_q <= KR20'(kf20_q);
      else if (k_sh[3])  kr20_q <= {km_s[3], kr20_q[KR20-1:1]};
      if (load2)         kr11_q <= kf11_q;
      else if (k_sh[4])  kr11_q <= {km_s[4], kr11_q[KR11-1:1]};
      if (load2)         kr02_q <= KR02'(kf02_q);
      else if (k_sh[5])  kr02_q <= {km_s[5], kr02_q[KR02-1:1]};
    end
  end

  // Operand streams F_ab of each image, bit k of the pass: the register's LSB
  // while k < N, then 0 (F < 2^N). Registered in the datapath: one pass bit
  // behind cnt_q.
  logic [Moments-1:0] gf_d, kf_d;  // {F02, F11, F20, F01, F10, F00}
  assign gf_d[0] = gr00_q[0] & in_win(cnt_q, PassStart, GR00);
  assign gf_d[1] = gr10_q[0] & in_win(cnt_q, PassStart, GR10);
  assign gf_d[2] = gr01_q[0] & in_win(cnt_q, PassStart, GR01);
  assign gf_d[3] = gr20_q[0] & in_win(cnt_q, PassStart, GR20);
  assign gf_d[4] = gr11_q[0] & in_win(cnt_q, PassStart, GR11);
  assign gf_d[5] = gr02_q[0] & in_win(cnt_q, PassStart, GR02);
  assign kf_d[0] = kr00_q[0] & in_win(cnt_q, PassStart, KR00);
  assign kf_d[1] = kr10_q[0] & in_win(cnt_q, PassStart, KR10);
  assign kf_d[2] = kr01_q[0] & in_win(cnt_q, PassStart, KR01);
  assign kf_d[3] = kr20_q[0] & in_win(cnt_q, PassStart, KR20);
  assign kf_d[4] = kr11_q[0] & in_win(cnt_q, PassStart, KR11);
  assign kf_d[5] = kr02_q[0] & in_win(cnt_q, PassStart, KR02);

  // One serial datapath per image (0: grey, 1: mask), identical.
  for (genvar img = 0; img < 2; img++) begin : g_img
    logic [Moments-1:0] f_d, f_q;
    logic       m00_s, m10_s, m01_s, m20_s, m11_s, m02_s;
    assign f_d = (img == 0) ? gf_d : kf_d;

    // Serial datapath state has no reset: ser_clr initialises it before use.
    logic f10_dly_q, f01_dly_q, f20_dly_q, f02_dly_q;  // 2 F_ab: the stream one bit later
    always_ff @(posedge clk_i) begin
      f_q <= f_d;
      if (ser_clr) begin
        f10_dly_q <= 1'b0;
        f01_dly_q <= 1'b0;
        f20_dly_q <= 1'b0;
        f02_dly_q <= 1'b0;
      end else begin
        f10_dly_q <= f_q[1];
        f01_dly_q <= f_q[2];
        f20_dly_q <= f_q[3];
        f02_dly_q <= f_q[5];
      end
    end

    // Six serial x parallel multipliers, product bit k out with operand bit k:
    // carry-save partial sums s, c of the part of the product above bit k.
    localparam int unsigned Muls = 6;
    // split_var: the bits of these vectors feed each other (no loop).
    logic [Muls-1:0]         mul_x /* verilator split_var */, mul_p /* verilator split_var */;
    logic [Muls*DimBits-1:0] mul_k;

    for (genvar i = 0; i < Muls; i++) begin : g_mul
      logic [DimBits-1:0] k, pp, s, c_q, sum, carry;
      logic [DimBits-2:0] s_q;
      assign k     = mul_k[i*DimBits +: DimBits];
      assign pp    = k & {DimBits{mul_x[i]}};
      assign s     = {1'b0, s_q};
      assign sum   = s ^ c_q ^ pp;
      assign carry = (s & c_q) | (s & pp) | (c_q & pp);
      always_ff @(posedge clk_i) begin
        if (ser_clr) begin
          s_q <= '0;
          c_q <= '0;
        end else begin
          s_q <= sum[DimBits-1:1];
          c_q <= carry;
        end
      end
      assign mul_p[i] = sum[0];
    end

    // Ten serial adders / subtractors (a - b = a + ~b + 1).
    localparam int unsigned Adds = 10;
    localparam logic [Adds-1:0] IsSub = 10'b10_1110_1110;  // adders 0, 4, 8 add; the rest subtract
    logic [Adds-1:0] add_a /* verilator split_var */, add_b /* verilator split_var */;
    logic [Adds-1:0] add_s /* verilator split_var */, add_c_q;
    for (genvar i = 0; i < Adds; i++) begin : g_add
      assign add_s[i] = add_a[i] ^ add_b[i] ^ IsSub[i] ^ add_c_q[i];
    end
    always_ff @(posedge clk_i) begin
      if (ser_clr) add_c_q <= IsSub;
      else add_c_q <= (add_a & (add_b ^ IsSub)) | (add_a & add_c_q) | ((add_b ^ IsSub) & add_c_q);
    end

    // m10 = W F00 - F10            m01 = H F00 - F01
    // m20 = W (m10 - F10) + 2 F20 - F10 = W (W F00 - 2 F10) + (2 F20 - F10)
    // m02 = H (H F00 - 2 F01) + (2 F02 - F01)
    // m11 = W m01 + (F11 - H F10)
    logic p_wf00, p_hf00, d1, d2, e20, e02, g11;
    assign mul_k = {h_q, w_q, h_q, w_q, h_q, w_q};
    assign mul_x[0] = f_q[0];          // W F00
    assign mul_x[1] = f_q[0];          // H F00
    assign mul_x[2] = d1;              // W (W F00 - 2 F10)
    assign mul_x[3] = d2;              // H (H F00 - 2 F01)
    assign mul_x[4] = m01_s;           // W m01
    assign mul_x[5] = f_q[1];          // H F10
    assign p_wf00 = mul_p[0];
    assign p_hf00 = mul_p[1];

    assign add_a[1] = p_wf00;   assign add_b[1] = f_q[1];      assign m10_s = add_s[1];
    assign add_a[2] = p_wf00;   assign add_b[2] = f10_dly_q;   assign d1    = add_s[2];
    assign add_a[3] = f20_dly_q; assign add_b[3] = f_q[1];     assign e20   = add_s[3];
    assign add_a[0] = mul_p[2]; assign add_b[0] = e20;         assign m20_s = add_s[0];
    assign add_a[5] = p_hf00;   assign add_b[5] = f_q[2];      assign m01_s = add_s[5];
    assign add_a[6] = p_hf00;   assign add_b[6] = f01_dly_q;   assign d2    = add_s[6];
    assign add_a[7] = f02_dly_q; assign add_b[7] = f_q[2];     assign e02   = add_s[7];
    assign add_a[4] = mul_p[3]; assign add_b[4] = e02;         assign m02_s = add_s[4];
    assign add_a[9] = f_q[4];   assign add_b[9] = mul_p[5];    assign g11   = add_s[9];
    assign add_a[8] = mul_p[4]; assign add_b[8] = g11;         assign m11_s = add_s[8];
    assign m00_s = f_q[0];

    if (img == 0) begin : g_grey
      assign gm_s = {m02_s, m11_s, m20_s, m01_s, m10_s, m00_s};
    end else begin : g_mask
      assign km_s = {m02_s, m11_s, m20_s, m01_s, m10_s, m00_s};
    end
  end

  // ---------------------------------------------------------------------------
  // Result words: on the done edge the 24 words load into a chain of slots
  // ordered by significant width, widest first (no word is wider than the one
  // ahead of it, so a shift loses nothing and every slot is only as wide as its
  // widest possible content: 477 flops, as many as the moments have bits);
  // the head slot is written out, one word per edge.
  localparam int unsigned MomWords = ceilnav_pkg::MomWords;
  localparam int unsigned ChainSlots = 20;  // words of nonzero width
  // Write order: word index of chain position k at [IndexBits*k +: IndexBits]
  // (k = 0 first; the entries are IndexBits = 5 bits wide).
  localparam logic [MomWords*IndexBits-1:0] WordOrder = {
    5'd20, 5'd19, 5'd18, 5'd6,                  // zero width: grey m00 hi, mask m00/m10/m01 hi
    5'd8, 5'd7, 5'd22, 5'd23, 5'd21, 5'd10,     // hi words: 8 8 10 11 11 18 bits
    5'd11, 5'd9, 5'd12, 5'd0,                   // 19 19 bits; mask m00 lo 23; grey m00 lo 30
    5'd17, 5'd16, 5'd15, 5'd14, 5'd13,          // mask lo words m02..m10: 32 bits
    5'd5, 5'd4, 5'd3, 5'd2, 5'd1};              // grey lo words m02..m10: 32 bits

  // Word w of the moments in the shift registers (after the last pass step).
  // Mask words carry the bits a mask moment can have (m10, m01 < 2^32; m11 < 2^42).
  localparam int unsigned MomBits = 2 * WordBits;  // a moment as two words, lo and hi
  function automatic ceilnav_pkg::word_t word_value(logic [IndexBits-1:0] w);
    logic [MomBits-1:0] m;
    unique case (w % IndexBits'(Moments))
      0: m = (w < 12) ? MomBits'(gr00_q) : MomBits'(kr00_q);
      1: m = (w < 12) ? MomBits'(gr10_q) : MomBits'(kr10_q[WordBits-1:0]);
      2: m = (w < 12) ? MomBits'(gr01_q) : MomBits'(kr01_q[WordBits-1:0]);
      3: m = (w < 12) ? MomBits'(gr20_q) : MomBits'(kr20_q);
      4: m = (w < 12) ? MomBits'(gr11_q) : MomBits'(kr11_q[41:0]);
      default: m = (w < 12) ? MomBits'(gr02_q) : MomBits'(kr02_q);
    endcase
    word_value = ((w / IndexBits'(Moments)) % 2 == 0) ? m[WordBits-1:0] : m[MomBits-1:WordBits];
  endfunction

  logic [ChainSlots*WordBits-1:0] slot_q;  // slot k at [WordBits*k +: WordBits]
  logic                        wr_active_q, done_q;
  logic [IndexBits-1:0]        wr_step_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      slot_q      <= '0;
      wr_active_q <= 1'b0;
      wr_step_q   <= '0;
      done_q      <= 1'b0;
    end else begin
      if (last_step) begin
        for (int unsigned k = 0; k < ChainSlots; k++) begin
          slot_q[WordBits*k +: WordBits] <= word_value(WordOrder[IndexBits*k +: IndexBits]);
        end
        wr_active_q <= 1'b1;
        wr_step_q   <= '0;
      end else if (wr_active_q) begin
        slot_q      <= {WordBits'(0), slot_q[ChainSlots*WordBits-1:WordBits]};
        wr_step_q   <= wr_step_q + IndexBits'(1);
        wr_active_q <= wr_step_q != IndexBits'(MomWords - 1);
      end
      done_q <= last_step;
    end
  end

  logic [IndexBits-1:0] step_word;  // WordOrder entry of wr_step_q (read only while writing)
  assign step_word = WordOrder[IndexBits*wr_step_q +: IndexBits];

  assign done_o          = done_q;
  assign mom_wr_valid_o  = wr_active_q;
  assign mom_wr_index_o  = wr_active_q ? step_word : '0;
  assign mom_wr_data_o   = slot_q[WordBits-1:0];
  assign combine_busy_o  = busy_q;
  assign done_next_o     = last_step;
  assign eof_accept_o    = accept;
  assign overrun_count_o = overrun_count_q;

  // The camera pixel itself is not used: moments are of the LUT output.
  logic unused;
  assign unused = ^{s_lut_grey_i, kr10_q[KR10-1:WordBits], kr01_q[KR01-1:WordBits],
                    kr11_q[KR11-1:42]};

`ifndef SYNTHESIS
  // frame_check guarantees the pixel position and rectangular frames; the
  // cascade needs both (the C++ model throws std::logic_error instead).
  ceilnav_pkg::coord_t x_chk_q, y_chk_q, w_chk_q;
  ceilnav_pkg::coord_t x_chk, y_chk;
  assign x_chk = s_lut_sof_i ? '0 : x_chk_q;
  assign y_chk = s_lut_sof_i ? '0 : y_chk_q;
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      x_chk_q <= '0;
      y_chk_q <= '0;
      w_chk_q <= '0;
    end else if (take) begin
      assert (s_lut_x_i == x_chk && s_lut_y_i == y_chk)
      else $error("moment_gen: pixel (%0d, %0d) but counters (%0d, %0d)",
                  s_lut_x_i, s_lut_y_i, x_chk, y_chk);
      assert (!s_lut_eof_i || s_lut_eol_i) else $error("moment_gen: EOF before the row end");
      assert (!s_lut_eol_i || first_row || x_chk == w_chk_q)
      else $error("moment_gen: row of %0d pixels, the first had %0d", x_chk + 1, w_chk_q + 1);
      x_chk_q <= s_lut_eol_i ? '0 : x_chk + CoordBits'(1);
      y_chk_q <= s_lut_eol_i ? y_chk + CoordBits'(1) : y_chk;
      if (s_lut_eol_i && first_row) w_chk_q <= x_chk;
    end
  end
`endif

endmodule
