// The register top: reset values and access types from the generated header,
// SLVERR without side effects, W1C/INTR_TEST/irq, the documented AXI4-Lite
// timing, and results / LUT / run FIFO through registers against a reference
// Pipeline clocked in lockstep, with random gaps and random AXI-Lite timing.
#include "stream/ceilnav_top.hpp"

#include <gtest/gtest.h>

#include <deque>
#include <random>
#include <string>
#include <vector>

#include "ceilnav/regs.hpp"
#include "common/version.hpp"
#include "drivers/axi_lite_master.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

namespace r = regs;
using drivers::AxiLiteMaster;

// The top and a reference Pipeline with the same video beats on the same
// edges; an AxiLiteMaster on the top's register port.
class Bench {
 public:
  // config: the device's configuration (the reference pipeline is the full one).
  explicit Bench(uint64_t seed = 1, AxiLiteMaster::Timing timing = {},
                 const r::Config& config = r::kConfigFull)
      : top(r::kRunFifoDepth, config), master_(seed, timing), rng_(static_cast<uint32_t>(seed)) {}

  void tick() {
    VideoBeat beat{};
    if (!video.empty()) {
      beat = video.front();
      video.pop_front();
    }
    const AxiLiteIn& in = master_.drive();
    const bool tready = !std::bernoulli_distribution(tready_low_probability)(rng_);
    const AxiLiteOut out = top.s_axil_out();
    const RunBeat top_runs = top.m_axis_runs();
    const RunBeat ref_runs = ref.m_axis_runs();
    const bool registers_sink = r::control::kRunSink.get(control_) != 0;
    if (registers_sink) {
      if (top_runs.tvalid) ++stream_beats_while_register_sink;
      if (ref_runs.tvalid) ref_stream.push_back(ref_runs);  // reference consumer: tready = 1
      ref.clock(beat, true);
    } else {
      if (!(top_runs == ref_runs)) ++stream_mismatches;
      if (ref_runs.tvalid && tready) ref_stream.push_back(ref_runs);
      ref.clock(beat, tready);
    }
    top.clock(beat, in, tready);
    master_.edge(out);
    if (ref.frame_done()) ref_published.push_back(ref.results());
    ++cycles;
  }
  uint32_t read(uint32_t addr, uint8_t* resp = nullptr) {
    master_.start_read(addr);
    run_master();
    if (resp != nullptr) {
      *resp = master_.resp();
    } else {
      EXPECT_EQ(master_.resp(), r::kRespOkay) << "read 0x" << std::hex << addr;
    }
    return master_.rdata();
  }
  uint8_t write(uint32_t addr, uint32_t value, uint8_t strb = 0xF) {
    master_.start_write(addr, value, strb);
    run_master();
    if (addr == r::control::kOffset && master_.resp() == r::kRespOkay) control_ = value;
    return master_.resp();
  }
  bool wait_irq(uint64_t max_cycles) {
    for (uint64_t i = 0; i < max_cycles; ++i) {
      if (top.irq()) return true;
      tick();
    }
    return top.irq();
  }
  void idle(uint64_t n) {
    for (uint64_t i = 0; i < n; ++i) tick();
  }
  void queue(const cv::Mat& img, double gap_probability, std::mt19937& rng) {
    std::vector<VideoBeat> beats;
    test::append_frame(beats, img, rng, gap_probability);
    video.insert(video.end(), beats.begin(), beats.end());
  }

  // Whole configuration through registers (LUT: all 256 entries).
  void configure(const PipelineConfig& cfg) {
    EXPECT_EQ(write(r::width::kOffset, cfg.width), r::kRespOkay);
    write(r::height::kOffset, cfg.height);
    write(r::background_level::kOffset, cfg.background_level);
    write(r::min_run_length::kOffset, cfg.min_run_length);
    write(r::max_runs_per_row::kOffset, cfg.max_runs_per_row);
    write(r::hist_source::kOffset, r::hist_source::kRemap.put(cfg.hist_source_remap ? 1u : 0u));
    write(r::lut_index::kOffset, 0);
    for (LutEntry e : cfg.lut) {
      write(r::lut_data::kOffset, r::lut_data::kRemap.put(e & kLutRemapMask) |
                                      r::lut_data::kMask.put((e & kLutMaskBit) != 0 ? 1u : 0u));
    }
  }

