// The pipeline top: clocked == fast == pipeline_ref on random images and
// photos, with random tvalid gaps and random tready back-pressure; config
// changes exactly at the next SOF; malformed frames; tiny frames; latency.
#include "stream/pipeline.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "common/edge_record.hpp"
#include "common/hough_params.hpp"
#include "golden/edge_ref.hpp"
#include "golden/hough_ref.hpp"
#include "golden/orientation_ref.hpp"
#include "golden/pipeline_ref.hpp"
#include "golden/renderer.hpp"
#include "golden/thresh_lut_ref.hpp"
#include "host/auto_threshold.hpp"
#include "stream/tests/video_source.hpp"

namespace ceilnav::stream {
namespace {

// Drives a Pipeline beat by beat with random tready; collects the run stream
// per frame (split at the trailers) and the results published at frame_done.
class Driver {
 public:
  Driver(Pipeline& p, uint32_t seed, double tready_prob)
      : p_(p), rng_(seed), tready_(tready_prob) {}

  void clock(const VideoBeat& beat) {
    const bool tready = tready_(rng_);
    const RunBeat out = p_.m_axis_runs();
    if (out.tvalid && tready) {
      if (out.tlast) {
        trailers.push_back(out.tdata);
        run_frames.push_back(current_runs_);
        current_runs_.clear();
      } else {
        current_runs_.push_back(out.tdata);
      }
    }
    p_.clock(beat, tready);
    ++cycle;
    if (p_.frame_done()) {
      published.push_back(p_.results());
      done_cycles.push_back(cycle - 1);
    }
  }
  void run(const std::vector<VideoBeat>& beats) {
    for (const VideoBeat& b : beats) {
      if (b.tvalid && b.tuser) {
        sof_cycles.push_back(cycle);
      }
      if (b.tvalid && b.tlast) {
        last_eol_cycle = cycle;
      }
      clock(b);
    }
  }
  // Idle cycles until the run stream and the results have drained.
  void drain(int max_cycles = 200000) {
    for (int i = 0; i < max_cycles; ++i) {
      clock(VideoBeat{});
      if (i > 2 * Pipeline::kEofToFrameDoneCycles && p_.run_fifo_occupancy() == 0 &&
          !p_.m_axis_runs().tvalid) {
        return;
      }
    }
    ADD_FAILURE() << "pipeline did not drain";
  }

  std::vector<FrameResults> published;
  std::vector<uint64_t> done_cycles;
  std::vector<uint64_t> sof_cycles;
  uint64_t last_eol_cycle = 0;
  std::vector<std::vector<RunRecord>> run_frames;
  std::vector<RunRecord> trailers;
  uint64_t cycle = 0;

