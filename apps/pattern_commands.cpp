// `ceilnav pattern`: the built-in station scene (pan, find the code, centre,
// verify) or recorded frames, with the fix CSV and the overlay PNG.
#include "apps/pattern_commands.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "common/csv.hpp"
#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/pattern/pattern.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/frame_io.hpp"
#include "host/pattern/pattern_frame.hpp"
#include "host/pattern/pattern_pose.hpp"
#include "host/pattern/pattern_search.hpp"
#include "host/pattern/world_fix.hpp"
#include "sim/pattern_analysis.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;
namespace gp = golden::pattern;
namespace hp = host::pattern;

namespace {

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

cv::Mat overlay(const cv::Mat& grey, const sim::PatternFrameAnalysis& a,
                const host::CameraModel& model, const std::string& text) {
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

std::string fixed_text(double v, int digits) {
  if (!std::isfinite(v)) return "";
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

}  // namespace

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
  double swing = kNaN;  // deg, eq. 70: from the up the bars measured (ok rows)
};

// One frame's fix: the exact conic pose refined with the bars, the code, the database.
FixRow make_fix(const sim::PatternFrameAnalysis& a, const gp::PatternDatabase& db,
                const Eigen::Vector3d& up_cam, double pan_rad) {
  FixRow r;
  r.code_status = std::string(hp::to_string(a.code.status));
  r.identity = a.code.identity;
  const hp::PatternPose& p = a.conic_bars;  // the conic pose refined with the bar centres
  const bool pose_ok =
      p.status == hp::PatternStatus::ok || p.status == hp::PatternStatus::ambiguous;
  if (p.status == hp::PatternStatus::uncalibrated) {
    r.status = "uncalibrated";  // the frame's photometry failed its calibration
  } else if (p.status == hp::PatternStatus::no_pattern &&
             a.code.status == hp::PatternStatus::no_pattern) {
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
    // Only an ok row carries a pose (docs/pattern.md, "Fix CSV"): every other
    // status leaves D, theta, beta, x, y and heading empty.
    r.status = "ok";
    r.d = p.d_m;
    r.theta = p.theta_rad / kDeg;
    if (p.beta_resolved) r.beta = p.beta_rad / kDeg;
    const gp::PatternPlacement& pl = *db.find(a.code.identity);
    // The world's up as the bars measured it when they refined the pose.
    const hp::WorldFix w =
        hp::world_fix(p, {pl.x_m, pl.y_m, pl.z_m, pl.facing_rad}, p.up_cam.value_or(up_cam));
    r.x = w.x_m;
    r.y = w.y_m;
    r.heading = std::remainder(w.camera_yaw_rad - pan_rad, 2.0 * std::numbers::pi) / kDeg;
    // The camera's swing (eq. 70) where the bars measured the up.
    if (p.up_cam) r.swing = hp::swing_from_up(*p.up_cam) / kDeg;
  }
  return r;
}

void write_fix_csv(const fs::path& path, const std::vector<FixRow>& rows) {
  AtomicFile f(path);
  CsvWriter w(f.stream());
  w.row({"frame", "pan_deg", "status", "identity", "code_status", "d_m", "theta_deg", "beta_deg",
         "x_m", "y_m", "heading_deg", "swing_deg"});
  for (const FixRow& r : rows) {
    w.text(r.frame).fixed(r.pan_deg, 3).text(r.status);
    if (r.identity >= 0) {
      w.integer(r.identity);
    } else {
      w.empty();
    }
    w.text(r.code_status).fixed(r.d, 5).fixed(r.theta, 4).fixed(r.beta, 4);
    w.fixed(r.x, 4).fixed(r.y, 4).fixed(r.heading, 4).fixed(r.swing, 4).end_row();
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

// --overlay-every N > 0: out/overlays/, staged, committed with the other outputs.
std::unique_ptr<OutputFolder> overlay_folder(const PatternOptions& o) {
  if (o.overlay_every <= 0) return nullptr;
  return std::make_unique<OutputFolder>(fs::path(o.out_dir) / "overlays");
}

int run_pattern_frames(const PatternOptions& o) {
  if (o.scene_file.empty() || o.database.empty()) {
    throw std::runtime_error("pattern --frames needs --scene and --database");
  }
  // Only the lens keys are needed; the scene keys (pitch, heights, tape width)
  // may be absent.
  const host::CameraConfig camera =
      host::load_camera_config(o.scene_file, host::ConfigKeys::camera_only);
  const gp::PatternDatabase db = gp::load_pattern_database(o.database);
  const std::vector<fs::path> frames = host::list_png_frames(o.frames_dir);
  make_dir(o.out_dir);
  const host::CameraModel model(camera);
  const gp::Radiometry radiometry;
  drivers::Device device(device_options(o.backend));
  hp::PoseOptions po = sim::pose_options_for(db.geometry);
  // The camera is taken as level with no swing (up = -y) for the start of
  // the pose; where the code is read the bars measure the actual up (tilt and
  // swing) and the fix uses that.
  po.up_cam = Eigen::Vector3d(0.0, -1.0, 0.0);
  std::vector<FixRow> rows;
  cv::Mat last_overlay;
  const std::unique_ptr<OutputFolder> overlays = overlay_folder(o);
  for (const fs::path& f : frames) {
    const cv::Mat grey = host::read_grey_frame(f, camera.image_width, camera.image_height);
    const sim::PatternFrameAnalysis a =
        sim::analyse_pattern_frame(device, grey, radiometry, model, po);
    FixRow r = make_fix(a, db, po.up_cam, 0.0);
    r.frame = f.filename().string();
    if (!o.quiet) std::printf("%s: %s\n", r.frame.c_str(), fix_text(r).c_str());
    last_overlay = overlay(grey, a, model, fix_text(r));
    if (overlays && overlay_due(o.overlay_every, rows.size())) {
      write_png(*overlays, overlay_file_name(r.frame), last_overlay);
    }
    rows.push_back(r);
  }
  if (overlays) overlays->commit();
  write_fix_csv(fs::path(o.out_dir) / "pattern.csv", rows);
  if (!last_overlay.empty()) write_png_file(fs::path(o.out_dir) / "overlay.png", last_overlay);
  return 0;
}

}  // namespace

int run_pattern(const PatternOptions& o) {
  check_overlay_every(o.overlay_every);
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
  drivers::Device device(device_options(o.backend));
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
  const std::unique_ptr<OutputFolder> overlays = overlay_folder(o);
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
    hp::PoseOptions po = sim::pose_options_for(db.geometry);
    po.noise_grey = o.noise_sigma;
    const sim::PatternFrameAnalysis a =
        sim::analyse_pattern_frame(device, grey, radiometry, model, po);
    FixRow r = make_fix(a, db, po.up_cam, pan);
    r.frame = frame_name(static_cast<int>(rows.size()));
    r.pan_deg = pan / kDeg;
    const gp::PatternTruth t = gp::pattern_truth(camera, db.geometry, station.identity, view);
    write_png_file(out / "frames" / r.frame, grey);
    truths.emplace_back(r.frame, t);
    if (!o.quiet) {
      std::printf("%s pan %7.2f: %s\n", r.frame.c_str(), pan / kDeg, fix_text(r).c_str());
    }
    last_overlay = overlay(grey, a, model, fix_text(r));
    if (overlays && overlay_due(o.overlay_every, rows.size())) {
      write_png(*overlays, overlay_file_name(r.frame), last_overlay);
    }
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
  if (overlays) overlays->commit();
  write_fix_csv(out / "pattern.csv", rows);
  {
    AtomicFile f(out / "truth.csv");
    CsvWriter w(f.stream());
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