  // The result registers as a FrameResults.
  FrameResults read_results() {
    FrameResults f;
    f.frame_index = read(r::res_frame_index::kOffset);
    f.valid = r::status::kResultsValid.get(read(r::status::kOffset)) != 0;
    write(r::hist_index::kOffset, 0);
    for (uint32_t& bin : f.histogram.bins) bin = read(r::hist_data::kOffset);
    for (uint32_t i = 0; i < static_cast<uint32_t>(kMomentCount); ++i) {
      f.moments.grey[i] =
          read(r::mom_grey_lo::kArray.at(i)) | uint64_t{read(r::mom_grey_hi::kArray.at(i))} << 32;
      f.moments.mask[i] =
          read(r::mom_mask_lo::kArray.at(i)) | uint64_t{read(r::mom_mask_hi::kArray.at(i))} << 32;
    }
    f.run_stats.runs_emitted = read(r::runs_emitted::kOffset);
    f.run_stats.runs_dropped_row_limit = read(r::runs_dropped_row_limit::kOffset);
    f.run_stats.runs_dropped_overflow = read(r::runs_dropped_overflow::kOffset);
    f.run_stats.fifo_high_water = read(r::run_fifo_high_water::kOffset);
    f.errors.early_eol = read(r::res_early_eol::kOffset);
    f.errors.late_eol = read(r::res_late_eol::kOffset);
    f.errors.early_sof = read(r::res_early_sof::kOffset);
    f.errors.missing_sof = read(r::res_missing_sof::kOffset);
    f.errors.frames_ok = read(r::res_frames_ok::kOffset);
    f.errors.frames_aborted = read(r::res_frames_aborted::kOffset);
    f.cycles_in_frame = read(r::cycles_per_frame::kOffset);
    EXPECT_EQ(read(r::res_frame_index::kOffset), f.frame_index) << "publication during readout";
    return f;
  }

  // Pops run entries through RUN_WORD0..3 until a trailer (included).
  std::vector<RunBeat> pop_runs_until_trailer(int max_entries) {
    std::vector<RunBeat> out;
    for (int i = 0; i < max_entries; ++i) {
      const uint32_t w0 = read(r::run_word0::kOffset);
      if (r::run_word0::kValid.get(w0) == 0) {
        tick();
        continue;
      }
      RunBeat b;
      b.tvalid = true;
      b.tlast = r::run_word0::kLast.get(w0) != 0;
      b.tdata.row = static_cast<uint16_t>(r::run_word0::kRow.get(w0));
      const uint32_t w1 = read(r::run_word1::kOffset);
      b.tdata.x_start = static_cast<uint16_t>(r::run_word1::kXStart.get(w1));
      b.tdata.x_end = static_cast<uint16_t>(r::run_word1::kXEnd.get(w1));
      b.tdata.sum_w = r::run_word2::kSumW.get(read(r::run_word2::kOffset));
      b.tdata.sum_xw = r::run_word3::kSumXw.get(read(r::run_word3::kOffset));  // pops
      out.push_back(b);
      if (b.tlast) break;
    }
    return out;
  }

  CeilnavTop top;
  Pipeline ref;
  std::deque<VideoBeat> video;
  double tready_low_probability = 0.0;
  std::vector<FrameResults> ref_published;
  std::vector<RunBeat> ref_stream;
  int stream_mismatches = 0;
  int stream_beats_while_register_sink = 0;
  uint64_t cycles = 0;

 private:
  void run_master() {
    for (int i = 0; i < 100000 && !master_.done(); ++i) tick();
    ASSERT_TRUE(master_.done()) << "AXI-Lite transaction did not complete";
  }

  AxiLiteMaster master_;
  std::mt19937 rng_;
  uint32_t control_ = r::control::kReset;
};

