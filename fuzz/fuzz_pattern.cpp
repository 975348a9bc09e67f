// Fuzz target: the standard pattern's host maths (seed 003) on arbitrary
// device output: host::pattern::analyse_pattern (disc/bar split, moments'
// ellipse, sub-pixel outline, coverage fit, the three pose methods, both
// bar-code readers, the refinement with the bars) and world_fix.
//
// Input: the camera header of fuzz_tape_pose (fuzz/decode.hpp), then 8 bytes
// of options (coverage model: k, contrast, dead zone, noise, blur and its
// form; the camera's up vector), then per class 1..3 a mode byte (0: the
// moments of every run's pixels x_start..x_end, as the device counts a
// class whose runs they are; 1: 27 bytes of arbitrary moments; 2: a u16 N,
// the moments of the first N runs), then run records of 13 bytes, exact as
// the device emits them (row, x_start, x_end: u16; sum_w: u24; sum_xw: u32),
// so that the seeds are real frames' runs. Layout: docs/fuzzing.md.
//
// Invariants (docs/fuzzing.md):
//  * every status is one of PatternStatus's; every double of every pose
//    (D, theta, beta, centre, normal, the ellipse) is finite whatever the
//    status (a status, never a NaN);
//  * a code identity is -1 or a valid identity, and ok reads have one;
//  * a coverage fit, when there is one, is a finite ellipse with a finite
//    covariance;
//  * world_fix of a pose is finite;
//  * the same call again gives the same result bit for bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "fuzz/byte_reader.hpp"
#include "fuzz/check.hpp"
#include "fuzz/decode.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/pattern/pattern_frame.hpp"