 private:
  Pipeline& p_;
  std::mt19937 rng_;
  std::bernoulli_distribution tready_;
  std::vector<RunRecord> current_runs_;
};

PipelineConfig random_config(std::mt19937& rng, int w, int h) {
  PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(w);
  cfg.height = static_cast<uint16_t>(h);
  std::uniform_int_distribution<int> byte(0, 255);
  std::bernoulli_distribution coin(0.5);
  if (coin(rng)) {
    cfg.lut = threshold_lut(static_cast<uint8_t>(byte(rng)));
  } else {
    for (LutEntry& e : cfg.lut) {
      e = lut_entry(static_cast<uint8_t>(byte(rng)), byte(rng) > 150);
    }
  }
  cfg.background_level = static_cast<uint8_t>(byte(rng) / 4);
  cfg.min_run_length = static_cast<uint16_t>(1 + byte(rng) % 3);
  cfg.max_runs_per_row = static_cast<uint16_t>(1 + byte(rng) % 12);
  cfg.hist_source_remap = coin(rng);
  // Pixel classes in grey bands (so that the classes form regions) and a
  // window: the whole frame or a random one.
  const auto band = static_cast<unsigned>(1 + byte(rng) / 4);
  for (unsigned g = 0; g < 256; ++g) {
    cfg.lut[g] = static_cast<LutEntry>((cfg.lut[g] & ~kLutClassMask) |
                                       lut_entry(0, false, static_cast<uint8_t>((g / band) % 4)));
  }
  if (coin(rng)) {
    std::uniform_int_distribution<int> xs(0, w + 1);
    std::uniform_int_distribution<int> ys(0, h + 1);
    cfg.class_window = {static_cast<uint16_t>(xs(rng)), static_cast<uint16_t>(xs(rng)),
                        static_cast<uint16_t>(ys(rng)), static_cast<uint16_t>(ys(rng))};
  }
  return cfg;
}

int count_gaps(const std::vector<VideoBeat>& beats) {
  int gaps = 0;
  bool started = false;
  for (const VideoBeat& b : beats) {
    started = started || (b.tvalid && b.tuser);
    gaps += (started && !b.tvalid) ? 1 : 0;
  }
  return gaps;
}

// Golden == the clocked result and run stream of one frame.
void expect_matches_ref(const FrameResults& r, const std::vector<RunRecord>& runs,
                        const golden::PipelineRef& ref, const char* what) {
  EXPECT_TRUE(r.valid) << what;
  EXPECT_EQ(r.histogram, ref.histogram) << what;
  EXPECT_EQ(r.moments, ref.moments) << what;
  EXPECT_EQ(r.class_moments, ref.class_moments) << what;
  EXPECT_EQ(runs, ref.runs) << what;
  EXPECT_EQ(r.run_stats.runs_emitted, ref.runs.size()) << what;
  EXPECT_EQ(r.run_stats.runs_dropped_row_limit, ref.runs_dropped_row_limit) << what;
  EXPECT_EQ(r.run_stats.runs_dropped_overflow, 0u) << what;
}

// One frame per fresh pipeline, clocked (gaps, back-pressure) vs fast vs golden.
void check_one_frame(const cv::Mat& img, const PipelineConfig& cfg, std::mt19937& rng,
                     double gap_prob, double tready_prob, const char* what) {
  Pipeline clocked(4096);
  clocked.set_config(cfg);
  Driver d(clocked, static_cast<uint32_t>(rng()), tready_prob);
  std::vector<VideoBeat> beats;
  test::append_frame(beats, img, rng, gap_prob);
  d.run(beats);
  d.drain();
  ASSERT_EQ(d.published.size(), 1u) << what;
  ASSERT_EQ(d.run_frames.size(), 1u) << what;
  const golden::PipelineRef ref = golden::pipeline_ref(img, cfg);
  expect_matches_ref(d.published[0], d.run_frames[0], ref, what);
  EXPECT_EQ(d.trailers[0].row, std::min<size_t>(ref.runs.size(), 0xFFFF)) << what;
  EXPECT_EQ(d.trailers[0].x_start, ref.runs_dropped_row_limit != 0 ? kTrailerRowLimitHit : 0)
      << what;
  EXPECT_EQ(d.published[0].cycles_in_frame,
            static_cast<uint64_t>(img.total()) + static_cast<uint64_t>(count_gaps(beats)))
      << what;
  EXPECT_EQ(d.published[0].errors.frames_ok, 1u);
  EXPECT_EQ(d.published[0].frame_index, 0u);

  Pipeline fast(4096);
  fast.set_config(cfg);
  std::vector<RunRecord> fast_runs;
  const FrameResults f =
      fast.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &fast_runs);
  EXPECT_EQ(fast.results(), f);
  EXPECT_EQ(fast_runs, d.run_frames[0]) << what;
  FrameResults expected = d.published[0];
  expected.cycles_in_frame = img.total();
  if (tready_prob < 1.0) {
    // The FIFO high-water mark depends on the consumer; the fast path models tready = 1.
    expected.run_stats.fifo_high_water = f.run_stats.fifo_high_water;
  }
  EXPECT_EQ(f.histogram, expected.histogram) << what;
  EXPECT_EQ(f.moments, expected.moments) << what;
  EXPECT_EQ(f.run_stats, expected.run_stats)
      << what << " high water " << f.run_stats.fifo_high_water << " vs "
      << expected.run_stats.fifo_high_water;
  EXPECT_EQ(f.errors, expected.errors) << what;
  EXPECT_EQ(f, expected) << what;
}

TEST(Pipeline, ClockedEqualsFastEqualsGoldenRandomImages) {
  std::mt19937 rng(41);
  const std::vector<std::pair<int, int>> sizes = {{1, 1},   {1, 9},     {9, 1},    {2, 2},
                                                  {37, 23}, {160, 120}, {640, 480}};
  for (const auto& [w, h] : sizes) {
    for (int variant = 0; variant < 3; ++variant) {
      const cv::Mat img =
          variant == 1 ? test::random_image(rng, w, h) : test::blob_image(rng, w, h);
      const PipelineConfig cfg = random_config(rng, w, h);
      const double gap_prob = variant == 0 ? 0.0 : 0.2;
      const double tready_prob = variant == 2 ? 0.6 : 1.0;
      const std::string what =
          std::to_string(w) + "x" + std::to_string(h) + " variant " + std::to_string(variant);
      check_one_frame(img, cfg, rng, gap_prob, tready_prob, what.c_str());
    }
  }
}

TEST(Pipeline, ClockedEqualsFastEqualsGoldenOnPhotos) {
  std::mt19937 rng(42);
  int photos = 0;
  for (const std::string& name : test::photo_names()) {
    const auto img = test::load_photo(name, 640, 480);
    if (!img) {
      continue;
    }
    ++photos;
    PipelineConfig cfg = random_config(rng, img->cols, img->rows);
    cfg.lut = threshold_lut(170);
    cfg.max_runs_per_row = 16;
    check_one_frame(*img, cfg, rng, 0.05, 0.7, name.c_str());
  }
  EXPECT_GE(photos, 3) << "opencv-doc photos missing";
}

// Frames back to back with zero blanking; the host rewrites the config in the
// middle of each frame (new LUT, new geometry, new run and histogram settings):
// each frame is processed exactly with the config written before its SOF.
TEST(Pipeline, BackToBackConfigChangesTakeEffectAtTheNextSof) {
  std::mt19937 rng(43);
  const std::vector<std::pair<int, int>> sizes = {{40, 12}, {40, 12}, {17, 30}, {64, 8}};
  std::vector<cv::Mat> images;
  std::vector<PipelineConfig> cfgs;
  for (const auto& [w, h] : sizes) {
    images.push_back(test::blob_image(rng, w, h));
    cfgs.push_back(random_config(rng, w, h));
  }
  Pipeline p(4096);
  p.set_config(cfgs[0]);
  Driver d(p, 7, 0.8);
  for (size_t f = 0; f < images.size(); ++f) {
    std::vector<VideoBeat> beats;
    test::append_frame(beats, images[f], rng, 0.0);
    const size_t half = beats.size() / 2;
    d.run({beats.begin(), beats.begin() + static_cast<long>(half)});
    if (f + 1 < images.size()) {
      p.set_config(cfgs[f + 1]);
    }
    d.run({beats.begin() + static_cast<long>(half), beats.end()});
  }
  d.drain();
  ASSERT_EQ(d.published.size(), images.size());
  ASSERT_EQ(d.run_frames.size(), images.size());
  for (size_t f = 0; f < images.size(); ++f) {
    const golden::PipelineRef ref = golden::pipeline_ref(images[f], cfgs[f]);
    const std::string what = "frame " + std::to_string(f);
    expect_matches_ref(d.published[f], d.run_frames[f], ref, what.c_str());
    EXPECT_EQ(d.published[f].frame_index, f);
    EXPECT_EQ(d.published[f].cycles_in_frame, images[f].total());
  }
  EXPECT_EQ(p.error_counters().frames_ok, images.size());
  EXPECT_EQ(p.frames_overrun(), 0u);
}

// Malformed frames between good ones: counted, aborted (trailer flagged, no
// frame_done), and the good frames around them exact, results and runs.
void check_malformed(bool with_early_sof) {
  std::mt19937 rng(44);
  const int w = 30;
  const int h = 10;
  const PipelineConfig cfg = random_config(rng, w, h);
  std::vector<cv::Mat> good;
  std::vector<VideoBeat> beats;
  auto add_good = [&] {
    good.push_back(test::blob_image(rng, w, h));
    test::append_frame(beats, good.back(), rng, 0.1);
  };
  FrameErrorCounters expected;
  add_good();
  std::vector<VideoBeat> bad;
  test::append_frame(bad, test::blob_image(rng, w, h), rng, 0.0);
  bad[3 * w + 5].tlast = true;  // early EOL
  beats.insert(beats.end(), bad.begin(), bad.end());
  expected.early_eol = 1;
  add_good();
  bad.clear();
  test::append_frame(bad, test::blob_image(rng, w, h), rng, 0.0);
  bad[4 * w - 1].tlast = false;  // late EOL
  beats.insert(beats.end(), bad.begin(), bad.end());
  expected.late_eol = 1;
  add_good();
  if (with_early_sof) {
    bad.clear();
    test::append_frame(bad, test::blob_image(rng, w, h), rng, 0.0);
    // The next frame's SOF cuts it short, late enough (>= kClearCycles + 2
    // beats after the last publication) for the histogram to have a clean
    // bank: the aborted frame's bank and the old result bank are both dirty.
    bad.resize(bad.size() - static_cast<size_t>(w));
    beats.insert(beats.end(), bad.begin(), bad.end());
    expected.early_sof = 1;
    add_good();
  }
  bad.clear();
  test::append_frame(bad, test::blob_image(rng, w, h), rng, 0.0);
  bad.resize(2 * w);
  beats.insert(beats.end(), bad.begin() + 1, bad.end());  // missing SOF
  expected.missing_sof = 1;
  test::append_gaps(beats, 5);
  add_good();
  expected.frames_ok = static_cast<uint32_t>(good.size());
  expected.frames_aborted = with_early_sof ? 3 : 2;

  Pipeline p(4096);
  p.set_config(cfg);
  Driver d(p, 9, 0.9);
  d.run(beats);
  d.drain();
  EXPECT_EQ(p.error_counters(), expected);
  ASSERT_EQ(d.published.size(), good.size());
  // Every aborted frame leaves a flagged trailer in the run stream.
  ASSERT_EQ(d.trailers.size(), good.size() + expected.frames_aborted);
  std::vector<size_t> good_frames;
  for (size_t i = 0; i < d.trailers.size(); ++i) {
    if ((d.trailers[i].x_start & kTrailerFrameAborted) == 0) {
      good_frames.push_back(i);
    }
  }
  ASSERT_EQ(good_frames.size(), good.size());
  for (size_t f = 0; f < good.size(); ++f) {
    const golden::PipelineRef ref = golden::pipeline_ref(good[f], cfg);
    const std::string what = "good frame " + std::to_string(f);
    expect_matches_ref(d.published[f], d.run_frames[good_frames[f]], ref, what.c_str());
    EXPECT_EQ(d.published[f].frame_index, f);
  }
  EXPECT_EQ(d.published.back().errors, expected);
}

TEST(Pipeline, MalformedFramesAbortAndTheNextFrameIsExact) {
  check_malformed(false);
}

// The early SOF: frame_check emits abort and the new SOF pixel on ONE beat
// (valid = sof = abort = 1); every downstream block must close the old frame
// (run_scanner: flagged trailer) and then take the pixel.
TEST(Pipeline, EarlySofAbortsAndTheNewFrameIsExact) {
  check_malformed(true);
}

// Frames shorter than moment_gen's combine with zero blanking: every frame
// either is published exactly (identified by frame_index) or counted as overrun.
TEST(Pipeline, TinyFramesBackToBackArePublishedExactOrCountedAsOverrun) {
  std::mt19937 rng(45);
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {2, 2}, {3, 3}, {3, 1}}) {
    const PipelineConfig cfg = random_config(rng, w, h);
    Pipeline p(4096);
    p.set_config(cfg);
    Driver d(p, 11, 1.0);
    std::vector<cv::Mat> images;
    std::vector<VideoBeat> beats;
    std::uniform_int_distribution<int> blank(0, 12);
    for (int f = 0; f < 40; ++f) {
      images.push_back(test::random_image(rng, w, h));
      test::append_frame(beats, images.back(), rng, 0.0);
      test::append_gaps(beats, f % 3 == 0 ? blank(rng) : 0);
    }
    d.run(beats);
    d.drain();
    EXPECT_EQ(d.published.size() + p.frames_overrun(), images.size());
    EXPECT_GT(d.published.size(), 0u);
    for (const FrameResults& r : d.published) {
      ASSERT_LT(r.frame_index, images.size());
      const golden::PipelineRef ref = golden::pipeline_ref(images[r.frame_index], cfg);
      EXPECT_EQ(r.histogram, ref.histogram) << w << "x" << h << " frame " << r.frame_index;
      EXPECT_EQ(r.moments, ref.moments) << w << "x" << h << " frame " << r.frame_index;
      EXPECT_EQ(r.class_moments, ref.class_moments) << w << "x" << h << " frame " << r.frame_index;
      EXPECT_EQ(r.run_stats.runs_emitted, ref.runs.size());
    }
  }
}

