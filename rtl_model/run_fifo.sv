// run_fifo: the run scanner's FIFO memory. Up to three writes per edge (at
// tail, tail+1, tail+2) and one read. Built from four banks interleaved by
// address mod 4, each a simple dual-port RAM of Depth/4 entries with a
// synchronous read: consecutive addresses always hit distinct banks, so every
// bank sees at most one write per edge (one BRAM write port).
//
// head_o is the head entry in the cycle after any edge, as if the memory were
// read combinationally (the C++ model, stream/run_scanner.cpp, reads
// fifo_[head] at the edge). Prefetch: at each edge every bank reads the row of
// the head of the NEXT cycle. The banks are write-first (transparent): the
// next head is written on the edge that reads it when it enters an empty
// FIFO. See docs/blocks/run_scanner.md, section RTL.

module run_fifo #(
  parameter int unsigned Depth = 1024,  // entries, power of two, >= 8
  parameter int unsigned Width = 87,
  localparam int unsigned AddrBits = $clog2(Depth),
  localparam int unsigned CountBits = AddrBits + 1
) (
  input  logic                 clk_i,
  input  logic                 rst_ni,
  // Writes 0 .. wr_count_i-1 go to tail .. tail+wr_count_i-1; the caller keeps
  // count_o + wr_count_i <= Depth (checked).
  input  logic [1:0]           wr_count_i,
  input  logic [3*Width-1:0]   wr_data_i,  // write i at [i*Width +: Width]
  input  logic                 rd_i,       // pop the head; only when count_o != 0 (checked)
  output logic [CountBits-1:0] count_o,    // entries in use, registered
  output logic [Width-1:0]     head_o      // the head entry, meaningful when count_o != 0
);

  localparam int unsigned Banks = 4;
  localparam int unsigned BankAddrBits = AddrBits - 2;

  if (Depth < 8 || (Depth & (Depth - 1)) != 0) begin : g_bad_depth
    $fatal(1, "run_fifo: Depth must be a power of two >= 8");
  end

  logic [AddrBits-1:0]  head_q, head_d, tail;
  logic [CountBits-1:0] count_q, count_d, count_after_read;

  assign tail = head_q + count_q[AddrBits-1:0];
  assign head_d = head_q + AddrBits'(rd_i);
  assign count_after_read = count_q - CountBits'(rd_i);
  assign count_d = count_after_read + CountBits'(wr_count_i);

  logic [Banks*Width-1:0] bank_rdata;

  for (genvar b = 0; b < Banks; b++) begin : g_bank
    localparam logic [1:0] B = 2'(b);
    // Which write lands in this bank: the one with (tail + i) mod 4 == b.
    logic [1:0]              wr_index;
    logic                    wr_en;
    logic [AddrBits-1:0]     wr_addr;
    logic [Width-1:0]        wr_data;
    logic [Width-1:0]        mem_q[2**BankAddrBits];
    logic [Width-1:0]        rdata_q;

    assign wr_index = B - tail[1:0];
    assign wr_en = wr_index < wr_count_i;
    assign wr_addr = tail + AddrBits'(wr_index);
    always_comb begin
      wr_data = wr_data_i[0 +: Width];
      if (wr_index == 2'd1) wr_data = wr_data_i[Width +: Width];
      if (wr_index == 2'd2) wr_data = wr_data_i[2*Width +: Width];
    end

    always_ff @(posedge clk_i) begin
      if (wr_en) mem_q[wr_addr[AddrBits-1:2]] <= wr_data;
    end
    always_ff @(posedge clk_i) begin
      if (wr_en && wr_addr[AddrBits-1:2] == head_d[AddrBits-1:2]) begin
        rdata_q <= wr_data;
      end else begin
        rdata_q <= mem_q[head_d[AddrBits-1:2]];
      end
    end
    assign bank_rdata[b*Width +: Width] = rdata_q;

    logic unused_addr;
    assign unused_addr = ^wr_addr[1:0];
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      head_q <= '0;
      count_q <= '0;
    end else begin
      head_q <= head_d;
      count_q <= count_d;
    end
  end

  assign count_o = count_q;
  always_comb begin
    unique case (head_q[1:0])
      2'd0: head_o = bank_rdata[0 +: Width];
      2'd1: head_o = bank_rdata[Width +: Width];
      2'd2: head_o = bank_rdata[2*Width +: Width];
      default: head_o = bank_rdata[3*Width +: Width];
    endcase
  end

`ifndef SYNTHESIS
  always_ff @(posedge clk_i) begin
    if (rst_ni) begin
      assert (!rd_i || count_q != '0)
      else $error("run_fifo: read from an empty FIFO");
      assert ({1'b0, count_after_read} + (CountBits + 1)'(wr_count_i) <= (CountBits + 1)'(Depth))
      else $error("run_fifo: write into a full FIFO");
    end
  end
`endif

endmodule