PipelineConfig random_config(std::mt19937& rng, int w, int h) {
  PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(w);
  cfg.height = static_cast<uint16_t>(h);
  std::uniform_int_distribution<int> byte(0, 255);
  if (byte(rng) < 128) {
    cfg.lut = threshold_lut(static_cast<uint8_t>(100 + byte(rng) / 2));
  } else {
    for (LutEntry& e : cfg.lut) e = lut_entry(static_cast<uint8_t>(byte(rng)), byte(rng) > 170);
  }
  cfg.background_level = static_cast<uint8_t>(byte(rng) / 4);
  cfg.min_run_length = static_cast<uint16_t>(1 + byte(rng) % 3);
  cfg.max_runs_per_row = static_cast<uint16_t>(1 + byte(rng) % 12);
  cfg.hist_source_remap = byte(rng) < 128;
  return cfg;
}

uint32_t read_once(CeilnavTop& top, uint32_t addr, uint8_t& resp) {
  AxiLiteMaster m;
  m.start_read(addr);
  for (int i = 0; i < 100 && !m.done(); ++i) {
    const AxiLiteIn& in = m.drive();
    const AxiLiteOut out = top.s_axil_out();
    top.clock(VideoBeat{}, in, true);
    m.edge(out);
  }
  resp = m.resp();
  return m.rdata();
}

// In every configuration: a present register reads its reset value (FEATURES
// reads the configuration), an absent one answers SLVERR with 0.
TEST(CeilnavTop, ResetValuesMatchTheGeneratedHeader) {
  for (const r::Config& config : r::kConfigs) {
    Bench b(1, {}, config);
    for (const r::Register& reg : r::kRegisters) {
      uint8_t resp = 0xFF;
      const uint32_t v = b.read(reg.offset, &resp);
      if (!config.has(reg)) {
        EXPECT_EQ(resp, r::kRespSlvErr) << config.name << " " << reg.name;
        EXPECT_EQ(v, 0u) << config.name << " " << reg.name;
        continue;
      }
      EXPECT_EQ(resp, r::kRespOkay) << config.name << " " << reg.name;
      if (reg.offset == r::features::kOffset) {
        EXPECT_EQ(v, r::features::kClassMoments.put(config.has_class_moments ? 1u : 0u) |
                         r::features::kCorridor.put(config.has_corridor ? 1u : 0u) |
                         r::features::kOrientation.put(config.has_orientation ? 1u : 0u))
            << config.name;
      } else if (reg.offset == r::ori_status::kOffset) {
        EXPECT_EQ(v, r::ori_status::kNumBins.put(Orientation::kDefaultBins)) << config.name;
      } else {
        EXPECT_EQ(v, reg.reset & reg.read_mask()) << config.name << " " << reg.name;
      }
    }
  }
  EXPECT_EQ(r::features::kReset, r::features::kClassMoments.put(r::kConfigFull.has_class_moments) |
                                     r::features::kCorridor.put(r::kConfigFull.has_corridor) |
                                     r::features::kOrientation.put(r::kConfigFull.has_orientation));
  Bench b;
  EXPECT_EQ(r::id::kReset, kDeviceId);
  EXPECT_EQ(r::version::kReset, version_word());
  EXPECT_EQ(r::run_fifo_depth::kReset, b.top.run_fifo_depth());
  EXPECT_EQ(r::width::kReset, PipelineConfig{}.width);
  EXPECT_EQ(r::height::kReset, PipelineConfig{}.height);
  EXPECT_EQ(r::min_run_length::kReset, PipelineConfig{}.min_run_length);
  EXPECT_EQ(r::max_runs_per_row::kReset, PipelineConfig{}.max_runs_per_row);
  EXPECT_EQ(r::background_level::kReset, PipelineConfig{}.background_level);
}