TEST(Pipeline, FrameDoneLatencyAndPulse) {
  std::mt19937 rng(46);
  for (double gap_prob : {0.0, 0.4}) {
    const cv::Mat img = test::random_image(rng, 12, 7);
    Pipeline p;
    p.set_config(random_config(rng, 12, 7));
    Driver d(p, 13, 1.0);
    std::vector<VideoBeat> beats;
    test::append_frame(beats, img, rng, gap_prob);
    d.run(beats);
    d.drain();
    ASSERT_EQ(d.done_cycles.size(), 1u);
    EXPECT_EQ(d.done_cycles[0] - d.last_eol_cycle,
              static_cast<uint64_t>(Pipeline::kEofToFrameDoneCycles));
    EXPECT_FALSE(p.frame_done());
    EXPECT_TRUE(p.results().valid);
  }
  Pipeline fresh;
  EXPECT_FALSE(fresh.results().valid);
}

// The corridor blocks (has_corridor) in a non-default hough shape (8 lanes,
// 2-degree thetas, 128 rho bins, 12-bit cells): each frame's accumulator, as
// the clocked pipeline publishes it and as the fast path leaves it, equals
// golden::hough_ref on golden::find_edges_ref of the remapped frame; a
// pipeline without the corridor (HasCorridor = 0), clocked in lockstep, has
// every other output equal and its corridor outputs idle.
TEST(Pipeline, CorridorInAnotherShapeEqualsGoldenAndLeavesTheRestUnchanged) {
  std::mt19937 rng(49);
  const HoughShape shape{8, 2, 7, 12};
  constexpr int kW = 96;
  constexpr int kH = 64;
  const PipelineConfig cfg = random_config(rng, kW, kH);
  const EdgeConfig edge{true, EdgeMode::kSobel, 250};
  HoughConfig hough;
  hough.enable = true;
  hough.weight_shift = 1;
  hough.rho_shift = 1;
  hough.width = kW;
  Pipeline with(64, true, true, shape);
  Pipeline without(64, true, false);
  Pipeline fast(64, true, true, shape);
  EXPECT_FALSE(without.has_corridor());
  for (Pipeline* p : {&with, &without, &fast}) {
    p->set_config(cfg);
    p->set_corridor_config(edge, hough);
  }
  std::vector<cv::Mat> images;
  std::vector<VideoBeat> beats;
  for (int f = 0; f < 3; ++f) {
    images.push_back(test::blob_image(rng, kW, kH));
    test::append_frame(beats, images.back(), rng, f == 1 ? 0.2 : 0.0);
    test::append_gaps(beats, 20000);  // the voter drains the edge FIFO
  }
  std::bernoulli_distribution tready(0.7);
  size_t published = 0;
  for (size_t i = 0; i < beats.size(); ++i) {
    const bool rdy = tready(rng);
    with.clock(beats[i], rdy, true, 7, true, static_cast<uint32_t>(i % 8192));
    without.clock(beats[i], rdy, true, 7, true, static_cast<uint32_t>(i % 8192));
    ASSERT_EQ(without.frame_done(), with.frame_done()) << i;
    ASSERT_EQ(without.m_axis_runs(), with.m_axis_runs()) << i;
    ASSERT_EQ(without.hist_rd_data(), with.hist_rd_data()) << i;
    ASSERT_EQ(without.results(), with.results()) << i;
    ASSERT_FALSE(without.hough_done());
    ASSERT_FALSE(without.corridor_pending());
    ASSERT_EQ(without.hough_rd_data(), 0u);
    ASSERT_EQ(without.hough_stalls(), 0u);
    if (!with.hough_done()) continue;
    ASSERT_LT(published, images.size());
    cv::Mat remap;
    cv::Mat mask;
    golden::lut_ref(images[published], cfg.lut, remap, mask);
    const std::vector<EdgeRecord> pts = golden::find_edges_ref(remap, {edge.mode, edge.threshold});
    const std::vector<uint32_t> want = golden::hough_cells_ref(shape, hough, pts);
    const HoughCounters& hc = with.hough().counters();
    EXPECT_EQ(hc.trailer_flags, 0u) << "frame " << published << ": edges dropped";
    EXPECT_EQ(hc.edges, pts.size()) << "frame " << published;
    EXPECT_GT(pts.size(), 50u);
    EXPECT_TRUE(with.hough().results() == want) << "frame " << published;
    // The fast path on the same frame.
    const cv::Mat& img = images[published];
    fast.process_frame(img.ptr<uint8_t>(0), kW, kH, img.step[0], nullptr);
    EXPECT_TRUE(fast.hough().results() == want) << "fast path, frame " << published;
    EXPECT_EQ(fast.hough().counters(), hc) << "fast path, frame " << published;
    ++published;
  }
  EXPECT_EQ(published, images.size());
  EXPECT_GT(with.hough_stalls(), 0u);
}

