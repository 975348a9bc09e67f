// ceilnav_pkg_check: elaboration-time check that every width ceilnav_pkg
// repeats from the generated ceilnav_widths_pkg (tools/regmap_gen, from
// fixedpoint/datapath.hpp) equals it, and that the package's structs have the
// widths of the flat vectors they describe. No ports, no logic: scripts/rtl_lint
// and scripts/rtl_synth elaborate it like every module (ctest rtl.lint,
// rtl.synth.ceilnav_pkg_check), and a mismatch stops both with $fatal.
module ceilnav_pkg_check;

  if (ceilnav_pkg::CoordBits   != ceilnav_widths_pkg::CoordBits   ||
      ceilnav_pkg::PixelBits   != ceilnav_widths_pkg::PixelBits   ||
      ceilnav_pkg::GeomBits    != ceilnav_widths_pkg::DimBits     ||
      ceilnav_pkg::CounterBits != ceilnav_widths_pkg::CounterBits ||
      ceilnav_pkg::BinBits     != ceilnav_widths_pkg::BinBits     ||
      ceilnav_pkg::WinBits     != ceilnav_widths_pkg::WindowBits  ||
      ceilnav_pkg::TermBits    != ceilnav_widths_pkg::TermBits    ||
      ceilnav_pkg::M00Bits     != ceilnav_widths_pkg::M00Bits     ||
      ceilnav_pkg::M10Bits     != ceilnav_widths_pkg::M10Bits     ||
      ceilnav_pkg::M20Bits     != ceilnav_widths_pkg::M20Bits     ||
      ceilnav_pkg::M11Bits     != ceilnav_widths_pkg::M11Bits     ||
      ceilnav_pkg::SumWBits    != ceilnav_widths_pkg::SumWBits    ||
      ceilnav_pkg::SumXwBits   != ceilnav_widths_pkg::SumXwBits) begin : g_width_mismatch
    $fatal(1, "ceilnav_pkg: a width differs from ceilnav_widths_pkg (fixedpoint/datapath.hpp)");
  end

  // Layouts the testbenches and the C++ models rely on ($bits of a constant
  // of each type: Yosys 0.23 takes $bits of no package type).
  localparam ceilnav_pkg::run_beat_t     RunBeat   = '0;
  localparam ceilnav_pkg::lut_entry_t    LutEntry  = '0;
  localparam ceilnav_pkg::frame_errors_t Errors    = '0;
  localparam ceilnav_pkg::pix_beat_t     PixBeat   = '0;
  if ($bits(RunBeat) != ceilnav_pkg::RunBeatBits ||
      ceilnav_pkg::RunBeatBits != 112 ||
      $bits(LutEntry) != ceilnav_pkg::LutEntryBits ||
      ceilnav_pkg::LutEntryBits != 11 ||
      $bits(Errors) != ceilnav_pkg::ErrCount * ceilnav_pkg::WordBits ||
      ceilnav_pkg::CounterBits != ceilnav_pkg::WordBits ||
      $bits(PixBeat) != 1 + ceilnav_pkg::PixelBits + 2 * ceilnav_pkg::CoordBits + 4 ||
      ceilnav_pkg::GeomBits != ceilnav_pkg::CoordBits + 1 ||
      ceilnav_pkg::WinBits != ceilnav_pkg::GeomBits ||
      (1 << ceilnav_pkg::MomIndexBits) < ceilnav_pkg::MomWords) begin : g_layout_mismatch
    $fatal(1, "ceilnav_pkg: a struct or a width has the wrong size");
  end

endmodule
