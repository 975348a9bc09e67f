#include "apps/pattern_commands.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Eigenvalues>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "apps/plot.hpp"
#include "golden/default_scene.hpp"
#include "golden/pattern/pattern.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/csv.hpp"
#include "host/device.hpp"
#include "host/frame_io.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/pattern_pose.hpp"
#include "host/pattern/pattern_search.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;
namespace gp = golden::pattern;
namespace hp = host::pattern;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// What the device and the host make of one frame.
struct Analysis : hp::PatternAnalysis {
  hp::FrameMoments moments{};
  std::vector<stream::RunRecord> runs;
};

// The frame streams through the device (class LUT, run mask of bars and
// disc, whole-frame class window); the host works on its class moments and
// run records (host::pattern::analyse_pattern).
Analysis analyse(host::Device& device, const cv::Mat& grey, const gp::Radiometry& radiometry,
                 const host::CameraModel& model, const hp::PoseOptions& pose_options) {
  Analysis a;
  uint64_t cycles = 0;
  const stream::FrameResults res =
      device.process(grey, gp::device_config(grey.cols, grey.rows, radiometry), a.runs, cycles);
  if (!res.valid) throw std::runtime_error("pattern: the device rejected the frame");
  a.moments = hp::device_moments(res.class_moments);
  hp::BarcodeOptions bo;
  bo.bar_contrast =
      radiometry.level(gp::PixelClass::background) - radiometry.level(gp::PixelClass::bar);
  bo.radius_m = pose_options.radius_m;
  bo.min_bar_run_weight = gp::bar_run_min_weight(radiometry);
  static_cast<hp::PatternAnalysis&>(a) = hp::analyse_pattern(
      a.runs, a.moments, model, grey.cols, grey.rows, pose_options, bo,
      gp::disc_coverage_model(radiometry, pose_options.noise_grey, pose_options.psf_sigma_px,
                              pose_options.blur_on_pixels));
  return a;
}

hp::PoseOptions pose_options_for(const gp::PatternGeometry& g) {
  hp::PoseOptions o;
  o.radius_m = g.radius_m;
  o.thickness_m = g.thickness_m;
  o.rim_m = g.rim_m;
  return o;
}

void write_png_file(const fs::path& path, const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", image, bytes)) {
    throw std::runtime_error("cannot encode PNG for '" + path.string() + "'");
  }
  AtomicFile f(path);
  f.stream().write(reinterpret_cast<const char*>(bytes.data()),
                   static_cast<std::streamsize>(bytes.size()));
  f.commit();
}

// The fitted ellipse (normalised) drawn through the lens model.
void draw_ellipse(cv::Mat& bgr, const hp::Ellipse& e, const host::CameraModel& model,
                  const cv::Scalar& colour) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(e.cov);
  std::vector<cv::Point> pts;
  for (int k = 0; k <= 180; ++k) {
    const double t = 2.0 * std::numbers::pi * k / 180.0;
    const Eigen::Vector2d p =
        Eigen::Vector2d(e.cx, e.cy) +
        2.0 * std::sqrt(es.eigenvalues()(1)) * std::cos(t) * es.eigenvectors().col(1) +
        2.0 * std::sqrt(es.eigenvalues()(0)) * std::sin(t) * es.eigenvectors().col(0);
    const Eigen::Vector2d px = model.distort_to_pixel(p);
    if (px.allFinite()) {
      pts.emplace_back(static_cast<int>(std::lround(px.x() * 16)),
                       static_cast<int>(std::lround(px.y() * 16)));
    }
  }
  if (pts.size() > 2) cv::polylines(bgr, pts, true, colour, 1, cv::LINE_AA, 4);
}

