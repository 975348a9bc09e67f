// Decoders shared by the host-maths fuzz targets (fuzz_tape_pose,
// fuzz_pattern): a camera configuration inside the ranges
// validate_camera_config accepts (except that its lens may fold), and a run
// list (layout: docs/fuzzing.md).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "common/camera_config.hpp"
#include "common/run_record.hpp"
#include "fuzz/byte_reader.hpp"
#include "fuzz/check.hpp"
#include "host/camera_config_io.hpp"

namespace ceilnav::fuzz {

inline constexpr size_t kMaxRuns = 4096;

inline ceilnav::host::CameraConfig decode_config(ByteReader& in) {
  ceilnav::host::CameraConfig cfg;
  cfg.image_width = 1 + in.u16() % 2048;
  cfg.image_height = 1 + in.u16() % 2048;
  const double fx = 20.0 + in.u16() / 16.0;  // 20 .. 4116 px
  const double fy = fx * (0.5 + in.u8() / 256.0);
  const double cx = (cfg.image_width - 1) * (in.u8() / 255.0);
  const double cy = (cfg.image_height - 1) * (in.u8() / 255.0);
  cfg.camera_matrix = {fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0};
  const uint8_t pitch = in.u8();
  cfg.camera_pitch_deg = pitch >= 250 ? 90.0 : 1.0 + 89.0 * pitch / 250.0;
  cfg.camera_height_m = 0.2 + in.u8() * 0.005;
  cfg.ceiling_height_m = cfg.camera_height_m + 0.3 + in.u8() * 0.02;
  cfg.tape_width_m = 0.005 + in.u8() * 0.001;
  const uint8_t dist = in.u8();
  if (dist % 4 == 0) {
    cfg.distortion_coefficients = {};
  } else {
    const double scale = dist % 4 == 3 ? 1.0 : 0.1;  // 3: strong, folded lenses too
    cfg.distortion_coefficients = {scale * in.s8() / 64.0, scale * in.s8() / 64.0,
                                   scale * in.s8() / 2048.0, scale * in.s8() / 2048.0,
                                   scale * in.s8() / 128.0};
  }
  return cfg;
}

// decode_config's contract: every field inside validate_camera_config's
// ranges, except that the lens may be one whose distortion is not invertible
// over the image (distortion_fold; the loader refuses such a file, but the
// pose maths must still survive a CameraModel built from one). Checked with
// the distortion of a folded lens set to zero.
inline void check_decoded_config(const ceilnav::host::CameraConfig& cfg) {
  ceilnav::host::CameraConfig ranges = cfg;
  if (ceilnav::host::distortion_fold(cfg)) ranges.distortion_coefficients = {};
  try {
    ceilnav::host::validate_camera_config(ranges, "fuzz");
  } catch (const ceilnav::host::ConfigError& e) {
    FUZZ_CHECK(false, "decode_config made an invalid config: %s", e.what());
  }
}

// Runs until the input ends (at most kMaxRuns), 10 bytes each.
inline std::vector<ceilnav::stream::RunRecord> decode_runs(ByteReader& in) {
  std::vector<ceilnav::stream::RunRecord> runs;
  ceilnav::stream::RunRecord prev;
  while (!in.empty() && runs.size() < kMaxRuns) {
    const uint8_t mode = in.u8();
    ceilnav::stream::RunRecord r;
    if ((mode & 1u) != 0) {
      // Relative: next row (or the same, or a gap), start shifted, a length.
      r.row = static_cast<uint16_t>(prev.row + (mode >> 1 & 3u));
      r.x_start = static_cast<uint16_t>(prev.x_start + in.s8());
      r.x_end = static_cast<uint16_t>(r.x_start + in.u8() % 64);
      const uint32_t level = in.u8();
      const uint32_t n = static_cast<uint32_t>(r.x_end - r.x_start) + 3u;
      r.sum_w = level * n;
      // Centre near the middle of the run, jittered by up to +-4 px.
      const int64_t centre2 = int64_t{r.x_start} + r.x_end + in.s8() / 16;
      r.sum_xw = static_cast<uint64_t>(std::max<int64_t>(0, centre2)) * r.sum_w / 2;
      for (int pad = 0; pad < 5; ++pad) (void)in.u8();  // 10 bytes per run in both modes
    } else {
      r.row = in.u16();
      r.x_start = in.u16();
      r.x_end = in.u16();
      r.sum_w = static_cast<uint32_t>(in.u16()) << (mode >> 4);
      r.sum_xw = static_cast<uint64_t>(r.sum_w) * in.u8() * 8u + (mode >> 1 & 7u);
    }
    runs.push_back(r);
    prev = r;
  }
  return runs;
}

}  // namespace ceilnav::fuzz
