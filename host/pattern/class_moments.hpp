// The pattern's pixel classes and what the device measures of them: the raw
// moments of each class's mask and the bounding boxes (the seed's
// projections), from a class image or the device's results (docs/pattern.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "common/results.hpp"
#include "common/run_record.hpp"

namespace ceilnav::host::pattern {

// Pixel classes (the hardware's fixed codes).
inline constexpr int kBackground = 0, kDisc = 1, kShadow = 2, kBar = 3, kClasses = 4;

// Raw moments of one class's mask, sums over the pixels (x = column, y = row)
// of x^a y^b: what the class-moment block delivers (and cv::moments of the
// 0/1 mask with binaryImage = true, exactly).
struct ClassMoments {
  int64_t m00 = 0, m10 = 0, m01 = 0;
  int64_t m20 = 0, m11 = 0, m02 = 0;
  friend bool operator==(const ClassMoments&, const ClassMoments&) = default;
};
using FrameMoments = std::array<ClassMoments, kClasses>;
// The moments of every class of a class image (CV_8UC1 of codes 0..3), exact
// in 64-bit integers (tools and tests; the hardware supplies the same numbers).
FrameMoments class_moments(const uint8_t* classes, int width, int height, std::size_t stride);

// The device's class moments (stream::FrameResults::class_moments) in the
// same form; the background (not measured by the device) is left zero.
FrameMoments device_moments(const stream::ClassMomentResults& r);

// Bounding box of a class's pixels (the seed's projections), inclusive.
struct Extents {
  int u_min = 0, u_max = -1, v_min = 0, v_max = -1;
  bool empty() const { return u_max < u_min; }
};
Extents class_extents(const uint8_t* classes, int width, int height, std::size_t stride, int cls);
// The same for the disc from its run records (split_disc_runs).
Extents disc_extents_from_runs(std::span<const stream::RunRecord> disc_runs);

}  // namespace ceilnav::host::pattern
