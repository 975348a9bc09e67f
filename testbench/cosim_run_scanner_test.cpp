// Co-simulation: rtl_model/run_scanner.sv (Verilated, FifoDepth 1024 and 8)
// against stream::RunScanner, every output port on every clock, under random
// frames, tvalid gaps, zero-blanking back-to-back frames, aborts (alone and
// combined with the next SOF), random configurations on the config port,
// random m_axis back-pressure (including long stalls), resets mid-frame and a
// real photo.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/cosim_common.hpp"

#include "Vrun_scanner.h"
#include "Vrun_scanner_d8.h"

#include "stream/beat.hpp"
#include "stream/run_scanner.hpp"
#include "stream/tests/beat_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::LutBeat;
using stream::RunScanConfig;
using stream::RunScanner;
using stream::test::LutFrame;

static_assert(stream::unpack_run_beat(stream::pack_run_beat({2047, 7, 2046, 522240, 534512640})) ==
              stream::RunRecord{2047, 7, 2046, 522240, 534512640});

// One clock of stimulus: the s_lut beat, the config port, tready, and an
// optional reset cycle before the edge.
struct Stim {
  LutBeat beat;
  RunScanConfig cfg;
  bool tready = true;
  bool reset_before = false;
};

struct Events {
  uint64_t runs = 0;        // run beats transferred
  uint64_t trailers = 0;    // trailer beats transferred
  uint64_t aborted = 0;     // trailers with kTrailerFrameAborted
  uint64_t overflowed = 0;  // trailers with kTrailerFifoOverflow
  uint64_t done = 0;        // done pulses
  uint32_t max_occupancy = 0;
  uint64_t trailers_lost = 0;  // across resets
};

template <class Top>
class RunScannerBench {
 public:
  RunScannerBench(const std::string& name, uint64_t seed, uint32_t depth)
      : sim_(name, seed), model_(depth) {
    compare();
  }

  bool step(const Stim& s) {
    if (s.reset_before) {
      sim_.reset_cycle();
      model_.reset();
      if (!compare()) return false;
    }
    auto& d = sim_.dut();
    const LutBeat& in = s.beat;
    d.s_lut_valid_i = in.pix.valid;
    d.s_lut_grey_i = in.pix.grey;
    d.s_lut_x_i = in.pix.x;
    d.s_lut_y_i = in.pix.y;
    d.s_lut_sof_i = in.pix.sof;
    d.s_lut_eol_i = in.pix.eol;
    d.s_lut_eof_i = in.pix.eof;
    d.s_lut_abort_i = in.pix.abort;
    d.s_lut_remap_i = in.remap;
    d.s_lut_mask_i = in.mask;
    d.cfg_background_level_i = s.cfg.background_level;
    d.cfg_min_run_length_i = s.cfg.min_run_length;
    d.cfg_max_runs_per_row_i = s.cfg.max_runs_per_row;
    d.m_axis_runs_tready_i = s.tready;
    // The beat on the output before the edge is transferred if tready.
    const stream::RunBeat before = model_.m_axis_runs();
    if (before.tvalid && s.tready) {
      if (before.tlast) {
        ++events_.trailers;
        if (before.tdata.x_start & stream::kTrailerFrameAborted) ++events_.aborted;
        if (before.tdata.x_start & stream::kTrailerFifoOverflow) ++events_.overflowed;
      } else {
        ++events_.runs;
      }
    }
    model_.set_active_config(s.cfg);
    sim_.edge();
    model_.clock(in, s.tready);
    if (sim_.ctx().gotError()) {
      sim_.fail("RTL assertion failed");
      return false;
    }
    return compare();
  }

  bool run(const std::vector<Stim>& stim) {
    for (const Stim& s : stim) {
      if (!step(s)) return false;
    }
    return true;
  }

  uint64_t cycles() const { return sim_.cycle(); }
  const Events& events() const { return events_; }
  const RunScanner& model() const { return model_; }