TEST(CeilnavTop, AccessTypesMatchTheGeneratedHeader) {
  std::mt19937 rng(3);  // 32-bit outputs
  const auto next = [&rng] { return static_cast<uint32_t>(rng()); };
  for (const r::Register& reg : r::kRegisters) {
    if (reg.offset == r::intr_state::kOffset) continue;  // W1C: own test
    // The register's configuration: full, or homing for the orientation block.
    Bench b(rng(), {}, r::kConfigFull.has(reg) ? r::kConfigFull : r::kConfigHoming);
    const uint32_t before = b.read(reg.offset);
    const uint32_t pattern = next();
    const uint8_t resp = b.write(reg.offset, pattern);
    const uint32_t after = b.read(reg.offset);
    if (reg.write_mask() == 0) {
      EXPECT_EQ(resp, r::kRespSlvErr) << reg.name;
      EXPECT_EQ(after, before) << reg.name;
      continue;
    }
    EXPECT_EQ(resp, r::kRespOkay) << reg.name;
    EXPECT_EQ(after & reg.rw_mask, pattern & reg.rw_mask) << reg.name;
    EXPECT_EQ(after & reg.wo_mask, 0u) << reg.name << ": write-only bits read 0";
    EXPECT_EQ(after & ~reg.read_mask(), 0u) << reg.name << ": bits outside fields read 0";
    if (reg.write_effect == r::Effect::kLutIndexInc) {
      EXPECT_EQ(b.read(r::lut_index::kOffset), 1u) << reg.name;
    }
    if (reg.offset == r::intr_test::kOffset) {
      EXPECT_EQ(b.read(r::intr_state::kOffset), pattern & reg.wo_mask);
    }
  }
}

TEST(CeilnavTop, W1cInterruptStateTestAndIrq) {
  Bench b;
  const uint32_t all =
      CeilnavTop::kIntrFrameDone | CeilnavTop::kIntrRunOverflow | CeilnavTop::kIntrFrameError;
  EXPECT_EQ(b.write(r::intr_test::kOffset, all), r::kRespOkay);
  EXPECT_EQ(b.read(r::intr_state::kOffset), all);
  EXPECT_FALSE(b.top.irq()) << "nothing enabled";
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrRunOverflow);
  EXPECT_TRUE(b.top.irq());
  b.write(r::intr_state::kOffset, CeilnavTop::kIntrFrameDone);  // W1C one bit
  EXPECT_EQ(b.read(r::intr_state::kOffset), all & ~CeilnavTop::kIntrFrameDone);
  EXPECT_TRUE(b.top.irq());
  b.write(r::intr_state::kOffset, 0);  // writing 0 clears nothing
  EXPECT_EQ(b.read(r::intr_state::kOffset), all & ~CeilnavTop::kIntrFrameDone);
  b.write(r::intr_state::kOffset, CeilnavTop::kIntrRunOverflow);
  EXPECT_FALSE(b.top.irq());
  EXPECT_EQ(b.read(r::intr_state::kOffset), CeilnavTop::kIntrFrameError);
  b.write(r::intr_state::kOffset, 0xFFFFFFFFu);
  EXPECT_EQ(b.read(r::intr_state::kOffset), 0u);
}

// Every readable register of the device's configuration without a read side effect.
std::vector<uint32_t> snapshot(Bench& b) {
  std::vector<uint32_t> v;
  for (const r::Register& reg : r::kRegisters) {
    if (reg.read_effect == r::Effect::kNone && b.top.config().has(reg)) {
      v.push_back(b.read(reg.offset));
    }
  }
  return v;
}

TEST(CeilnavTop, UnmappedAddressesAnswerSlverrWithoutSideEffects) {
  std::mt19937 rng(5);
  const auto next = [&rng] { return static_cast<uint32_t>(rng()); };
  Bench b(7, {0.3, 0.3});
  // Some state worth disturbing: a frame's results and non-reset registers.
  b.write(r::control::kOffset, r::control::kEnable.put(1));
  PipelineConfig cfg = random_config(rng, 24, 16);
  b.configure(cfg);
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrFrameDone);
  b.queue(test::random_image(rng, 24, 16), 0.1, rng);
  ASSERT_TRUE(b.wait_irq(20000));
  b.write(r::hist_index::kOffset, 17);
  const std::vector<uint32_t> before = snapshot(b);
  int probed = 0;
  for (uint32_t a = 0; a < (1u << r::kAddrWidth); ++a) {
    uint8_t resp = 0;
    // A register of an absent block (ORI_* in the full device) is unmapped.
    if (a % 4 == 0 && r::find(a) != nullptr && b.top.config().has(*r::find(a))) {
      if (r::find(a)->write_mask() == 0) {
        EXPECT_EQ(b.write(a, next()), r::kRespSlvErr) << "read-only " << r::find(a)->name;
      } else if (a != r::control::kOffset && a != r::intr_test::kOffset &&
                 a != r::intr_state::kOffset) {
        EXPECT_EQ(b.write(a, next(), 0x7), r::kRespSlvErr) << "partial strobe";
      }
      continue;
    }
    b.read(a, &resp);
    EXPECT_EQ(resp, r::kRespSlvErr) << "read 0x" << std::hex << a;
    EXPECT_EQ(b.write(a, next()), r::kRespSlvErr) << "write 0x" << std::hex << a;
    ++probed;
  }
  EXPECT_GT(probed, 100);
  EXPECT_EQ(snapshot(b), before);
}

