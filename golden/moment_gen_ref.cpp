#include "golden/moment_gen_ref.hpp"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace ceilnav::golden {

namespace {

uint64_t exact_u64(double v, const char* what) {
  // Above 2^53 a double no longer holds every integer: refuse.
  if (!(v >= 0.0) || v >= 9007199254740992.0 || std::floor(v) != v) {
    throw std::runtime_error(std::string("moments_ref: not an exact integer: ") + what);
  }
  return static_cast<uint64_t>(v);
}

std::array<uint64_t, stream::kMomentCount> spatial(const cv::Moments& m) {
  return {exact_u64(m.m00, "m00"), exact_u64(m.m10, "m10"), exact_u64(m.m01, "m01"),
          exact_u64(m.m20, "m20"), exact_u64(m.m11, "m11"), exact_u64(m.m02, "m02")};
}

}  // namespace

stream::MomentResults moments_ref(const cv::Mat& remap8u, const cv::Mat& mask8u) {
  if (remap8u.type() != CV_8UC1 || mask8u.type() != CV_8UC1 || remap8u.size() != mask8u.size()) {
    throw std::invalid_argument("moments_ref: need two CV_8UC1 images of one size");
  }
  stream::MomentResults r;
  r.grey = spatial(cv::moments(remap8u, false));
  r.mask = spatial(cv::moments(mask8u, true));  // binaryImage: nonzero counts as 1
  return r;
}

}  // namespace ceilnav::golden