 private:
  bool compare() {
    auto& d = sim_.dut();
    const stream::RunBeat out = model_.m_axis_runs();
    const stream::RunBeatWords words = stream::pack_run_beat(out.tdata);
    // One packing for all: the model's record must survive it.
    bool ok =
        sim_.check("pack_run_beat round trip", stream::unpack_run_beat(words) == out.tdata, true);
    ok = sim_.check("m_axis_runs_tvalid_o", d.m_axis_runs_tvalid_o, out.tvalid) && ok;
    ok = sim_.check("m_axis_runs_tlast_o", d.m_axis_runs_tlast_o, out.tlast) && ok;
    static const char* const kWordNames[4] = {
        "m_axis_runs_tdata_o[31:0]", "m_axis_runs_tdata_o[63:32]", "m_axis_runs_tdata_o[95:64]",
        "m_axis_runs_tdata_o[111:96]"};
    for (size_t i = 0; i < 4; ++i) {
      ok = sim_.check(kWordNames[i], d.m_axis_runs_tdata_o[i], words[i]) && ok;
    }
    const stream::RunStats& st = model_.last_frame_stats();
    ok = sim_.check("done_o", d.done_o, model_.done()) && ok;
    ok = sim_.check("runs_emitted_o", d.runs_emitted_o, st.runs_emitted) && ok;
    ok = sim_.check("runs_dropped_row_limit_o", d.runs_dropped_row_limit_o,
                    st.runs_dropped_row_limit) &&
         ok;
    ok = sim_.check("runs_dropped_overflow_o", d.runs_dropped_overflow_o,
                    st.runs_dropped_overflow) &&
         ok;
    ok = sim_.check("fifo_high_water_o", d.fifo_high_water_o, st.fifo_high_water) && ok;
    ok = sim_.check("fifo_occupancy_o", d.fifo_occupancy_o, model_.fifo_occupancy()) && ok;
    ok = sim_.check("trailers_lost_o", d.trailers_lost_o, model_.trailers_lost()) && ok;
    if (model_.done()) ++events_.done;
    if (model_.trailers_lost() > lost_seen_)
      events_.trailers_lost += model_.trailers_lost() - lost_seen_;
    lost_seen_ = model_.trailers_lost();
    events_.max_occupancy = std::max(events_.max_occupancy, model_.fifo_occupancy());
    return ok;
  }

  Cosim<Top> sim_;
  RunScanner model_;
  Events events_;
  uint32_t lost_seen_ = 0;
};

// Random legal LutBeat streams with a random config port and tready.
class StimGen {
 public:
  StimGen(uint64_t seed, uint32_t max_stall_cycles)
      : rng_(seed), mt_(static_cast<uint32_t>(seed)), max_stall_(max_stall_cycles) {
    cfg_ = random_config();
  }

  RunScanConfig random_config() {
    RunScanConfig c;
    c.background_level = rng_.chance(0.3) ? 0 : rng_.byte();
    static constexpr uint16_t kMinLen[] = {0, 1, 1, 2, 3, 5, 0xFFFF};
    c.min_run_length =
        rng_.chance(0.8) ? kMinLen[rng_.uniform(0, 6)] : rng_.uniform_as<uint16_t>(0, 40);
    static constexpr uint16_t kMaxRuns[] = {0, 1, 2, 4, 8, 8, 64, 0xFFFF};
    c.max_runs_per_row =
        rng_.chance(0.8) ? kMaxRuns[rng_.uniform(0, 7)] : rng_.uniform_as<uint16_t>(0, 20);
    return c;
  }

  // tready: phases of random length, each with its own P(tready), some of
  // them full stalls.
  bool next_tready() {
    if (phase_left_ == 0) {
      static constexpr double kP[] = {1.0, 1.0, 0.95, 0.7, 0.3, 0.05, 0.0};
      p_ready_ = kP[rng_.uniform(0, 6)];
      phase_left_ = static_cast<uint32_t>(
          rng_.uniform(1, p_ready_ == 0.0 ? max_stall_ : std::max<uint32_t>(64, max_stall_ / 4)));
    }
    --phase_left_;
    return p_ready_ >= 1.0 || (p_ready_ > 0.0 && rng_.chance(p_ready_));
  }

