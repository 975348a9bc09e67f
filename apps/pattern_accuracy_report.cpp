// `ceilnav pattern-accuracy`'s report: the figures over the study's rows, the
// tables on stdout, the per-frame CSV and the error chart.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "apps/pattern_accuracy.hpp"
#include "apps/plot.hpp"
#include "common/csv.hpp"
#include "sim/pattern_analysis.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMethodNames[kPatternMethods] = {"projection", "moment", "conic",
                                                       "conic+bars"};

// The conic+bars frames behind a row of the table (at least 1).
int frames_at(const std::map<double, std::array<int, 2>>& counts, double key) {
  const auto it = counts.find(key);
  return std::max(1, it == counts.end() ? 0 : it->second[0]);
}

}  // namespace

PatternAccuracyStats summarise_pattern_accuracy(const std::vector<PatternAccuracyRow>& rows,
                                                double radius_m) {
  PatternAccuracyStats st;
  for (const PatternAccuracyRow& r : rows) {
    for (int m = 0; m < kPatternMethods; ++m) {
      if (!r.ok[m] || (m == 0 && !r.seed_set)) continue;
      const auto k = static_cast<std::size_t>(m);
      auto& t = st.by_theta[r.theta];
      t[k] = std::max(t[k], std::abs(r.err[m][1]));
      auto& dd = st.by_d[r.d];
      dd[k] = std::max(dd[k], std::abs(r.err[m][0]));
      if (m == 3) {
        t[4] += r.err[m][1] * r.err[m][1];
        dd[4] += r.err[m][0] * r.err[m][0];
        ++st.counts_theta[r.theta][0];
        ++st.counts_d[r.d][0];
        st.conic_d_max = std::max(st.conic_d_max, std::abs(r.err[m][0]));
        if (r.theta >= 15.0) {
          st.conic_theta_max15 = std::max(st.conic_theta_max15, std::abs(r.err[m][1]));
        }
      }
    }
    if (!r.ok[3]) st.bars_ok = false;
  }
  for (const PatternAccuracyRow& r : rows) {
    if (r.theta < 15.0 || r.d * std::sin(r.theta * kDeg) < 1.5 * radius_m) continue;
    ++st.beta_frames;
    for (int m = 1; m < kPatternMethods; ++m)
      st.beta_resolved[static_cast<std::size_t>(m)] += r.beta_ok[m];
  }
  for (const PatternAccuracyRow& r : rows) {
    if (r.read >= 0 && r.read != r.identity) ++st.wrong;
    if (r.code_visible && r.bar_px >= 1.5) {
      ++st.visible;
      st.visible_read += r.read == r.identity;
    } else if (r.code_visible) {
      ++st.visible_thin;
    }
  }
  return st;
}

void print_pattern_accuracy(const PatternAccuracyOptions& o, size_t frames,
                            const PatternAccuracyStats& st) {
  std::printf(
      "ceilnav pattern-accuracy: %zu frames, %dx%d, noise %.1f, blur %.2f px, %s; host "
      "calibration: noise %.1f, blur %.2f px\n",
      frames, o.width, o.height, o.noise_sigma, o.blur_sigma,
      o.distortion ? "distortion" : "no distortion",
      o.calib_noise_sigma >= 0.0 ? o.calib_noise_sigma : o.noise_sigma,
      o.calib_blur_sigma >= 0.0 ? o.calib_blur_sigma : o.blur_sigma);
  // Table I shape: theta error vs theta (max |error| over D and beta).
  std::printf("\ntheta error (deg) by theta, max |err| over D (projection: beta = +-90 only)\n");
  fmt::print("{:>8} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "theta", "projection", "moment", "conic",
             "conic+bars", "c+b rms");
  for (const auto& [th, v] : st.by_theta) {
    fmt::print("{:8.1f} {:12.3f} {:12.3f} {:12.3f} {:12.3f} {:12.3f}\n", th, v[0], v[1], v[2], v[3],
               std::sqrt(v[4] / frames_at(st.counts_theta, th)));
  }
  std::printf("\ndistance error (%%) by D, max |err| over theta (projection: beta = +-90 only)\n");
  fmt::print("{:>8} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "D (m)", "projection", "moment", "conic",
             "conic+bars", "c+b rms");
  for (const auto& [d, v] : st.by_d) {
    fmt::print("{:8.1f} {:12.3f} {:12.3f} {:12.3f} {:12.3f} {:12.3f}\n", d, v[0], v[1], v[2], v[3],
               std::sqrt(v[4] / frames_at(st.counts_d, d)));
  }
  std::printf(
      "\nbeta right (theta >= 15, D sin(theta) >= 1.5 R): moment %d/%d, conic %d/%d, conic+bars "
      "%d/%d\n",
      st.beta_resolved[1], st.beta_frames, st.beta_resolved[2], st.beta_frames, st.beta_resolved[3],
      st.beta_frames);
  std::printf(
      "bar code: read on %d of %d frames with the code in view and thin bars >= 1.5 px; "
      "%d more in view with thinner bars; wrong identities: %d\n",
      st.visible_read, st.visible, st.visible_thin, st.wrong);
  std::printf(
      "bars (conic+bars): max |D err| %.3f %% (<= 0.3), max |theta err| for theta >= 15: %.3f "
      "deg (<= 0.3); identity: %s -> %s\n",
      st.conic_d_max, st.conic_theta_max15, st.identity_ok() ? "ok" : "FAIL",
      st.pass() ? "PASS" : "FAIL");
}

