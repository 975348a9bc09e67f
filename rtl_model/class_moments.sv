// class_moments: m00 m10 m01 m20 m11 m02 of the binary mask of each pixel
// class 1..NumClasses (LUT bits 10:9: 1 pattern, 2 shadow, 3 bar) inside the
// window [x0, x1) x [y0, y1), all classes concurrently, in frame coordinates.
// Counters and adders only (seed 003, eq. 20-28), no multiplier: each pixel's
// terms x^2, x y, y^2 are increments of the previous pixel's (x^2 += 2x + 1,
// x y += y along a row, y^2 += 2y + 1 at a row change), and every moment
// accumulator of the pixel's class adds its term.
// Cycle model: stream/class_moments.{hpp,cpp}; spec: docs/blocks/class_moments.md.
// Latency: the EOF pixel taken on edge e shows on the outputs after edge e+2.
module class_moments #(
  parameter  int unsigned NumClasses = ceilnav_pkg::MaxClasses  // classes 1 .. NumClasses are measured (1..3)
) (
  input  logic                             clk_i,
  input  logic                             rst_ni,

  // s_lut: pixel beat from thresh_lut (LutBeat); grey, remap and mask unused.
  input  logic                             s_lut_valid_i,
  input  ceilnav_pkg::pixel_t              s_lut_grey_i,
  input  ceilnav_pkg::coord_t              s_lut_x_i,
  input  ceilnav_pkg::coord_t              s_lut_y_i,
  input  logic                             s_lut_sof_i,
  input  logic                             s_lut_eol_i,
  input  logic                             s_lut_eof_i,
  input  logic                             s_lut_abort_i,
  input  ceilnav_pkg::pixel_t              s_lut_remap_i,
  input  logic                             s_lut_mask_i,
  input  ceilnav_pkg::class_t              s_lut_class_i,

  // Window, sampled with the SOF pixel.
  input  ceilnav_pkg::win_t                win_x0_i,
  input  ceilnav_pkg::win_t                win_x1_i,
  input  ceilnav_pkg::win_t                win_y0_i,
  input  ceilnav_pkg::win_t                win_y1_i,
  // Sampled with the EOF pixel: 0 discards the frame (no done, outputs kept).
  input  logic                             eof_keep_i,

  output logic                             done_o,  // one-cycle pulse: outputs just updated
  // Class c (1 .. NumClasses) at [(c-1)*MxxBits +: MxxBits].
  output logic [NumClasses*ceilnav_pkg::M00Bits-1:0] m00_o,
  output logic [NumClasses*ceilnav_pkg::M10Bits-1:0] m10_o,
  output logic [NumClasses*ceilnav_pkg::M10Bits-1:0] m01_o,
  output logic [NumClasses*ceilnav_pkg::M20Bits-1:0] m20_o,
  output logic [NumClasses*ceilnav_pkg::M11Bits-1:0] m11_o,
  output logic [NumClasses*ceilnav_pkg::M20Bits-1:0] m02_o
);

  // Frames up to 2^CoordBits square. Moment widths for a full 2^k x 2^k frame
  // of ones (k = CoordBits), derived in fixedpoint/datapath.hpp
  // (class_moments::moment_bits: m00 2k+1, m10 3k-1, m20 4k-1, m11 4k-2 bits).
  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned M00Bits   = ceilnav_pkg::M00Bits;
  localparam int unsigned M10Bits   = ceilnav_pkg::M10Bits;
  localparam int unsigned M20Bits   = ceilnav_pkg::M20Bits;
  localparam int unsigned M11Bits   = ceilnav_pkg::M11Bits;
  localparam int unsigned TermBits  = ceilnav_pkg::TermBits;  // x^2, x y, y^2 <= (2^k - 1)^2

  // ---------------------------------------------------------------------------
  // Stage 0: take the pixel; its terms are increments of the previous pixel's
  // (held in the stage-1 registers until the next pixel is taken).
  logic frame_open_q, row_start_q;
  logic take, row_start;

  assign take      = s_lut_valid_i & (s_lut_sof_i | frame_open_q);
  assign row_start = s_lut_sof_i | row_start_q;

  logic                 t_valid_q, t_start_q, t_end_q;
  ceilnav_pkg::class_t  t_class_q;
  ceilnav_pkg::coord_t  t_x_q, t_y_q;
  logic [TermBits-1:0]  t_x2_q, t_xy_q, t_y2_q;
  logic [TermBits-1:0]  x2_d, xy_d, y2_d;
  ceilnav_pkg::win_t    win_x0_q, win_x1_q, win_y0_q, win_y1_q;

  // x^2 + 2x + 1 = (x + 1)^2; x y + y = (x + 1) y; y^2 + 2y + 1 = (y + 1)^2.
  assign x2_d = row_start ? '0 : t_x2_q + TermBits'({t_x_q, 1'b1});
  assign xy_d = row_start ? '0 : t_xy_q + TermBits'(t_y_q);
  assign y2_d = s_lut_sof_i ? '0 :
                row_start_q ? t_y2_q + TermBits'({t_y_q, 1'b1}) : t_y2_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      frame_open_q <= 1'b0;
      row_start_q  <= 1'b0;
    end else if (take) begin
      frame_open_q <= ~s_lut_eof_i;
      row_start_q  <= s_lut_eol_i;
    end else if (s_lut_abort_i) begin
      frame_open_q <= 1'b0;  // the partial sums are never shown
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      t_valid_q <= 1'b0;
    end else begin
      t_valid_q <= take;
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      t_start_q <= 1'b0;
      t_end_q   <= 1'b0;
      t_class_q <= '0;
      t_x_q     <= '0;
      t_y_q     <= '0;
      t_x2_q    <= '0;
      t_xy_q    <= '0;
      t_y2_q    <= '0;
    end else if (take) begin
      t_start_q <= s_lut_sof_i;
      t_end_q   <= s_lut_eof_i & eof_keep_i;
      t_class_q <= s_lut_class_i;
      t_x_q     <= s_lut_x_i;
      t_y_q     <= s_lut_y_i;
      t_x2_q    <= x2_d;
      t_xy_q    <= xy_d;
      t_y2_q    <= y2_d;
    end
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      win_x0_q <= '0;
      win_x1_q <= '0;
      win_y0_q <= '0;
      win_y1_q <= '0;
    end else if (take && s_lut_sof_i) begin
      win_x0_q <= win_x0_i;
      win_x1_q <= win_x1_i;
      win_y0_q <= win_y0_i;
      win_y1_q <= win_y1_i;
    end
  end

  // ---------------------------------------------------------------------------
  // Stage 1 -> 2: the accumulators of the pixel's class add its terms; the
  // frame's first pixel restarts all of them (start ? term : acc + term, the
  // start mux behind the adder, as in moment_gen).
  logic in_win;
  assign in_win = ({1'b0, t_x_q} >= win_x0_q) && ({1'b0, t_x_q} < win_x1_q) &&
                  ({1'b0, t_y_q} >= win_y0_q) && ({1'b0, t_y_q} < win_y1_q);

  logic end_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      end_q  <= 1'b0;
      done_o <= 1'b0;
    end else begin
      end_q  <= t_valid_q & t_end_q;
      done_o <= end_q;
    end
  end

  for (genvar c = 0; c < NumClasses; c++) begin : g_class
    logic               hit;
    logic [M00Bits-1:0] acc00_q, out00_q;
    logic [M10Bits-1:0] acc10_q, acc01_q, out10_q, out01_q;
    logic [M20Bits-1:0] acc20_q, acc02_q, out20_q, out02_q;
    logic [M11Bits-1:0] acc11_q, out11_q;

    assign hit = in_win && (t_class_q == ceilnav_pkg::ClassBits'(c + 1));

    // No reset: the frame's first pixel initialises every accumulator before
    // any of them can reach the outputs (then iCE40 maps the clear of a
    // non-hit start onto the flip-flop's synchronous reset).
    always_ff @(posedge clk_i) begin
      if (t_valid_q && t_start_q && !hit) begin
        acc00_q <= '0;
        acc10_q <= '0;
        acc01_q <= '0;
        acc20_q <= '0;
        acc11_q <= '0;
        acc02_q <= '0;
      end else if (t_valid_q && hit) begin
        acc00_q <= t_start_q ? M00Bits'(1)      : acc00_q + M00Bits'(1);
        acc10_q <= t_start_q ? M10Bits'(t_x_q)  : acc10_q + M10Bits'(t_x_q);
        acc01_q <= t_start_q ? M10Bits'(t_y_q)  : acc01_q + M10Bits'(t_y_q);
        acc20_q <= t_start_q ? M20Bits'(t_x2_q) : acc20_q + M20Bits'(t_x2_q);
        acc11_q <= t_start_q ? M11Bits'(t_xy_q) : acc11_q + M11Bits'(t_xy_q);
        acc02_q <= t_start_q ? M20Bits'(t_y2_q) : acc02_q + M20Bits'(t_y2_q);
      end
    end

    // Stage 2 -> outputs: the finished frame's accumulators, on the edge on
    // which the next frame's first pixel may already restart them.
    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        out00_q <= '0;
        out10_q <= '0;
        out01_q <= '0;
        out20_q <= '0;
        out11_q <= '0;
        out02_q <= '0;
      end else if (end_q) begin
        out00_q <= acc00_q;
        out10_q <= acc10_q;
        out01_q <= acc01_q;
        out20_q <= acc20_q;
        out11_q <= acc11_q;
        out02_q <= acc02_q;
      end
    end

    assign m00_o[c*M00Bits +: M00Bits] = out00_q;
    assign m10_o[c*M10Bits +: M10Bits] = out10_q;
    assign m01_o[c*M10Bits +: M10Bits] = out01_q;
    assign m20_o[c*M20Bits +: M20Bits] = out20_q;
    assign m11_o[c*M11Bits +: M11Bits] = out11_q;
    assign m02_o[c*M20Bits +: M20Bits] = out02_q;
  end

  // Only the class and the position are used.
  logic unused;
  assign unused = ^{s_lut_grey_i, s_lut_remap_i, s_lut_mask_i};

`ifndef SYNTHESIS
  // frame_check guarantees that each pixel follows the previous one; the
  // increments need it (the C++ model throws std::logic_error instead).
  ceilnav_pkg::coord_t want_x, want_y;
  assign want_x = row_start ? '0 : t_x_q + CoordBits'(1);
  assign want_y = s_lut_sof_i ? '0 : (row_start_q ? t_y_q + CoordBits'(1) : t_y_q);
  always_ff @(posedge clk_i) begin
    if (rst_ni && take) begin
      assert (s_lut_x_i == want_x && s_lut_y_i == want_y)
      else $error("class_moments: pixel (%0d, %0d) does not follow (%0d, %0d)",
                  s_lut_x_i, s_lut_y_i, want_x, want_y);
    end
  end
  initial begin
    assert (NumClasses >= 1 && NumClasses <= ceilnav_pkg::MaxClasses) else $fatal(1, "NumClasses must be 1..3");
  end
`endif

endmodule