  Stim make(const LutBeat& b) {
    if (rng_.chance(0.003)) cfg_ = random_config();  // the port may change at any time
    Stim s;
    s.beat = b;
    s.cfg = cfg_;
    s.tready = next_tready() && !stall_;
    return s;
  }

  // Salt-and-pepper mask: about width/4 runs per row.
  LutFrame noise_frame(uint16_t w, uint16_t h) {
    LutFrame f{w, h, {}, std::vector<uint8_t>(size_t{w} * h), std::vector<uint8_t>(size_t{w} * h)};
    for (size_t i = 0; i < f.pixels(); ++i) {
      f.remap[i] = rng_.byte();
      f.mask[i] = rng_.chance(0.5) ? 1 : 0;
    }
    return f;
  }

  // A frame with thousands of runs while the consumer stalls: fills a FIFO of
  // 1024 entries, so runs overflow and trailers get lost.
  void append_burst(std::vector<Stim>& out) {
    cfg_ = {rng_.byte(), 1, 0xFFFF};
    stall_ = true;
    append_frame(
        out, noise_frame(rng_.uniform_as<uint16_t>(100, 300), rng_.uniform_as<uint16_t>(20, 60)));
    stall_ = rng_.chance(0.5);  // sometimes the next frame's trailer is lost too
    append_frame(out,
                 noise_frame(rng_.uniform_as<uint16_t>(1, 20), rng_.uniform_as<uint16_t>(1, 4)));
    stall_ = false;
  }

  void random_size(uint16_t& w, uint16_t& h) {
    const int64_t kind = rng_.uniform(0, 999);
    if (kind < 600) {
      w = rng_.uniform_as<uint16_t>(1, 12);
      h = rng_.uniform_as<uint16_t>(1, 12);
    } else if (kind < 900) {
      w = rng_.uniform_as<uint16_t>(1, 64);
      h = rng_.uniform_as<uint16_t>(1, 48);
    } else if (kind < 998) {
      w = rng_.uniform_as<uint16_t>(1, 200);
      h = rng_.uniform_as<uint16_t>(1, 150);
    } else {
      w = rng_.uniform_as<uint16_t>(320, 640);
      h = rng_.uniform_as<uint16_t>(200, 480);
    }
  }

  // Appends one frame (possibly cut short) and the blanking after it.
  void append_frame(std::vector<Stim>& out, const LutFrame& f) {
    static constexpr double kGapChoices[] = {0.0, 0.0, 0.0, 0.05, 0.2, 0.6};
    const double gap = kGapChoices[rng_.uniform(0, 5)];
    const int64_t mode = rng_.uniform(0, 199);
    const auto pixels = static_cast<int64_t>(f.pixels());
    std::vector<LutBeat> beats;
    bool combine_abort_with_next_sof = false;
    size_t reset_at = SIZE_MAX;
    if (mode < 140) {
      stream::test::append_frame(beats, f, mt_, gap);
    } else if (mode < 165) {  // abort beat (valid = 0) after some pixels
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
    } else if (mode < 196) {  // early SOF: the next frame's SOF beat carries the abort
      stream::test::append_frame(beats, f, mt_, gap, rng_.uniform(0, pixels - 1));
      beats.pop_back();
      combine_abort_with_next_sof = true;
    } else {  // reset somewhere in the frame
      stream::test::append_frame(beats, f, mt_, gap);
      reset_at = static_cast<size_t>(rng_.uniform(0, static_cast<int64_t>(beats.size()) - 1));
    }
    for (size_t i = 0; i < beats.size(); ++i) {
      Stim s = make(beats[i]);
      if (pending_abort_ && s.beat.pix.valid) {
        s.beat.pix.abort = true;  // combined abort + SOF beat (frame_check's early SOF)
        pending_abort_ = false;
      }
      s.reset_before = i == reset_at;
      out.push_back(s);
    }
    pending_abort_ = combine_abort_with_next_sof;
    if (pending_abort_) return;
    const int64_t blank_kind = rng_.uniform(0, 9);
    const int64_t blank = blank_kind < 4   ? 0
                          : blank_kind < 8 ? rng_.uniform(1, 10)
                                           : rng_.uniform(10, 60);
    for (int64_t i = 0; i < blank; ++i) {
      LutBeat b;
      if (rng_.chance(0.1)) {
        b.pix.abort = true;  // abort with no frame open
      } else if (rng_.chance(0.1)) {
        b.pix.valid = true;  // pixel outside a frame, no SOF
        b.pix.x = rng_.uniform_as<uint16_t>(0, 2047);
        b.pix.y = rng_.uniform_as<uint16_t>(0, 2047);
        b.pix.eol = rng_.chance(0.5);
        b.pix.eof = b.pix.eol && rng_.chance(0.5);
        b.remap = rng_.byte();
        b.mask = rng_.chance(0.5);
      }
      out.push_back(make(b));
    }
  }

