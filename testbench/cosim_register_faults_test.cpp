// Register faults at device level: bus errors, writes to read-only
// registers, LUT writes during a frame, back-to-back configuration changes and
// results held while the next frame runs. Vceilnav_top and stream::CeilnavTop
// run in lockstep (TopCosim: every port compared after every edge), so each
// register value checked here is checked for both.
#include <algorithm>
#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "ceilnav/regs.hpp"
#include "common/pipeline_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "stream/beat.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/pipeline.hpp"
#include "testbench/cosim_common.hpp"
#include "testbench/top_cosim.hpp"
#include "testbench/video_stream.hpp"

namespace ceilnav::testbench {
namespace {

namespace r = regs;
using stream::PipelineConfig;
using stream::VideoBeat;

// The bench: run back-pressure with tready 0.7 throughout.
class Bench : public DeviceBench {
 public:
  explicit Bench(uint64_t seed) : DeviceBench(seed, "ceilnav_top_register_faults", 0.7) {}

  // Every register without a read side effect (HIST_DATA and RUN_WORD3 move
  // an index / pop the FIFO), in map order.
  std::vector<uint32_t> dump() {
    std::vector<uint32_t> values;
    for (const r::Register& reg : present_registers()) {
      if (reg.read_effect == r::Effect::kNone) values.push_back(read(reg.offset));
    }
    return values;
  }
};

// Dark noise with bright rectangles (at least 4 pixels wide where the
// frame allows: runs for every MIN_RUN_LENGTH used here; at least 110, above
// every random_lut threshold).
std::vector<uint8_t> frame_pixels(Rng& rng, int w, int h) {
  return blob_pixels(rng, w, h, BlobStyle{70, 70, 2, 6, 4, 140});
}

// Blanking (up to 30 idle beats), then a well-formed frame with random tvalid gaps.
void enqueue(Bench& b, const std::vector<uint8_t>& px, int w, double gap_p) {
  b.queue(video_beats(px, w), gap_p, 30, b.rng());
}

// A random LUT: remap and mask independent, so a wrong bank shows in both
// the grey and the mask moments.
std::array<stream::LutEntry, 256> random_lut(Rng& rng) {
  std::array<stream::LutEntry, 256> lut{};
  const auto threshold = rng.uniform(60, 110);
  const auto gain = rng.uniform(1, 3);
  for (unsigned g = 0; g < 256; ++g) {
    const auto remap = static_cast<uint8_t>(std::min<int64_t>(255, gain * g / 2));
    lut[g] = stream::lut_entry(remap, g >= threshold);
  }
  return lut;
}

void write_config(Bench& b, const PipelineConfig& cfg) {
  b.write(r::width::kOffset, cfg.width);
  b.write(r::height::kOffset, cfg.height);
  b.write(r::background_level::kOffset, cfg.background_level);
  b.write(r::min_run_length::kOffset, cfg.min_run_length);
  b.write(r::max_runs_per_row::kOffset, cfg.max_runs_per_row);
}

void program_lut(Bench& b, const std::array<stream::LutEntry, 256>& lut) {
  b.write(r::lut_index::kOffset, 0);
  for (unsigned g = 0; g < 256; ++g) {
    b.write(r::lut_data::kOffset, r::lut_data::kRemap.put(lut[g] & stream::kLutRemapMask) |
                                      r::lut_data::kMask.put((lut[g] & stream::kLutMaskBit) != 0));
  }
}

PipelineConfig random_config(Rng& rng, int w, int h) {
  PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(w);
  cfg.height = static_cast<uint16_t>(h);
  cfg.background_level = rng.uniform_as<uint8_t>(0, 40);
  cfg.min_run_length = rng.uniform_as<uint16_t>(1, 3);
  cfg.max_runs_per_row = rng.uniform_as<uint16_t>(1, 8);
  cfg.lut = random_lut(rng);
  return cfg;
}

// A fresh device configured with cfg (LUT in the shadow bank, swapped in by
// the first SOF) and enabled.
void bring_up(Bench& b, const PipelineConfig& cfg) {
  write_config(b, cfg);
  program_lut(b, cfg.lut);
  b.write(r::control::kOffset, r::control::kEnable.mask());
}

// Result registers: moments, run stats, published counters, histogram.
struct Results {
  std::vector<uint32_t> words;  // RES_FRAME_INDEX .. MOM_MASK_HI[5], map order
  std::vector<uint32_t> hist;
  bool operator==(const Results&) const = default;
};

bool is_result(uint32_t offset) {
  // HOUGH_* (0x300 ..) belong to the hough block, which is not in this device.
  return offset >= r::res_frame_index::kOffset && offset != r::frame_count::kOffset &&
         (offset < r::cnt_early_eol::kOffset || offset >= r::mom_grey_lo::kOffset) &&
         offset < r::hough_control::kOffset;
}

std::vector<uint32_t> read_result_words(Bench& b) {
  std::vector<uint32_t> words;
  for (const r::Register& reg : present_registers()) {
    if (is_result(reg.offset)) words.push_back(b.read(reg.offset));
  }
  return words;
}

// count bins from first (mod 256).
std::vector<uint32_t> read_hist(Bench& b, unsigned first, unsigned count) {
  b.write(r::hist_index::kOffset, first);
  std::vector<uint32_t> bins;
  for (unsigned k = 0; k < count; ++k) bins.push_back(b.read(r::hist_data::kOffset));
  return bins;
}

Results read_results(Bench& b) {
  return Results{read_result_words(b), read_hist(b, 0, 256)};
}

uint32_t word_at(const Results& res, uint32_t offset) {
  size_t i = 0;
  for (const r::Register& reg : present_registers()) {
    if (!is_result(reg.offset)) continue;
    if (reg.offset == offset) return res.words[i];
    ++i;
  }
  ADD_FAILURE() << "no result register at 0x" << std::hex << offset;
  return 0;
}

// The read results against the fast path of the same pixels.
void expect_results(const Results& got, const PipelineConfig& cfg, const std::vector<uint8_t>& px,
                    uint32_t frame_index, Bench* runs_of = nullptr) {
  stream::Pipeline fast(stream::RunScanner::kDefaultFifoDepth, kTopConfig.has_class_moments);
  fast.set_config(cfg);
  std::vector<stream::RunRecord> want_runs;
  const stream::FrameResults want = fast.process_frame(px.data(), cfg.width, cfg.height,
                                                       static_cast<size_t>(cfg.width), &want_runs);
  EXPECT_EQ(word_at(got, r::res_frame_index::kOffset), frame_index);
  for (uint32_t i = 0; i < stream::kMomentCount; ++i) {
    const uint32_t grey = r::mom_grey_lo::kArray.at(i);
    const uint32_t mask = r::mom_mask_lo::kArray.at(i);
    EXPECT_EQ(word_at(got, grey) | (uint64_t{word_at(got, grey + 4)} << 32), want.moments.grey[i])
        << "grey m" << i;
    EXPECT_EQ(word_at(got, mask) | (uint64_t{word_at(got, mask + 4)} << 32), want.moments.mask[i])
        << "mask m" << i;
  }
  EXPECT_EQ(word_at(got, r::runs_emitted::kOffset), want.run_stats.runs_emitted);
  EXPECT_EQ(word_at(got, r::runs_dropped_row_limit::kOffset),
            want.run_stats.runs_dropped_row_limit);
  EXPECT_EQ(word_at(got, r::runs_dropped_overflow::kOffset), want.run_stats.runs_dropped_overflow);
  ASSERT_EQ(got.hist.size(), 256u);
  for (size_t bin = 0; bin < 256; ++bin) {
    EXPECT_EQ(r::hist_data::kCount.get(got.hist[bin]), want.histogram.bins[bin]) << "bin " << bin;
  }
  EXPECT_GT(want.moments.mask[0], 0u) << "a frame with no mask pixel checks little";
  // The run stream carries what the registers do not: BACKGROUND_LEVEL (sum_w).
  if (runs_of != nullptr) {
    EXPECT_FALSE(want_runs.empty());
    EXPECT_EQ(runs_of->last_frame_runs(), want_runs);
  }
}

void run_frame(Bench& b, const std::vector<uint8_t>& px, int w, double gap_p) {
  enqueue(b, px, w, gap_p);
  b.drain_video();
}

constexpr int kWidth = 32;
constexpr int kHeight = 24;

// Offsets with no register in the configuration under test (word aligned,
// inside the 10-bit window).
std::vector<uint32_t> unmapped_offsets() {
  std::vector<uint32_t> out;
  for (uint32_t a = 0; a <= r::kAddrMask; a += 4) {
    if (present(a) == nullptr) out.push_back(a);
  }
  return out;
}

TEST(RegisterFaultsCosim, UnmappedAndMisalignedAccessGiveSlverrAndNoSideEffect) {
  Bench b(cosim_seed(601));
  const PipelineConfig cfg = random_config(b.rng(), kWidth, kHeight);
  bring_up(b, cfg);
  run_frame(b, frame_pixels(b.rng(), kWidth, kHeight), kWidth, 0.2);
  b.write(r::intr_enable::kOffset, 0x5);
  const std::vector<uint32_t> before = b.dump();
  ASSERT_EQ(b.read(r::frame_count::kOffset), 1u);

  const std::vector<uint32_t> unmapped = unmapped_offsets();
  ASSERT_GT(unmapped.size(), 100u);
  for (const uint32_t a : unmapped) {
    EXPECT_EQ(b.read(a, r::kRespSlvErr), 0u) << "SLVERR reads return 0";
    b.write(a, 0xFFFFFFFFu, 0xF, r::kRespSlvErr);
  }
  // Misaligned: every byte lane of every register, including the ones whose
  // write has an effect (CONTROL.SOFT_RESET, LUT_DATA, INTR_STATE, INTR_TEST).
  for (const r::Register& reg : present_registers()) {
    for (uint32_t lane = 1; lane < 4; ++lane) {
      EXPECT_EQ(b.read(reg.offset + lane, r::kRespSlvErr), 0u);
      b.write(reg.offset + lane, 0xFFFFFFFFu, 0xF, r::kRespSlvErr);
    }
  }
  // Partial strobes on every writable register, with data that would act.
  for (const r::Register& reg : present_registers()) {
    if (reg.write_mask() == 0) continue;
    for (const uint8_t strb : std::array<uint8_t, 6>{0x0, 0x1, 0x3, 0x7, 0xE, 0x8}) {
      b.write(reg.offset, 0xFFFFFFFFu, strb, r::kRespSlvErr);
    }
  }
  EXPECT_EQ(b.dump(), before);
  // LUT contents and configuration untouched: the next frame is the fast path's.
  const std::vector<uint8_t> px = frame_pixels(b.rng(), kWidth, kHeight);
  run_frame(b, px, kWidth, 0.2);
  expect_results(read_results(b), cfg, px, 1);
  EXPECT_FALSE(b.sim().failed());
}

TEST(RegisterFaultsCosim, WritesToReadOnlyRegistersAreRejected) {
  Bench b(cosim_seed(602));
  const PipelineConfig cfg = random_config(b.rng(), kWidth, kHeight);
  bring_up(b, cfg);
  const std::vector<uint8_t> px = frame_pixels(b.rng(), kWidth, kHeight);
  run_frame(b, px, kWidth, 0.2);
  const std::vector<uint32_t> before = b.dump();
  const Results res_before = read_results(b);
  size_t read_only = 0;
  for (const r::Register& reg : present_registers()) {
    if (reg.write_mask() != 0) continue;
    ++read_only;
    for (const uint32_t data : {0xFFFFFFFFu, 0u, ~reg.reset}) {
      b.write(reg.offset, data, 0xF, r::kRespSlvErr);
    }
  }
  // ID, VERSION, STATUS, HIST_DATA, RUN_FIFO_*, RUN_WORD*, all result and counter registers.
  EXPECT_GE(read_only, 50u);
  EXPECT_EQ(b.dump(), before);
  EXPECT_EQ(b.read(r::id::kOffset), r::id::kValue.reset);
  const Results res_after = read_results(b);
  EXPECT_EQ(res_after, res_before);
  expect_results(res_after, cfg, px, 0);
  EXPECT_FALSE(b.sim().failed());
}

TEST(RegisterFaultsCosim, LutWritesDuringAFrameTakeEffectAtTheNextSof) {
  Bench b(cosim_seed(603));
  Rng& rng = b.rng();
  PipelineConfig old_cfg = random_config(rng, kWidth, kHeight);
  bring_up(b, old_cfg);
  PipelineConfig new_cfg = old_cfg;
  do {
    new_cfg.lut = random_lut(rng);
  } while (new_cfg.lut == old_cfg.lut);

  // Frame 1 with the old LUT; the whole new table is written while it streams.
  const std::vector<uint8_t> px1 = frame_pixels(rng, kWidth, kHeight);
  enqueue(b, px1, kWidth, 0.75);
  while (b.video().front().tvalid == false || b.video().front().tuser == false) b.step();
  b.step();  // the SOF beat enters
  ASSERT_NE(b.read(r::status::kOffset) & r::status::kInFrame.mask(), 0u);
  program_lut(b, new_cfg.lut);
  ASSERT_TRUE(b.frame_streaming()) << "the LUT writes must end inside the frame";
  EXPECT_NE(b.read(r::status::kOffset) & r::status::kLutPending.mask(), 0u);
  b.drain_video();
  expect_results(read_results(b), old_cfg, px1, 0, &b);
  EXPECT_NE(b.read(r::status::kOffset) & r::status::kLutPending.mask(), 0u);

  const std::vector<uint8_t> px2 = frame_pixels(rng, kWidth, kHeight);
  run_frame(b, px2, kWidth, 0.2);
  expect_results(read_results(b), new_cfg, px2, 1, &b);
  EXPECT_EQ(b.read(r::status::kOffset) & r::status::kLutPending.mask(), 0u);
  EXPECT_FALSE(b.sim().failed());
}

TEST(RegisterFaultsCosim, BackToBackConfigChanges) {
  Bench b(cosim_seed(604));
  Rng& rng = b.rng();
  bring_up(b, random_config(rng, kWidth, kHeight));
  run_frame(b, frame_pixels(rng, kWidth, kHeight), kWidth, 0.2);

  // Several complete configurations (size, run scanner, LUT) with no frame in
  // between; only the last may apply.
  PipelineConfig last;
  PipelineConfig before_last;
  for (int k = 0; k < 4; ++k) {
    const int w = static_cast<int>(rng.uniform(8, 40));
    const int h = static_cast<int>(rng.uniform(4, 24));
    before_last = last;
    last = random_config(rng, w, h);
    write_config(b, last);
    if (k != 3) program_lut(b, last.lut);  // the final table is written after the loop
    b.write(r::background_level::kOffset, rng.uniform_as<uint32_t>(0, 255));
    b.write(r::width::kOffset, rng.uniform_as<uint32_t>(1, 64));
    write_config(b, last);
  }
  program_lut(b, last.lut);
  EXPECT_EQ(b.read(r::width::kOffset), last.width);
  EXPECT_EQ(b.read(r::height::kOffset), last.height);
  EXPECT_EQ(b.read(r::background_level::kOffset), last.background_level);

  const std::vector<uint8_t> px = frame_pixels(rng, last.width, last.height);
  run_frame(b, px, last.width, 0.3);
  EXPECT_EQ(b.read(r::cnt_frames_ok::kOffset), 2u);
  EXPECT_EQ(b.read(r::cnt_frames_aborted::kOffset), 0u);
  expect_results(read_results(b), last, px, 1, &b);
  EXPECT_FALSE(b.sim().failed());
}

TEST(RegisterFaultsCosim, ResultsHoldWhileTheNextFrameRuns) {
  Bench b(cosim_seed(605));
  Rng& rng = b.rng();
  const PipelineConfig cfg = random_config(rng, kWidth, kHeight);
  bring_up(b, cfg);
  const std::vector<uint8_t> px1 = frame_pixels(rng, kWidth, kHeight);
  run_frame(b, px1, kWidth, 0.2);
  const Results first = read_results(b);
  expect_results(first, cfg, px1, 0);

  // Frame 2 streams slowly; every result register is read over and over, the
  // histogram 32 bins a pass, until its last pixel has entered.
  const std::vector<uint8_t> px2 = frame_pixels(rng, kWidth, kHeight);
  enqueue(b, px2, kWidth, 0.85);
  unsigned passes = 0;
  bool saw_in_frame = false;
  // A pass counts only if the frame still streams after it: then all its
  // reads came before frame 2's EOF, so before its publication.
  for (;;) {
    saw_in_frame |= (b.read(r::status::kOffset) & r::status::kInFrame.mask()) != 0;
    const std::vector<uint32_t> words = read_result_words(b);
    const unsigned from = (passes * 32) % 256;
    const std::vector<uint32_t> bins = read_hist(b, from, 32);
    if (!b.frame_streaming() || b.sim().failed()) break;
    EXPECT_EQ(words, first.words) << "pass " << passes;
    EXPECT_TRUE(std::equal(bins.begin(), bins.end(), first.hist.begin() + from))
        << "histogram bins " << from << ".. in pass " << passes;
    ++passes;
  }
  EXPECT_TRUE(saw_in_frame);
  EXPECT_GE(passes, 8u) << "every histogram bin read during frame 2";
  b.drain_video();
  const Results second = read_results(b);
  EXPECT_NE(second, first);
  expect_results(second, cfg, px2, 1);
  EXPECT_FALSE(b.sim().failed());
}

}  // namespace
}  // namespace ceilnav::testbench
