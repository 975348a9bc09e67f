// thresh_lut: 256 x 11-bit programmable LUT (bits 7:0 remap, bit 8 mask,
// bits 10:9 pixel class) with
// a synchronous read, double-banked: host writes go to the shadow bank and are
// committed (bank swap) on the frame-start edge. Cycle-exact twin of
// stream/thresh_lut.cpp (ThreshLut::clock with LutWrite); see
// docs/blocks/thresh_lut.md. Latency 1 cycle.
module thresh_lut #(
  parameter int unsigned CoordBits = ceilnav_widths_pkg::CoordBits
) (
  input  logic                 clk_i,
  input  logic                 rst_ni,

  // Pixel stream from frame_check (PixelBeat)
  input  logic                 s_pix_valid_i,
  input  logic [7:0]           s_pix_grey_i,
  input  logic [CoordBits-1:0] s_pix_x_i,
  input  logic [CoordBits-1:0] s_pix_y_i,
  input  logic                 s_pix_sof_i,
  input  logic                 s_pix_eol_i,
  input  logic                 s_pix_eof_i,
  input  logic                 s_pix_abort_i,

  // Frame-start strobe: frame_check samples an SOF beat on this edge
  input  logic                 frame_start_i,

  // Host write port into the shadow bank
  input  logic                 lut_wr_en_i,
  input  logic [7:0]           lut_wr_index_i,
  input  logic [10:0]          lut_wr_data_i,

  // LutBeat: the delayed pixel beat plus LUT[grey]
  output logic                 m_lut_valid_o,
  output logic [7:0]           m_lut_grey_o,
  output logic [CoordBits-1:0] m_lut_x_o,
  output logic [CoordBits-1:0] m_lut_y_o,
  output logic                 m_lut_sof_o,
  output logic                 m_lut_eol_o,
  output logic                 m_lut_eof_o,
  output logic                 m_lut_abort_o,
  output logic [7:0]           m_lut_remap_o,
  output logic                 m_lut_mask_o,
  output logic [1:0]           m_lut_class_o
);

  // Two BRAM banks, 256 x 11, one write and one synchronous read port each.
  // A bank is read only while active and written only while shadow: the read
  // and write enables exclude each other, so no read-during-write collision
  // exists and no bypass logic is needed.
  (* ram_style = "block" *) logic [10:0] bank0_mem [256];
  (* ram_style = "block" *) logic [10:0] bank1_mem [256];
  logic [10:0] bank0_rd_q, bank1_rd_q;

  logic active_d, active_q;    // bank select
  logic pending_d, pending_q;  // shadow bank written since the last swap
  logic rd_bank_q;             // bank the registered read came from
  logic swap;

  // The write of this edge lands first, so it is part of a commit on this edge.
  assign swap      = frame_start_i & (pending_q | lut_wr_en_i);
  assign active_d  = active_q ^ swap;
  assign pending_d = swap ? 1'b0 : (pending_q | lut_wr_en_i);

  always_ff @(posedge clk_i) begin
    if (lut_wr_en_i && active_q) begin
      bank0_mem[lut_wr_index_i] <= lut_wr_data_i;
    end
    if (!active_q) begin
      bank0_rd_q <= bank0_mem[s_pix_grey_i];
    end
  end

  always_ff @(posedge clk_i) begin
    if (lut_wr_en_i && !active_q) begin
      bank1_mem[lut_wr_index_i] <= lut_wr_data_i;
    end
    if (active_q) begin
      bank1_rd_q <= bank1_mem[s_pix_grey_i];
    end
  end

  logic                 pix_valid_q;
  logic [7:0]           pix_grey_q;
  logic [CoordBits-1:0] pix_x_q;
  logic [CoordBits-1:0] pix_y_q;
  logic                 pix_sof_q;
  logic                 pix_eol_q;
  logic                 pix_eof_q;
  logic                 pix_abort_q;

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      active_q    <= 1'b0;
      pending_q   <= 1'b0;
      rd_bank_q   <= 1'b0;
      pix_valid_q <= 1'b0;
      pix_grey_q  <= 8'd0;
      pix_x_q     <= '0;
      pix_y_q     <= '0;
      pix_sof_q   <= 1'b0;
      pix_eol_q   <= 1'b0;
      pix_eof_q   <= 1'b0;
      pix_abort_q <= 1'b0;
    end else begin
      active_q    <= active_d;
      pending_q   <= pending_d;
      rd_bank_q   <= active_q;  // the lookup reads the bank before the swap
      pix_valid_q <= s_pix_valid_i;
      pix_grey_q  <= s_pix_grey_i;
      pix_x_q     <= s_pix_x_i;
      pix_y_q     <= s_pix_y_i;
      pix_sof_q   <= s_pix_sof_i;
      pix_eol_q   <= s_pix_eol_i;
      pix_eof_q   <= s_pix_eof_i;
      pix_abort_q <= s_pix_abort_i;
    end
  end

  // remap, mask and class are 0 on beats without a pixel (the BRAM output register
  // has no reset; the gate keeps its power-up value off the port).
  logic [10:0] entry;
  assign entry = pix_valid_q ? (rd_bank_q ? bank1_rd_q : bank0_rd_q) : 11'd0;

  assign m_lut_valid_o = pix_valid_q;
  assign m_lut_grey_o  = pix_grey_q;
  assign m_lut_x_o     = pix_x_q;
  assign m_lut_y_o     = pix_y_q;
  assign m_lut_sof_o   = pix_sof_q;
  assign m_lut_eol_o   = pix_eol_q;
  assign m_lut_eof_o   = pix_eof_q;
  assign m_lut_abort_o = pix_abort_q;
  assign m_lut_remap_o = entry[7:0];
  assign m_lut_mask_o  = entry[8];
  assign m_lut_class_o = entry[10:9];

endmodule
