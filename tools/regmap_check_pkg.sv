// Lint target for the generated package: imports it and uses its values.
module regmap_check_pkg
  import ceilnav_reg_pkg::*;
(
  input  logic [CeilnavAddrWidth-1:0] addr_i,
  output logic                        hit_o
);
  assign hit_o = (addr_i == CEILNAV_CONTROL_OFFSET) || (addr_i == CEILNAV_HIST_DATA_OFFSET);
endmodule
