// frame_check: checks the camera's AXI4-Stream video against the configured
// geometry, numbers the pixels and realigns after framing errors.
// Cycle-exact twin of stream/frame_check.cpp (FrameCheck::clock); see
// docs/blocks/frame_check.md. Latency 1 cycle, all outputs registered.
//
// Timing: the end-of-line / end-of-frame tests of the next pixel are kept in
// registers (x_last_q, y_last_q), computed one edge ahead from the position
// counters, so no comparator or subtractor sits between the input beat and
// the registers. An SOF beat is checked at (0, 0) against its own
// configuration, where only "width <= 1" / "height <= 1" matter.
module frame_check (
  input  logic                  clk_i,
  input  logic                  rst_ni,

  // AXI4-Stream video from the camera (tuser = SOF, tlast = EOL)
  input  ceilnav_pkg::pixel_t   s_axis_video_tdata_i,
  input  logic                  s_axis_video_tvalid_i,
  output logic                  s_axis_video_tready_o,
  input  logic                  s_axis_video_tuser_i,
  input  logic                  s_axis_video_tlast_i,

  // Geometry, sampled on an SOF beat, clamped to 1 .. 2^CoordBits
  input  ceilnav_pkg::geom_t    cfg_width_i,
  input  ceilnav_pkg::geom_t    cfg_height_i,

  // Pixel stream (PixelBeat)
  output logic                  m_pix_valid_o,
  output ceilnav_pkg::pixel_t   m_pix_grey_o,
  output ceilnav_pkg::coord_t   m_pix_x_o,
  output ceilnav_pkg::coord_t   m_pix_y_o,
  output logic                  m_pix_sof_o,
  output logic                  m_pix_eol_o,
  output logic                  m_pix_eof_o,
  output logic                  m_pix_abort_o,

  // Error counters (FrameErrorCounters), cumulative since reset, saturating
  output ceilnav_pkg::word_t    early_eol_o,
  output ceilnav_pkg::word_t    late_eol_o,
  output ceilnav_pkg::word_t    early_sof_o,
  output ceilnav_pkg::word_t    missing_sof_o,
  output ceilnav_pkg::word_t    frames_ok_o,
  output ceilnav_pkg::word_t    frames_aborted_o
);

  localparam int unsigned CoordBits   = ceilnav_pkg::CoordBits;    // x, y in [0, 2^CoordBits - 1]
  localparam int unsigned GeomBits    = ceilnav_pkg::GeomBits;     // cfg ports: CoordBits + 1
  localparam int unsigned CounterBits = ceilnav_pkg::CounterBits;  // = WordBits (the ports)
  localparam int unsigned ErrCount    = ceilnav_pkg::ErrCount;
  localparam ceilnav_pkg::geom_t  MaxGeom  = GeomBits'(1) << CoordBits;
  // Not '1: Yosys 0.23 synthesises a '1 fill in a localparam as 1.
  localparam ceilnav_pkg::coord_t MaxCoord = CoordBits'(MaxGeom - GeomBits'(1));

  ceilnav_pkg::fc_state_e state_d, state_q;
  // Latched geometry minus one: the last column / line of the open frame.
  ceilnav_pkg::coord_t  x_max_q, y_max_q;
  ceilnav_pkg::coord_t  x_d, x_q, y_d, y_q;
  logic                 x_last_d, x_last_q;  // x_q == x_max_q
  logic                 y_last_d, y_last_q;  // y_q == y_max_q

  // The registered output beat.
  ceilnav_pkg::pix_beat_t pix_q;
  logic                   pix_abort_d;

  assign s_axis_video_tready_o = 1'b1;  // the camera cannot be stalled

  // clamp(cfg, 1, 2^CoordBits) - 1 (function results by name: yosys 0.23 has no `return`).
  function automatic ceilnav_pkg::coord_t geom_max(ceilnav_pkg::geom_t cfg);
    geom_max = (cfg == '0) ? '0 : (cfg > MaxGeom) ? MaxCoord : CoordBits'(cfg - GeomBits'(1));
  endfunction

  // ---------------------------------------------------------------------------
  // Classification of this beat.
  logic sof_beat, in_frame, checked, at_eol, at_eof, eol_error, good, early_sof, missing_sof;
  logic cfg_w_le1, cfg_h_le1, cfg_w_is2, cfg_h_is2;

  assign cfg_w_le1 = cfg_width_i[CoordBits:1] == '0;
  assign cfg_h_le1 = cfg_height_i[CoordBits:1] == '0;
  assign cfg_w_is2 = cfg_width_i == GeomBits'(2);
  assign cfg_h_is2 = cfg_height_i == GeomBits'(2);

  assign sof_beat    = s_axis_video_tvalid_i & s_axis_video_tuser_i;
  assign in_frame    = state_q == ceilnav_pkg::FcInFrame;
  // The SOF pixel is at (0, 0) of its own geometry: the last column iff width <= 1.
  assign at_eol      = sof_beat ? cfg_w_le1 : x_last_q;
  assign at_eof      = at_eol & (sof_beat ? cfg_h_le1 : y_last_q);
  assign checked     = s_axis_video_tvalid_i & (s_axis_video_tuser_i | in_frame);
  assign eol_error   = checked & (s_axis_video_tlast_i ^ at_eol);
  assign good        = checked & ~(s_axis_video_tlast_i ^ at_eol);
  assign early_sof   = sof_beat & in_frame;
  assign missing_sof = s_axis_video_tvalid_i & ~s_axis_video_tuser_i & (state_q == ceilnav_pkg::FcIdle);

  // In a frame, (x, y) = (0, 0) only on the SOF beat (x or y moves on with
  // every good pixel until the EOF), so the first pixel is the SOF beat. A
  // malformed SOF pixel never opened its frame: no abort for it.
  assign pix_abort_d = early_sof | (eol_error & ~sof_beat);

  // ---------------------------------------------------------------------------
  // Position of the next pixel and the registered last-column/line tests.
  ceilnav_pkg::coord_t x_inc, y_inc;
  assign x_inc = x_q + CoordBits'(1);
  assign y_inc = y_q + CoordBits'(1);

  always_comb begin
    state_d  = state_q;
    x_d      = x_q;
    y_d      = y_q;
    x_last_d = x_last_q;
    y_last_d = y_last_q;
    if (missing_sof || eol_error) begin
      state_d = ceilnav_pkg::FcDiscard;
    end else if (good) begin
      state_d = at_eof ? ceilnav_pkg::FcIdle : ceilnav_pkg::FcInFrame;
      if (sof_beat) begin
        // Next pixel: (1, 0), or (0, 1) in a frame one pixel wide.
        x_d      = at_eol ? '0 : CoordBits'(1);
        y_d      = at_eol ? CoordBits'(1) : '0;
        x_last_d = at_eol ? 1'b1 : cfg_w_is2;
        y_last_d = at_eol ? cfg_h_is2 : cfg_h_le1;
      end else if (at_eol) begin
        x_d      = '0;
        y_d      = y_inc;
        x_last_d = x_max_q == '0;
        y_last_d = y_inc == y_max_q;
      end else begin
        x_d      = x_inc;
        x_last_d = x_inc == x_max_q;
      end
    end
  end

  // ---------------------------------------------------------------------------
  // Saturating error counters: the carry out of q + 1 is "q is all ones".
  logic [ErrCount-1:0] inc;  // early_eol, late_eol, early_sof, missing_sof, frames_ok, frames_aborted
  logic [ErrCount*CounterBits-1:0] cnt_q;  // counter i at [i*CounterBits +: CounterBits]
  assign inc[0] = eol_error & s_axis_video_tlast_i;
  assign inc[1] = eol_error & ~s_axis_video_tlast_i;
  assign inc[2] = early_sof;
  assign inc[3] = missing_sof;
  assign inc[4] = good & at_eof;
  assign inc[5] = pix_abort_d;

  for (genvar i = 0; i < ErrCount; i++) begin : g_counter
    logic [CounterBits:0] sum;
    assign sum = {1'b0, cnt_q[i*CounterBits +: CounterBits]} + (CounterBits + 1)'(1);
    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        cnt_q[i*CounterBits +: CounterBits] <= '0;
      end else if (inc[i] && !sum[CounterBits]) begin
        cnt_q[i*CounterBits +: CounterBits] <= sum[CounterBits-1:0];
      end
    end
  end

  // ---------------------------------------------------------------------------
  // Registers.
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      state_q     <= ceilnav_pkg::FcIdle;
      x_max_q     <= '0;
      y_max_q     <= '0;
      x_q         <= '0;
      y_q         <= '0;
      x_last_q    <= 1'b0;
      y_last_q    <= 1'b0;
      pix_q       <= '0;
    end else begin
      state_q  <= state_d;
      x_q      <= x_d;
      y_q      <= y_d;
      x_last_q <= x_last_d;
      y_last_q <= y_last_d;
      if (sof_beat) begin
        x_max_q <= geom_max(cfg_width_i);
        y_max_q <= geom_max(cfg_height_i);
      end
      pix_q.valid <= good;
      pix_q.grey  <= good ? s_axis_video_tdata_i : '0;
      pix_q.x     <= good && !sof_beat ? x_q : '0;
      pix_q.y     <= good && !sof_beat ? y_q : '0;
      pix_q.sof   <= good & sof_beat;
      pix_q.eol   <= good & at_eol;
      pix_q.eof   <= good & at_eof;
      pix_q.abort_frame <= pix_abort_d;
    end
  end

  assign m_pix_valid_o    = pix_q.valid;
  assign m_pix_grey_o     = pix_q.grey;
  assign m_pix_x_o        = pix_q.x;
  assign m_pix_y_o        = pix_q.y;
  assign m_pix_sof_o      = pix_q.sof;
  assign m_pix_eol_o      = pix_q.eol;
  assign m_pix_eof_o      = pix_q.eof;
  assign m_pix_abort_o    = pix_q.abort_frame;
  assign early_eol_o      = cnt_q[0*CounterBits +: CounterBits];
  assign late_eol_o       = cnt_q[1*CounterBits +: CounterBits];
  assign early_sof_o      = cnt_q[2*CounterBits +: CounterBits];
  assign missing_sof_o    = cnt_q[3*CounterBits +: CounterBits];
  assign frames_ok_o      = cnt_q[4*CounterBits +: CounterBits];
  assign frames_aborted_o = cnt_q[5*CounterBits +: CounterBits];

`ifndef SYNTHESIS
  // The registered tests agree with the position, which stays inside the
  // open frame; (0, 0) is never the next pixel of an open frame.
  LastFlagsExact: assert property (@(posedge clk_i) disable iff (!rst_ni)
      state_q != ceilnav_pkg::FcInFrame || (x_last_q == (x_q == x_max_q) && y_last_q == (y_q == y_max_q)));
  PositionInFrame: assert property (@(posedge clk_i) disable iff (!rst_ni)
      state_q != ceilnav_pkg::FcInFrame || (x_q <= x_max_q && y_q <= y_max_q));
  NotFirstPixel: assert property (@(posedge clk_i) disable iff (!rst_ni)
      state_q != ceilnav_pkg::FcInFrame || x_q != '0 || y_q != '0);
  StateLegal: assert property (@(posedge clk_i) disable iff (!rst_ni)
      state_q inside {ceilnav_pkg::FcIdle, ceilnav_pkg::FcInFrame, ceilnav_pkg::FcDiscard});
`endif

endmodule
