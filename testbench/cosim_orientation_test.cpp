// Co-simulation: rtl_model/orientation.sv (Verilated, Bins 90, 7 and 256)
// against stream::Orientation, every output port on every clock, under
// random frames (1x1 up to 640x480 and 2048-long thin frames; noise, smooth
// frames, and stripes whose votes hit one bin back to back: the RMW
// forwarding), tvalid gaps, zero-blanking back-to-back frames (frames that
// meet the clear sweep and are skipped), aborts (alone and combined with the
// next SOF), resets mid-frame, stray beats, random configurations (enable,
// thresholds 0..4095) on the config port at any cycle, random reads and full
// read sweeps of the published histogram while the next frame votes, and
// real photos (whose published histograms also equal the bit-true golden).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <vector>

// First: it includes verilated.h with the warnings that it trips switched off.
#include "testbench/block_bench.hpp"
#include "testbench/lut_stream.hpp"
#include "testbench/ports.hpp"

#include "Vorientation.h"
#include "Vorientation_b256.h"
#include "Vorientation_b7.h"

#include "golden/orientation_ref.hpp"
#include "stream/beat.hpp"
#include "stream/orientation.hpp"
#include "stream/tests/beat_source.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::testbench {
namespace {

using stream::LutBeat;
using stream::Orientation;
using stream::OrientationConfig;
using stream::test::LutFrame;

// One clock of stimulus: the s_lut beat, the config port, the read port, and
// an optional reset cycle before the edge.
struct Stim {
  LutBeat beat;
  OrientationConfig cfg;
  bool rd_en = false;
  uint16_t rd_bin = 0;
  bool reset_before = false;
};

struct Events {
  uint64_t published = 0;                         // done pulses
  uint64_t skipped = 0;                           // frames ended unpublished (across resets)
  uint64_t votes = 0;                             // frame_votes at the done pulses
  uint64_t reads = 0;                             // read-port data != 0
  uint64_t clearing = 0;                          // cycles with the sweep running
  std::vector<std::vector<uint32_t>> histograms;  // at every done pulse, if kept
};

// orientation's ports for BlockBench (any Bins).
template <class Top>
struct OrientationPorts {
  using Stim = testbench::Stim;

  void drive(Top& d, const Stim& s) {
    drive_s_lut(d, s.beat);
    d.cfg_enable_i = s.cfg.enable;
    d.cfg_threshold_i = s.cfg.threshold & 0xFFFu;
    d.hist_rd_en_i = s.rd_en;
    d.hist_rd_bin_i = s.rd_bin & 0xFFu;
  }
  void clock(Orientation& m, const Stim& s) {
    m.set_config({s.cfg.enable, static_cast<uint16_t>(s.cfg.threshold & 0xFFFu)});
    m.clock(s.beat, s.rd_en, static_cast<uint16_t>(s.rd_bin & 0xFFu));
  }
  bool compare(Cosim<Top>& sim, const Orientation& m) {
    auto& d = sim.dut();
    bool ok = sim.check("done_o", d.done_o, m.done());
    ok = sim.check("hist_rd_data_o", d.hist_rd_data_o, m.hist_rd_data()) && ok;
    ok = sim.check("results_valid_o", d.results_valid_o, m.results_valid()) && ok;
    ok = sim.check("clearing_o", d.clearing_o, m.clearing()) && ok;
    ok = sim.check("frame_votes_o", d.frame_votes_o, m.frame_votes()) && ok;
    ok = sim.check("frames_o", d.frames_o, m.frames()) && ok;
    ok = sim.check("frames_skipped_o", d.frames_skipped_o, m.frames_skipped()) && ok;
    if (m.done()) {
      ++events.published;
      events.votes += m.frame_votes();
      if (keep_histograms) events.histograms.push_back(m.results());
    }
    if (m.frames_skipped() > skipped_seen) events.skipped += m.frames_skipped() - skipped_seen;
    skipped_seen = m.frames_skipped();
    if (m.hist_rd_data() != 0) ++events.reads;
    if (m.clearing()) ++events.clearing;
    return ok;
  }

