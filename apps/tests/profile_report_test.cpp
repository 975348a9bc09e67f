// `ceilnav profile`'s report on hand-made frames: the statistics over frames
// and the summary CSV row built from them.
#include "apps/profile_report.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

namespace ceilnav::app {
namespace {

FrameProfile frame(uint64_t cycles, int64_t irq, uint32_t high_water, double driver_us) {
  FrameProfile f;
  f.cycles = cycles;
  f.tvalid_cycles = cycles;
  f.accepted = cycles;
  f.eof_to_irq_cycles = irq;
  f.fifo_high_water = high_water;
  f.host_driver_us = driver_us;
  return f;
}

TEST(ProfileReport, StatisticsOverFrames) {
  const std::vector<FrameProfile> v{frame(10, 7, 3, 5.0), frame(30, 9, 1, 1.0),
                                    frame(20, 8, 2, 9.0), frame(40, 6, 4, 2.0)};
  const auto cycles = [](const FrameProfile& f) { return f.cycles; };
  EXPECT_DOUBLE_EQ(mean_of(v, cycles), 25.0);
  EXPECT_DOUBLE_EQ(sum_of(v, cycles), 100.0);
  EXPECT_DOUBLE_EQ(min_of(v, [](const FrameProfile& f) { return f.eof_to_irq_cycles; }), 6.0);
  EXPECT_DOUBLE_EQ(max_of(v, [](const FrameProfile& f) { return f.fifo_high_water; }), 4.0);
  // Even count: the mean of the middle two; odd: the middle one.
  EXPECT_DOUBLE_EQ(median_of(v, [](const FrameProfile& f) { return f.host_driver_us; }), 3.5);
  const std::vector<FrameProfile> odd(v.begin(), v.begin() + 3);
  EXPECT_DOUBLE_EQ(median_of(odd, [](const FrameProfile& f) { return f.host_driver_us; }), 5.0);
}

TEST(ProfileReport, NoFramesGiveZeros) {
  const std::vector<FrameProfile> none;
  const auto cycles = [](const FrameProfile& f) { return f.cycles; };
  EXPECT_EQ(mean_of(none, cycles), 0.0);
  EXPECT_EQ(min_of(none, cycles), 0.0);
  EXPECT_EQ(max_of(none, cycles), 0.0);
  EXPECT_EQ(median_of(none, cycles), 0.0);
  EXPECT_EQ(sum_of(none, cycles), 0.0);
}

TEST(ProfileReport, SummaryRowMatchesItsHeader) {
  ProfileSummary m;
  m.name = "scenario";
  m.s.width = 8;
  m.s.height = 4;
  m.s.blanking = Blanking::random;
  m.s.gap_probability = 0.25;
  m.s.backpressure = 0.5;
  m.frames = {frame(32, 12, 3, 5.0), frame(40, 14, 5, 7.0)};
  m.frames[1].accepted = 30;  // II 0.75 on the second frame
  m.problems = {"one"};
  std::ostringstream out;
  CsvWriter w(out);
  write_summary_header(w);
  write_summary_row(w, m, "model");
  std::istringstream lines(out.str());
  std::string header, row;
  std::getline(lines, header);
  std::getline(lines, row);
  const auto fields = [](const std::string& s) {
    std::vector<std::string> f;
    std::istringstream in(s);
    for (std::string x; std::getline(in, x, ',');) f.push_back(x);
    return f;
  };
  const std::vector<std::string> h = fields(header), r = fields(row);
  ASSERT_EQ(h.size(), r.size());
  const auto at = [&](const std::string& name) {
    for (size_t i = 0; i < h.size(); ++i) {
      if (h[i] == name) return r[i];
    }
    return std::string("(no column)");
  };
  EXPECT_EQ(at("scenario"), "scenario");
  EXPECT_EQ(at("backend"), "model");
  EXPECT_EQ(at("blanking"), "random");
  EXPECT_EQ(at("gap_probability"), "0.250");
  EXPECT_EQ(at("frames"), "2");
  EXPECT_EQ(at("cycles_min"), "32");
  EXPECT_EQ(at("cycles_max"), "40");
  EXPECT_EQ(at("pixels_per_valid_cycle_min"), "0.750000");
  EXPECT_EQ(at("eof_to_irq_min"), "12");
  EXPECT_EQ(at("eof_to_irq_max"), "14");
  EXPECT_EQ(at("fifo_high_water_max"), "5");
  EXPECT_EQ(at("vertical_blanking_cycles"), std::to_string(kMinFrameBlankingCycles));
  EXPECT_EQ(at("host_driver_us_median"), "6.0");
  EXPECT_EQ(at("violations"), "1");
}

}  // namespace
}  // namespace ceilnav::app