  std::vector<Stim> random_stream(uint64_t cycles, double burst_probability) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      if (rng_.chance(burst_probability)) {
        append_burst(out);
        continue;
      }
      uint16_t w = 0;
      uint16_t h = 0;
      random_size(w, h);
      append_frame(out, stream::test::random_frame(mt_, w, h));
    }
    finish(out);
    return out;
  }

  // Tiny frames (1..3 x 1..2) back to back, many aborted by the next SOF:
  // an edge can then write an aborted-frame trailer, a run and a trailer.
  std::vector<Stim> tiny_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      const auto w = rng_.uniform_as<uint16_t>(1, 3);
      const auto h = rng_.uniform_as<uint16_t>(1, 2);
      append_frame(out, stream::test::random_frame(mt_, w, h));
    }
    finish(out);
    return out;
  }

  void finish(std::vector<Stim>& out) {
    if (pending_abort_) append_frame(out, stream::test::random_frame(mt_, 3, 2));
    // Drain: tready high until the FIFO must be empty.
    for (int i = 0; i < 1100; ++i) {
      Stim s = make(LutBeat{});
      s.tready = true;
      out.push_back(s);
    }
  }

  Rng& rng() { return rng_; }
  std::mt19937& mt() { return mt_; }

 private:
  Rng rng_;
  std::mt19937 mt_;
  uint32_t max_stall_;
  RunScanConfig cfg_;
  bool pending_abort_ = false;
  bool stall_ = false;
  uint32_t phase_left_ = 0;
  double p_ready_ = 1.0;
};

void print_events(const char* name, uint64_t cycles, const Events& e) {
  std::printf(
      "%s: %llu cycles compared; %llu runs, %llu trailers (%llu aborted, %llu overflow), "
      "%llu done, max occupancy %u, %llu trailers lost\n",
      name, static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(e.runs),
      static_cast<unsigned long long>(e.trailers), static_cast<unsigned long long>(e.aborted),
      static_cast<unsigned long long>(e.overflowed), static_cast<unsigned long long>(e.done),
      e.max_occupancy, static_cast<unsigned long long>(e.trailers_lost));
}