TEST(CeilnavTop, AxiLiteTimingIsAsDocumented) {
  CeilnavTop top;
  // Write: AW and W valid in cycle 0 -> awready/wready in cycle 1 (handshake on
  // edge 1) -> bvalid in cycle 2.
  AxiLiteIn in;
  in.awvalid = in.wvalid = true;
  in.awaddr = r::width::kOffset;
  in.wdata = 77;
  EXPECT_FALSE(top.s_axil_out().awready);
  top.clock({}, in, true);
  EXPECT_TRUE(top.s_axil_out().awready && top.s_axil_out().wready);
  EXPECT_FALSE(top.s_axil_out().bvalid);
  top.clock({}, in, true);
  EXPECT_FALSE(top.s_axil_out().awready);
  EXPECT_TRUE(top.s_axil_out().bvalid);
  EXPECT_EQ(top.s_axil_out().bresp, r::kRespOkay);
  in = {};
  top.clock({}, in, true);  // bready low: B holds
  EXPECT_TRUE(top.s_axil_out().bvalid);
  in.bready = true;
  top.clock({}, in, true);
  EXPECT_FALSE(top.s_axil_out().bvalid);

  // Read: arready high while idle; handshake on edge 0, rvalid in cycle 3
  // (kReadLatencyCycles = 2 edges after the handshake edge).
  in = {};
  EXPECT_TRUE(top.s_axil_out().arready);
  in.arvalid = true;
  in.araddr = r::width::kOffset;
  top.clock({}, in, true);
  in.arvalid = false;
  EXPECT_FALSE(top.s_axil_out().arready);
  for (int i = 1; i < CeilnavTop::kReadLatencyCycles; ++i) {
    EXPECT_FALSE(top.s_axil_out().rvalid);
    top.clock({}, in, true);
  }
  EXPECT_FALSE(top.s_axil_out().rvalid);
  top.clock({}, in, true);
  EXPECT_TRUE(top.s_axil_out().rvalid);
  EXPECT_EQ(top.s_axil_out().rdata, 77u);
  top.clock({}, in, true);  // rready low: R holds
  EXPECT_TRUE(top.s_axil_out().rvalid);
  EXPECT_FALSE(top.s_axil_out().arready);
  in.rready = true;
  top.clock({}, in, true);
  EXPECT_FALSE(top.s_axil_out().rvalid);
  EXPECT_TRUE(top.s_axil_out().arready);

  // A write with only AW valid is not accepted (the slave waits for W).
  in = {};
  in.awvalid = true;
  in.awaddr = r::width::kOffset;
  for (int i = 0; i < 4; ++i) {
    top.clock({}, in, true);
    EXPECT_FALSE(top.s_axil_out().awready);
  }
  uint8_t resp = 0;
  EXPECT_EQ(read_once(top, r::width::kOffset, resp), 77u);
}