cv::Mat overlay(const cv::Mat& grey, const Analysis& a, const host::CameraModel& model,
                const std::string& text) {
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  for (const auto& r : hp::split_disc_runs(a.runs, a.moments[hp::kDisc]).second) {
    cv::line(bgr, {r.x_start, r.row}, {r.x_end, r.row}, cv::Scalar(0, 160, 0), 1);
  }
  if (a.conic.status != hp::PatternStatus::no_pattern &&
      a.conic.status != hp::PatternStatus::degenerate) {
    draw_ellipse(bgr, a.conic.ellipse, model, cv::Scalar(0, 220, 255));
  }
  cv::putText(bgr, text, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 255), 1,
              cv::LINE_AA);
  return bgr;
}

std::string frame_name_png(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%04d.png", i);
  return buf;
}

std::string fixed_text(double v, int digits) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

// ---------------------------------------------------------------- accuracy

namespace {

// One frame of the pattern-accuracy study.
struct Row {
  double d, theta, beta;
  bool seed_set;     // beta = +-90 deg (the seed's experiments)
  double err[4][2];  // method (projection, moment, conic) x (D %, theta deg)
  bool ok[4];
  bool beta_ok[4];
  bool code_visible;
  double bar_px;
  int identity, read;
  std::string code_status;
};

// The study's per-frame CSV: one row per rendered frame, the errors of each
// method (empty where it found no pose) and whether beta came out right.
void write_accuracy_csv(const fs::path& path, const std::vector<Row>& rows) {
  AtomicFile f(path);
  host::CsvWriter w(f.stream());
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
  for (const Row& r : rows) {
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

}  // namespace

int run_pattern_accuracy(const PatternAccuracyOptions& o) {
  if (!o.csv.empty()) check_writable(o.csv);
  if (!o.plot.empty()) check_writable(o.plot);
  const host::CameraConfig camera = scaled_camera(o.width, o.height, o.distortion);
  const host::CameraModel model(camera);
  const gp::PatternGeometry geometry;
  const gp::Radiometry radiometry;
  host::Device device(device_options(o.backend));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const std::vector<double> distances{1.0, 1.5, 2.0, 3.0, 4.0, 5.0};
  std::vector<double> thetas;
  for (int k = 0; k <= 10; ++k) thetas.push_back(7.5 * k);  // the seed's Table I

  std::vector<Row> rows;
  int frame = 0;
  uint64_t frame_seed = 0;
  for (double d : distances) {
    for (double th : thetas) {
      for (int b = 0; b <= o.betas; ++b) {
        Row r{};
        r.d = d;
        r.theta = th;
        r.seed_set = b == 0;
        r.beta = b == 0 ? ((frame / 3) % 2 == 0 ? 90.0 : -90.0) : 360.0 * u01(rng) - 180.0;
        r.identity = static_cast<int>(rng() % gp::kIdentityCount);
        const gp::PatternView v = gp::spherical_view(d, th * kDeg, r.beta * kDeg);
        gp::PatternRenderParams p;
        p.noise_sigma_grey = o.noise_sigma;
        p.blur_sigma_px = o.blur_sigma;
        p.noise_seed = o.seed * 1000003U + frame_seed++;
        p.supersample = o.supersample;
        const cv::Mat grey = gp::render_pattern(camera, geometry, radiometry, r.identity, v, p);
        const gp::PatternTruth t = gp::pattern_truth(camera, geometry, r.identity, v);
        hp::PoseOptions po = pose_options_for(geometry);
        po.up_cam = v.rotation.col(1);  // the mount's known tilt (docs/pattern.md)
        // The camera's blur and noise (calibrated, not per frame).
        po.psf_sigma_px = o.calib_blur_sigma >= 0.0 ? o.calib_blur_sigma : o.blur_sigma;
        po.noise_grey = o.calib_noise_sigma >= 0.0 ? o.calib_noise_sigma : o.noise_sigma;
        const Analysis a = analyse(device, grey, radiometry, model, po);
        const hp::PatternPose* poses[4] = {&a.projection, &a.moment, &a.conic, &a.conic_bars};
        for (int m = 0; m < 4; ++m) {
          const hp::PatternPose& q = *poses[m];
          r.ok[m] =
              (q.status == hp::PatternStatus::ok || q.status == hp::PatternStatus::ambiguous) &&
              t.disc_in_view;
          r.err[m][0] = 100.0 * (q.d_m - d) / d;
          r.err[m][1] = q.theta_rad / kDeg - th;
          r.beta_ok[m] =
              q.beta_resolved && std::abs(std::remainder(q.beta_rad / kDeg - r.beta, 360.0)) < 5.0;
        }
        r.code_visible = t.code_in_view;
        r.bar_px = t.min_bar_width_px;
        r.read = a.code.identity;
        r.code_status = std::string(hp::to_string(a.code.status));
        rows.push_back(r);
        ++frame;
      }
    }
  }

  const char* names[4] = {"projection", "moment", "conic", "conic+bars"};
  std::printf(
      "ceilnav pattern-accuracy: %zu frames, %dx%d, noise %.1f, blur %.2f px, %s; host "
      "calibration: noise %.1f, blur %.2f px\n",
      rows.size(), o.width, o.height, o.noise_sigma, o.blur_sigma,
      o.distortion ? "distortion" : "no distortion",
      o.calib_noise_sigma >= 0.0 ? o.calib_noise_sigma : o.noise_sigma,
      o.calib_blur_sigma >= 0.0 ? o.calib_blur_sigma : o.blur_sigma);
  // Table I shape: theta error vs theta (max |error| over D and beta).
  std::printf("\ntheta error (deg) by theta, max |err| over D (projection: beta = +-90 only)\n");
  fmt::print("{:>8} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "theta", "projection", "moment", "conic",
             "conic+bars", "c+b rms");
  std::map<double, std::array<double, 5>> by_theta;
  std::map<double, std::array<double, 5>> by_d;
  std::map<double, std::array<int, 2>> counts_theta, counts_d;
  bool bars_ok = true;
  double conic_d_max = 0, conic_theta_max15 = 0;
  for (const Row& r : rows) {
    for (int m = 0; m < 4; ++m) {
      if (!r.ok[m] || (m == 0 && !r.seed_set)) continue;
      auto& t = by_theta[r.theta];
      t[static_cast<std::size_t>(m)] =
          std::max(t[static_cast<std::size_t>(m)], std::abs(r.err[m][1]));
      auto& dd = by_d[r.d];
      dd[static_cast<std::size_t>(m)] =
          std::max(dd[static_cast<std::size_t>(m)], std::abs(r.err[m][0]));
      if (m == 3) {
        t[4] += r.err[m][1] * r.err[m][1];
        dd[4] += r.err[m][0] * r.err[m][0];
        ++counts_theta[r.theta][0];
        ++counts_d[r.d][0];
        conic_d_max = std::max(conic_d_max, std::abs(r.err[m][0]));
        if (r.theta >= 15.0) conic_theta_max15 = std::max(conic_theta_max15, std::abs(r.err[m][1]));
      }
    }
    if (!r.ok[3]) bars_ok = false;
  }
  for (auto& [th, v] : by_theta) {
    fmt::print("{:8.1f} {:12.3f} {:12.3f} {:12.3f} {:12.3f} {:12.3f}\n", th, v[0], v[1], v[2], v[3],
               std::sqrt(v[4] / std::max(1, counts_theta[th][0])));
  }
  std::printf("\ndistance error (%%) by D, max |err| over theta (projection: beta = +-90 only)\n");
  fmt::print("{:>8} {:>12} {:>12} {:>12} {:>12} {:>12}\n", "D (m)", "projection", "moment", "conic",
             "conic+bars", "c+b rms");
  for (auto& [d, v] : by_d) {
    fmt::print("{:8.1f} {:12.3f} {:12.3f} {:12.3f} {:12.3f} {:12.3f}\n", d, v[0], v[1], v[2], v[3],
               std::sqrt(v[4] / std::max(1, counts_d[d][0])));
  }
  int beta_frames = 0, beta_resolved[4] = {0, 0, 0, 0};
  for (const Row& r : rows) {
    if (r.theta < 15.0 || r.d * std::sin(r.theta * kDeg) < 1.5 * geometry.radius_m) continue;
    ++beta_frames;
    for (int m = 1; m < 4; ++m) beta_resolved[m] += r.beta_ok[m];
  }
  int visible = 0, visible_read = 0, wrong = 0, visible_thin = 0;
  for (const Row& r : rows) {
    if (r.read >= 0 && r.read != r.identity) ++wrong;
    if (r.code_visible && r.bar_px >= 1.5) {
      ++visible;
      visible_read += r.read == r.identity;
    } else if (r.code_visible) {
      ++visible_thin;
    }
  }
  std::printf(
      "\nbeta right (theta >= 15, D sin(theta) >= 1.5 R): moment %d/%d, conic %d/%d, conic+bars "
      "%d/%d\n",
      beta_resolved[1], beta_frames, beta_resolved[2], beta_frames, beta_resolved[3], beta_frames);
  std::printf(
      "bar code: read on %d of %d frames with the code in view and thin bars >= 1.5 px; "
      "%d more in view with thinner bars; wrong identities: %d\n",
      visible_read, visible, visible_thin, wrong);
  const bool pass = bars_ok && conic_d_max <= 0.3 && conic_theta_max15 <= 0.3 && wrong == 0 &&
                    visible_read == visible;
  std::printf(
      "bars (conic+bars): max |D err| %.3f %% (<= 0.3), max |theta err| for theta >= 15: %.3f "
      "deg (<= 0.3); identity: %s -> %s\n",
      conic_d_max, conic_theta_max15, (wrong == 0 && visible_read == visible) ? "ok" : "FAIL",
      pass ? "PASS" : "FAIL");

  if (!o.csv.empty()) write_accuracy_csv(o.csv, rows);
  if (!o.plot.empty()) {
    // Seed Table I (greatest absolute error, deg) and Table II (percent).
    const std::vector<double> t1x{0, 7.5, 15, 22.5, 30, 37.5, 45, 52.5, 60, 67.5, 75};
    const std::vector<double> t1y{0.31, 7.32, 2.94, 1.39, 0.47, 2.15, 0.52, 1.48, 0.84, 1.62, 1.90};
    const std::vector<double> t2x{1, 2, 3, 4, 5}, t2y{2, 0.5, 0.33, 1.78, 2.2};
    PlotPanel pt{"theta error vs theta (max over D = 1..5 m)",
                 "theta (deg)",
                 "|theta error| (deg)",
                 {},
                 true};
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
    write_plots(o.plot, {pt, pd});  // with its .dat and .gp beside it
  }
  return (o.require && !pass) ? 1 : 0;
}

// ---------------------------------------------------------------- pattern

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct FixRow {
  std::string frame;
  double pan_deg = kNaN;
  std::string status;
  int identity = -1;
  std::string code_status;
  double d = kNaN, theta = kNaN, beta = kNaN;
  double x = kNaN, y = kNaN, heading = kNaN;
};

// One frame's fix: the exact conic pose refined with the bars, the code, the database.
FixRow make_fix(const Analysis& a, const gp::PatternDatabase& db, const Eigen::Vector3d& up_cam,
                double pan_rad) {
  FixRow r;
  r.code_status = std::string(hp::to_string(a.code.status));
  r.identity = a.code.identity;
  const hp::PatternPose& p = a.conic_bars;  // the conic pose refined with the bar centres
  const bool pose_ok =
      p.status == hp::PatternStatus::ok || p.status == hp::PatternStatus::ambiguous;
  if (pose_ok) {
    r.d = p.d_m;
    r.theta = p.theta_rad / kDeg;
    if (p.beta_resolved) r.beta = p.beta_rad / kDeg;
  }
  if (p.status == hp::PatternStatus::no_pattern && a.code.status == hp::PatternStatus::no_pattern) {
    r.status = "no_pattern";
  } else if (a.code.status == hp::PatternStatus::unreadable) {
    r.status = "unreadable";
  } else if (a.code.status != hp::PatternStatus::ok || !pose_ok) {
    r.status = "partial";
  } else if (db.find(a.code.identity) == nullptr) {
    r.status = "unknown_pattern";
  } else if (p.status == hp::PatternStatus::ambiguous) {
    r.status = "ambiguous";
  } else {
    r.status = "ok";
    const gp::PatternPlacement& pl = *db.find(a.code.identity);
    // The world's up as the bars measured it when they refined the pose.
    const hp::WorldFix w =
        hp::world_fix(p, {pl.x_m, pl.y_m, pl.z_m, pl.facing_rad}, p.up_cam.value_or(up_cam));
    r.x = w.x_m;
    r.y = w.y_m;
    r.heading = std::remainder(w.camera_yaw_rad - pan_rad, 2.0 * std::numbers::pi) / kDeg;
  }
  return r;
}

void write_fix_csv(const fs::path& path, const std::vector<FixRow>& rows) {
  AtomicFile f(path);
  host::CsvWriter w(f.stream());
  w.row({"frame", "pan_deg", "status", "identity", "code_status", "d_m", "theta_deg", "beta_deg",
         "x_m", "y_m", "heading_deg"});
  for (const FixRow& r : rows) {
    w.text(r.frame).fixed(r.pan_deg, 3).text(r.status);
    if (r.identity >= 0) {
      w.integer(r.identity);
    } else {
      w.empty();
    }
    w.text(r.code_status).fixed(r.d, 5).fixed(r.theta, 4).fixed(r.beta, 4);
    w.fixed(r.x, 4).fixed(r.y, 4).fixed(r.heading, 4).end_row();
  }
  f.commit();
}

std::string fix_text(const FixRow& r) {
  std::ostringstream s;
  s << r.status;
  if (r.identity >= 0) s << " id " << r.identity;
  if (std::isfinite(r.d))
    s << "  D " << fixed_text(r.d, 3) << " m  theta " << fixed_text(r.theta, 2);
  if (std::isfinite(r.beta)) s << "  beta " << fixed_text(r.beta, 1);
  if (std::isfinite(r.x)) {
    s << "  x " << fixed_text(r.x, 3) << " y " << fixed_text(r.y, 3) << " heading "
      << fixed_text(r.heading, 2);
  }
  return s.str();
}

void make_dir(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw std::runtime_error("cannot create output folder '" + dir.string() + "'");
  }
  check_writable(dir / "probe");
}

int run_pattern_frames(const PatternOptions& o) {
  if (o.scene_file.empty() || o.database.empty()) {
    throw std::runtime_error("pattern --frames needs --scene and --database");
  }
  const host::CameraConfig camera = host::load_camera_config(o.scene_file);
  const gp::PatternDatabase db = gp::load_pattern_database(o.database);
  const std::vector<fs::path> frames = host::list_png_frames(o.frames_dir);
  make_dir(o.out_dir);
  const host::CameraModel model(camera);
  const gp::Radiometry radiometry;
  host::Device device(device_options(o.backend));
  hp::PoseOptions po = pose_options_for(db.geometry);
  // The camera is taken as level with no swing (up = -y) for the start of
  // the pose; where the code is read the bars measure the actual up (tilt and
  // swing) and the fix uses that. The scene's ceiling keys (camera_pitch_deg,
  // heights, tape width) are not used here.
  po.up_cam = Eigen::Vector3d(0.0, -1.0, 0.0);
  std::vector<FixRow> rows;
  cv::Mat last_overlay;
  for (const fs::path& f : frames) {
    const cv::Mat grey = host::read_grey_frame(f, camera.image_width, camera.image_height);
    const Analysis a = analyse(device, grey, radiometry, model, po);
    FixRow r = make_fix(a, db, po.up_cam, 0.0);
    r.frame = f.filename().string();
    if (!o.quiet) std::printf("%s: %s\n", r.frame.c_str(), fix_text(r).c_str());
    last_overlay = overlay(grey, a, model, fix_text(r));
    rows.push_back(r);
  }
  write_fix_csv(fs::path(o.out_dir) / "pattern.csv", rows);
  if (!last_overlay.empty()) write_png_file(fs::path(o.out_dir) / "overlay.png", last_overlay);
  return 0;
}

}  // namespace

