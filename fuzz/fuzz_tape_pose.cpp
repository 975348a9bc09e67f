// Fuzz target: the host pose maths on arbitrary run lists.
//
// Input: a 16-byte header that decodes to a camera configuration inside the
// ranges validate_camera_config accepts (image size, focal lengths, principal
// point, pitch 1..90 deg, heights, tape width, lens distortion from none to
// strong) and to TapePoseOptions, then 10 bytes per run record. A run is
// either absolute (any row, x_start, x_end, sums: also outside the image,
// reversed, zero-weight) or relative to the previous one (so that tape-like
// chains of runs are easy for the fuzzer to build). Layout: docs/fuzzing.md.
//
// Invariants (docs/fuzzing.md):
//  * estimate_tape_pose returns a defined Status; every double of the result
//    is finite whatever the status (BRIEF: a status, never a NaN);
//  * points_total = the run count, 0 <= points_used <= points_total;
//  * status ok: points_used >= min_points, |yaw| <= max_abs_yaw_deg,
//    line_norm has (l1, l2) of unit length, residual_rms_px >= 0;
//    pitch_est (when valid) in (0, pi/2 + 0.2);
//  * the same call again gives the same result bit for bit (the per-thread
//    scratch buffers carry nothing over from the previous input);
//  * find_tape_end on an ok pose returns nothing or a finite point;
//  * zenith_pose_from_moments on the mask moments of the same runs obeys the
//    same status / finiteness rules.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/camera_config.hpp"
#include "common/results.hpp"
#include "common/run_record.hpp"
#include "fuzz/byte_reader.hpp"
#include "fuzz/check.hpp"
#include "fuzz/decode.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/flow_height.hpp"
#include "host/status.hpp"
#include "host/tape_pose.hpp"

