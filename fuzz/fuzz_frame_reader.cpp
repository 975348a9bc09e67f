// Fuzz target: the frame reader (host::read_grey_frame) on arbitrary file
// contents (PNG in the seed corpus; OpenCV picks the decoder from the
// contents, so any format it knows is reached).
//
// Invariants (docs/fuzzing.md):
//  * the reader returns an image or throws host::InputError; any other
//    exception escaping it is a bug;
//  * a file whose PNG header (parsed here, independently) claims more than the
//    device's 2048 x 2048 is refused for its size, whatever follows the header
//    (without that check OpenCV allocates the claimed size first: up to 16 GB);
//  * a returned image is non-empty CV_8UC1, at most 2048 x 2048, of the size
//    its header states;
//  * reading again with its own size as the expected size returns the same
//    pixels; with a different expected size it throws InputError;
//  * the frame goes through the fast path of the device model
//    (stream::Pipeline::process_frame) and its histogram counts every pixel;
//  * host::choose_threshold on that histogram gives a finite background in
//    0..255 and a finite, non-negative noise sigma.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <numeric>
#include <vector>

#include <opencv2/core.hpp>

#include "common/limits.hpp"
#include "fuzz/check.hpp"
#include "fuzz/temp_file.hpp"
#include "host/auto_threshold.hpp"
#include "host/frame_io.hpp"
#include "stream/pipeline.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ceilnav;
  static fuzz::TempFile file(".png");
  const std::string& path = file.write(data, size);
  // The header's size, if the input starts like a PNG with an IHDR chunk.
  uint32_t header_w = 0, header_h = 0;
  static constexpr uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (size >= 24 && std::memcmp(data, kPng, 8) == 0 && std::memcmp(data + 12, "IHDR", 4) == 0) {
    const auto be32 = [&](size_t at) {
      return uint32_t{data[at]} << 24 | uint32_t{data[at + 1]} << 16 | uint32_t{data[at + 2]} << 8 |
             uint32_t{data[at + 3]};
    };
    header_w = be32(16);
    header_h = be32(20);
  }
  const bool too_large = header_w > stream::kMaxWidth || header_h > stream::kMaxHeight;
  cv::Mat grey;
  try {
    grey = host::read_grey_frame(path);
  } catch (const host::InputError& e) {
    if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) std::printf("refused: %s\n", e.what());
    // Refused for its size, from the header, not after a failed decode.
    FUZZ_CHECK(!too_large || std::strstr(e.what(), "the device takes at most") != nullptr ||
                   std::strstr(e.what(), "corrupt PNG header") != nullptr,
               "a %ux%u header was not refused for its size: %s", header_w, header_h, e.what());
    return 0;  // refused with a message: fine
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "read_grey_frame let a non-InputError escape: %s", e.what());
  }
  if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) {
    std::printf("read %dx%d\n", grey.cols, grey.rows);
  }
  FUZZ_CHECK(!too_large, "a frame whose header says %ux%u was accepted", header_w, header_h);
  FUZZ_CHECK(!grey.empty() && grey.type() == CV_8UC1, "returned type %d, empty %d", grey.type(),
             grey.empty() ? 1 : 0);
  FUZZ_CHECK(
      static_cast<uint32_t>(grey.cols) == header_w && static_cast<uint32_t>(grey.rows) == header_h,
      "decoded %dx%d, header %ux%u", grey.cols, grey.rows, header_w, header_h);
  try {
    const cv::Mat same = host::read_grey_frame(path, grey.cols, grey.rows);
    FUZZ_CHECK(same.size() == grey.size() && cv::countNonZero(same != grey) == 0,
               "a second read returned other pixels");
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "reading with its own size failed: %s", e.what());
  }
  bool refused = false;
  try {
    (void)host::read_grey_frame(path, grey.cols + 1, grey.rows);
  } catch (const host::InputError&) {
    refused = true;
  }
  FUZZ_CHECK(refused, "a %dx%d frame was accepted as %dx%d", grey.cols, grey.rows, grey.cols + 1,
             grey.rows);

  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(grey.cols);
  cfg.height = static_cast<uint16_t>(grey.rows);
  cfg.lut = stream::threshold_lut(128);
  cfg.max_runs_per_row = 16;
  stream::Pipeline pipeline;
  pipeline.set_config(cfg);
  std::vector<stream::RunRecord> runs;
  const stream::FrameResults r =
      pipeline.process_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], &runs);
  const uint64_t counted =
      std::accumulate(r.histogram.bins.begin(), r.histogram.bins.end(), uint64_t{0});
  FUZZ_CHECK(counted == grey.total(), "histogram counts %llu of %zu pixels",
             static_cast<unsigned long long>(counted), grey.total());
  // The host's threshold choice on that histogram (what it does between frames).
  const host::ThresholdSettings ts = host::choose_threshold(r.histogram);
  FUZZ_CHECK(std::isfinite(ts.background_grey) && ts.background_grey >= 0.0 &&
                 ts.background_grey <= 255.0 && std::isfinite(ts.noise_sigma_grey) &&
                 ts.noise_sigma_grey >= 0.0,
             "threshold settings: background %g sigma %g", ts.background_grey, ts.noise_sigma_grey);
  return 0;
}