// HasClassMoments = 0 (has_class_moments = false): clocked in lockstep with a
// full pipeline on the same beats and tready, every output equal on every
// cycle except results().class_moments, which stays zero; the fast path too.
TEST(Pipeline, WithoutClassMomentsEverythingElseIsEqual) {
  std::mt19937 rng(48);
  const ClassMomentResults zero{};
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{{2, 2}, {37, 23}, {160, 120}}) {
    PipelineConfig cfg = random_config(rng, w, h);
    cfg.class_window = ClassWindow{};  // the whole frame: the full pipeline has class moments
    Pipeline full(64);
    Pipeline tape(64, false);
    EXPECT_TRUE(full.has_class_moments());
    EXPECT_FALSE(tape.has_class_moments());
    full.set_config(cfg);
    tape.set_config(cfg);
    std::vector<VideoBeat> beats;
    std::uniform_int_distribution<int> blank(0, 80);
    for (int f = 0; f < 6; ++f) {
      test::append_frame(beats, test::blob_image(rng, w, h), rng, f % 2 == 0 ? 0.0 : 0.2);
      test::append_gaps(beats, blank(rng));
    }
    beats.resize(beats.size() + 4 * Pipeline::kEofToFrameDoneCycles + 4096);
    std::bernoulli_distribution tready(0.7);
    std::uniform_int_distribution<int> bin(0, 255);
    int done = 0;
    bool class_seen = false;
    for (size_t i = 0; i < beats.size(); ++i) {
      const bool rdy = tready(rng);
      const auto b = static_cast<uint8_t>(bin(rng));
      full.clock(beats[i], rdy, true, b);
      tape.clock(beats[i], rdy, true, b);
      ASSERT_EQ(tape.frame_done(), full.frame_done()) << i;
      ASSERT_EQ(tape.m_axis_runs(), full.m_axis_runs()) << i;
      ASSERT_EQ(tape.hist_rd_data(), full.hist_rd_data()) << i;
      ASSERT_EQ(tape.error_counters(), full.error_counters()) << i;
      ASSERT_EQ(tape.frames_overrun(), full.frames_overrun()) << i;
      ASSERT_EQ(tape.run_trailers_lost(), full.run_trailers_lost()) << i;
      ASSERT_EQ(tape.run_fifo_occupancy(), full.run_fifo_occupancy()) << i;
      ASSERT_EQ(tape.results().class_moments, zero) << i;
      FrameResults expected = full.results();
      class_seen = class_seen || expected.class_moments != zero;
      expected.class_moments = zero;
      ASSERT_EQ(tape.results(), expected) << i;
      done += full.frame_done() ? 1 : 0;
    }
    EXPECT_EQ(static_cast<uint32_t>(done) + full.frames_overrun(), 6u) << w << "x" << h;
    EXPECT_GT(done, 0) << w << "x" << h;
    EXPECT_TRUE(class_seen) << w << "x" << h << ": the full pipeline had class moments";

    const cv::Mat img = test::blob_image(rng, w, h);
    Pipeline full_fast(64);
    Pipeline tape_fast(64, false);
    full_fast.set_config(cfg);
    tape_fast.set_config(cfg);
    std::vector<RunRecord> full_runs, tape_runs;
    FrameResults expected =
        full_fast.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &full_runs);
    const FrameResults got =
        tape_fast.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &tape_runs);
    EXPECT_EQ(got.class_moments, zero);
    expected.class_moments = zero;
    EXPECT_EQ(got, expected);
    EXPECT_EQ(tape_runs, full_runs);
  }
}

