// Reading recorded frames: every PNG of a folder in name order, as 8-bit grey.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ceilnav::host {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The *.png files (case-insensitive extension) directly in `folder`, sorted by
// file name (byte order). Throws InputError for a missing folder, a path that
// is not a folder, or a folder without PNG files.
std::vector<std::filesystem::path> list_png_frames(const std::filesystem::path& folder);

// Reads one PNG frame as CV_8UC1. Colour (3 or 4 channel, 8-bit) is converted
// to grey with OpenCV's BGR weights. Throws InputError for an unreadable or
// corrupt file, a file that is not a PNG, a bit depth other than 8, a size
// above the device's 2048 x 2048, or a size other than expected_width x
// expected_height (when those are > 0). The signature and the device limit
// are checked from the PNG header before the image is decoded.
cv::Mat read_grey_frame(const std::filesystem::path& file, int expected_width = 0,
                        int expected_height = 0);

}  // namespace ceilnav::host
