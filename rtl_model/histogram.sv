// histogram: 256 bins per frame of the camera grey or the LUT remap.
// Two ping-pong BRAM banks of 256 x BinBits with a pipelined read-modify-write
// (read on the sampling edge, write on the next edge, forwarding for
// back-to-back hits on one bin) and a flash-cleared valid bit per bin in
// flip-flops: one set for the accumulating frame, one copy for the result
// bank (the bank roles swap, the valid sets do not: no bank mux on them).
// Cycle-exact twin of stream/histogram.cpp
// (Histogram::clock with the read port); see docs/blocks/histogram.md.
// done_o: EOF sampled on edge e -> done_o high after edge e+1 (1 cycle).
// Read port: hist_rd_en_i/hist_rd_bin_i sampled on edge t ->
// hist_rd_data_o after edge t (bin of the results before edge t), else 0.
module histogram #(
  parameter int unsigned CoordBits = ceilnav_widths_pkg::CoordBits,
  // A bin counts at most every pixel of the largest frame, 2^(2*CoordBits).
  parameter int unsigned BinBits   = 2 * CoordBits + 1
) (
  input  logic                 clk_i,
  input  logic                 rst_ni,

  // LutBeat from thresh_lut
  input  logic                 s_lut_valid_i,
  input  logic [7:0]           s_lut_grey_i,
  input  logic [CoordBits-1:0] s_lut_x_i,
  input  logic [CoordBits-1:0] s_lut_y_i,
  input  logic                 s_lut_sof_i,
  input  logic                 s_lut_eol_i,
  input  logic                 s_lut_eof_i,
  input  logic                 s_lut_abort_i,
  input  logic [7:0]           s_lut_remap_i,
  input  logic                 s_lut_mask_i,

  // Source of the bin index: 0 = camera grey, 1 = LUT remap; latched at SOF
  input  logic                 source_remap_i,

  // Results: one-cycle pulse when a new frame's bins become readable
  output logic                 done_o,

  // Results read port (BRAM style, one cycle)
  input  logic                 hist_rd_en_i,
  input  logic [7:0]           hist_rd_bin_i,
  output logic [BinBits-1:0]   hist_rd_data_o
);

  localparam logic [BinBits-1:0] MaxCount = BinBits'(1) << (2 * CoordBits);

  // Position, EOL and mask are not needed for a histogram.
  logic unused_lut;
  assign unused_lut = ^{s_lut_x_i, s_lut_y_i, s_lut_eol_i, s_lut_mask_i};

  // ---------------------------------------------------------------------------
  // Bank roles and frame state
  logic acc_bank_d, acc_bank_q;    // bank the open frame accumulates into
  logic disp_bank_d, disp_bank_q;  // bank the read port reads
  logic fin_bank_d, fin_bank_q;    // bank that completed on the previous edge
  logic frame_open_d, frame_open_q;
  logic source_remap_d, source_remap_q;
  logic eof_d, eof_q;              // EOF pixel sampled on the previous edge
  logic done_q;

  logic [255:0] valid_acc_q;   // per bin: counted in the accumulating bank's frame
  logic [255:0] valid_disp_q;  // per bin: counted in the result bank's frame

  // Stage 1 -> 2 of the read-modify-write
  logic               s1_accum_d, s1_accum_q;  // count written on the next edge
  logic [7:0]         s1_bin_d, s1_bin_q;
  logic               s1_bank_d, s1_bank_q;
  logic               s1_hit_d, s1_hit_q;      // bin already counted this frame
  logic               s1_fwd_d, s1_fwd_q;      // its count is being written: forward it
  logic [BinBits-1:0] last_count_q;            // count written on the last edge

  // Read port
  logic rd_en_q, rd_hit_q, rd_bank_q;

  // ---------------------------------------------------------------------------
  // Stage 1: classify the sampled beat
  logic         open_eff;  // frame open after this beat's abort
  logic         src_remap;
  logic [7:0]   bin;
  logic         accum;
  logic [255:0] bin_onehot;
  logic [255:0] valid_acc_d;

  assign open_eff    = frame_open_q & ~s_lut_abort_i;
  assign src_remap   = s_lut_sof_i ? source_remap_i : source_remap_q;
  assign bin         = src_remap ? s_lut_remap_i : s_lut_grey_i;
  assign accum       = s_lut_valid_i & (s_lut_sof_i | open_eff);

  always_comb begin
    bin_onehot      = '0;
    bin_onehot[bin] = accum;
  end

  // The SOF pixel flash-clears its bank's valid bits in its own edge.
  assign valid_acc_d = ((s_lut_valid_i && s_lut_sof_i) ? '0 : valid_acc_q) | bin_onehot;

  assign done_o = done_q;

  always_comb begin
    // Stage 2 of the finished frame: switch the result bank.
    disp_bank_d = eof_q ? fin_bank_q : disp_bank_q;
    eof_d       = 1'b0;

    acc_bank_d     = acc_bank_q;
    fin_bank_d     = fin_bank_q;
    frame_open_d   = open_eff;
    source_remap_d = source_remap_q;

    if (s_lut_valid_i && s_lut_sof_i) begin
      source_remap_d = source_remap_i;
      frame_open_d   = 1'b1;
    end
    if (accum && s_lut_eof_i) begin
      fin_bank_d   = acc_bank_q;
      acc_bank_d   = ~acc_bank_q;
      frame_open_d = 1'b0;
      eof_d        = 1'b1;
    end
  end

  assign s1_accum_d = accum;
  assign s1_bin_d   = bin;
  assign s1_bank_d  = acc_bank_q;
  assign s1_hit_d   = ~s_lut_sof_i & valid_acc_q[bin];
  assign s1_fwd_d   = s1_accum_q & (s1_bin_q == bin) & (s1_bank_q == acc_bank_q);

  // ---------------------------------------------------------------------------
  // BRAM banks: one write port (stage 2) and one synchronous read port, shared
  // by the pixel read (accumulating bank) and the host read (result bank). The
  // SOF pixel needs no read (its bin is invalid), and a bank is both the
  // accumulating and the result bank only in the cycle after an EOF edge, when
  // only an SOF pixel can accumulate: the two reads never meet on one bank.
  (* ram_style = "block" *) logic [BinBits-1:0] bank0_mem [256];
  (* ram_style = "block" *) logic [BinBits-1:0] bank1_mem [256];
  logic [BinBits-1:0] bank0_rd_q, bank1_rd_q;

  logic               pix_rd, host_rd0, host_rd1, rd0_en, rd1_en;
  logic [7:0]         rd0_addr, rd1_addr;
  logic [BinBits-1:0] count_rd, new_count;
  logic               wr0_en, wr1_en;

  assign pix_rd   = accum & ~s_lut_sof_i;
  assign host_rd0 = hist_rd_en_i & ~disp_bank_q;
  assign host_rd1 = hist_rd_en_i & disp_bank_q;
  assign rd0_en   = (pix_rd & ~acc_bank_q) | host_rd0;
  assign rd1_en   = (pix_rd & acc_bank_q) | host_rd1;
  assign rd0_addr = (pix_rd & ~acc_bank_q) ? bin : hist_rd_bin_i;
  assign rd1_addr = (pix_rd & acc_bank_q) ? bin : hist_rd_bin_i;

  // Stage 2: the count of the pixel sampled on the previous edge.
  assign count_rd  = s1_fwd_q ? last_count_q : (s1_bank_q ? bank1_rd_q : bank0_rd_q);
  assign new_count = (s1_hit_q ? count_rd : '0) + BinBits'(1);
  assign wr0_en    = s1_accum_q & ~s1_bank_q;
  assign wr1_en    = s1_accum_q & s1_bank_q;

  always_ff @(posedge clk_i) begin
    if (wr0_en) begin
      bank0_mem[s1_bin_q] <= new_count;
    end
    if (rd0_en) begin
      bank0_rd_q <= bank0_mem[rd0_addr];
    end
  end

  always_ff @(posedge clk_i) begin
    if (wr1_en) begin
      bank1_mem[s1_bin_q] <= new_count;
    end
    if (rd1_en) begin
      bank1_rd_q <= bank1_mem[rd1_addr];
    end
  end

  // ---------------------------------------------------------------------------
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      acc_bank_q     <= 1'b0;
      disp_bank_q    <= 1'b1;
      fin_bank_q     <= 1'b0;
      frame_open_q   <= 1'b0;
      source_remap_q <= 1'b0;
      eof_q          <= 1'b0;
      done_q         <= 1'b0;
      valid_acc_q    <= '0;
      valid_disp_q   <= '0;
      s1_accum_q     <= 1'b0;
      s1_bin_q       <= 8'd0;
      s1_bank_q      <= 1'b0;
      s1_hit_q       <= 1'b0;
      s1_fwd_q       <= 1'b0;
      last_count_q   <= '0;
      rd_en_q        <= 1'b0;
      rd_hit_q       <= 1'b0;
      rd_bank_q      <= 1'b0;
    end else begin
      acc_bank_q     <= acc_bank_d;
      disp_bank_q    <= disp_bank_d;
      fin_bank_q     <= fin_bank_d;
      frame_open_q   <= frame_open_d;
      source_remap_q <= source_remap_d;
      eof_q          <= eof_d;
      done_q         <= eof_q;
      if (accum) begin
        valid_acc_q <= valid_acc_d;
      end
      // The result bank switches to the finished frame's bank on this edge:
      // its valid set is the accumulating set before this edge (an SOF pixel
      // on this edge clears valid_acc_q only after it).
      if (eof_q) begin
        valid_disp_q <= valid_acc_q;
      end
      s1_accum_q     <= s1_accum_d;
      s1_bin_q       <= s1_bin_d;
      s1_bank_q      <= s1_bank_d;
      s1_hit_q       <= s1_hit_d;
      s1_fwd_q       <= s1_fwd_d;
      if (s1_accum_q) begin
        last_count_q <= new_count;
      end
      rd_en_q        <= hist_rd_en_i;
      rd_hit_q       <= valid_disp_q[hist_rd_bin_i];
      rd_bank_q      <= disp_bank_q;
    end
  end

  // The BRAM output registers have no reset: gated by the read's valid bit.
  assign hist_rd_data_o = (rd_en_q && rd_hit_q) ? (rd_bank_q ? bank1_rd_q : bank0_rd_q) : '0;

`ifndef SYNTHESIS
  // A bin counts at most every pixel of the largest frame.
  CountInRange: assert property (@(posedge clk_i) disable iff (!rst_ni)
      s1_accum_q |-> (new_count <= MaxCount));
  // The pixel read and the host read never want the same bank's port.
  ReadPortsDisjoint: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(pix_rd && hist_rd_en_i && acc_bank_q == disp_bank_q));
  // The result bank is never written while the host may read it.
  ResultBankNotWritten: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(s1_accum_q && s1_bank_q == disp_bank_q));
`endif

endmodule
