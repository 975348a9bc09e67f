// moment_gen: m00 m10 m01 m20 m11 m02 of the LUT remap value and of the mask,
// once per frame, as seed 003 eq. 20-28 builds them: counters and adders make
// the factors p_ab = x^a y^b, each bit plane of the pixel is ANDed with them
// into a plane accumulator F_k, and m_ab = sum_k 2^k F_k is formed by a Horner
// unit over 8 cycles after EOF. No multiplier anywhere.
// Cycle model: stream/moment_gen.{hpp,cpp}; spec: docs/blocks/moment_gen.md.

module moment_gen (
  input  logic        clk_i,
  input  logic        rst_ni,

  // s_lut: pixel beat from thresh_lut (LutBeat).
  input  logic        s_lut_valid_i,
  input  logic [7:0]  s_lut_grey_i,
  input  logic [10:0] s_lut_x_i,
  input  logic [10:0] s_lut_y_i,
  input  logic        s_lut_sof_i,
  input  logic        s_lut_eol_i,
  input  logic        s_lut_eof_i,
  input  logic        s_lut_abort_i,
  input  logic [7:0]  s_lut_remap_i,
  input  logic        s_lut_mask_i,

  output logic        done_o,          // one-cycle pulse: the moment outputs were just updated
  output logic [29:0] grey_m00_o,
  output logic [39:0] grey_m10_o,
  output logic [39:0] grey_m01_o,
  output logic [50:0] grey_m20_o,
  output logic [49:0] grey_m11_o,
  output logic [50:0] grey_m02_o,
  output logic [22:0] mask_m00_o,
  output logic [31:0] mask_m10_o,
  output logic [31:0] mask_m01_o,
  output logic [42:0] mask_m20_o,
  output logic [41:0] mask_m11_o,
  output logic [42:0] mask_m02_o,
  output logic        combine_busy_o,
  output logic [31:0] overrun_count_o
);

  // Widths for W = H = 2^CoordBits (stream/limits.hpp), C = CoordBits; the
  // closed forms equal the static_asserts in stream/moment_gen.hpp.
  localparam int unsigned CoordBits = 11;
  localparam int unsigned Planes = 8;
  localparam int unsigned FactorBits = 2 * CoordBits;  // x^2, x y, y^2 <= (W-1)^2
  localparam int unsigned F00Bits = 2 * CoordBits + 1;  // sum 1 = W H = 2^(2C)
  localparam int unsigned F10Bits = 3 * CoordBits - 1;  // sum x = H W (W-1) / 2 < 2^(3C-1)
  localparam int unsigned F20Bits = 4 * CoordBits - 1;  // sum x^2 ~ W^4 / 3
  localparam int unsigned F11Bits = 4 * CoordBits - 2;  // sum x y = (W (W-1) / 2)^2 < 2^(4C-2)
  localparam int unsigned PixelBits = 8;                // m_ab <= 255 F_ab
  localparam int unsigned M00Bits = 2 * CoordBits + PixelBits;  // 255 2^(2C) < 2^(2C+8)
  localparam int unsigned M10Bits = F10Bits + PixelBits;
  localparam int unsigned M20Bits = F20Bits + PixelBits;
  localparam int unsigned M11Bits = F11Bits + PixelBits;
  localparam logic [2:0] LastStep = 3'(Planes - 1);

  // ---------------------------------------------------------------------------
  // Factor generator (eq. 23-25): registers hold the factors of the NEXT pixel.
  logic [CoordBits-1:0]  x_q, y_q, x_d, y_d;
  logic [FactorBits-1:0] p20_q, p11_q, p02_q, p20_d, p11_d, p02_d;
  logic                  frame_open_q, frame_open_d;

  logic                  take;
  logic [CoordBits-1:0]  x, y;          // factors of the pixel on the input
  logic [FactorBits-1:0] p20, p11, p02;

  assign take = s_lut_valid_i & (s_lut_sof_i | frame_open_q);
  // Top of screen / left margin: every factor of the SOF pixel is 0.
  assign x   = s_lut_sof_i ? '0 : x_q;
  assign y   = s_lut_sof_i ? '0 : y_q;
  assign p20 = s_lut_sof_i ? '0 : p20_q;
  assign p11 = s_lut_sof_i ? '0 : p11_q;
  assign p02 = s_lut_sof_i ? '0 : p02_q;

  always_comb begin
    x_d = x_q;
    y_d = y_q;
    p20_d = p20_q;
    p11_d = p11_q;
    p02_d = p02_q;
    frame_open_d = frame_open_q;
    if (take) begin
      frame_open_d = ~s_lut_eof_i;
      if (s_lut_eol_i) begin
        x_d = '0;
        p20_d = '0;
        p11_d = '0;
        y_d = y + 11'd1;
        p02_d = p02 + {10'd0, y, 1'b1};  // (y+1)^2 = y^2 + 2y + 1: shift, carry-in
      end else begin
        x_d = x + 11'd1;
        p20_d = p20 + {10'd0, x, 1'b1};  // (x+1)^2 = x^2 + 2x + 1
        p11_d = p11 + {11'd0, y};        // (x+1) y = x y + y
        y_d = y;
        p02_d = p02;
      end
    end else if (s_lut_abort_i) begin
      frame_open_d = 1'b0;  // the partial sums are never snapshot
    end
  end

  // ---------------------------------------------------------------------------
  // Plane accumulators (eq. 26-28): F_k,ab += bit_k(I) ? p_ab : 0. Plane
  // index Planes is the mask. On the SOF pixel the adders start from 0.
  // One flat vector per factor, plane k at [k*Bits +: Bits] (Yosys 0.23 reads
  // no packed 2-D arrays).
  localparam int unsigned Sets = Planes + 1;
  logic [Sets*F00Bits-1:0] acc00_q, acc00_d, snap00_q, snap00_d;
  logic [Sets*F10Bits-1:0] acc10_q, acc10_d, snap10_q, snap10_d;
  logic [Sets*F10Bits-1:0] acc01_q, acc01_d, snap01_q, snap01_d;
  logic [Sets*F20Bits-1:0] acc20_q, acc20_d, snap20_q, snap20_d;
  logic [Sets*F11Bits-1:0] acc11_q, acc11_d, snap11_q, snap11_d;
  logic [Sets*F20Bits-1:0] acc02_q, acc02_d, snap02_q, snap02_d;
  logic [Planes:0] plane_bit;

  assign plane_bit = {s_lut_mask_i, s_lut_remap_i};

  for (genvar k = 0; k <= Planes; k++) begin : g_plane
    localparam int unsigned K = k;
    // AND gates: the factor if this plane's bit is set, else 0.
    logic [F00Bits-1:0] and00;
    logic [F10Bits-1:0] and10, and01;
    logic [F20Bits-1:0] and20, and02;
    logic [F11Bits-1:0] and11;
    assign and00 = F00Bits'(plane_bit[K]);
    assign and10 = F10Bits'(x) & {F10Bits{plane_bit[K]}};
    assign and01 = F10Bits'(y) & {F10Bits{plane_bit[K]}};
    assign and20 = F20Bits'(p20) & {F20Bits{plane_bit[K]}};
    assign and11 = F11Bits'(p11) & {F11Bits{plane_bit[K]}};
    assign and02 = F20Bits'(p02) & {F20Bits{plane_bit[K]}};

    logic [F00Bits-1:0] a00;
    logic [F10Bits-1:0] a10, a01;
    logic [F20Bits-1:0] a20, a02;
    logic [F11Bits-1:0] a11;
    assign a00 = s_lut_sof_i ? '0 : acc00_q[K*F00Bits +: F00Bits];
    assign a10 = s_lut_sof_i ? '0 : acc10_q[K*F10Bits +: F10Bits];
    assign a01 = s_lut_sof_i ? '0 : acc01_q[K*F10Bits +: F10Bits];
    assign a20 = s_lut_sof_i ? '0 : acc20_q[K*F20Bits +: F20Bits];
    assign a11 = s_lut_sof_i ? '0 : acc11_q[K*F11Bits +: F11Bits];
    assign a02 = s_lut_sof_i ? '0 : acc02_q[K*F20Bits +: F20Bits];

    assign acc00_d[K*F00Bits +: F00Bits] = take ? a00 + and00 : acc00_q[K*F00Bits +: F00Bits];
    assign acc10_d[K*F10Bits +: F10Bits] = take ? a10 + and10 : acc10_q[K*F10Bits +: F10Bits];
    assign acc01_d[K*F10Bits +: F10Bits] = take ? a01 + and01 : acc01_q[K*F10Bits +: F10Bits];
    assign acc20_d[K*F20Bits +: F20Bits] = take ? a20 + and20 : acc20_q[K*F20Bits +: F20Bits];
    assign acc11_d[K*F11Bits +: F11Bits] = take ? a11 + and11 : acc11_q[K*F11Bits +: F11Bits];
    assign acc02_d[K*F20Bits +: F20Bits] = take ? a02 + and02 : acc02_q[K*F20Bits +: F20Bits];
  end

  // ---------------------------------------------------------------------------
  // Snapshot and Horner combine (eq. 27). The snapshot of the grey planes is
  // a shift register: step s reads plane Planes-1-s from the top slot, so no
  // plane multiplexer is needed. The snapshot may be reloaded on the edge at
  // which the combine reads its last plane (F_0), not earlier: an EOF that
  // comes sooner is an overrun and its frame is dropped.
  logic       combine_busy_q, combine_busy_d;
  logic [2:0] combine_step_q, combine_step_d;  // plane Planes-1-step is added at the next edge
  logic       last_step;
  logic       eof_take, snap_load;
  logic [31:0] overrun_count_q, overrun_count_d;

  assign last_step = combine_step_q == LastStep;
  assign eof_take  = take & s_lut_eof_i;
  assign snap_load = eof_take & (~combine_busy_q | last_step);

  always_comb begin
    snap00_d = snap00_q;
    snap10_d = snap10_q;
    snap01_d = snap01_q;
    snap20_d = snap20_q;
    snap11_d = snap11_q;
    snap02_d = snap02_q;
    if (snap_load) begin
      snap00_d = acc00_d;
      snap10_d = acc10_d;
      snap01_d = acc01_d;
      snap20_d = acc20_d;
      snap11_d = acc11_d;
      snap02_d = acc02_d;
    end else if (combine_busy_q) begin
      // Shift the grey planes up by one; the mask (index Planes) holds.
      for (int unsigned k = Planes - 1; k > 0; k--) begin
        snap00_d[k*F00Bits +: F00Bits] = snap00_q[(k-1)*F00Bits +: F00Bits];
        snap10_d[k*F10Bits +: F10Bits] = snap10_q[(k-1)*F10Bits +: F10Bits];
        snap01_d[k*F10Bits +: F10Bits] = snap01_q[(k-1)*F10Bits +: F10Bits];
        snap20_d[k*F20Bits +: F20Bits] = snap20_q[(k-1)*F20Bits +: F20Bits];
        snap11_d[k*F11Bits +: F11Bits] = snap11_q[(k-1)*F11Bits +: F11Bits];
        snap02_d[k*F20Bits +: F20Bits] = snap02_q[(k-1)*F20Bits +: F20Bits];
      end
    end
  end

  logic [M00Bits-1:0] h00_q, h00_d;
  logic [M10Bits-1:0] h10_q, h10_d, h01_q, h01_d;
  logic [M20Bits-1:0] h20_q, h20_d, h02_q, h02_d;
  logic [M11Bits-1:0] h11_q, h11_d;
  logic               first_step;

  assign first_step = combine_step_q == 3'd0;

  // h = 2 h + F (h = F on the first, MSB, plane). 2 h is a shift.
  always_comb begin
    h00_d = h00_q;
    h10_d = h10_q;
    h01_d = h01_q;
    h20_d = h20_q;
    h11_d = h11_q;
    h02_d = h02_q;
    if (combine_busy_q) begin
      h00_d = (first_step ? '0 : {h00_q[M00Bits-2:0], 1'b0})
            + M00Bits'(snap00_q[(Planes-1)*F00Bits +: F00Bits]);
      h10_d = (first_step ? '0 : {h10_q[M10Bits-2:0], 1'b0})
            + M10Bits'(snap10_q[(Planes-1)*F10Bits +: F10Bits]);
      h01_d = (first_step ? '0 : {h01_q[M10Bits-2:0], 1'b0})
            + M10Bits'(snap01_q[(Planes-1)*F10Bits +: F10Bits]);
      h20_d = (first_step ? '0 : {h20_q[M20Bits-2:0], 1'b0})
            + M20Bits'(snap20_q[(Planes-1)*F20Bits +: F20Bits]);
      h11_d = (first_step ? '0 : {h11_q[M11Bits-2:0], 1'b0})
            + M11Bits'(snap11_q[(Planes-1)*F11Bits +: F11Bits]);
      h02_d = (first_step ? '0 : {h02_q[M20Bits-2:0], 1'b0})
            + M20Bits'(snap02_q[(Planes-1)*F20Bits +: F20Bits]);
    end
  end

  logic combine_done;
  assign combine_done = combine_busy_q & last_step;

  always_comb begin
    combine_busy_d = combine_busy_q;
    combine_step_d = combine_step_q;
    if (combine_busy_q) begin
      combine_step_d = last_step ? 3'd0 : combine_step_q + 3'd1;
      combine_busy_d = ~last_step;
    end
    if (snap_load) begin
      combine_busy_d = 1'b1;
      combine_step_d = 3'd0;
    end
  end

  always_comb begin
    overrun_count_d = overrun_count_q;
    if (eof_take && !snap_load && overrun_count_q != 32'hFFFF_FFFF) begin
      overrun_count_d = overrun_count_q + 32'd1;
    end
  end

  // ---------------------------------------------------------------------------
  // Registers.
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      x_q <= '0;
      y_q <= '0;
      p20_q <= '0;
      p11_q <= '0;
      p02_q <= '0;
      frame_open_q <= 1'b0;
      acc00_q <= '0;
      acc10_q <= '0;
      acc01_q <= '0;
      acc20_q <= '0;
      acc11_q <= '0;
      acc02_q <= '0;
      snap00_q <= '0;
      snap10_q <= '0;
      snap01_q <= '0;
      snap20_q <= '0;
      snap11_q <= '0;
      snap02_q <= '0;
      combine_busy_q <= 1'b0;
      combine_step_q <= 3'd0;
      h00_q <= '0;
      h10_q <= '0;
      h01_q <= '0;
      h20_q <= '0;
      h11_q <= '0;
      h02_q <= '0;
      grey_m00_o <= '0;
      grey_m10_o <= '0;
      grey_m01_o <= '0;
      grey_m20_o <= '0;
      grey_m11_o <= '0;
      grey_m02_o <= '0;
      mask_m00_o <= '0;
      mask_m10_o <= '0;
      mask_m01_o <= '0;
      mask_m20_o <= '0;
      mask_m11_o <= '0;
      mask_m02_o <= '0;
      done_o <= 1'b0;
      overrun_count_q <= '0;
    end else begin
      x_q <= x_d;
      y_q <= y_d;
      p20_q <= p20_d;
      p11_q <= p11_d;
      p02_q <= p02_d;
      frame_open_q <= frame_open_d;
      acc00_q <= acc00_d;
      acc10_q <= acc10_d;
      acc01_q <= acc01_d;
      acc20_q <= acc20_d;
      acc11_q <= acc11_d;
      acc02_q <= acc02_d;
      snap00_q <= snap00_d;
      snap10_q <= snap10_d;
      snap01_q <= snap01_d;
      snap20_q <= snap20_d;
      snap11_q <= snap11_d;
      snap02_q <= snap02_d;
      combine_busy_q <= combine_busy_d;
      combine_step_q <= combine_step_d;
      h00_q <= h00_d;
      h10_q <= h10_d;
      h01_q <= h01_d;
      h20_q <= h20_d;
      h11_q <= h11_d;
      h02_q <= h02_d;
      if (combine_done) begin
        grey_m00_o <= h00_d;
        grey_m10_o <= h10_d;
        grey_m01_o <= h01_d;
        grey_m20_o <= h20_d;
        grey_m11_o <= h11_d;
        grey_m02_o <= h02_d;
        mask_m00_o <= snap00_q[Planes*F00Bits +: F00Bits];
        mask_m10_o <= snap10_q[Planes*F10Bits +: F10Bits];
        mask_m01_o <= snap01_q[Planes*F10Bits +: F10Bits];
        mask_m20_o <= snap20_q[Planes*F20Bits +: F20Bits];
        mask_m11_o <= snap11_q[Planes*F11Bits +: F11Bits];
        mask_m02_o <= snap02_q[Planes*F20Bits +: F20Bits];
      end
      done_o <= combine_done;
      overrun_count_q <= overrun_count_d;
    end
  end

  assign combine_busy_o  = combine_busy_q;
  assign overrun_count_o = overrun_count_q;

  // The camera pixel itself is not used: moments are of the LUT output.
  logic unused_grey;
  assign unused_grey = ^s_lut_grey_i;

`ifndef SYNTHESIS
  // frame_check guarantees the pixel position; the counters must agree.
  always_ff @(posedge clk_i) begin
    if (rst_ni && take) begin
      assert (s_lut_x_i == x && s_lut_y_i == y)
      else $error("moment_gen: pixel (%0d, %0d) but counters (%0d, %0d)",
                  s_lut_x_i, s_lut_y_i, x, y);
    end
  end
`else
  logic unused_pos;
  assign unused_pos = ^{s_lut_x_i, s_lut_y_i};
`endif

endmodule