namespace {

using ceilnav::fuzz::ByteReader;
using ceilnav::fuzz::decode_config;
using ceilnav::fuzz::decode_runs;
using ceilnav::host::Status;
using ceilnav::host::TapePose;

bool known_status(Status s) {
  switch (s) {
    case Status::ok:
    case Status::no_tape:
    case Status::too_few_points:
    case Status::degenerate:
    case Status::bad_config:
    case Status::frame_invalid:
    case Status::inconsistent:
    case Status::jump:
      return true;
  }
  return false;
}

void check_pose(const TapePose& p, const char* what) {
  FUZZ_CHECK(known_status(p.status), "%s: status %d", what, static_cast<int>(p.status));
  FUZZ_CHECK(p.method != nullptr, "%s: no method", what);
  const double fields[] = {p.yaw_rad,
                           p.offset_m,
                           p.pitch_rad,
                           p.pitch_est_rad,
                           p.vp_u_px,
                           p.vp_v_px,
                           p.residual_rms_px,
                           p.line_norm.x(),
                           p.line_norm.y(),
                           p.line_norm.z(),
                           p.evidence.residual_px,
                           p.evidence.width_ratio_median,
                           p.evidence.visible_length_m,
                           p.evidence.span_m,
                           p.evidence.max_gap_m,
                           p.evidence.contrast_sigma};
  for (double v : fields) {
    FUZZ_CHECK(std::isfinite(v), "%s: non-finite field in a result with status %d", what,
               static_cast<int>(p.status));
  }
  FUZZ_CHECK(p.points_used >= 0 && p.points_used <= p.points_total, "%s: points_used %d of %d",
             what, p.points_used, p.points_total);
  if (p.pitch_est_valid) {
    FUZZ_CHECK(p.pitch_est_rad > 0.0 && p.pitch_est_rad < 0.5 * std::numbers::pi + 0.2,
               "%s: pitch_est %g", what, p.pitch_est_rad);
  }
  if (p.status == Status::ok) {
    const double n12 = std::hypot(p.line_norm.x(), p.line_norm.y());
    FUZZ_CHECK(std::abs(n12 - 1.0) < 1e-9, "%s: |(l1, l2)| = %.17g", what, n12);
    FUZZ_CHECK(p.residual_rms_px >= 0.0, "%s: residual %g", what, p.residual_rms_px);
  }
}

bool same_pose(const TapePose& a, const TapePose& b) {
  const auto bits_equal = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  return a.status == b.status && std::strcmp(a.method, b.method) == 0 &&
         bits_equal(a.yaw_rad, b.yaw_rad) && bits_equal(a.offset_m, b.offset_m) &&
         bits_equal(a.pitch_rad, b.pitch_rad) && a.pitch_est_valid == b.pitch_est_valid &&
         bits_equal(a.pitch_est_rad, b.pitch_est_rad) && a.vp_finite == b.vp_finite &&
         bits_equal(a.vp_u_px, b.vp_u_px) && bits_equal(a.vp_v_px, b.vp_v_px) &&
         a.points_total == b.points_total && a.points_used == b.points_used &&
         bits_equal(a.residual_rms_px, b.residual_rms_px) &&
         bits_equal(a.line_norm.x(), b.line_norm.x()) &&
         bits_equal(a.line_norm.y(), b.line_norm.y()) &&
         bits_equal(a.line_norm.z(), b.line_norm.z());
}

ceilnav::host::TapePoseOptions decode_options(ByteReader& in) {
  const uint8_t flags = in.u8();
  ceilnav::host::TapePoseOptions opt;
  opt.weighted_fit = (flags & 1u) != 0;
  opt.estimate_pitch = (flags & 2u) == 0;
  if ((flags & 4u) != 0) opt.max_width_factor = 0.0;  // width gate off
  opt.min_points = 2 + (flags >> 4);                  // 2 .. 17
  return opt;
}

// Mask moments of the pixels the runs cover (x_start .. x_end on their row).
ceilnav::stream::MomentResults moments_of(const std::vector<ceilnav::stream::RunRecord>& runs) {
  using namespace ceilnav::stream;
  MomentResults m;
  for (const RunRecord& r : runs) {
    if (r.x_end < r.x_start) continue;
    const uint64_t a = r.x_start, b = r.x_end, y = r.row;
    const uint64_t n = b - a + 1;
    const uint64_t sx = (a + b) * n / 2;
    // sum x^2 over a..b = S(b) - S(a - 1), S(k) = k (k + 1) (2k + 1) / 6.
    const auto s2 = [](uint64_t k) { return k * (k + 1) * (2 * k + 1) / 6; };
    const uint64_t sxx = s2(b) - (a > 0 ? s2(a - 1) : 0);
    m.mask[kM00] += n;
    m.mask[kM10] += sx;
    m.mask[kM01] += n * y;
    m.mask[kM20] += sxx;
    m.mask[kM11] += sx * y;
    m.mask[kM02] += n * y * y;
  }
  m.grey = m.mask;
  return m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ceilnav;
  ByteReader in(data, size);
  const host::CameraConfig cfg = decode_config(in);
  ceilnav::fuzz::check_decoded_config(cfg);
  const host::TapePoseOptions opt = decode_options(in);
  const std::vector<stream::RunRecord> runs = decode_runs(in);
  const host::CameraModel cam(cfg);

  const TapePose pose = host::estimate_tape_pose(runs, cam, cfg, opt);
  check_pose(pose, "estimate_tape_pose");
  FUZZ_CHECK(pose.points_total == static_cast<int>(runs.size()), "points_total %d of %zu runs",
             pose.points_total, runs.size());
  if (runs.empty())
    FUZZ_CHECK(pose.status == Status::no_tape, "no runs but status %d",
               static_cast<int>(pose.status));
  if (pose.status == Status::ok) {
    FUZZ_CHECK(pose.points_used >= opt.min_points, "ok with %d < %d points", pose.points_used,
               opt.min_points);
    FUZZ_CHECK(std::abs(pose.yaw_rad) <= opt.max_abs_yaw_deg * std::numbers::pi / 180.0 + 1e-12,
               "yaw %g beyond the limit", pose.yaw_rad);
  }
  if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) {
    std::printf("%zu runs: %s status %s, %d points used, yaw %g offset %g\n", runs.size(),
                pose.method, std::string(host::to_string(pose.status)).c_str(), pose.points_used,
                pose.yaw_rad, pose.offset_m);
  }
  const TapePose again = host::estimate_tape_pose(runs, cam, cfg, opt);
  FUZZ_CHECK(same_pose(pose, again), "a second call gave another result");

  if (pose.status == Status::ok) {
    const std::optional<Eigen::Vector2d> end = host::find_tape_end(runs, cam, cfg, pose);
    FUZZ_CHECK(!end || end->allFinite(), "find_tape_end returned a non-finite point");
  }

  const TapePose zenith = host::zenith_pose_from_moments(moments_of(runs), cam, cfg);
  check_pose(zenith, "zenith_pose_from_moments");
  if (zenith.status == Status::ok) {
    FUZZ_CHECK(std::abs(zenith.yaw_rad) <= 85.0 * std::numbers::pi / 180.0 + 1e-12,
               "zenith yaw %g beyond 85 deg", zenith.yaw_rad);
  }
  return 0;
}
