// ceilnav_pkg: the named widths, stream beats, block results, flag and error
// structs and state enums shared by the blocks of rtl_model/ (docs/rtl_style.md,
// "Package"). Modules refer to items as ceilnav_pkg::NAME (no import: Yosys
// 0.23). Struct fields are listed MSB first, so each struct has the bit layout
// of the flat vector it replaces.
//
// The widths that fixedpoint/datapath.hpp derives are generated into
// ceilnav_widths_pkg (tools/regmap_gen). Yosys 0.23 cannot refer to another
// package from inside a package, so the types' widths are repeated here as
// numbers, each with the name of its generated counterpart, and
// ceilnav_pkg_check.sv stops elaboration (Verilator, Yosys: rtl.lint,
// rtl.synth) if any of them differs from the generated value.
package ceilnav_pkg;

  // verilator lint_off UNUSEDPARAM
  // ---------------------------------------------------------------------------
  // Widths derived in fixedpoint/datapath.hpp, each equal to the
  // ceilnav_widths_pkg item named first in its comment.
  localparam int unsigned CoordBits   = 11;  // CoordBits: x, y in 0 .. 2^CoordBits - 1
  localparam int unsigned PixelBits   = 8;   // PixelBits: grey level, LUT remap
  localparam int unsigned GeomBits    = 12;  // DimBits: W, H in 1 .. 2^CoordBits
  localparam int unsigned CounterBits = 32;  // CounterBits: saturating counters
  localparam int unsigned BinBits     = 23;  // BinBits: histogram bin count
  localparam int unsigned WinBits     = 12;  // WindowBits: class window bound
  localparam int unsigned TermBits    = 22;  // TermBits: class_moments x^2, x y, y^2
  localparam int unsigned M00Bits     = 23;  // M00Bits: class moment m00
  localparam int unsigned M10Bits     = 32;  // M10Bits: m10, m01
  localparam int unsigned M20Bits     = 43;  // M20Bits: m20, m02
  localparam int unsigned M11Bits     = 42;  // M11Bits: m11
  localparam int unsigned SumWBits    = 19;  // SumWBits: run sum of w
  localparam int unsigned SumXwBits   = 29;  // SumXwBits: run sum of x w

  // ---------------------------------------------------------------------------
  // Widths with no datapath derivation: interfaces and fixed formats.
  localparam int unsigned WordBits      = 32;              // register word, statistics
  localparam int unsigned ClassBits     = 2;               // LUT pixel class (stream/config.hpp)
  localparam int unsigned LutEntryBits  = PixelBits + 1 + ClassBits;  // {class, mask, remap}
  localparam int unsigned LutEntries    = 1 << PixelBits;  // one LUT entry per grey level
  localparam int unsigned BinIndexBits  = PixelBits;       // histogram bin = grey or remap
  localparam int unsigned ErrCount      = 6;               // frame_check error counters
  localparam int unsigned RunFieldBits  = 16;              // run beat row, x_start, x_end
  localparam int unsigned RunFlagBits   = 3;               // run trailer flags
  localparam int unsigned FifoWrBits    = 2;               // run FIFO writes per edge: 0 .. 3
  localparam int unsigned RunBeatBits   = 2 * RunFieldBits + 2 * WordBits + RunFieldBits;  // 112
  localparam int unsigned MomentCount   = 6;               // m00 m10 m01 m20 m11 m02
  localparam int unsigned MomentBits    = 64;              // a published class moment
  localparam int unsigned MomWords      = 24;              // moment_gen result words
  localparam int unsigned MomIndexBits  = 5;               // 0 .. MomWords - 1
  localparam int unsigned StoreAddrBits = 8;               // result store: 256 words
  localparam int unsigned MaxClasses    = 3;               // LUT classes 1 .. 3 (0: background)
  localparam int unsigned AxilAddrBits  = 32;              // AXI4-Lite address
  localparam int unsigned AxilDataBits  = WordBits;        // AXI4-Lite data
  localparam int unsigned AxilStrbBits  = AxilDataBits / 8;
  localparam int unsigned AxiRespBits   = 2;               // xRESP
  // verilator lint_on UNUSEDPARAM

  // ---------------------------------------------------------------------------
  // Scalar types.
  typedef logic [CoordBits-1:0]   coord_t;  // x, y
  typedef logic [GeomBits-1:0]    geom_t;   // W, H and their configuration
  typedef logic [PixelBits-1:0]   pixel_t;  // grey level, remap value
  typedef logic [ClassBits-1:0]   class_t;  // LUT pixel class
  typedef logic [WordBits-1:0]    word_t;   // register word
  typedef logic [WinBits-1:0]     win_t;    // class window bound
  typedef logic [RunFieldBits-1:0] run_field_t;

  // A LUT entry (stream/config.hpp LutEntry): bits 10:9 class, 8 mask, 7:0 remap.
  typedef struct packed {
    class_t cls;
    logic   mask;
    pixel_t remap;
  } lut_entry_t;

  // ---------------------------------------------------------------------------
  // Stream beats.
  // PixelBeat: frame_check's output, thresh_lut's input.
  typedef struct packed {
    logic   valid;
    pixel_t grey;
    coord_t x;
    coord_t y;
    logic   sof;
    logic   eol;
    logic   eof;
    logic   abort_frame;  // the open frame is aborted (ports: *_abort_*)
  } pix_beat_t;

  // LutBeat: the pixel beat delayed by thresh_lut plus LUT[grey].
  typedef struct packed {
    pix_beat_t  pix;
    lut_entry_t lut;
  } lut_beat_t;

  // Run trailer flags (stream/results.hpp RunTrailerFlags), in x_start.
  typedef struct packed {
    logic aborted;    // frame_check aborted the frame
    logic overflow;   // a run or a trailer was lost: FIFO full
    logic row_limit;  // some row had more than max_runs_per_row runs
  } run_flags_t;

  // m_axis_runs_tdata (pack_run_beat() in stream/run_scanner.hpp): no field
  // crosses a 32-bit word. A trailer carries the runs emitted in row and the
  // flags in x_start.
  typedef struct packed {
    run_field_t x_end;    // [111:96]
    word_t      sum_xw;   // [95:64]
    word_t      sum_w;    // [63:32]
    run_field_t x_start;  // [31:16]
    run_field_t row;      // [15:0]
  } run_beat_t;

  // A run FIFO entry (run_scanner): a run, or a trailer with the flags in the
  // low bits of x_start and the run count in row; impl_t: a run followed by
  // the constant trailer {row 1, flags 0}. sum_xw travels in run_fifo's late field.
  typedef struct packed {
    logic               impl_t;
    logic               last;   // a trailer (tlast)
    logic [SumWBits-1:0] sum_w;
    coord_t             x_end;
    coord_t             x_start;
    run_field_t         row;
  } run_entry_t;

  // ---------------------------------------------------------------------------
  // Block results.
  // frame_check's error counters (FrameErrorCounters), early_eol at the LSB:
  // counter i at [i*WordBits +: WordBits].
  typedef struct packed {
    word_t frames_aborted;
    word_t frames_ok;
    word_t missing_sof;
    word_t early_sof;
    word_t late_eol;
    word_t early_eol;
  } frame_errors_t;

  // FrameMeta of an EOF pixel: cycles since its SOF pixel and the counters.
  typedef struct packed {
    word_t         cycles;
    frame_errors_t errors;
  } frame_meta_t;

  // RunStats of a frame, as the pipeline stages them.
  typedef struct packed {
    word_t high_water;
    word_t dropped_overflow;
    word_t dropped_row_limit;
    word_t emitted;
  } run_stats_t;

  // The six moments of one class mask (class_moments), m00 at the LSB.
  typedef struct packed {
    logic [M20Bits-1:0] m02;
    logic [M11Bits-1:0] m11;
    logic [M20Bits-1:0] m20;
    logic [M10Bits-1:0] m01;
    logic [M10Bits-1:0] m10;
    logic [M00Bits-1:0] m00;
  } class_mom_t;

  // The configuration that travels with the SOF through the pipeline's stages
  // (StageConfig), background level at the LSB.
  typedef struct packed {
    win_t       win_y1;
    win_t       win_y0;
    win_t       win_x1;
    win_t       win_x0;
    logic       hist_source_remap;
    run_field_t max_runs_per_row;
    run_field_t min_run_length;
    pixel_t     background_level;
  } stage_cfg_t;

  // ---------------------------------------------------------------------------
  // State machines.
  // frame_check (stream/frame_check.hpp FrameCheck::State).
  typedef enum logic [1:0] {
    FcIdle    = 2'd0,  // expecting an SOF
    FcInFrame = 2'd1,  // x_q/y_q: position of the next pixel
    FcDiscard = 2'd2   // after an error: drop until the next SOF
  } fc_state_e;

endpackage
