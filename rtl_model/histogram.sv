// histogram: 256 bins per frame of the camera grey or the LUT remap.
// Three BRAM banks of 256 x BinBits rotate: the accumulating bank (pipelined
// read-modify-write: read on the sampling edge, write on the next edge,
// forwarding for back-to-back hits on one bin), the result bank (read port)
// and a bank being cleared by a sweep (one bin per edge on its otherwise idle
// write port) after it stopped being the result bank. Every frame starts in a
// clean bank, so no per-bin valid bits exist. A frame that starts while no
// clean bank is free is not counted (count_ok_o low at its SOF); the
// pipeline then drops it at EOF (moment_gen eof_drop_i).
// Cycle-exact twin of stream/histogram.cpp; see docs/blocks/histogram.md.
// done_o: kept EOF sampled on edge e -> done_o high after edge e+1 (1 cycle).
// Read port: hist_rd_en_i/hist_rd_bin_i sampled on edge t ->
// hist_rd_data_o after edge t (bin of the results before edge t), else 0.
module histogram (
  input  logic                 clk_i,
  input  logic                 rst_ni,

  // LutBeat from thresh_lut
  input  logic                 s_lut_valid_i,
  input  ceilnav_pkg::pixel_t  s_lut_grey_i,
  input  ceilnav_pkg::coord_t  s_lut_x_i,
  input  ceilnav_pkg::coord_t  s_lut_y_i,
  input  logic                 s_lut_sof_i,
  input  logic                 s_lut_eol_i,
  input  logic                 s_lut_eof_i,
  input  logic                 s_lut_abort_i,
  input  ceilnav_pkg::pixel_t  s_lut_remap_i,
  input  logic                 s_lut_mask_i,

  // Source of the bin index: 0 = camera grey, 1 = LUT remap; latched at SOF
  input  logic                 source_remap_i,
  // The frame of the beat on the input is counted (Mealy; Histogram::counts)
  output logic                 count_ok_o,
  // With the EOF beat: 1 = the pipeline publishes this frame, 0 = dropped
  input  logic                 keep_i,

  // Results: one-cycle pulse when a new frame's bins become readable
  output logic                 done_o,

  // Results read port (BRAM style, one cycle)
  input  logic                 hist_rd_en_i,
  input  ceilnav_pkg::pixel_t  hist_rd_bin_i,
  output logic [ceilnav_pkg::BinBits-1:0] hist_rd_data_o
);

  localparam int unsigned CoordBits = ceilnav_pkg::CoordBits;
  // A bin counts at most every pixel of the largest frame, 2^(2*CoordBits).
  localparam int unsigned BinBits   = ceilnav_pkg::BinBits;
  localparam int unsigned IndexBits = ceilnav_pkg::BinIndexBits;  // bin index: grey or remap
  localparam int unsigned Bins      = 1 << IndexBits;
  localparam logic [IndexBits-1:0] LastBin = IndexBits'(Bins - 1);
  typedef logic [IndexBits-1:0] index_t;

  localparam int unsigned Banks = 3;
  localparam logic [BinBits-1:0] MaxCount = BinBits'(1) << (2 * CoordBits);

  localparam int unsigned BankBits = 2;
  typedef logic [BankBits-1:0] bank_t;

  // Position, EOL and mask are not needed for a histogram.
  logic unused_lut;
  assign unused_lut = ^{s_lut_x_i, s_lut_y_i, s_lut_eol_i, s_lut_mask_i};

  // ---------------------------------------------------------------------------
  // State that describes the BRAM contents: not reset (initialised with the
  // configuration, like the BRAM); a reset marks the last frame's bank dirty.
  logic [Banks-1:0] dirty_q = '0;  // bank needs clearing or is being cleared
  bank_t            disp_q  = '0;  // result bank
  bank_t            acc_q   = '0;  // bank of the open or last frame

  logic        counting_q, frame_open_q, source_remap_q, eof_q, done_q, res_valid_q;
  logic        rst_mark_q;  // set by a reset until the edge after it: acc_q counts as dirty
  logic [Banks-1:0] dirty;  // dirty_q with the reset's mark

  // Stage 1 -> 2 of the read-modify-write
  logic               s1_accum_q;  // count written on the next edge
  logic               s1_sof_q;    // first pixel of its frame: the bank reads 0
  index_t             s1_bin_q;
  bank_t              s1_bank_q;
  logic               s1_fwd_q;    // its count is being written: forward it
  logic [BinBits-1:0] last_count_q;

  // Read port
  logic  rd_en_q;
  bank_t rd_bank_q;

  // ---------------------------------------------------------------------------
  // Stage 1: classify the sampled beat
  logic  sof, free_ok, beat_counts, src_remap;
  bank_t free_bank, bank;
  index_t bin;

  // A reset marks the bank of the last frame dirty (it may hold a partial
  // count) from its edge on; dirty_q takes the mark on the next edge.
  always_comb begin
    dirty = dirty_q;
    if (rst_mark_q) begin
      dirty[acc_q] = 1'b1;
    end
  end

  // The lowest clean bank that is neither the result bank nor the last frame's.
  always_comb begin
    free_ok   = 1'b0;
    free_bank = '0;
    for (int b = Banks - 1; b >= 0; b--) begin
      if (!dirty[b] && BankBits'(b) != disp_q && BankBits'(b) != acc_q) begin
        free_ok   = 1'b1;
        free_bank = BankBits'(b);
      end
    end
  end

  assign sof         = s_lut_valid_i & s_lut_sof_i;
  assign beat_counts = sof ? free_ok
                           : (s_lut_valid_i & frame_open_q & ~s_lut_abort_i & counting_q);
  assign count_ok_o  = beat_counts;
  assign src_remap   = s_lut_sof_i ? source_remap_i : source_remap_q;
  assign bin         = src_remap ? s_lut_remap_i : s_lut_grey_i;
  // The bank this beat counts into.
  assign bank        = sof ? free_bank : acc_q;

  // ---------------------------------------------------------------------------
  // BRAM banks: one write port (stage 2 of the accumulating bank, or the
  // bank's own clear sweep while it is dirty: never both) and one synchronous
  // read port (the pixel read of the accumulating bank, or the host read of
  // the result bank: the same bank only after a publication, until the next
  // SOF, when no pixel read happens).
  logic                     pix_rd;
  logic [Banks*BinBits-1:0] bank_rd_q;  // bank b at [b*BinBits +: BinBits]
  logic [Banks-1:0]         clr_busy_q, clr_done;
  logic [BinBits-1:0]       count_rd, new_count;

  assign pix_rd = beat_counts & ~sof;

  for (genvar b = 0; b < Banks; b++) begin : g_bank
    (* ram_style = "block" *) logic [BinBits-1:0] mem [Bins];
    // Configuration contents: zeros (every bank clean, dirty_q = 0).
    initial begin
      for (int i = 0; i < Bins; i++) begin
        mem[i] = '0;
      end
    end

    logic       rd_pix, rd_en, wr_acc, wr_en;
    index_t     rd_addr, wr_addr, clr_ptr_q;

    assign rd_pix  = pix_rd && acc_q == BankBits'(b);
    assign rd_en   = rd_pix || (hist_rd_en_i && disp_q == BankBits'(b));
    assign rd_addr = rd_pix ? bin : hist_rd_bin_i;
    assign wr_acc  = s1_accum_q && s1_bank_q == BankBits'(b);
    // No write on an edge in reset: the registers that drive it may hold
    // anything there (power-up), and a reset changes no bank contents.
    assign wr_en   = rst_ni && (wr_acc || clr_busy_q[b]);
    assign wr_addr = wr_acc ? s1_bin_q : clr_ptr_q;
    assign clr_done[b] = rst_ni & clr_busy_q[b] & (clr_ptr_q == LastBin);

    always_ff @(posedge clk_i) begin
      if (wr_en) begin
        mem[wr_addr] <= wr_acc ? new_count : '0;
      end
      if (rd_en) begin
        bank_rd_q[b*BinBits +: BinBits] <= mem[rd_addr];
      end
    end

    // Clear sweep: starts the edge after the bank became dirty, one bin per edge.
    always_ff @(posedge clk_i) begin
      if (!rst_ni) begin
        clr_busy_q[b] <= 1'b0;
        clr_ptr_q     <= '0;
      end else if (clr_busy_q[b]) begin
        clr_ptr_q <= clr_ptr_q + IndexBits'(1);
        if (clr_done[b]) begin
          clr_busy_q[b] <= 1'b0;
        end
      end else if (dirty[b]) begin
        clr_busy_q[b] <= 1'b1;
        clr_ptr_q     <= '0;
      end
    end
  end

  // Stage 2: the count of the pixel sampled on the previous edge.
  assign count_rd  = s1_fwd_q ? last_count_q : bank_rd_q[s1_bank_q*BinBits +: BinBits];
  assign new_count = (s1_sof_q ? '0 : count_rd) + BinBits'(1);

  // ---------------------------------------------------------------------------
  // Bank roles (not reset): an edge in reset changes nothing but the reset's
  // mark. Order of the marks within an edge: the sweeps' "clean" first, then
  // every "dirty" (a set wins).
  logic [Banks-1:0] dirty_d;

  always_comb begin
    dirty_d = dirty & ~clr_done;
    if (!rst_ni) begin
      dirty_d = dirty;
    end else begin
      if (eof_q) begin
        dirty_d[disp_q] = 1'b1;  // the old result bank
      end
      if (s_lut_abort_i && frame_open_q && counting_q) begin
        dirty_d[acc_q] = 1'b1;
      end
      if (s_lut_valid_i && s_lut_eof_i && beat_counts && !keep_i) begin
        dirty_d[bank] = 1'b1;
      end
    end
  end

  always_ff @(posedge clk_i) begin
    dirty_q <= dirty_d;
    if (rst_ni && eof_q) begin
      disp_q <= acc_q;
    end
    if (rst_ni && sof && free_ok) begin
      acc_q <= free_bank;
    end
  end

  // ---------------------------------------------------------------------------
  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      rst_mark_q     <= 1'b1;
      counting_q     <= 1'b0;
      frame_open_q   <= 1'b0;
      source_remap_q <= 1'b0;
      eof_q          <= 1'b0;
      done_q         <= 1'b0;
      res_valid_q    <= 1'b0;
      s1_accum_q     <= 1'b0;
      s1_sof_q       <= 1'b0;
      s1_bin_q       <= '0;
      s1_bank_q      <= '0;
      s1_fwd_q       <= 1'b0;
      last_count_q   <= '0;
      rd_en_q        <= 1'b0;
      rd_bank_q      <= '0;
    end else begin
      rst_mark_q <= 1'b0;
      // Publication (stage 2 of the kept EOF)
      done_q <= eof_q;
      if (eof_q) begin
        res_valid_q <= 1'b1;
      end
      eof_q <= 1'b0;
      // Stage 1: frame state
      if (s_lut_abort_i) begin
        frame_open_q <= 1'b0;
        counting_q   <= 1'b0;
      end
      if (sof) begin
        source_remap_q <= source_remap_i;
        frame_open_q   <= 1'b1;
      end
      if (s_lut_valid_i && (sof || (frame_open_q && !s_lut_abort_i))) begin
        counting_q <= beat_counts;
        if (s_lut_eof_i) begin
          frame_open_q <= 1'b0;
          counting_q   <= 1'b0;
          eof_q        <= beat_counts & keep_i;
        end
      end
      s1_accum_q <= beat_counts;
      s1_sof_q   <= sof;
      s1_bin_q   <= bin;
      s1_bank_q  <= bank;
      s1_fwd_q   <= s1_accum_q & ~sof & (s1_bin_q == bin) & (s1_bank_q == bank);
      if (s1_accum_q) begin
        last_count_q <= new_count;
      end
      rd_en_q   <= hist_rd_en_i & res_valid_q;
      rd_bank_q <= disp_q;
    end
  end

  assign done_o = done_q;

  // The BRAM output registers have no reset: gated by the read's enable.
  assign hist_rd_data_o = rd_en_q ? bank_rd_q[rd_bank_q*BinBits +: BinBits] : '0;

`ifndef SYNTHESIS
  // A bin counts at most every pixel of the largest frame.
  CountInRange: assert property (@(posedge clk_i) disable iff (!rst_ni)
      s1_accum_q |-> (new_count <= MaxCount));
  // The pixel read and the host read never want the same bank's port.
  ReadPortsDisjoint: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(pix_rd && hist_rd_en_i && acc_q == disp_q));
  // A sweep never clears the bank being written or read as the result.
  SweepDisjoint: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !(s1_accum_q && clr_busy_q[s1_bank_q]) && !(res_valid_q && clr_busy_q[disp_q]));
  // A frame only ever counts into a clean bank.
  CountsIntoCleanBank: assert property (@(posedge clk_i) disable iff (!rst_ni)
      beat_counts |-> !dirty[bank]);
`endif

endmodule