// Frames from random images with gaps, random AXI-Lite timing, the host
// reading each frame's results while the next frame streams.
void run_results_test(uint64_t seed, bool register_sink, double tready_low) {
  std::mt19937 rng(static_cast<uint32_t>(seed));
  Bench b(seed, {0.3, 0.3});
  b.tready_low_probability = tready_low;
  const int w = 80, h = 48;
  const PipelineConfig cfg = random_config(rng, w, h);
  b.configure(cfg);
  b.ref.set_config(cfg);
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrFrameDone);
  b.write(r::control::kOffset,
          r::control::kEnable.put(1) | r::control::kRunSink.put(register_sink ? 1u : 0u));
  const int frames = 4;
  for (int k = 0; k < frames; ++k) {
    b.queue(k % 2 == 0 ? test::random_image(rng, w, h) : test::blob_image(rng, w, h), 0.25, rng);
    // Popping runs through registers takes ~25 cycles per run: give it time.
    const int blanking = register_sink ? 20000 : 300;
    for (int g = 0; g < blanking; ++g) b.video.push_back(VideoBeat{});
  }
  std::vector<RunBeat> popped;
  for (int k = 0; k < frames; ++k) {
    ASSERT_TRUE(b.wait_irq(100000)) << "frame " << k;
    const uint64_t irq_cycle = b.cycles;
    EXPECT_EQ(b.read(r::intr_state::kOffset), CeilnavTop::kIntrFrameDone);
    b.write(r::intr_state::kOffset, CeilnavTop::kIntrFrameDone);
    const FrameResults got = b.read_results();
    ASSERT_EQ(b.ref_published.size(), static_cast<size_t>(k + 1));
    FrameResults expected = b.ref_published[static_cast<size_t>(k)];
    if (register_sink) {
      // The reference drains its FIFO at once; the host pops the top's later.
      EXPECT_GE(got.run_stats.fifo_high_water, expected.run_stats.fifo_high_water);
      expected.run_stats.fifo_high_water = got.run_stats.fifo_high_water;
    }
    EXPECT_EQ(got, expected) << "frame " << k;
    EXPECT_EQ(b.read(r::frame_count::kOffset), static_cast<uint32_t>(k + 1));
    EXPECT_EQ(b.read(r::eof_to_irq_cycles::kOffset),
              static_cast<uint32_t>(CeilnavTop::kEofToIntrCycles));
    if (register_sink) {
      const std::vector<RunBeat> runs = b.pop_runs_until_trailer(4000);
      popped.insert(popped.end(), runs.begin(), runs.end());
    }
    EXPECT_LT(irq_cycle, b.cycles);
  }
  b.idle(2000);
  EXPECT_EQ(b.stream_mismatches, 0);
  if (register_sink) {
    EXPECT_EQ(b.stream_beats_while_register_sink, 0);
    EXPECT_EQ(popped, b.ref_stream);
    EXPECT_EQ(b.read(r::run_fifo_level::kOffset), 0u);
  }
  EXPECT_GE(b.ref_stream.size(), static_cast<size_t>(frames));
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), static_cast<uint32_t>(frames));
}

TEST(CeilnavTop, ResultsThroughRegistersEqualPipelineStreamSink) {
  run_results_test(11, false, 0.0);
  run_results_test(12, false, 0.4);
}

TEST(CeilnavTop, RunFifoPoppedThroughRegistersEqualsStream) {
  run_results_test(21, true, 0.0);
  run_results_test(22, true, 0.0);
}

TEST(CeilnavTop, ConfigWrittenMidFrameTakesEffectAtNextSof) {
  std::mt19937 rng(31);
  Bench b(31, {0.2, 0.2});
  const int w = 64, h = 40;
  const PipelineConfig cfg_a = random_config(rng, w, h);
  PipelineConfig cfg_b = random_config(rng, w, h);
  cfg_b.lut = threshold_lut(90);
  cfg_b.hist_source_remap = !cfg_a.hist_source_remap;
  b.configure(cfg_a);
  b.ref.set_config(cfg_a);
  b.write(r::control::kOffset, r::control::kEnable.put(1));
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrFrameDone);
  b.queue(test::blob_image(rng, w, h), 0.0, rng);
  for (int g = 0; g < 8000; ++g) b.video.push_back(VideoBeat{});  // blanking > the LUT writes
  b.queue(test::blob_image(rng, w, h), 0.0, rng);
  b.idle(200);  // frame 0 is streaming
  EXPECT_EQ(r::status::kInFrame.get(b.read(r::status::kOffset)), 1u);
  b.configure(cfg_b);  // during frame 0 and its blanking
  EXPECT_EQ(r::status::kLutPending.get(b.read(r::status::kOffset)), 1u);
  b.ref.set_config(cfg_b);
  ASSERT_FALSE(b.video.empty());
  ASSERT_TRUE(b.wait_irq(100000));
  b.write(r::intr_state::kOffset, CeilnavTop::kIntrFrameDone);
  EXPECT_EQ(b.read_results(), b.ref_published.at(0));
  ASSERT_TRUE(b.wait_irq(100000));
  EXPECT_EQ(r::status::kLutPending.get(b.read(r::status::kOffset)), 0u);
  EXPECT_EQ(b.read_results(), b.ref_published.at(1));
  EXPECT_NE(b.ref_published.at(0).histogram, b.ref_published.at(1).histogram);
  b.idle(500);
  EXPECT_EQ(b.stream_mismatches, 0);
}

