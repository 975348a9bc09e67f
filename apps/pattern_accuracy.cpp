// `ceilnav pattern-accuracy`: the study's rendered frames measured through the
// device and the host, and the command that reports them.
#include "apps/pattern_accuracy.hpp"

#include <cmath>
#include <limits>
#include <random>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "drivers/device.hpp"
#include "host/camera_model.hpp"
#include "sim/pattern_analysis.hpp"

namespace ceilnav::app {
namespace gp = golden::pattern;
namespace hp = host::pattern;

std::vector<PatternAccuracyRow> measure_pattern_accuracy(const PatternAccuracyOptions& o,
                                                         const host::CameraConfig& camera,
                                                         const gp::PatternGeometry& geometry) {
  const host::CameraModel model(camera);
  const gp::Radiometry radiometry;
  drivers::Device device(device_options(o.backend));
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const std::vector<double> distances{1.0, 1.5, 2.0, 3.0, 4.0, 5.0};
  std::vector<double> thetas;
  for (int k = 0; k <= 10; ++k) thetas.push_back(7.5 * k);  // the seed's Table I

  std::vector<PatternAccuracyRow> rows;
  int frame = 0;
  uint64_t frame_seed = 0;
  for (double d : distances) {
    for (double th : thetas) {
      for (int b = 0; b <= o.betas; ++b) {
        PatternAccuracyRow r{};
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
        p.photometry = {o.gain, o.offset_grey, o.vignetting};
        const cv::Mat grey = gp::render_pattern(camera, geometry, radiometry, r.identity, v, p);
        const gp::PatternTruth t = gp::pattern_truth(camera, geometry, r.identity, v);
        hp::PoseOptions po = sim::pose_options_for(geometry);
        po.up_cam = v.rotation.col(1);  // the mount's known tilt (docs/pattern.md)
        // The camera's blur and noise (calibrated, not per frame).
        po.psf_sigma_px = o.calib_blur_sigma >= 0.0 ? o.calib_blur_sigma : o.blur_sigma;
        po.noise_grey = o.calib_noise_sigma >= 0.0 ? o.calib_noise_sigma : o.noise_sigma;
        const sim::PatternFrameAnalysis a =
            sim::analyse_pattern_frame(device, grey, radiometry, model, po, o.self_calibrate);
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
        const hp::PatternPose& q = a.conic_bars;
        r.beta_err = q.beta_resolved ? std::remainder(q.beta_rad / kDeg - r.beta, 360.0)
                                     : std::numeric_limits<double>::quiet_NaN();
        r.pos_err = (gp::spherical_position(q.d_m, q.theta_rad, q.beta_rad) -
                     gp::spherical_position(d, th * kDeg, r.beta * kDeg))
                        .norm();
        r.reported_ok = q.status == hp::PatternStatus::ok && a.code.status == hp::PatternStatus::ok;
        rows.push_back(r);
        ++frame;
      }
    }
  }
  return rows;
}

int run_pattern_accuracy(const PatternAccuracyOptions& o) {
  if (o.swing_height) return run_pattern_swing_height_study(o);
  if (!o.csv.empty()) check_writable(o.csv);
  if (!o.plot.empty()) check_writable(o.plot);
  const host::CameraConfig camera = scaled_camera(o.width, o.height, o.distortion);
  const gp::PatternGeometry geometry;
  if (o.photometric_sweep) return run_photometric_sweep(o, camera, geometry);
  const std::vector<PatternAccuracyRow> rows = measure_pattern_accuracy(o, camera, geometry);
  const PatternAccuracyStats st = summarise_pattern_accuracy(rows, geometry.radius_m);
  print_pattern_accuracy(o, rows.size(), st);
  if (!o.csv.empty()) write_pattern_accuracy_csv(o.csv, rows);
  if (!o.plot.empty()) plot_pattern_accuracy(o.plot, st, camera, geometry);
  return (o.require && !st.pass()) ? 1 : 0;
}

}  // namespace ceilnav::app
