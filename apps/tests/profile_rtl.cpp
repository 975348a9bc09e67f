// `ceilnav profile`: the C++ cycle model and the Verilated RTL give the same
// cycle figures, frame by frame, for scenarios with every blanking pattern,
// run-stream back-pressure and several tapes, in both device configurations;
// and both meet II = 1 with no bubbles.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "apps/profile.hpp"
#include "ceilnav/regs.hpp"

namespace ceilnav::app {
namespace {

struct Case {
  const char* name;
  int width, height;
  Blanking blanking;
  double backpressure;
  int tapes;
  size_t frames;
  regs::Config config = regs::kConfigFull;
};

std::vector<FrameProfile> run(const std::string& backend, const ProfileScenario& s,
                              const host::CameraConfig& cam, const std::vector<cv::Mat>& frames,
                              const regs::Config& config) {
  drivers::SimBusOptions opt;
  opt.seed = s.seed;
  opt.device_config = config;
  opt.run_tready_low_probability = s.backpressure;
  const auto bus = make_profile_bus(backend, opt);
  return profile_frames(
      *bus, [&](size_t i) { return frames[i]; }, frames.size(), s, cam);
}

TEST(ProfileRtl, ModelAndRtlReportTheSameCycleFigures) {
  const Case cases[] = {
      {"none", 96, 64, Blanking::none, 0.0, 1, 3},
      {"random+bp0.5+2 tapes", 96, 64, Blanking::random, 0.5, 2, 3},
      {"vga+bp0.25+3 tapes", 128, 96, Blanking::vga, 0.25, 3, 2},
      {"random+bp0.9", 160, 120, Blanking::random, 0.9, 2, 2},
      {"tape device, random+bp0.5", 96, 64, Blanking::random, 0.5, 2, 2, regs::kConfigTape},
  };
  uint64_t runs_total = 0, stalls_total = 0;
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    ProfileScenario s;
    s.width = k.width;
    s.height = k.height;
    s.blanking = k.blanking;
    s.backpressure = k.backpressure;
    s.tapes = k.tapes;
    s.seed = 11;
    const host::CameraConfig cam = profile_camera(s);
    std::vector<cv::Mat> frames;
    for (size_t i = 0; i < k.frames; ++i) {
      frames.push_back(render_profile_frame(s, cam, i, k.frames));
    }
    const std::vector<FrameProfile> m = run("model", s, cam, frames, k.config);
    const std::vector<FrameProfile> r = run("rtl", s, cam, frames, k.config);
    ASSERT_EQ(m.size(), k.frames);
    ASSERT_EQ(r.size(), k.frames);
    for (size_t i = 0; i < k.frames; ++i) {
      SCOPED_TRACE("frame " + std::to_string(i));
      EXPECT_EQ(m[i].cycles, r[i].cycles);
      EXPECT_EQ(m[i].tvalid_cycles, r[i].tvalid_cycles);
      EXPECT_EQ(m[i].accepted, r[i].accepted);
      EXPECT_EQ(m[i].bubbles, r[i].bubbles);
      EXPECT_EQ(m[i].pixels_counted, r[i].pixels_counted);
      EXPECT_EQ(m[i].device_cycles, r[i].device_cycles);
      EXPECT_EQ(m[i].eof_to_irq_cycles, r[i].eof_to_irq_cycles);
      EXPECT_EQ(m[i].eof_to_irq_register, r[i].eof_to_irq_register);
      EXPECT_EQ(m[i].fifo_high_water, r[i].fifo_high_water);
      EXPECT_EQ(m[i].runs_dropped_overflow, r[i].runs_dropped_overflow);
      EXPECT_EQ(m[i].runs_dropped_row_limit, r[i].runs_dropped_row_limit);
      EXPECT_EQ(m[i].runs_emitted, r[i].runs_emitted);
      EXPECT_EQ(m[i].runs, r[i].runs);
      EXPECT_EQ(m[i].run_beats, r[i].run_beats);
      EXPECT_EQ(m[i].run_stall_cycles, r[i].run_stall_cycles);
      EXPECT_EQ(m[i].words_read, r[i].words_read);
      EXPECT_EQ(m[i].words_written, r[i].words_written);
      EXPECT_EQ(m[i].configure_cycles, r[i].configure_cycles);
      EXPECT_EQ(m[i].readout_cycles, r[i].readout_cycles);
      EXPECT_EQ(m[i].host_cycles, r[i].host_cycles);
      EXPECT_EQ(m[i].frame_ok, r[i].frame_ok);
      EXPECT_EQ(m[i].pose_status, r[i].pose_status);
      runs_total += r[i].runs;
      stalls_total += r[i].run_stall_cycles;
    }
    const std::vector<std::string> pm = check_profile(m, s), pr = check_profile(r, s);
    EXPECT_TRUE(pm.empty()) << pm.front();
    EXPECT_TRUE(pr.empty()) << pr.front();
  }
  EXPECT_GT(runs_total, 0u);    // the scenarios carry runs ...
  EXPECT_GT(stalls_total, 0u);  // ... that meet back-pressure
}

}  // namespace
}  // namespace ceilnav::app
