// run_fifo: the run scanner's FIFO memory. Up to two writes per edge (at the
// write pointer and the one after it) and one read. Two banks interleaved by
// address mod 2, each a simple dual-port RAM of Depth/2 entries: consecutive
// addresses hit distinct banks, so each bank sees at most one write per edge
// (one BRAM write port).
//
// The read is synchronous and the bank's read register is the consumer's
// output register: rd_i at an edge loads the entry at the read pointer into
// rdata_o, which then holds until the next rd_i. The caller never reads an
// entry on the edge that writes it and never lets writes reach unread entries
// (run_scanner's occupancy count guarantees both), so a read never meets a
// write to the same address: the banks need no read-during-write behaviour
// (no_rw_check: Yosys maps them onto bare SB_RAM40_4K). No count is kept here.
//
// Late field: LateWidth more bits of one of the entries written on an edge
// arrive one edge later (late_data_i in the cycle after the edge that wrote
// the entry with late_en_i, late_slot_i) and are written into their own two
// banks then. A read on that same edge takes them from the write instead of
// the bank (late_byp_q): the only case in which an entry is read before its
// late field is in memory.
// See docs/blocks/run_scanner.md, section RTL.

module run_fifo #(
  parameter int unsigned Depth = 1024,  // entries, power of two, >= 8
  parameter int unsigned Width = 59,
  parameter int unsigned LateWidth = 29,
  localparam int unsigned AddrBits = $clog2(Depth)
) (
  input  logic               clk_i,
  input  logic               rst_ni,
  // Writes 0 .. wr_count_i-1 (wr_count_i <= 2) go to wp, wp+1.
  input  logic [ceilnav_pkg::FifoWrBits-1:0] wr_count_i,
  input  logic [2*Width-1:0] wr_data_i,  // write i at [i*Width +: Width]
  input  logic               late_en_i,    // this edge's write late_slot_i has a late field
  input  logic               late_slot_i,
  input  logic [LateWidth-1:0] late_data_i,  // the late field of the last edge's write
  input  logic               rd_i,       // load the entry at the read pointer into rdata_o
  output logic [Width-1:0]   rdata_o,    // the entry of the last rd_i edge
  output logic [LateWidth-1:0] rdata_late_o  // and its late field
);

  localparam int unsigned BankAddrBits = AddrBits - 1;

  if (Depth < 8 || (Depth & (Depth - 1)) != 0) begin : g_bad_depth
    $fatal(1, "run_fifo: Depth must be a power of two >= 8");
  end

  logic [AddrBits-1:0] wp_q, rp_q;
  logic                rd_bank_q;
  logic [2*Width-1:0]  bank_rdata;  // bank b at [b*Width +: Width]
  logic [2*LateWidth-1:0] late_rdata;
  logic                late_en_q, late_hit, late_byp_q;
  logic [AddrBits-1:0] late_addr_q;
  logic [LateWidth-1:0] late_byp_data_q;
  assign late_hit = late_en_q && late_addr_q == rp_q;

  for (genvar b = 0; b < 2; b++) begin : g_bank
    // Write 0 lands in bank wp[0], write 1 in the other one.
    logic                    slot;
    logic                    wr_en;
    logic [BankAddrBits-1:0] wr_row;
    logic [Width-1:0]        wr_data;
    (* no_rw_check *)
    logic [Width-1:0]        mem_q[2**BankAddrBits];
    logic [Width-1:0]        rdata_q;

    assign slot    = wp_q[0] != 1'(b);
    // No write on an edge in reset (docs/rtl_style.md, "Reset"): wr_count_i
    // and the pointers may hold anything there.
    assign wr_en   = rst_ni && ceilnav_pkg::FifoWrBits'(slot) < wr_count_i;
    // Bank 1 row wp/2 (wp or wp+1 odd); bank 0 row (wp+1)/2.
    assign wr_row  = wp_q[AddrBits-1:1] + BankAddrBits'(b == 0 && wp_q[0]);
    assign wr_data = slot ? wr_data_i[Width +: Width] : wr_data_i[0 +: Width];

    always_ff @(posedge clk_i) begin
      if (wr_en) mem_q[wr_row] <= wr_data;
    end
    always_ff @(posedge clk_i) begin
      if (rd_i && rp_q[0] == 1'(b)) rdata_q <= mem_q[rp_q[AddrBits-1:1]];
    end
    assign bank_rdata[b*Width +: Width] = rdata_q;

    (* no_rw_check *)
    logic [LateWidth-1:0] late_mem_q[2**BankAddrBits];
    logic [LateWidth-1:0] late_rdata_q;
    always_ff @(posedge clk_i) begin
      if (rst_ni && late_en_q && late_addr_q[0] == 1'(b)) begin
        late_mem_q[late_addr_q[AddrBits-1:1]] <= late_data_i;
      end
    end
    always_ff @(posedge clk_i) begin
      if (rd_i && rp_q[0] == 1'(b)) late_rdata_q <= late_mem_q[rp_q[AddrBits-1:1]];
    end
    assign late_rdata[b*LateWidth +: LateWidth] = late_rdata_q;
  end

  always_ff @(posedge clk_i) begin
    if (!rst_ni) begin
      wp_q       <= '0;
      rp_q       <= '0;
      rd_bank_q  <= 1'b0;
      late_en_q  <= 1'b0;
      late_addr_q <= '0;
      late_byp_q <= 1'b0;
    end else begin
      wp_q <= wp_q + AddrBits'(wr_count_i);
      late_en_q <= late_en_i;
      late_addr_q <= wp_q + AddrBits'(late_slot_i);
      if (rd_i) begin
        rp_q       <= rp_q + AddrBits'(1);
        rd_bank_q  <= rp_q[0];
        late_byp_q <= late_hit;
      end
    end
  end
  always_ff @(posedge clk_i) begin
    if (rd_i && late_hit) late_byp_data_q <= late_data_i;
  end

  assign rdata_o = rd_bank_q ? bank_rdata[Width +: Width] : bank_rdata[0 +: Width];
  assign rdata_late_o = late_byp_q ? late_byp_data_q :
                        rd_bank_q ? late_rdata[LateWidth +: LateWidth] : late_rdata[0 +: LateWidth];

`ifndef SYNTHESIS
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      assert (wr_count_i <= ceilnav_pkg::FifoWrBits'(2))
      else $error("run_fifo: more than two writes in one edge");
    end
  end
`endif

endmodule
