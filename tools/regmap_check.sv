// Checks that the generated package elaborates in yosys
// (read_verilog -sv) and that a few values are what the register map says.
module regmap_check (
  input  logic [9:0]  addr_i,
  output logic        hit_o,
  output logic        status_o,
  output logic [31:0] resval_o
);
  // yosys 0.23 takes package items by explicit scope only (no import).
  assign status_o = addr_i == ceilnav_reg_pkg::CEILNAV_STATUS_OFFSET;

  always_comb begin
    hit_o = 1'b0;
    resval_o = 32'h0;
    if (addr_i == ceilnav_reg_pkg::CEILNAV_ID_OFFSET) begin
      hit_o = 1'b1;
      resval_o = ceilnav_reg_pkg::CEILNAV_ID_RESVAL;
    end else if (addr_i == ceilnav_reg_pkg::CEILNAV_MOM_MASK_HI_5_OFFSET) begin
      hit_o = 1'b1;
      resval_o = ceilnav_reg_pkg::CEILNAV_MOM_MASK_HI_RESVAL;
    end
  end

  always_comb begin
    assert (ceilnav_reg_pkg::CEILNAV_ID_RESVAL == 32'h4345494C);
    assert (ceilnav_reg_pkg::CEILNAV_WIDTH_RESVAL == 32'd640);
    assert (ceilnav_reg_pkg::CEILNAV_CONTROL_SOFT_RESET_LSB == 2);
    assert (ceilnav_reg_pkg::CEILNAV_MOM_GREY_LO_1_OFFSET == ceilnav_reg_pkg::CEILNAV_MOM_GREY_LO_OFFSET + 10'(ceilnav_reg_pkg::CEILNAV_MOM_GREY_LO_STRIDE));
  end
endmodule
