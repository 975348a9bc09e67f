// Golden reference of the major orientation of a whole image (seed 004's
// FindOrientation): the 3 x 3 Sobel gradient of every interior pixel
// (cv::Sobel, as golden::find_edges_ref's Sobel mode), its angle and length
// (cv::cartToPolar, degrees), the angle folded modulo 90 degrees (a ceiling's
// structures are mostly perpendicular: the four directions of a grid vote
// together) and voted into `bins` equal bins weighted by the length. Its
// peak is the host's (host/homing/orientation.hpp). Floating point: the
// reference of the orientation block's fixed-point histogram
// (docs/homing.md, "Orientation").
//
// Angles are the image's: atan2(gy, gx) with u right and v down, so
// positive angles turn clockwise on the screen.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace ceilnav::golden {

struct OrientationParams {
  int bins = 90;                // over [0, 90) degrees: 1 degree each
  double min_magnitude = 16.0;  // gradients of this length or less do not vote (noise)
};

// grey: CV_8UC1, at least 3 x 3. Bin k holds the summed length of the
// gradients whose folded angle rounds to k x 90 / bins degrees (bin 0 also
// takes the angles that round to 90).
// Throws std::invalid_argument on a bad image or parameters.
std::vector<double> orientation_histogram_ref(const cv::Mat& grey, const OrientationParams& p = {});

// The orientation block's fixed-point histogram, bit true (equal to
// stream::Orientation's published bins): the same interior 3 x 3 Sobel
// gradients (exact integers), each voted by fp::orientation::vote()
// (fixedpoint/orientation.hpp: the folded angle by an arctangent table, the
// alpha-max-beta-min weight) when its weight exceeds `threshold`; 32-bit
// bins, saturating. docs/blocks/orientation.md derives its bound against
// orientation_histogram_ref.
struct OrientationFixedParams {
  int bins = 90;       // 1 .. fp::orientation::kMaxBins
  int threshold = 16;  // 0 .. 4095: a gradient votes if its weight > threshold
};

// grey: CV_8UC1, at least 3 x 3. Throws std::invalid_argument on a bad image
// or parameters.
std::vector<uint32_t> orientation_histogram_fixed(const cv::Mat& grey,
                                                  const OrientationFixedParams& p = {});

}  // namespace ceilnav::golden
