#include "golden/scene.hpp"

#include "common/csv.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <system_error>

namespace ceilnav::golden {

CeilingScene corridor_scene(double tape_width_m, const CorridorOptions& options) {
  if (!(tape_width_m > 0.0)) throw std::invalid_argument("corridor_scene: tape width must be > 0");
  if (!(options.x_end_m > options.x_start_m)) {
    throw std::invalid_argument("corridor_scene: x_end_m must exceed x_start_m");
  }
  std::vector<std::pair<double, double>> gaps = options.gaps_m;
  std::sort(gaps.begin(), gaps.end());
  CeilingScene scene;
  scene.reference_y_m = options.reference_y_m;
  const double y = options.reference_y_m;
  double x = options.x_start_m;
  for (const auto& [gap_start, gap_end] : gaps) {
    if (!(gap_end > gap_start) || gap_start <= x || gap_end >= options.x_end_m) {
      throw std::invalid_argument("corridor_scene: gaps must be ordered, non-empty and inside");
    }
    scene.tapes.push_back({x, y, gap_start, y, tape_width_m});
    x = gap_end;
  }
  scene.tapes.push_back({x, y, options.x_end_m, y, tape_width_m});
  if (options.branch_length_m > 0.0) {
    scene.tapes.push_back(
        {options.branch_x_m, y - options.branch_length_m, options.branch_x_m, y, tape_width_m});
  }
  if (options.second_tape) {
    scene.tapes.push_back({options.x_start_m, options.second_tape_y_m, options.x_end_m,
                           options.second_tape_y_m, tape_width_m});
  }
  return scene;
}

CeilingScene single_tape_scene(double tape_width_m) {
  if (!(tape_width_m > 0.0)) throw std::invalid_argument("single_tape_scene: width must be > 0");
  CeilingScene scene;
  scene.tapes.push_back({-10.0, 0.0, 100.0, 0.0, tape_width_m});
  return scene;
}

CeilingScene lamp_grid_scene(const LampGridOptions& o) {
  CeilingScene s;
  for (double x = o.x_min; x <= o.x_max + 1e-9; x += o.pitch_x_m) {
    for (double y = o.y_min; y <= o.y_max + 1e-9; y += o.pitch_y_m) {
      // A strip along X through (x, y): width_m wide, length_m long.
      s.tapes.push_back(
          {x - 0.5 * o.length_m, y, x + 0.5 * o.length_m, y, o.width_m, o.reflectance});
    }
  }
  return s;
}

std::vector<std::pair<std::string, CeilingScene>> distractor_scenes() {
  std::vector<std::pair<std::string, CeilingScene>> scenes;
  scenes.emplace_back("lamp grid", lamp_grid_scene());
  LampGridOptions panels;
  panels.width_m = 0.6;
  panels.pitch_x_m = 2.4;
  panels.pitch_y_m = 2.4;
  scenes.emplace_back("panels", lamp_grid_scene(panels));
  LampGridOptions tubes;
  tubes.length_m = 1.2;
  tubes.width_m = 0.03;
  tubes.pitch_x_m = 3.0;
  tubes.pitch_y_m = 2.0;
  scenes.emplace_back("tubes 3 cm", lamp_grid_scene(tubes));
  LampGridOptions bars;
  bars.length_m = 1.2;
  bars.width_m = 0.15;
  bars.pitch_x_m = 1.5;
  bars.pitch_y_m = 100.0;  // one row of bars end to end with 0.3 m gaps
  bars.y_min = bars.y_max = 0.3;
  scenes.emplace_back("bar row", lamp_grid_scene(bars));
  CeilingScene dashes;
  for (double x = -6.0; x < 40.0; x += 1.2) dashes.tapes.push_back({x, 0.0, x + 0.3, 0.0, 0.05});
  scenes.emplace_back("dashes", dashes);
  CeilingScene wide;
  wide.tapes.push_back({-10.0, 0.0, 100.0, 0.0, 0.10});
  scenes.emplace_back("10 cm strip", wide);
  return scenes;
}

double pitch_rad(const host::CameraConfig& camera) {
  return camera.camera_pitch_deg * std::numbers::pi / 180.0;
}

Eigen::Vector3d camera_centre(const host::CameraConfig& camera, const CameraPose& pose) {
  return {pose.x_m, pose.y_m, camera.camera_height_m};
}

Eigen::Matrix3d world_to_camera_rotation(double yaw_rad, double pitch_rad) {
  const double cpsi = std::cos(yaw_rad), spsi = std::sin(yaw_rad);
  const double cp = std::cos(pitch_rad), sp = std::sin(pitch_rad);
  Eigen::Matrix3d r;
  // right = heading rotated -90 deg about Z; forward = heading tilted up by the
  // pitch; down = forward x right (right-handed x, y, z = right, down, forward).
  r << spsi, -cpsi, 0.0,          //
      sp * cpsi, sp * spsi, -cp,  //
      cp * cpsi, cp * spsi, sp;
  return r;
}

Eigen::Matrix3d world_to_camera_rotation(double yaw_rad, double pitch_rad, double roll_rad) {
  Eigen::Matrix3d r = world_to_camera_rotation(yaw_rad, pitch_rad);
  if (roll_rad != 0.0) {
    const double cr = std::cos(roll_rad), sr = std::sin(roll_rad);
    Eigen::Matrix3d roll;
    roll << cr, sr, 0.0, -sr, cr, 0.0, 0.0, 0.0, 1.0;
    r = roll * r;
  }
  return r;
}

Eigen::Vector2d distort_normalised(const host::CameraConfig& camera, const Eigen::Vector2d& xy) {
  const auto& k = camera.distortion_coefficients;
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + k[0] * r2 + k[1] * r2 * r2 + k[4] * r2 * r2 * r2;
  const double a1 = 2.0 * x * y;
  const double a2 = r2 + 2.0 * x * x;
  const double a3 = r2 + 2.0 * y * y;
  return {x * radial + k[2] * a1 + k[3] * a2, y * radial + k[2] * a3 + k[3] * a1};
}

std::optional<Eigen::Vector2d> project_point(const host::CameraConfig& camera,
                                             const CameraPose& pose,
                                             const Eigen::Vector3d& world_point,
                                             bool apply_distortion) {
  const Eigen::Matrix3d r = world_to_camera_rotation(pose.yaw_rad, pitch_rad(camera));
  const Eigen::Vector3d p = r * (world_point - camera_centre(camera, pose));
  if (!(p.z() > 0.0)) return std::nullopt;
  Eigen::Vector2d xy(p.x() / p.z(), p.y() / p.z());
  if (apply_distortion) xy = distort_normalised(camera, xy);
  return Eigen::Vector2d(camera.fx() * xy.x() + camera.cx(), camera.fy() * xy.y() + camera.cy());
}

FrameTruth truth_for(const host::CameraConfig& camera, const CeilingScene& scene,
                     const CameraPose& pose) {
  if (!(camera.ceiling_above_camera_m() > 0.0)) {
    throw std::invalid_argument("truth_for: the ceiling must be above the camera");
  }
  if (!scene.tapes.empty()) {
    const TapeSegment& t = scene.tapes[0];
    if (t.y0_m != scene.reference_y_m || t.y1_m != scene.reference_y_m || !(t.x1_m > t.x0_m)) {
      throw std::invalid_argument("truth_for: tapes[0] must run along +X on reference_y_m");
    }
  }
  FrameTruth truth{};
  truth.yaw_rad = pose.yaw_rad;
  truth.offset_m = pose.y_m - scene.reference_y_m;
  truth.pitch_rad = pitch_rad(camera);
  truth.ceiling_above_camera_m = camera.ceiling_above_camera_m();
  // The vanishing point of +X is the image of the camera-frame direction R e_x
  // (the first column of R); it is finite when that direction has a z component.
  const Eigen::Vector3d dir = world_to_camera_rotation(pose.yaw_rad, truth.pitch_rad).col(0);
  truth.vp_finite = std::abs(dir.z()) > 1e-9;
  if (truth.vp_finite) {
    truth.vp_u_px = camera.cx() + camera.fx() * dir.x() / dir.z();
    truth.vp_v_px = camera.cy() + camera.fy() * dir.y() / dir.z();
  } else {
    truth.vp_u_px = std::numeric_limits<double>::quiet_NaN();
    truth.vp_v_px = std::numeric_limits<double>::quiet_NaN();
  }
  return truth;
}

void write_truth_csv(const std::string& path,
                     const std::vector<std::pair<std::string, FrameTruth>>& rows) {
  const std::string tmp_path = path + ".tmp";
  {
    std::ofstream out(tmp_path, std::ios::out | std::ios::trunc);
    if (!out) {
      throw std::runtime_error("write_truth_csv: cannot open '" + tmp_path +
                               "' for writing: " + std::strerror(errno));
    }
    CsvWriter csv(out);
    csv.row({"frame", "yaw_rad", "offset_m", "pitch_rad", "vp_u_px", "vp_v_px", "vp_finite",
             "ceiling_above_camera_m"});
    constexpr int kExact = 17;  // significant digits: an exact round trip of a double
    for (const auto& [name, t] : rows) {
      csv.text(name)
          .general(t.yaw_rad, kExact)
          .general(t.offset_m, kExact)
          .general(t.pitch_rad, kExact)
          .general(t.vp_u_px, kExact)
          .general(t.vp_v_px, kExact)
          .integer(t.vp_finite)
          .general(t.ceiling_above_camera_m, kExact)
          .end_row();
    }
    out.flush();
    if (!out) {
      out.close();
      std::error_code ignored;
      std::filesystem::remove(tmp_path, ignored);
      throw std::runtime_error("write_truth_csv: writing '" + tmp_path + "' failed");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp_path, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp_path, ignored);
    throw std::runtime_error("write_truth_csv: cannot rename '" + tmp_path + "' to '" + path +
                             "': " + ec.message());
  }
}

}  // namespace ceilnav::golden
