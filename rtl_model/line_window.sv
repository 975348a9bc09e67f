// line_window: the frame a block takes from the LUT remap stream and the
// line buffer of its 3x3 window, shared by edge_detect and orientation
// (C++: stream::LineWindow, stream/line_window.hpp). A frame is taken from an
// SOF pixel with enable_i = 1 to its EOF pixel or an abort.
//
// Line buffer: one BRAM word per column, {p(x,y-2), p(x,y-1)}. The
// synchronous read of a pixel's column is issued on the edge before it: the
// address is the next pixel's column (next_col_q, or the one after the pixel
// taken on this edge). Only a one-pixel-wide frame reads on the edge that
// writes the same word; that read takes the written word (the bypass). Words
// of rows a frame has not written yet are read but never used (row y-1 only
// from y >= 1, row y-2 only from y >= 2), so the stale word an early SOF
// pixel reads is harmless.
//
// Inputs are assumed legal as frame_check/thresh_lut make them: pix.x/pix.y
// equal the position counters (a simulation assertion checks it).

module line_window (
  input  logic                clk_i,
  input  logic                rst_ni,

  input  logic                s_valid_i,
  input  ceilnav_pkg::coord_t s_x_i,
  input  ceilnav_pkg::coord_t s_y_i,  // for the position assertion only
  input  logic                s_sof_i,
  input  logic                s_eol_i,
  input  logic                s_eof_i,
  input  logic                s_abort_i,
  input  ceilnav_pkg::pixel_t s_remap_i,
  input  logic                enable_i,  // the block's enable, used at an SOF pixel

  output logic                take_o,        // the pixel belongs to the taken frame
  output logic                sof_take_o,    // an SOF pixel taken: the block latches its config
  output logic                frame_open_o,  // a frame is open (before this edge)
  output ceilnav_pkg::pixel_t r1_o,          // p(x, y-1) (through the bypass)
  output ceilnav_pkg::pixel_t r2_o,          // p(x, y-2)
  output ceilnav_pkg::pixel_t sr1_o,         // the read register's p(x, y-1), no bypass
  output ceilnav_pkg::pixel_t sr2_o          // and p(x, y-2)
);

  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  localparam int unsigned PixelBits = ceilnav_pkg::PixelBits;
  localparam int unsigned LbBits    = 2 * PixelBits;  // rows y-1, y-2
  localparam int unsigned LbDepth   = 1 << CoordBits;

  logic frame_open_q, frame_open_d, take;
  assign take = s_valid_i & (s_sof_i ? enable_i : frame_open_q);

  always_comb begin
    frame_open_d = frame_open_q;
    if (s_valid_i & s_sof_i) frame_open_d = take & ~s_eof_i;  // a disabled frame is not opened
    else if (take) frame_open_d = ~s_eof_i;
    else if (s_abort_i) frame_open_d = 1'b0;
  end

  ceilnav_pkg::coord_t next_col_q, rd_col, x;
  logic                lb_we, lb_byp, lb_byp_q;
  logic [LbBits-1:0]   lb_wdata, lb_rdata_q, lb_byp_data_q, lb_word;
  (* no_rw_check *)
  logic [LbBits-1:0]   lb_mem_q[LbDepth];

  assign x = s_x_i;  // == the position counter (asserted below)
  always_comb begin
    rd_col = frame_open_d ? next_col_q : '0;
    if (take) rd_col = s_eol_i ? '0 : x + CoordBits'(1);
  end
  assign lb_word  = lb_byp_q ? lb_byp_data_q : lb_rdata_q;
  // No write on an edge in reset (docs/rtl_style.md, "Reset").
  assign lb_we    = rst_ni & take;
  assign lb_wdata = {lb_word[PixelBits-1:0], s_remap_i};
  assign lb_byp   = take & s_eol_i & (x == '0);

  always_ff @(posedge clk_i) begin
    if (lb_we) lb_mem_q[x] <= lb_wdata;
  end
  always_ff @(posedge clk_i) begin
    lb_rdata_q <= lb_mem_q[rd_col];
    lb_byp_q <= lb_byp;
    lb_byp_data_q <= lb_wdata;
  end
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      frame_open_q <= 1'b0;
      next_col_q <= '0;
    end else begin
      frame_open_q <= frame_open_d;
      next_col_q <= rd_col;
    end
  end

  assign take_o       = take;
  assign sof_take_o   = s_valid_i & s_sof_i & enable_i;
  assign frame_open_o = frame_open_q;
  assign r1_o         = lb_word[PixelBits-1:0];
  assign r2_o         = lb_word[LbBits-1:PixelBits];
  assign sr1_o        = lb_rdata_q[PixelBits-1:0];
  assign sr2_o        = lb_rdata_q[LbBits-1:PixelBits];

`ifndef SYNTHESIS
  // Position counters, for the assertion only: the RTL uses pix.x/pix.y.
  ceilnav_pkg::coord_t x_q, y_q, x_cnt, y_cnt;
  assign x_cnt = s_sof_i ? '0 : x_q;
  assign y_cnt = s_sof_i ? '0 : y_q;
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      x_q <= '0;
      y_q <= '0;
    end else if (take) begin
      x_q <= s_eol_i ? '0 : x_cnt + CoordBits'(1);
      y_q <= s_eol_i ? y_cnt + CoordBits'(1) : y_cnt;
    end
  end
  always_ff @(posedge clk_i) begin
    if (rst_ni && take) begin
      assert (s_x_i == x_cnt && s_y_i == y_cnt)
      else $error("line_window: pixel (%0d, %0d) but counters (%0d, %0d)",
                  s_x_i, s_y_i, x_cnt, y_cnt);
      // The line buffer read this pixel's column on the edge before (an
      // early SOF pixel finds the read of the aborted frame's next column:
      // row 0 uses no line buffer word, and its stale words are never read).
      assert (s_sof_i || lb_byp || next_col_q == x)
      else $error("line_window: line buffer read column %0d, pixel at %0d", next_col_q, x);
    end
  end
`endif

endmodule