int run_pattern(const PatternOptions& o) {
  if (!o.frames_dir.empty()) return run_pattern_frames(o);
  if (!o.scene_file.empty() || !o.database.empty()) {
    throw std::runtime_error("pattern: --scene and --database go with --frames");
  }
  // Built-in scene: a station with pattern 7 on a wall facing -X; the robot's
  // trajectory ends 3 m before it, 0.6 m off the pattern's axis, its camera
  // (level, 1.1 m high) panned 70 deg away. It pans at 90 % of the seed's
  // maximum rate (eq. 34-37) until a code is seen, centres the disc, verifies.
  // The camera of the ceiling demo, level here (its pitch key is not used).
  const host::CameraConfig camera = golden::default_camera();
  const host::CameraModel model(camera);
  gp::PatternDatabase db;
  db.patterns = {{7, 6.0, 0.0, 1.25, 180 * kDeg},
                 {23, 0.0, 5.0, 1.25, -90 * kDeg},
                 {41, -3.0, -4.0, 1.25, 60 * kDeg}};
  const gp::PatternPlacement station = db.patterns[0];
  const gp::Radiometry radiometry;
  host::Device device(device_options(o.backend));
  const fs::path out(o.out_dir);
  make_dir(out);
  make_dir(out / "frames");
  gp::save_pattern_database((out / "patterns.yaml").string(), db);
  host::save_camera_config(camera, (out / "scene.yaml").string());

  const double robot_x = 3.0, robot_y = 0.6, robot_heading = 4.0 * kDeg, height = 1.1;
  const double fov = 2.0 * std::atan(0.5 * camera.image_width / camera.fx());
  const hp::ScanParams scan{fov, 30.0, -gp::block_outer_x_m(db.geometry), 2.0, 0.0};
  const double step = 0.9 * hp::max_pan_rate(scan) / scan.video_rate_hz;  // rad per frame
  std::printf(
      "ceilnav pattern: fov %.1f deg, pattern angle at 2 m %.1f deg (eq. 34), max pan %.1f "
      "deg/s at 30 Hz (eq. 35); panning %.1f deg per frame\n",
      fov / kDeg, hp::pattern_angle_rad(scan) / kDeg, hp::max_pan_rate(scan) / kDeg, step / kDeg);
  double pan = -70.0 * kDeg;
  std::vector<FixRow> rows;
  std::vector<std::pair<std::string, gp::PatternTruth>> truths;
  cv::Mat last_overlay;
  int centring = 0;
  bool verified = false;
  FixRow final_row;
  gp::PatternTruth final_truth{};
  for (int k = 0; k < 60 && !verified; ++k) {
    const gp::RobotCamera cam{robot_x, robot_y, height, robot_heading + pan, 0.0, 0.0};
    const gp::PatternView view = gp::robot_view(station, cam);
    gp::PatternRenderParams rp;
    rp.noise_sigma_grey = o.noise_sigma;
    rp.noise_seed = o.seed * 7919U + static_cast<uint64_t>(rows.size());
    cv::Mat grey;
    const Eigen::Vector3d forward = view.rotation.row(2).transpose();
    if (forward.z() < 0.0) {  // looking toward the wall
      grey = gp::render_pattern(camera, db.geometry, radiometry, station.identity, view, rp);
    } else {  // facing away from the wall: the surroundings only
      grey = cv::Mat(camera.image_height, camera.image_width, CV_8UC1,
                     cv::Scalar(radiometry.level(gp::PixelClass::background)));
    }
    hp::PoseOptions po = pose_options_for(db.geometry);
    po.noise_grey = o.noise_sigma;
    const Analysis a = analyse(device, grey, radiometry, model, po);
    FixRow r = make_fix(a, db, po.up_cam, pan);
    r.frame = frame_name_png(static_cast<int>(rows.size()));
    r.pan_deg = pan / kDeg;
    const gp::PatternTruth t = gp::pattern_truth(camera, db.geometry, station.identity, view);
    write_png_file(out / "frames" / r.frame, grey);
    truths.emplace_back(r.frame, t);
    if (!o.quiet) {
      std::printf("%s pan %7.2f: %s\n", r.frame.c_str(), pan / kDeg, fix_text(r).c_str());
    }
    last_overlay = overlay(grey, a, model, fix_text(r));
    rows.push_back(r);
    // Control: pan on until a code is seen; then turn toward the disc.
    const bool disc_seen =
        a.conic.status == hp::PatternStatus::ok || a.conic.status == hp::PatternStatus::ambiguous;
    // Bearing of the disc centre from the optical axis (camera x right).
    const double bearing =
        disc_seen ? std::atan2(a.conic.centre_cam.x(), a.conic.centre_cam.z()) : 0.0;
    if (a.code.status == hp::PatternStatus::ok && a.code.identity != station.identity) {
      pan += step;  // another pattern: search on
    } else if (disc_seen && a.code.status == hp::PatternStatus::ok) {
      if (std::abs(bearing) < 0.5 * kDeg || centring >= 4) {
        verified = r.status == "ok";
        final_row = r;
        final_truth = t;
      }
      pan -= bearing;  // yaw is CCW: a disc to the right needs a smaller yaw
      ++centring;
    } else if (a.code.status == hp::PatternStatus::partial && a.code.disc_direction != 0) {
      pan -= 0.25 * fov * a.code.disc_direction;
    } else if (disc_seen) {
      pan -= bearing;
    } else {
      pan += step;
    }
  }
  write_fix_csv(out / "pattern.csv", rows);
  {
    AtomicFile f(out / "truth.csv");
    host::CsvWriter w(f.stream());
    w.row({"frame", "d_m", "theta_deg", "beta_deg", "identity", "disc_in_view", "code_in_view"});
    for (const auto& [name, t] : truths) {
      w.text(name).fixed(t.d_m, 5).fixed(t.theta_rad / kDeg, 4).fixed(t.beta_rad / kDeg, 4);
      w.integer(t.identity).integer(t.disc_in_view).integer(t.code_in_view).end_row();
    }
    f.commit();
  }
  if (!last_overlay.empty()) write_png_file(out / "overlay.png", last_overlay);
  if (!verified) {
    std::printf("ceilnav pattern: station %d NOT verified after %zu frames\n", station.identity,
                rows.size());
    return 1;
  }
  std::printf(
      "ceilnav pattern: station %d verified after %zu frames: D %.4f m (truth %.4f), theta %.3f "
      "deg (truth %.3f), robot x %.4f y %.4f heading %.3f deg (truth %.4f %.4f %.3f) -> %s\n",
      station.identity, rows.size(), final_row.d, final_truth.d_m, final_row.theta,
      final_truth.theta_rad / kDeg, final_row.x, final_row.y, final_row.heading, robot_x, robot_y,
      robot_heading / kDeg, out.string().c_str());
  return 0;
}

}  // namespace ceilnav::app