TEST(Pipeline, FastPathRejectsWrongGeometryAndBusyPipeline) {
  PipelineConfig cfg;
  cfg.width = 8;
  cfg.height = 4;
  Pipeline p;
  p.set_config(cfg);
  std::vector<uint8_t> img(64, 0);
  EXPECT_THROW(p.process_frame(img.data(), 8, 8, 8, nullptr), std::invalid_argument);
  p.clock(test::pixel_beat(1, true, false), true);
  EXPECT_THROW(p.process_frame(img.data(), 8, 4, 8, nullptr), std::logic_error);
}

// The fast path publishes every frame it is given, one after the other
// (throughput: bench/ceilnav_bench.cpp, BM_FastPath).
TEST(Pipeline, FastPathPublishesEveryFrame) {
  std::mt19937 rng(47);
  const cv::Mat img = test::blob_image(rng, 640, 480);
  PipelineConfig cfg = random_config(rng, 640, 480);
  cfg.lut = threshold_lut(128);
  Pipeline p;
  p.set_config(cfg);
  std::vector<RunRecord> runs;
  const int frames = 3;
  std::vector<RunRecord> first;
  for (int i = 0; i < frames; ++i) {
    p.process_frame(img.ptr<uint8_t>(0), img.cols, img.rows, img.step[0], &runs);
    EXPECT_EQ(p.results().frame_index, static_cast<uint32_t>(i));
    if (i == 0) first = runs;
    EXPECT_EQ(runs, first) << "frame " << i;
  }
  EXPECT_FALSE(first.empty());
}

}  // namespace
}  // namespace ceilnav::stream

