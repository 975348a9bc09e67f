// `ceilnav profile` on the C++ cycle model: the figures measured at the ports
// against what the stimulus implies (cycles from the feed, latency from the
// device's constant), the host's bus words against a counting bus, and a
// device that drops tready: its bubbles must be seen and reported.
#include "apps/profile.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "apps/plot.hpp"
#include "drivers/model_bus.hpp"
#include "host/driver.hpp"
#include "stream/ceilnav_top.hpp"

namespace ceilnav::app {
namespace {

constexpr int kW = 96, kH = 64;
constexpr uint64_t kPixels = uint64_t{kW} * kH;

ProfileScenario small(Blanking b, double backpressure = 0.0, int tapes = 1) {
  ProfileScenario s;
  s.width = kW;
  s.height = kH;
  s.blanking = b;
  s.backpressure = backpressure;
  s.tapes = tapes;
  s.seed = 5;
  return s;
}

std::vector<cv::Mat> render(const ProfileScenario& s, const host::CameraConfig& cam, size_t n) {
  std::vector<cv::Mat> frames;
  for (size_t i = 0; i < n; ++i) frames.push_back(render_profile_frame(s, cam, i, n));
  return frames;
}

// A ModelBus that counts the driver's register accesses itself.
class CountingBus : public drivers::ModelBus {
 public:
  using drivers::ModelBus::ModelBus;
  uint32_t read32(uint32_t addr) override {
    ++reads;
    return drivers::ModelBus::read32(addr);
  }
  void write32(uint32_t addr, uint32_t value) override {
    ++writes;
    drivers::ModelBus::write32(addr, value);
  }
  uint64_t reads = 0, writes = 0;
};

struct ModelRun {
  std::vector<FrameProfile> frames;
  uint64_t reads = 0, writes = 0;  // over all passes, warm-up included
};

ModelRun profile_on_model(const ProfileScenario& s, size_t n) {
  const host::CameraConfig cam = profile_camera(s);
  const std::vector<cv::Mat> frames = render(s, cam, n);
  drivers::SimBusOptions opt;
  opt.seed = s.seed;
  opt.run_tready_low_probability = s.backpressure;
  CountingBus bus(opt);
  ModelRun r;
  r.frames = profile_frames(
      bus, [&](size_t i) { return frames[i]; }, n, s, cam);
  r.reads = bus.reads;
  r.writes = bus.writes;
  return r;
}

void expect_common(const std::vector<FrameProfile>& frames, const ProfileScenario& s) {
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameProfile& f = frames[i];
    SCOPED_TRACE("frame " + std::to_string(i));
    EXPECT_EQ(f.tvalid_cycles, kPixels);
    EXPECT_EQ(f.accepted, kPixels);
    EXPECT_EQ(f.bubbles, 0u);
    EXPECT_EQ(f.pixels_per_valid_cycle(), 1.0);
    EXPECT_EQ(f.pixels_counted, kPixels);
    EXPECT_EQ(f.device_cycles, f.cycles);
    EXPECT_EQ(f.eof_to_irq_cycles, stream::CeilnavTop::kEofToIntrCycles);
    EXPECT_EQ(f.eof_to_irq_register, static_cast<uint32_t>(stream::CeilnavTop::kEofToIntrCycles));
    EXPECT_EQ(f.runs, f.runs_emitted);
    EXPECT_EQ(f.run_beats, f.runs + 1);  // the runs and the frame's trailer
    EXPECT_EQ(f.runs_dropped_overflow, 0u);
    EXPECT_TRUE(f.frame_ok);
    EXPECT_GT(f.readout_cycles, 0u);
    EXPECT_LT(f.readout_cycles, f.host_cycles);
  }
  EXPECT_TRUE(check_profile(frames, s).empty());
}

TEST(Profile, NoGapsFrameTakesOneCyclePerPixel) {
  const ProfileScenario s = small(Blanking::none);
  const ModelRun r = profile_on_model(s, 3);
  ASSERT_EQ(r.frames.size(), 3u);
  expect_common(r.frames, s);
  for (const FrameProfile& f : r.frames) {
    EXPECT_EQ(f.cycles, kPixels);
    EXPECT_EQ(f.run_stall_cycles, 0u);
    EXPECT_GE(f.words_written, 256u);  // the whole LUT every frame
    EXPECT_GE(f.words_read, 256u);     // the whole histogram every frame
  }
  EXPECT_GT(r.reads, 3 * r.frames[0].words_read);  // and the warm-up pass
}

TEST(Profile, ProbeCountsEveryBusTransaction) {
  const ProfileScenario s = small(Blanking::none);
  const host::CameraConfig cam = profile_camera(s);
  const cv::Mat frame = render(s, cam, 1)[0];
  CountingBus bus;
  host::Driver driver(bus);
  PortProbe probe(kH);
  bus.set_observer(&probe);
  driver.identify();
  stream::PipelineConfig cfg;
  cfg.width = kW;
  cfg.height = kH;
  driver.configure(cfg);
  bus.queue_frame(frame.ptr<uint8_t>(0), kW, kH, frame.step[0], frame_feed(s));
  const host::FrameReadout r = driver.read_frame();
  const PortProbe::Counts c = probe.take();
  EXPECT_EQ(c.axil_reads, bus.reads);
  EXPECT_EQ(c.axil_writes, bus.writes);
  EXPECT_EQ(c.edges, bus.cycles());
  EXPECT_EQ(c.frames_started, 1);
  EXPECT_TRUE(c.eof_seen);
  EXPECT_EQ(c.frame_cycles, kPixels);
  EXPECT_EQ(c.frame_cycles, r.results.cycles_in_frame);
  EXPECT_EQ(c.run_beats, r.runs.size() + 1);
  ASSERT_TRUE(c.irq_rise_seen);
  EXPECT_EQ(c.irq_rise_edge - c.eof_edge, uint64_t{stream::CeilnavTop::kEofToIntrCycles});
}

TEST(Profile, VgaBlankingAddsLineBlankingInsideTheFrame) {
  const VideoTiming vga = vga_like_timing(640, 480);  // VESA 640x480@60
  EXPECT_EQ(vga.line_blanking_cycles, 800u - 640u);
  EXPECT_EQ(vga.frame_blanking_cycles, (525u - 480u) * 800u);
  const ProfileScenario s = small(Blanking::vga);
  const VideoTiming t = vga_like_timing(kW, kH);
  const ModelRun r = profile_on_model(s, 2);
  expect_common(r.frames, s);
  for (const FrameProfile& f : r.frames) {
    EXPECT_EQ(f.cycles, kPixels + uint64_t{kH - 1} * t.line_blanking_cycles);
  }
}

TEST(Profile, RandomGapsAndBackPressureKeepIiOne) {
  const ProfileScenario s = small(Blanking::random, 0.5, 2);
  const ModelRun r = profile_on_model(s, 3);
  expect_common(r.frames, s);
  uint64_t stalls = 0, runs = 0;
  for (const FrameProfile& f : r.frames) {
    EXPECT_GT(f.cycles, kPixels);  // P = 0.25 of a gap before each of 6144 pixels
    stalls += f.run_stall_cycles;
    runs += f.runs;
  }
  EXPECT_GT(runs, 0u);
  EXPECT_GT(stalls, 0u);
}

// The model with tready forced low on every 7th edge (a pipeline that stalls).
class StallingDevice : public drivers::SimDevice {
 public:
  void reset() override {
    top_.reset();
    n_ = 0;
  }
  drivers::SimOutputs outputs() const override {
    drivers::SimOutputs o;
    o.s_axil = top_.s_axil_out();
    o.m_axis_runs = top_.m_axis_runs();
    o.irq = top_.irq();
    o.s_axis_video_tready = n_ % 7 != 3;
    return o;
  }
  void clock(const drivers::SimInputs& in) override {
    const bool ready = outputs().s_axis_video_tready;
    top_.clock(ready ? in.s_axis_video : stream::VideoBeat{}, in.s_axil, in.m_axis_runs_tready);
    ++n_;
  }