void write_pattern_accuracy_csv(const fs::path& path, const std::vector<PatternAccuracyRow>& rows) {
  AtomicFile f(path);
  CsvWriter w(f.stream());
  w.row({"d_m",
         "theta_deg",
         "beta_deg",
         "seed_set",
         "identity",
         "read",
         "code_status",
         "code_in_view",
         "min_bar_px",
         "proj_d_err_pct",
         "proj_theta_err_deg",
         "moment_d_err_pct",
         "moment_theta_err_deg",
         "conic_d_err_pct",
         "conic_theta_err_deg",
         "bars_d_err_pct",
         "bars_theta_err_deg",
         "moment_beta_ok",
         "conic_beta_ok",
         "bars_beta_ok"});
  for (const PatternAccuracyRow& r : rows) {
    w.general(r.d, 6).general(r.theta, 6).fixed(r.beta, 3).integer(r.seed_set);
    w.integer(r.identity).integer(r.read).text(r.code_status).integer(r.code_visible);
    w.fixed(r.bar_px, 2);
    for (int m = 0; m < 4; ++m) {
      if (r.ok[m]) {
        w.fixed(r.err[m][0], 4).fixed(r.err[m][1], 4);
      } else {
        w.empty().empty();
      }
    }
    w.integer(r.beta_ok[1]).integer(r.beta_ok[2]).integer(r.beta_ok[3]).end_row();
  }
  f.commit();
}

void plot_pattern_accuracy(const fs::path& png, const PatternAccuracyStats& stats,
                           const host::CameraConfig& camera,
                           const golden::pattern::PatternGeometry& geometry) {
  const auto& by_theta = stats.by_theta;
  const auto& by_d = stats.by_d;
  const char* const* names = kMethodNames;
  // Seed Table I (greatest absolute error, deg) and Table II (percent).
  const std::vector<double> t1x{0, 7.5, 15, 22.5, 30, 37.5, 45, 52.5, 60, 67.5, 75};
  const std::vector<double> t1y{0.31, 7.32, 2.94, 1.39, 0.47, 2.15, 0.52, 1.48, 0.84, 1.62, 1.90};
  const std::vector<double> t2x{1, 2, 3, 4, 5}, t2y{2, 0.5, 0.33, 1.78, 2.2};
  PlotPanel pt{
      "theta error vs theta (max over D = 1..5 m)", "theta (deg)", "|theta error| (deg)", {}, true};
  PlotPanel pd{
      "distance error vs D (max over theta = 0..75 deg)", "D (m)", "|D error| (%)", {}, true};
  const cv::Scalar colours[4] = {{0, 140, 255}, {200, 80, 0}, {0, 160, 0}, {160, 0, 160}};
  for (int m = 0; m < 4; ++m) {
    PlotSeries st{names[m], {}, {}, colours[m]}, sd{names[m], {}, {}, colours[m]};
    for (auto& [th, v] : by_theta) {
      st.x.push_back(th);
      st.y.push_back(v[static_cast<std::size_t>(m)]);
    }
    for (auto& [d, v] : by_d) {
      sd.x.push_back(d);
      sd.y.push_back(v[static_cast<std::size_t>(m)]);
    }
    pt.series.push_back(st);
    pd.series.push_back(sd);
  }
  pt.series.push_back({"seed Table I (greatest)", t1x, t1y, {0, 0, 200}});
  pd.series.push_back({"seed Table II", t2x, t2y, {0, 0, 200}});
  // Seed eq. 48 / 55 with k = 1 for this camera at D = 5 m (projection method).
  PlotSeries m48{"seed eq. 48, k = 1", {}, {}, {120, 120, 120}};
  for (double d = 1.0; d <= 5.0; d += 0.5) {
    m48.x.push_back(d);
    m48.y.push_back(100.0 * d * (1.0 / camera.fy()) / (2.0 * geometry.radius_m));
  }
  pd.series.push_back(m48);
  PlotSeries m55{"seed eq. 55, k = 1, D = 5 m", {}, {}, {120, 120, 120}};
  const double nb = 2.0 * camera.fy() * geometry.radius_m / 5.0;
  for (double th = 0; th <= 75.0; th += 2.5) {
    const double na = nb * std::cos(th * kDeg);
    const double worst =
        std::max(std::abs(th - std::acos(std::min(1.0, (na + 1) / (nb - 1))) / kDeg),
                 std::abs(th - std::acos(std::min(1.0, (na - 1) / (nb + 1))) / kDeg));
    m55.x.push_back(th);
    m55.y.push_back(worst);
  }
  pt.series.push_back(m55);
  write_plots(png, {pt, pd});  // with its .dat and .gp beside it
}

}  // namespace ceilnav::app