namespace ceilnav::stream {
namespace {

// Rendered ceiling frames (corridor with gaps, T-branch, two tapes, lens
// distortion, noise, blur) with the host's threshold rule: clocked (gaps,
// back-pressure) == fast == golden.
TEST(Pipeline, ClockedEqualsFastEqualsGoldenOnRenderedFrames) {
  std::mt19937 rng(43);
  host::CameraConfig cam;
  cam.image_width = 320;
  cam.image_height = 240;
  cam.camera_matrix = {260.0, 0.0, 160.3, 0.0, 259.0, 119.2, 0.0, 0.0, 1.0};
  cam.distortion_coefficients = {-0.08, 0.015, 0.0, 0.0, 0.0};
  golden::CorridorOptions corridor;
  corridor.second_tape = true;
  corridor.second_tape_y_m = 0.9;
  const golden::CeilingScene scene = golden::corridor_scene(0.05, corridor);
  for (int i = 0; i < 6; ++i) {
    cam.camera_pitch_deg = 20.0 + 14.0 * i;
    golden::RenderParams rp;
    rp.noise_sigma_grey = 1.0 + i;
    rp.noise_seed = 7u + static_cast<uint64_t>(i);
    const cv::Mat img = golden::render_frame(cam, scene, {3.0 + 1.7 * i, 0.2, 0.1 - 0.04 * i}, rp);
    HistogramResults hist;
    for (int r = 0; r < img.rows; ++r) {
      for (int c = 0; c < img.cols; ++c) ++hist.bins[img.at<uint8_t>(r, c)];
    }
    const host::ThresholdSettings t = host::choose_threshold(hist);
    PipelineConfig cfg;
    cfg.width = static_cast<uint16_t>(img.cols);
    cfg.height = static_cast<uint16_t>(img.rows);
    cfg.min_run_length = 2;
    cfg.max_runs_per_row = 4;  // the T-branch row and two tapes hit the limit sometimes
    cfg = host::apply_threshold(cfg, t);
    const std::string what = "rendered frame " + std::to_string(i);
    EXPECT_GT(golden::pipeline_ref(img, cfg).runs.size(), 50u) << what;  // the tapes are seen
    check_one_frame(img, cfg, rng, 0.15, 0.5, what.c_str());
  }
}

}  // namespace
}  // namespace ceilnav::stream