  Events events;
  uint32_t skipped_seen = 0;
  bool keep_histograms = false;
};

template <class Top>
using OrientationBench = BlockBench<Top, Orientation, OrientationPorts<Top>>;

// Random legal LutBeat streams with a random config port and read port.
class StimGen : public LutStreamGen<StimGen, Stim> {
 public:
  StimGen(uint64_t seed, uint32_t bins)
      : LutStreamGen(seed, LutStreamShape{.thin_frames = true}), bins_(bins) {
    cfg_ = random_config();
  }

  OrientationConfig random_config() {
    OrientationConfig c;
    c.enable = rng_.chance(0.93);
    static constexpr uint16_t kT[] = {0, 1, 8, 16, 40, 100, 500, 1402, 1403, 4095};
    c.threshold = rng_.chance(0.4) ? kT[rng_.uniform(0, 9)] : rng_.uniform_as<uint16_t>(0, 200);
    return c;
  }

  // The read port: random reads (mostly inside the bins), and now and then a
  // full sweep of every bin address 0 .. 255.
  void read_port(Stim& s) {
    if (sweep_left_ == 0 && rng_.chance(0.002)) sweep_left_ = 256;
    if (sweep_left_ > 0) {
      s.rd_en = true;
      s.rd_bin = static_cast<uint16_t>(256 - sweep_left_);
      --sweep_left_;
      return;
    }
    s.rd_en = rng_.chance(0.3);
    s.rd_bin = rng_.chance(0.9) ? rng_.uniform_as<uint16_t>(0, static_cast<int64_t>(bins_) - 1)
                                : rng_.uniform_as<uint16_t>(0, 255);
  }

  // LutStreamGen's hooks.
  Stim make(const LutBeat& b) {
    if (rng_.chance(0.003)) cfg_ = random_config();  // the port may change any time
    Stim s;
    s.beat = b;
    s.cfg = cfg_;
    read_port(s);
    return s;
  }
  Stim make_blank() { return make(blank_beat()); }
  void begin_frame(const LutFrame& /*f*/) {}
  LutFrame frame(uint16_t w, uint16_t h) {
    LutFrame f = stream::test::random_frame(mt_, w, h);
    const int64_t kind = rng_.uniform(0, 9);
    if (kind < 3) {  // noise: every gradient strong, bins all over
      for (auto& p : f.remap) p = rng_.byte();
    } else if (kind < 6) {  // stripes at one angle: long runs of votes into one bin
      const int64_t dx = rng_.uniform(-3, 3);
      const int64_t dy = rng_.uniform(-3, 3);
      const int64_t period = rng_.uniform(2, 9);
      for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x) {
          const int64_t s = dx * x + dy * y;
          f.remap[size_t{y} * w + x] = ((s % period) + period) % period < period / 2 ? 30 : 220;
        }
      }
    }  // else: random_frame's smooth rows
    return f;
  }
  // Drain: long enough for the last frame's publication and sweep.
  void drain(std::vector<Stim>& out) {
    for (int i = 0; i < 400; ++i) out.push_back(make(LutBeat{}));
  }

  // Frames: a third tiny (mostly skipped or without votes), the rest wide
  // enough for the sweep, now and then large or thin.
  void random_dims(uint16_t& w, uint16_t& h) {
    const int64_t kind = rng_.uniform(0, 99);
    if (kind < 30) {
      w = rng_.uniform_as<uint16_t>(1, 12);
      h = rng_.uniform_as<uint16_t>(1, 12);
    } else if (kind < 90) {
      w = rng_.uniform_as<uint16_t>(3, 200);
      h = rng_.uniform_as<uint16_t>(1, 60);
    } else {
      random_size(w, h);
    }
  }

  std::vector<Stim> random_stream(uint64_t cycles) {
    std::vector<Stim> out;
    while (out.size() < cycles) {
      uint16_t w = 0;
      uint16_t h = 0;
      random_dims(w, h);
      append_frame(out, frame(w, h));
    }
    finish(out);
    return out;
  }

 private:
  uint32_t bins_;
  OrientationConfig cfg_{};
  int sweep_left_ = 0;
};