TEST(CeilnavTop, EnableGatesWholeFrames) {
  std::mt19937 rng(41);
  Bench b;
  b.configure(random_config(rng, 16, 8));
  b.queue(test::random_image(rng, 16, 8), 0.0, rng);  // ENABLE = 0: dropped
  b.idle(40);
  b.write(r::control::kOffset, r::control::kEnable.put(1));  // mid-frame: still dropped
  b.idle(200);
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), 0u);
  EXPECT_EQ(b.read(r::cnt_missing_sof::kOffset), 0u);
  b.queue(test::random_image(rng, 16, 8), 0.0, rng);
  b.idle(200);
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), 1u);
  EXPECT_EQ(r::status::kGateOpen.get(b.read(r::status::kOffset)), 1u);
  b.queue(test::random_image(rng, 16, 8), 0.0, rng);
  b.idle(20);
  b.write(r::control::kOffset, 0);  // mid-frame: this frame completes
  b.idle(200);
  b.queue(test::random_image(rng, 16, 8), 0.0, rng);
  b.idle(200);
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), 2u);
  EXPECT_EQ(b.read(r::cnt_missing_sof::kOffset), 0u);
}

TEST(CeilnavTop, FrameErrorsInterruptAndSoftReset) {
  std::mt19937 rng(51);
  Bench b;
  const PipelineConfig cfg = random_config(rng, 16, 8);
  b.configure(cfg);
  b.write(r::control::kOffset, r::control::kEnable.put(1));
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrFrameError);
  b.queue(test::random_image(rng, 16, 8), 0.0, rng);
  b.idle(200);
  EXPECT_FALSE(b.top.irq());
  // A frame whose third line ends early.
  std::vector<VideoBeat> beats;
  test::append_frame(beats, test::random_image(rng, 16, 8), rng, 0.0);
  beats[2 * 16 + 5].tlast = true;
  b.video.insert(b.video.end(), beats.begin(), beats.end());
  ASSERT_TRUE(b.wait_irq(1000));
  EXPECT_EQ(b.read(r::cnt_early_eol::kOffset), 1u);
  EXPECT_EQ(b.read(r::cnt_frames_aborted::kOffset), 1u);
  EXPECT_EQ(b.read(r::res_frames_ok::kOffset), 1u);
  b.idle(300);
  EXPECT_EQ(r::status::kInFrame.get(b.read(r::status::kOffset)), 0u);

  b.write(r::control::kOffset, r::control::kEnable.put(1) | r::control::kSoftReset.put(1));
  EXPECT_EQ(b.read(r::cnt_early_eol::kOffset), 0u);
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), 0u);
  EXPECT_EQ(r::status::kResultsValid.get(b.read(r::status::kOffset)), 0u);
  EXPECT_EQ(b.read(r::control::kOffset), r::control::kEnable.put(1)) << "SOFT_RESET reads 0";
  EXPECT_EQ(b.read(r::width::kOffset), cfg.width) << "configuration kept";
  // After the documented LUT reprogramming, frames equal a fresh pipeline's.
  b.configure(cfg);
  b.ref = Pipeline();
  b.ref.set_config(cfg);
  b.write(r::intr_enable::kOffset, CeilnavTop::kIntrFrameDone);
  b.write(r::intr_state::kOffset, 0xFFFFFFFFu);
  b.queue(test::blob_image(rng, 16, 8), 0.0, rng);
  ASSERT_TRUE(b.wait_irq(1000));
  EXPECT_EQ(b.read_results(), b.ref_published.back());
  EXPECT_EQ(b.read(r::res_frame_index::kOffset), 0u);
}

}  // namespace
}  // namespace ceilnav::stream
