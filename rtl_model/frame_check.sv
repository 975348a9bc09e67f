// frame_check: checks the camera's AXI4-Stream video against the configured
// geometry, numbers the pixels and realigns after framing errors.
// Cycle-exact twin of stream/frame_check.cpp (FrameCheck::clock); see
// docs/blocks/frame_check.md. Latency 1 cycle, all outputs registered.
module frame_check #(
  parameter int unsigned CoordBits   = 11,  // x, y in [0, 2^CoordBits - 1]
  parameter int unsigned CounterBits = 32
) (
  input  logic                   clk_i,
  input  logic                   rst_ni,

  // AXI4-Stream video from the camera (tuser = SOF, tlast = EOL)
  input  logic [7:0]             s_axis_video_tdata_i,
  input  logic                   s_axis_video_tvalid_i,
  output logic                   s_axis_video_tready_o,
  input  logic                   s_axis_video_tuser_i,
  input  logic                   s_axis_video_tlast_i,

  // Geometry, sampled on an SOF beat, clamped to 1 .. 2^CoordBits
  input  logic [CoordBits:0]     cfg_width_i,
  input  logic [CoordBits:0]     cfg_height_i,

  // Pixel stream (PixelBeat)
  output logic                   m_pix_valid_o,
  output logic [7:0]             m_pix_grey_o,
  output logic [CoordBits-1:0]   m_pix_x_o,
  output logic [CoordBits-1:0]   m_pix_y_o,
  output logic                   m_pix_sof_o,
  output logic                   m_pix_eol_o,
  output logic                   m_pix_eof_o,
  output logic                   m_pix_abort_o,

  // Error counters (FrameErrorCounters), cumulative since reset, saturating
  output logic [CounterBits-1:0] early_eol_o,
  output logic [CounterBits-1:0] late_eol_o,
  output logic [CounterBits-1:0] early_sof_o,
  output logic [CounterBits-1:0] missing_sof_o,
  output logic [CounterBits-1:0] frames_ok_o,
  output logic [CounterBits-1:0] frames_aborted_o
);

  localparam int unsigned GeomBits = CoordBits + 1;  // holds 1 .. 2^CoordBits
  localparam logic [GeomBits-1:0] MaxGeom = GeomBits'(1) << CoordBits;
  localparam logic [GeomBits-1:0] MinGeom = GeomBits'(1);
  localparam logic [CounterBits-1:0] CounterMax = '1;

  localparam logic [1:0] StIdle    = 2'd0;  // expecting an SOF
  localparam logic [1:0] StInFrame = 2'd1;  // x_q/y_q: position of the next pixel
  localparam logic [1:0] StDiscard = 2'd2;  // after an error: drop until the next SOF

  logic [1:0]           state_d, state_q;
  logic [GeomBits-1:0]  width_d, width_q;
  logic [GeomBits-1:0]  height_d, height_q;
  logic [CoordBits-1:0] x_d, x_q;
  logic [CoordBits-1:0] y_d, y_q;

  logic                 pix_valid_d, pix_valid_q;
  logic [7:0]           pix_grey_d, pix_grey_q;
  logic [CoordBits-1:0] pix_x_d, pix_x_q;
  logic [CoordBits-1:0] pix_y_d, pix_y_q;
  logic                 pix_sof_d, pix_sof_q;
  logic                 pix_eol_d, pix_eol_q;
  logic                 pix_eof_d, pix_eof_q;
  logic                 pix_abort_d, pix_abort_q;

  logic [CounterBits-1:0] early_eol_q, late_eol_q, early_sof_q, missing_sof_q;
  logic [CounterBits-1:0] frames_ok_q, frames_aborted_q;
  logic inc_early_eol, inc_late_eol, inc_early_sof, inc_missing_sof;
  logic inc_frames_ok, inc_frames_aborted;

  assign s_axis_video_tready_o = 1'b1;  // the camera cannot be stalled

  // (Function results by name: yosys 0.23 has no `return`.)
  function automatic logic [GeomBits-1:0] clamp_geom(logic [GeomBits-1:0] value);
    clamp_geom = (value < MinGeom) ? MinGeom : (value > MaxGeom) ? MaxGeom : value;
  endfunction

  function automatic logic [CounterBits-1:0] sat_inc(logic [CounterBits-1:0] value, logic inc);
    sat_inc = (inc && value != CounterMax) ? value + CounterBits'(1) : value;
  endfunction

  // The SOF beat restarts the checker with the configuration of this edge; the
  // pixel is then checked against that geometry at position (0, 0).
  logic                 sof_beat;
  logic [GeomBits-1:0]  width_eff, height_eff;
  logic [CoordBits-1:0] x_eff, y_eff;
  logic                 at_eol, at_eof, first_pixel;

  assign sof_beat    = s_axis_video_tvalid_i & s_axis_video_tuser_i;
  assign width_eff   = sof_beat ? clamp_geom(cfg_width_i) : width_q;
  assign height_eff  = sof_beat ? clamp_geom(cfg_height_i) : height_q;
  assign x_eff       = sof_beat ? '0 : x_q;
  assign y_eff       = sof_beat ? '0 : y_q;
  assign at_eol      = {1'b0, x_eff} == width_eff - GeomBits'(1);
  assign at_eof      = at_eol && ({1'b0, y_eff} == height_eff - GeomBits'(1));
  assign first_pixel = x_eff == '0 && y_eff == '0;

  always_comb begin
    state_d  = state_q;
    width_d  = width_q;
    height_d = height_q;
    x_d      = x_q;
    y_d      = y_q;

    pix_valid_d = 1'b0;
    pix_grey_d  = 8'd0;
    pix_x_d     = '0;
    pix_y_d     = '0;
    pix_sof_d   = 1'b0;
    pix_eol_d   = 1'b0;
    pix_eof_d   = 1'b0;
    pix_abort_d = 1'b0;

    inc_early_eol      = 1'b0;
    inc_late_eol       = 1'b0;
    inc_early_sof      = 1'b0;
    inc_missing_sof    = 1'b0;
    inc_frames_ok      = 1'b0;
    inc_frames_aborted = 1'b0;

    if (s_axis_video_tvalid_i) begin
      if (sof_beat && state_q == StInFrame) begin
        // Early SOF: abort the open frame; this pixel starts the next one.
        inc_early_sof      = 1'b1;
        inc_frames_aborted = 1'b1;
        pix_abort_d        = 1'b1;
      end
      if (sof_beat) begin
        width_d  = width_eff;
        height_d = height_eff;
        x_d      = '0;
        y_d      = '0;
      end

      if (!sof_beat && state_q == StIdle) begin
        // A pixel outside any frame (also an extra line after a full frame).
        inc_missing_sof = 1'b1;
        state_d         = StDiscard;
      end else if (sof_beat || state_q == StInFrame) begin
        if (s_axis_video_tlast_i != at_eol) begin
          inc_early_eol = s_axis_video_tlast_i;
          inc_late_eol  = ~s_axis_video_tlast_i;
          // A malformed SOF pixel never opened its frame: no abort for it.
          if (!first_pixel) begin
            inc_frames_aborted = 1'b1;
            pix_abort_d        = 1'b1;
          end
          state_d = StDiscard;
        end else begin
          pix_valid_d = 1'b1;
          pix_grey_d  = s_axis_video_tdata_i;
          pix_x_d     = x_eff;
          pix_y_d     = y_eff;
          pix_sof_d   = first_pixel;
          pix_eol_d   = at_eol;
          pix_eof_d   = at_eof;
          if (at_eof) begin
            inc_frames_ok = 1'b1;
            state_d       = StIdle;
          end else if (at_eol) begin
            state_d = StInFrame;
            x_d     = '0;
            y_d     = y_eff + CoordBits'(1);
          end else begin
            state_d = StInFrame;
            x_d     = x_eff + CoordBits'(1);
          end
        end
      end
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      state_q          <= StIdle;
      width_q          <= MinGeom;
      height_q         <= MinGeom;
      x_q              <= '0;
      y_q              <= '0;
      pix_valid_q      <= 1'b0;
      pix_grey_q       <= 8'd0;
      pix_x_q          <= '0;
      pix_y_q          <= '0;
      pix_sof_q        <= 1'b0;
      pix_eol_q        <= 1'b0;
      pix_eof_q        <= 1'b0;
      pix_abort_q      <= 1'b0;
      early_eol_q      <= '0;
      late_eol_q       <= '0;
      early_sof_q      <= '0;
      missing_sof_q    <= '0;
      frames_ok_q      <= '0;
      frames_aborted_q <= '0;
    end else begin
      state_q          <= state_d;
      width_q          <= width_d;
      height_q         <= height_d;
      x_q              <= x_d;
      y_q              <= y_d;
      pix_valid_q      <= pix_valid_d;
      pix_grey_q       <= pix_grey_d;
      pix_x_q          <= pix_x_d;
      pix_y_q          <= pix_y_d;
      pix_sof_q        <= pix_sof_d;
      pix_eol_q        <= pix_eol_d;
      pix_eof_q        <= pix_eof_d;
      pix_abort_q      <= pix_abort_d;
      early_eol_q      <= sat_inc(early_eol_q, inc_early_eol);
      late_eol_q       <= sat_inc(late_eol_q, inc_late_eol);
      early_sof_q      <= sat_inc(early_sof_q, inc_early_sof);
      missing_sof_q    <= sat_inc(missing_sof_q, inc_missing_sof);
      frames_ok_q      <= sat_inc(frames_ok_q, inc_frames_ok);
      frames_aborted_q <= sat_inc(frames_aborted_q, inc_frames_aborted);
    end
  end

  assign m_pix_valid_o    = pix_valid_q;
  assign m_pix_grey_o     = pix_grey_q;
  assign m_pix_x_o        = pix_x_q;
  assign m_pix_y_o        = pix_y_q;
  assign m_pix_sof_o      = pix_sof_q;
  assign m_pix_eol_o      = pix_eol_q;
  assign m_pix_eof_o      = pix_eof_q;
  assign m_pix_abort_o    = pix_abort_q;
  assign early_eol_o      = early_eol_q;
  assign late_eol_o       = late_eol_q;
  assign early_sof_o      = early_sof_q;
  assign missing_sof_o    = missing_sof_q;
  assign frames_ok_o      = frames_ok_q;
  assign frames_aborted_o = frames_aborted_q;

`ifndef SYNTHESIS
  // Geometry limits 1 .. 2^CoordBits, and the open frame's position inside it.
  GeometryInRange: assert property (@(posedge clk_i) disable iff (!rst_ni)
      width_q >= MinGeom && width_q <= MaxGeom && height_q >= MinGeom && height_q <= MaxGeom);
  PositionInFrame: assert property (@(posedge clk_i) disable iff (!rst_ni)
      state_q != StInFrame || ({1'b0, x_q} < width_q && {1'b0, y_q} < height_q));
  StateLegal: assert property (@(posedge clk_i) disable iff (!rst_ni) state_q != 2'd3);
`endif

endmodule