void print_events(const char* name, uint64_t cycles, const Events& e) {
  std::printf(
      "%s: %llu cycles compared; %llu frames published (%llu votes), %llu skipped; %llu reads "
      "with data, %llu clearing cycles\n",
      name, static_cast<unsigned long long>(cycles), static_cast<unsigned long long>(e.published),
      static_cast<unsigned long long>(e.votes), static_cast<unsigned long long>(e.skipped),
      static_cast<unsigned long long>(e.reads), static_cast<unsigned long long>(e.clearing));
}

template <class Top>
Events run_bench(const char* name, uint64_t seed, uint32_t bins, const std::vector<Stim>& stim,
                 bool keep_histograms = false) {
  OrientationBench<Top> bench(name, seed, bins);
  bench.ports().keep_histograms = keep_histograms;
  EXPECT_TRUE(bench.run(stim));
  print_events(name, bench.cycles(), bench.ports().events);
  return bench.ports().events;
}

TEST(CosimOrientation, RandomFrames90Bins) {
  const uint64_t seed = cosim_seed(0x0A1E0001);
  StimGen gen(seed, 90);
  const auto stim = gen.random_stream(cosim_count(1500000));
  const Events e = run_bench<Vorientation>("orientation_b90", seed, 90, stim);
  EXPECT_GT(e.published, 200u);
  EXPECT_GT(e.votes, 300000u);
  EXPECT_GT(e.skipped, 100u);
  EXPECT_GT(e.reads, 100000u);
  EXPECT_GT(e.clearing, 30000u);
}

TEST(CosimOrientation, RandomFrames7Bins) {
  const uint64_t seed = cosim_seed(0x0A1E0002);
  StimGen gen(seed, 7);
  const auto stim = gen.random_stream(cosim_count(600000));
  const Events e = run_bench<Vorientation_b7>("orientation_b7", seed, 7, stim);
  EXPECT_GT(e.published, 120u);
  EXPECT_GT(e.votes, 100000u);
  EXPECT_GT(e.reads, 30000u);
}

TEST(CosimOrientation, RandomFrames256Bins) {
  const uint64_t seed = cosim_seed(0x0A1E0003);
  StimGen gen(seed, 256);
  const auto stim = gen.random_stream(cosim_count(600000));
  const Events e = run_bench<Vorientation_b256>("orientation_b256", seed, 256, stim);
  EXPECT_GT(e.published, 50u);
  EXPECT_GT(e.votes, 100000u);
  EXPECT_GT(e.skipped, 60u);
  EXPECT_GT(e.reads, 50000u);
}

// Real photos back to back (zero blanking, random gaps) with random reads
// and read sweeps; every published histogram equals the bit-true golden.
TEST(CosimOrientation, RealPhotos) {
  const uint64_t seed = cosim_seed(0x0A1E0004);
  StimGen gen(seed, 90);
  std::vector<cv::Mat> imgs;
  std::vector<Stim> stim;
  for (int i = 0; i < 100; ++i) stim.push_back(gen.make(LutBeat{}));  // the reset's sweep
  const OrientationConfig cfg{true, 40};
  for (const auto& name : stream::test::photo_names()) {
    const auto img = stream::test::load_photo(name, 640, 480);
    ASSERT_TRUE(img) << name << ": opencv-doc sample data missing";
    imgs.push_back(*img);
    LutFrame f{static_cast<uint16_t>(img->cols), static_cast<uint16_t>(img->rows), {}, {}, {}};
    f.remap.assign(img->begin<uint8_t>(), img->end<uint8_t>());
    f.grey = f.remap;
    f.mask.assign(f.remap.size(), 0);
    std::vector<LutBeat> beats;
    stream::test::append_frame(beats, f, gen.mt(), imgs.size() % 2 == 0 ? 0.1 : 0.0);
    for (const auto& b : beats) {
      Stim s = gen.make(b);
      s.cfg = cfg;
      stim.push_back(s);
    }
  }
  gen.drain(stim);
  const Events e = run_bench<Vorientation>("orientation_photo", seed, 90, stim, true);
  ASSERT_EQ(e.histograms.size(), imgs.size());
  for (size_t i = 0; i < imgs.size(); ++i) {
    EXPECT_EQ(e.histograms[i], golden::orientation_histogram_fixed(imgs[i], {90, 40})) << i;
  }
  EXPECT_EQ(e.skipped, 0u);
}

}  // namespace
}  // namespace ceilnav::testbench