namespace {

using ceilnav::fuzz::ByteReader;
namespace hp = ceilnav::host::pattern;

bool known_status(hp::PatternStatus s) {
  switch (s) {
    case hp::PatternStatus::ok:
    case hp::PatternStatus::no_pattern:
    case hp::PatternStatus::partial:
    case hp::PatternStatus::unreadable:
    case hp::PatternStatus::ambiguous:
    case hp::PatternStatus::degenerate:
    case hp::PatternStatus::unknown_pattern:
      return true;
    case hp::PatternStatus::uncalibrated:  // set by the app's photometric calibration only
      return false;
  }
  return false;
}

void check_pose(const hp::PatternPose& p, const char* what) {
  FUZZ_CHECK(known_status(p.status), "%s: status %d", what, static_cast<int>(p.status));
  const double fields[] = {p.d_m,        p.theta_rad, p.beta_rad,  p.ellipse.cx,
                           p.ellipse.cy, p.ellipse.a, p.ellipse.b, p.ellipse.psi};
  for (double v : fields) {
    FUZZ_CHECK(std::isfinite(v), "%s: non-finite field with status %s", what,
               std::string(hp::to_string(p.status)).c_str());
  }
  FUZZ_CHECK(p.centre_cam.allFinite() && p.normal_cam.allFinite(), "%s: non-finite pose", what);
  FUZZ_CHECK(!p.up_cam || p.up_cam->allFinite(), "%s: non-finite up", what);
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

bool same_pose(const hp::PatternPose& a, const hp::PatternPose& b) {
  return a.status == b.status && same_bits(a.d_m, b.d_m) && same_bits(a.theta_rad, b.theta_rad) &&
         same_bits(a.beta_rad, b.beta_rad) && a.beta_resolved == b.beta_resolved &&
         a.centre_cam == b.centre_cam && a.normal_cam == b.normal_cam;
}

// Moments of the pixels x_start .. x_end of the runs (reversed runs skipped).
hp::ClassMoments moments_of(const std::vector<ceilnav::stream::RunRecord>& runs) {
  hp::ClassMoments m;
  for (const auto& r : runs) {
    if (r.x_end < r.x_start) continue;
    const int64_t a = r.x_start, b = r.x_end, y = r.row, n = b - a + 1;
    const auto s2 = [](int64_t k) { return k * (k + 1) * (2 * k + 1) / 6; };
    const int64_t sx = (a + b) * n / 2;
    m.m00 += n;
    m.m10 += sx;
    m.m01 += n * y;
    m.m20 += s2(b) - (a > 0 ? s2(a - 1) : 0);
    m.m11 += sx * y;
    m.m02 += n * y * y;
  }
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ceilnav;
  ByteReader in(data, size);
  const host::CameraConfig cfg = ceilnav::fuzz::decode_config(in);
  ceilnav::fuzz::check_decoded_config(cfg);
  // Options: the coverage model (k 1..256, contrast 1..256 grey, dead zone
  // 0..0.25, noise 0..8 grey, blur 0..1.5 px on pixels or as a PSF) and the
  // camera's up (default when zero).
  hp::DiscCoverageModel cov;
  cov.k = 1u + in.u8();
  cov.contrast = 1.0 + in.u8();
  cov.dead_lo = in.u8() / 1024.0;
  cov.dead_hi = 1.0 - cov.dead_lo;
  cov.noise_grey = in.u8() / 32.0;
  const uint8_t blur = in.u8();
  (blur & 1u ? cov.kernel_sigma_px : cov.psf_sigma_px) = (blur >> 1) % 49 / 32.0;
  hp::PoseOptions po;
  po.psf_sigma_px = (blur >> 1) % 49 / 32.0;
  po.blur_on_pixels = (blur & 1u) != 0;
  po.noise_grey = cov.noise_grey;
  // One read per statement: the order of reads within an expression is unspecified.
  const double ux = in.s8(), uy = in.s8(), uz = in.s8();
  const Eigen::Vector3d up(ux, uy, uz);
  if (up.norm() > 0.0) po.up_cam = up.normalized();
  int modes[3];
  std::size_t first_runs[3] = {0, 0, 0};
  hp::FrameMoments fm{};
  for (int c = 0; c < 3; ++c) {
    modes[c] = in.u8() % 3;
    if (modes[c] == 1) {
      hp::ClassMoments& m = fm[static_cast<std::size_t>(c + 1)];
      int64_t v[15];
      for (int k = 0; k < 15; ++k)
        v[k] = k == 11 ? in.s8() : (k == 7 || k == 14 ? in.u8() : in.u16());
      m.m00 = v[0];
      m.m10 = v[1] * v[2];
      m.m01 = v[3] * v[4];
      m.m20 = v[5] * v[6] * (1 + v[7]);
      m.m11 = v[11] * v[8] * v[9];
      m.m02 = v[10] * v[12] * (1 + v[14]) + v[13];
    } else if (modes[c] == 2) {
      first_runs[c] = in.u16();
    }
  }
  std::vector<stream::RunRecord> runs;
  while (!in.empty() && runs.size() < ceilnav::fuzz::kMaxRuns) {
    stream::RunRecord r;
    r.row = in.u16();
    r.x_start = in.u16();
    r.x_end = in.u16();
    const uint32_t w_lo = in.u16(), w_hi = in.u8();
    r.sum_w = w_lo | w_hi << 16;
    const uint64_t xw_lo = in.u16(), xw_hi = in.u16();
    r.sum_xw = xw_lo | xw_hi << 16;
    runs.push_back(r);
  }
  for (int c = 0; c < 3; ++c) {
    if (modes[c] == 1) continue;
    const std::size_t n = modes[c] == 0 ? runs.size() : std::min(first_runs[c], runs.size());
    fm[static_cast<std::size_t>(c + 1)] = moments_of(
        std::vector<stream::RunRecord>(runs.begin(), runs.begin() + static_cast<long>(n)));
  }
  hp::BarcodeOptions bo;
  bo.bar_contrast = 45.0;
  bo.min_bar_run_weight = 16;
  const host::CameraModel cam(cfg);

  const hp::PatternAnalysis a =
      hp::analyse_pattern(runs, fm, cam, cfg.image_width, cfg.image_height, po, bo, cov);
  check_pose(a.conic, "conic");
  check_pose(a.moment, "moment");
  check_pose(a.projection, "projection");
  check_pose(a.conic_bars, "conic+bars");
  FUZZ_CHECK(known_status(a.code.status), "code status %d", static_cast<int>(a.code.status));
  FUZZ_CHECK(a.code.identity >= -1 && a.code.identity < 50, "identity %d", a.code.identity);
  FUZZ_CHECK(a.code.status != hp::PatternStatus::ok || a.code.identity >= 0,
             "ok code without an identity");
  for (const hp::BarEdge& e : a.code.edges) {
    FUZZ_CHECK(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.width),
               "non-finite bar edge");
  }
  if (a.fit) {
    const hp::Ellipse& e = a.fit->ellipse;
    FUZZ_CHECK(std::isfinite(e.cx) && std::isfinite(e.cy) && std::isfinite(e.a) &&
                   std::isfinite(e.b) && e.param_cov.allFinite() && std::isfinite(a.fit->rms_px),
               "non-finite coverage fit");
  }
  const hp::WorldFix w = hp::world_fix(a.conic_bars, {1.0, 2.0, 1.2, 0.7}, po.up_cam);
  FUZZ_CHECK(std::isfinite(w.x_m) && std::isfinite(w.y_m) && std::isfinite(w.z_m) &&
                 std::isfinite(w.camera_yaw_rad),
             "non-finite world fix");
  if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) {
    std::printf("%zu runs: conic %s D %g, code %s id %d, fit %s\n", runs.size(),
                std::string(hp::to_string(a.conic.status)).c_str(), a.conic.d_m,
                std::string(hp::to_string(a.code.status)).c_str(), a.code.identity,
                a.fit ? "yes" : "no");
  }
  const hp::PatternAnalysis again =
      hp::analyse_pattern(runs, fm, cam, cfg.image_width, cfg.image_height, po, bo, cov);
  FUZZ_CHECK(same_pose(a.conic_bars, again.conic_bars) && same_pose(a.conic, again.conic) &&
                 a.code.identity == again.code.identity && a.code.status == again.code.status,
             "a second call gave another result");
  return 0;
}
