// `ceilnav pattern-accuracy --swing-height`: seed 003's error analysis of
// swing (eq. 57-66, 70) and sensor height (eq. 69) reproduced on rendered
// frames: the seed's projection method (eq. 39-49), the moment method's beta
// and the reported pose (conic refined with the bars), against the seed's
// predictions. docs/pattern.md, "Swing and height errors".
#include <cmath>
#include <cstdio>

#include "apps/commands.hpp"
#include "apps/pattern_accuracy.hpp"
#include "host/pattern/world_fix.hpp"
#include "sim/pattern_analysis.hpp"

namespace ceilnav::app {
namespace gp = golden::pattern;
namespace hp = host::pattern;

namespace {

struct Study {
  host::CameraConfig camera;
  host::CameraModel model;
  gp::Radiometry radiometry;
  gp::PatternGeometry geometry;
  drivers::Device device;
  const PatternAccuracyOptions& o;
  uint64_t frame = 0;

  // The host assumes a level camera without swing (it does not know either).
  sim::PatternFrameAnalysis analyse(const gp::PatternView& v) {
    gp::PatternRenderParams p;
    p.noise_sigma_grey = o.noise_sigma;
    p.blur_sigma_px = o.blur_sigma;
    p.noise_seed = o.seed * 1000003U + frame++;
    p.supersample = o.supersample;
    const cv::Mat grey = gp::render_pattern(camera, geometry, radiometry, 17, v, p);
    hp::PoseOptions po = sim::pose_options_for(geometry);
    po.up_cam = Eigen::Vector3d(0.0, -1.0, 0.0);
    po.psf_sigma_px = o.blur_sigma;
    po.noise_grey = o.noise_sigma;
    return sim::analyse_pattern_frame(device, grey, radiometry, model, po);
  }
};

std::string cell(double v, int digits) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%+.*f", digits, v);
  return buf;
}

bool has_pose(const hp::PatternPose& p) {
  return p.status == hp::PatternStatus::ok || p.status == hp::PatternStatus::ambiguous;
}

}  // namespace

int run_pattern_swing_height_study(const PatternAccuracyOptions& o) {
  // A pinhole camera, as the seed's analysis assumes.
  Study s{scaled_camera(o.width, o.height, false),
          host::CameraModel(scaled_camera(o.width, o.height, false)),
          gp::Radiometry{},
          gp::PatternGeometry{},
          drivers::Device(device_options(o.backend)),
          o};
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::printf(
      "Swing sigma (seed set-up: beta 90 deg, optical axis through the disc, D 2 m; host "
      "assumes no swing)\n");
  std::printf(
      "| theta | sigma | D err %% eq. 62 | D err %% projection | theta err eq. 64 | theta err "
      "projection | beta' - beta eq. 70 | -sigma / cos theta | beta' - beta moment | conic+bars D "
      "err %% | conic+bars "
      "theta err | swing measured - sigma |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const double th : {15.0, 30.0, 45.0, 60.0}) {
    for (const double sg : {2.0, 5.0, 10.0}) {
      const double d = 2.0, t = th * kDeg, g = sg * kDeg;
      const sim::PatternFrameAnalysis a = s.analyse(gp::spherical_view(d, t, 90.0 * kDeg, g));
      const double c2s = std::cos(g) * std::cos(g), s2s = std::sin(g) * std::sin(g);
      const double c2t = std::cos(t) * std::cos(t), s2t = std::sin(t) * std::sin(t);
      const double d_pred = 100.0 * (1.0 / std::sqrt(c2s + c2t * s2s) - 1.0);  // eq. 61-62
      const double th_pred =
          std::acos(std::sqrt((c2t + s2t * s2s) / (1.0 - s2t * s2s))) / kDeg - th;  // eq. 64
      auto d_err = [&](const hp::PatternPose& p) {
        return has_pose(p) ? 100.0 * (p.d_m / d - 1.0) : kNaN;
      };
      auto th_err = [&](const hp::PatternPose& p) {
        return has_pose(p) ? p.theta_rad / kDeg - th : kNaN;
      };
      const double beta_shift = has_pose(a.moment) && a.moment.beta_resolved
                                    ? std::remainder(a.moment.beta_rad / kDeg - 90.0, 360.0)
                                    : kNaN;
      const double swing =
          a.conic_bars.up_cam ? hp::swing_from_up(*a.conic_bars.up_cam) / kDeg : kNaN;
      // Eq. 70 with the inversion of erratum 2 (tan beta = cos theta tan
      // psi): at beta 90 deg a swing sigma (clockwise) moves beta by
      // -sigma / cos theta, not sigma.
      std::printf("| %.0f | %.0f | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", th, sg,
                  cell(d_pred, 3).c_str(), cell(d_err(a.projection), 3).c_str(),
                  cell(th_pred, 2).c_str(), cell(th_err(a.projection), 2).c_str(),
                  cell(sg, 1).c_str(), cell(-sg / std::cos(t), 2).c_str(),
                  cell(beta_shift, 2).c_str(), cell(d_err(a.conic_bars), 3).c_str(),
                  cell(th_err(a.conic_bars), 3).c_str(), cell(swing - sg, 3).c_str());
    }
  }
  std::printf(
      "\nSensor height dy (camera dy above the disc centre, optical axis horizontal, facing "
      "the wall; truth D = sqrt(L^2 + dy^2), theta = atan(dy / L))\n");
  std::printf(
      "| L (m) | dy (m) | theta err eq. 69 | theta err projection | D err %% (perpendicular "
      "distance) | D err %% projection | conic+bars D err %% | conic+bars theta err |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const double l : {1.0, 3.0}) {
    for (const double dy : {0.05, 0.1, 0.2, 0.4}) {
      const Eigen::Vector3d c(0.0, dy, l);
      const sim::PatternFrameAnalysis a =
          s.analyse(gp::look_at(c, Eigen::Vector3d(0.0, dy, 0.0), 0.0));
      const double d = c.norm(), th = std::atan2(dy, l) / kDeg;
      auto d_err = [&](const hp::PatternPose& p) {
        return has_pose(p) ? 100.0 * (p.d_m / d - 1.0) : kNaN;
      };
      auto th_err = [&](const hp::PatternPose& p) {
        return has_pose(p) ? p.theta_rad / kDeg - th : kNaN;
      };
      std::printf("| %.0f | %.2f | %s | %s | %s | %s | %s | %s |\n", l, dy, cell(-th, 2).c_str(),
                  cell(th_err(a.projection), 2).c_str(), cell(100.0 * (l / d - 1.0), 3).c_str(),
                  cell(d_err(a.projection), 3).c_str(), cell(d_err(a.conic_bars), 3).c_str(),
                  cell(th_err(a.conic_bars), 3).c_str());
    }
  }
  return 0;
}

}  // namespace ceilnav::app
