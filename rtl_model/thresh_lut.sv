// thresh_lut: 256 x 11-bit programmable LUT (ceilnav_pkg::lut_entry_t: bits
// 7:0 remap, bit 8 mask, bits 10:9 pixel class) with
// a synchronous read, double-banked: host writes go to the shadow bank and are
// committed (bank swap) on the frame-start edge. Cycle-exact twin of
// stream/thresh_lut.cpp (ThreshLut::clock with LutWrite); see
// docs/blocks/thresh_lut.md. Latency 1 cycle.
module thresh_lut (
  input  logic                    clk_i,
  input  logic                    rst_ni,

  // Pixel stream from frame_check (PixelBeat)
  input  logic                    s_pix_valid_i,
  input  ceilnav_pkg::pixel_t     s_pix_grey_i,
  input  ceilnav_pkg::coord_t     s_pix_x_i,
  input  ceilnav_pkg::coord_t     s_pix_y_i,
  input  logic                    s_pix_sof_i,
  input  logic                    s_pix_eol_i,
  input  logic                    s_pix_eof_i,
  input  logic                    s_pix_abort_i,

  // Frame-start strobe: frame_check samples an SOF beat on this edge
  input  logic                    frame_start_i,

  // Host write port into the shadow bank (entry: {class, mask, remap})
  input  logic                    lut_wr_en_i,
  input  ceilnav_pkg::pixel_t     lut_wr_index_i,
  input  ceilnav_pkg::lut_entry_t lut_wr_data_i,

  // LutBeat: the delayed pixel beat plus LUT[grey]
  output logic                    m_lut_valid_o,
  output ceilnav_pkg::pixel_t     m_lut_grey_o,
  output ceilnav_pkg::coord_t     m_lut_x_o,
  output ceilnav_pkg::coord_t     m_lut_y_o,
  output logic                    m_lut_sof_o,
  output logic                    m_lut_eol_o,
  output logic                    m_lut_eof_o,
  output logic                    m_lut_abort_o,
  output ceilnav_pkg::pixel_t     m_lut_remap_o,
  output logic                    m_lut_mask_o,
  output ceilnav_pkg::class_t     m_lut_class_o
);

  localparam int unsigned Entries = ceilnav_pkg::LutEntries;  // one per grey level

  // Two BRAM banks, 256 x 11, one write and one synchronous read port each.
  // A bank is read only while active and written only while shadow: the read
  // and write enables exclude each other, so no read-during-write collision
  // exists and no bypass logic is needed.
  // (Memories of a plain vector: Yosys 0.23 makes an array of a struct type one register.)
  (* ram_style = "block" *) logic [ceilnav_pkg::LutEntryBits-1:0] bank0_mem [Entries];
  (* ram_style = "block" *) logic [ceilnav_pkg::LutEntryBits-1:0] bank1_mem [Entries];
  ceilnav_pkg::lut_entry_t bank0_rd_q, bank1_rd_q;

  logic active_d, active_q;    // bank select
  logic pending_d, pending_q;  // shadow bank written since the last swap
  logic rd_bank_q;             // bank the registered read came from
  logic swap;

  // The write of this edge lands first, so it is part of a commit on this edge.
  assign swap      = frame_start_i & (pending_q | lut_wr_en_i);
  assign active_d  = active_q ^ swap;
  assign pending_d = swap ? 1'b0 : (pending_q | lut_wr_en_i);

  // No write on an edge in reset: the write port's drivers may hold anything
  // there (power-up), and a reset changes no bank contents (docs/rtl_style.md).
  logic wr_en;
  assign wr_en = rst_ni & lut_wr_en_i;

  always_ff @(posedge clk_i) begin
    if (wr_en && active_q) begin
      bank0_mem[lut_wr_index_i] <= lut_wr_data_i;
    end
    if (!active_q) begin
      bank0_rd_q <= bank0_mem[s_pix_grey_i];
    end
  end

  always_ff @(posedge clk_i) begin
    if (wr_en && !active_q) begin
      bank1_mem[lut_wr_index_i] <= lut_wr_data_i;
    end
    if (active_q) begin
      bank1_rd_q <= bank1_mem[s_pix_grey_i];
    end
  end

  ceilnav_pkg::pix_beat_t s_pix, pix_q;  // the input beat and its one-edge delay
  // (Concatenation in field order: Yosys 0.23 reads no assignment patterns.)
  assign s_pix = {s_pix_valid_i, s_pix_grey_i, s_pix_x_i, s_pix_y_i, s_pix_sof_i, s_pix_eol_i,
                  s_pix_eof_i, s_pix_abort_i};

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      active_q    <= 1'b0;
      pending_q   <= 1'b0;
      rd_bank_q   <= 1'b0;
      pix_q       <= '0;
    end else begin
      active_q    <= active_d;
      pending_q   <= pending_d;
      rd_bank_q   <= active_q;  // the lookup reads the bank before the swap
      pix_q       <= s_pix;
    end
  end

  // remap, mask and class are 0 on beats without a pixel (the BRAM output register
  // has no reset; the gate keeps its power-up value off the port).
  ceilnav_pkg::lut_entry_t entry;
  assign entry = pix_q.valid ? (rd_bank_q ? bank1_rd_q : bank0_rd_q) : '0;

  assign m_lut_valid_o = pix_q.valid;
  assign m_lut_grey_o  = pix_q.grey;
  assign m_lut_x_o     = pix_q.x;
  assign m_lut_y_o     = pix_q.y;
  assign m_lut_sof_o   = pix_q.sof;
  assign m_lut_eol_o   = pix_q.eol;
  assign m_lut_eof_o   = pix_q.eof;
  assign m_lut_abort_o = pix_q.abort_frame;
  assign m_lut_remap_o = entry.remap;
  assign m_lut_mask_o  = entry.mask;
  assign m_lut_class_o = entry.cls;

endmodule
