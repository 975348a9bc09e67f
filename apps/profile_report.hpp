// `ceilnav profile`'s report: the statistics over a run's frames, the
// frame and summary CSVs, the text summary and the charts.
#pragma once

#include <algorithm>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "apps/profile.hpp"
#include "common/csv.hpp"

namespace ceilnav::app {

// One profiled run: a scenario, its frames and the violated rules (check_profile).
struct ProfileSummary {
  std::string name;
  ProfileScenario s;
  std::vector<FrameProfile> frames;
  std::vector<std::string> problems;
};

// Statistics of get(frame) over frames; 0 for no frames.
template <typename F>
double mean_of(const std::vector<FrameProfile>& v, F get) {
  double sum = 0.0;
  for (const auto& f : v) sum += static_cast<double>(get(f));
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}
template <typename F>
double max_of(const std::vector<FrameProfile>& v, F get) {
  double m = v.empty() ? 0.0 : -std::numeric_limits<double>::infinity();
  for (const auto& f : v) m = std::max(m, static_cast<double>(get(f)));
  return m;
}
template <typename F>
double min_of(const std::vector<FrameProfile>& v, F get) {
  double m = v.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (const auto& f : v) m = std::min(m, static_cast<double>(get(f)));
  return m;
}
template <typename F>
double median_of(const std::vector<FrameProfile>& v, F get) {
  std::vector<double> x;
  for (const auto& f : v) x.push_back(static_cast<double>(get(f)));
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  return n % 2 == 1 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}
template <typename F>
double sum_of(const std::vector<FrameProfile>& v, F get) {
  double sum = 0.0;
  for (const auto& f : v) sum += static_cast<double>(get(f));
  return sum;
}

void write_frame_header(CsvWriter& w);
void write_frame_row(CsvWriter& w, size_t i, const FrameProfile& f);
void write_summary_header(CsvWriter& w);
void write_summary_row(CsvWriter& w, const ProfileSummary& m, const std::string& backend);

// The text summary of a run on stdout.
void print_summary(const ProfileSummary& m, const std::string& backend);
// The back-pressure sweep's table on stdout, each violation on stderr; returns
// the number of violations.
size_t print_sweep(const std::vector<ProfileSummary>& sweep, int frames_per_point);

// latency.png and fifo.png of the main run, throughput.png of the sweep (if any), in `dir`.
void write_profile_plots(const std::filesystem::path& dir, const ProfileSummary& main_run,
                         const std::vector<ProfileSummary>& sweep);

}  // namespace ceilnav::app