TEST(CosimRunScanner, RandomFramesDepth1024) {
  const uint64_t seed = cosim_seed(0x72756e31);
  StimGen gen(seed, 6000);
  const auto stim = gen.random_stream(cosim_count(1500000), 0.03);
  RunScannerBench<Vrun_scanner> bench("run_scanner_d1024", seed, 1024);
  EXPECT_TRUE(bench.run(stim));
  const Events& e = bench.events();
  print_events("run_scanner d1024", bench.cycles(), e);
  EXPECT_GT(e.runs, 10000u);
  EXPECT_GT(e.aborted, 50u);
  EXPECT_GT(e.done, 200u);
  EXPECT_EQ(e.max_occupancy, 1024u);
  EXPECT_GT(e.overflowed, 5u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, RandomFramesDepth8BackPressure) {
  const uint64_t seed = cosim_seed(0x72756e32);
  StimGen gen(seed, 400);
  const auto stim = gen.random_stream(cosim_count(1000000), 0.01);
  RunScannerBench<Vrun_scanner_d8> bench("run_scanner_d8", seed, 8);
  EXPECT_TRUE(bench.run(stim));
  const Events& e = bench.events();
  print_events("run_scanner d8", bench.cycles(), e);
  EXPECT_EQ(e.max_occupancy, 8u);
  EXPECT_GT(e.overflowed, 50u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, TinyFramesDepth8ThreeWritesPerEdge) {
  const uint64_t seed = cosim_seed(0x72756e33);
  StimGen gen(seed, 200);
  const auto stim = gen.tiny_stream(cosim_count(200000));
  RunScannerBench<Vrun_scanner_d8> bench("run_scanner_tiny_d8", seed, 8);
  EXPECT_TRUE(bench.run(stim));
  const Events& e = bench.events();
  print_events("run_scanner tiny d8", bench.cycles(), e);
  EXPECT_GT(e.aborted, 1000u);
  EXPECT_GT(e.trailers_lost, 0u);
}

TEST(CosimRunScanner, TinyFramesDepth1024) {
  const uint64_t seed = cosim_seed(0x72756e34);
  StimGen gen(seed, 3000);
  const auto stim = gen.tiny_stream(cosim_count(150000));
  RunScannerBench<Vrun_scanner> bench("run_scanner_tiny_d1024", seed, 1024);
  EXPECT_TRUE(bench.run(stim));
  const Events& e = bench.events();
  print_events("run_scanner tiny d1024", bench.cycles(), e);
  EXPECT_GT(e.aborted, 1000u);
}

// A real photo (building.jpg from opencv-doc), random LUT and threshold, three
// times back to back under random back-pressure, with a different config each.
TEST(CosimRunScanner, RealPhotoBuilding) {
  const uint64_t seed = cosim_seed(0x72756e35);
  const cv::Mat img =
      cv::imread("/usr/share/doc/opencv-doc/examples/data/building.jpg", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(img.empty()) << "opencv-doc sample data missing";
  ASSERT_TRUE(img.isContinuous());
  StimGen gen(seed, 3000);
  std::array<stream::LutEntry, 256> lut{};
  const int threshold = gen.rng().uniform_as<int>(100, 200);
  for (int g = 0; g < 256; ++g) {
    lut[static_cast<size_t>(g)] = stream::lut_entry(static_cast<uint8_t>(g), g >= threshold);
  }
  const std::vector<uint8_t> grey(img.data, img.data + img.total());
  const auto f = LutFrame::from_grey(grey, static_cast<uint16_t>(img.cols),
                                     static_cast<uint16_t>(img.rows), lut);
  std::vector<Stim> stim;
  for (int pass = 0; pass < 3; ++pass) {
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), pass == 1 ? 0.2 : 0.0);
    RunScanConfig cfg = gen.random_config();
    cfg.max_runs_per_row = pass == 0 ? 0xFFFF : cfg.max_runs_per_row;
    for (const auto& b : beats) {
      Stim s = gen.make(b);
      s.cfg = cfg;
      stim.push_back(s);
    }
  }
  gen.finish(stim);
  RunScannerBench<Vrun_scanner> bench("run_scanner_photo", seed, 1024);
  EXPECT_TRUE(bench.run(stim));
  const Events& e = bench.events();
  print_events("run_scanner photo", bench.cycles(), e);
  EXPECT_EQ(e.done, 3u);
  EXPECT_GT(e.runs, 1000u);
}

}  // namespace
}  // namespace ceilnav::testbench