 private:
  stream::CeilnavTop top_;
  uint64_t n_ = 0;
};

TEST(Profile, StallsAreCountedAsBubblesAndReported) {
  const ProfileScenario s = small(Blanking::none);
  const host::CameraConfig cam = profile_camera(s);
  const std::vector<cv::Mat> frames = render(s, cam, 2);
  drivers::SimBus bus(std::make_unique<StallingDevice>());
  const std::vector<FrameProfile> p = profile_frames(
      bus, [&](size_t i) { return frames[i]; }, frames.size(), s, cam);
  for (const FrameProfile& f : p) {
    EXPECT_EQ(f.accepted, kPixels);  // SimBus holds a beat until tready
    EXPECT_EQ(f.pixels_counted, kPixels);
    EXPECT_GT(f.bubbles, kPixels / 7 - 2);
    EXPECT_EQ(f.tvalid_cycles, f.cycles);
    // No other gaps in the frame; a stall on the SOF beat is before the frame.
    EXPECT_LE(f.cycles, kPixels + f.bubbles);
    EXPECT_GE(f.cycles + 1, kPixels + f.bubbles);
    EXPECT_LT(f.pixels_per_valid_cycle(), 1.0);
  }
  const std::vector<std::string> problems = check_profile(p, s);
  ASSERT_FALSE(problems.empty());
  EXPECT_NE(problems[0].find("II != 1"), std::string::npos) << problems[0];
}

TEST(Profile, BlankingNames) {
  for (Blanking b : {Blanking::none, Blanking::vga, Blanking::random}) {
    EXPECT_EQ(parse_blanking(std::string(to_string(b))), b);
  }
  EXPECT_THROW(parse_blanking("ntsc"), std::runtime_error);
}

}  // namespace
}  // namespace ceilnav::app