namespace ceilnav::stream {
namespace {

// The orientation block (HasOrientation = 1, the homing device): the fast
// path's published histogram and counters equal the clocked pipeline's (the
// frames streamed with tvalid gaps and enough blanking for the block's
// sweep) and golden::orientation_histogram_fixed of the remap, at 90 and 7
// bins; a frame with ORI_CONTROL.ENABLE = 0 leaves both as they were.
TEST(Pipeline, OrientationFastPathEqualsClockedEqualsGolden) {
  std::mt19937 rng(50);
  const std::vector<std::pair<int, int>> sizes = {{3, 3}, {37, 23}, {160, 120}, {64, 9}, {96, 72}};
  for (const uint32_t bins : {90u, 7u}) {
    Pipeline clocked(1024, false, false, HoughShape{}, EdgeDetector::kDefaultFifoDepth, true, bins);
    Pipeline fast(1024, false, false, HoughShape{}, EdgeDetector::kDefaultFifoDepth, true, bins);
    ASSERT_TRUE(fast.has_orientation());
    uint32_t published = 0;
    for (size_t f = 0; f < sizes.size(); ++f) {
      const auto [w, h] = sizes[f];
      const cv::Mat img = f % 2 == 0 ? test::blob_image(rng, w, h) : test::random_image(rng, w, h);
      const PipelineConfig cfg = random_config(rng, w, h);
      const OrientationConfig ori{f != 3, static_cast<uint16_t>(f == 2 ? 0 : 8 + 40 * f)};
      const std::string what = "bins " + std::to_string(bins) + " frame " + std::to_string(f);
      for (Pipeline* p : {&clocked, &fast}) {
        p->set_config(cfg);
        p->set_orientation_config(ori);
      }
      const std::vector<uint32_t> before = clocked.orientation().results();
      // Blanking before the frame (the sweep after the reset or the last
      // publication ends) and after it (the pipeline drains).
      std::vector<VideoBeat> beats;
      test::append_gaps(beats, 300);
      test::append_frame(beats, img, rng, 0.2);
      test::append_gaps(beats, 100);
      for (const VideoBeat& b : beats) clocked.clock(b, true);
      fast.process_frame(img.ptr<uint8_t>(0), w, h, img.step[0], nullptr);
      const Orientation& c = clocked.orientation();
      const Orientation& q = fast.orientation();
      if (ori.enable) ++published;
      EXPECT_EQ(c.frames(), published) << what;
      EXPECT_EQ(q.frames(), c.frames()) << what;
      EXPECT_EQ(q.frames_skipped(), 0u) << what;
      EXPECT_EQ(c.frames_skipped(), 0u) << what;
      EXPECT_EQ(q.frame_votes(), c.frame_votes()) << what;
      EXPECT_EQ(q.results_valid(), c.results_valid()) << what;
      EXPECT_FALSE(q.clearing()) << what;
      EXPECT_EQ(q.results(), c.results()) << what;
      if (!ori.enable) {
        EXPECT_EQ(c.results(), before) << what;
        continue;
      }
      cv::Mat remap;
      cv::Mat mask;
      golden::lut_ref(img, cfg.lut, remap, mask);
      EXPECT_EQ(q.results(),
                golden::orientation_histogram_fixed(remap, {static_cast<int>(bins), ori.threshold}))
          << what;
      // Every other result of the frame is the clocked path's too.
      EXPECT_EQ(fast.results().histogram, clocked.results().histogram) << what;
      EXPECT_EQ(fast.results().moments, clocked.results().moments) << what;
    }
    EXPECT_GT(clocked.orientation().frame_votes(), 100u);
  }
}

}  // namespace
}  // namespace ceilnav::stream
