// Normalised cross-correlation as cv::matchTemplate's TM_CCOEFF_NORMED, for
// the tracker's many templates against one image: the image's sums over
// every template-sized block (integral images) and its spectrum are
// computed once, each template is made zero-mean once, and a score is then
// one dot product (a few offsets: the refinement) or the whole surface is
// one product of spectra and an inverse DFT (the coarse search).
// docs/homing.md, "Tracking".
#pragma once

#include <opencv2/core.hpp>

namespace ceilnav::host::homing {

// A template ready to be scored: its zero-mean copy and that copy's sum of
// squares.
struct NccTemplate {
  cv::Mat zero_mean;  // CV_32FC1
  double norm2 = 0.0;
};
NccTemplate ncc_template(const cv::Mat& tmpl);

// Scores of t x t templates against one CV_32FC1 image at offsets (x, y)
// (the block's top-left corner), 0 <= x < cols(), 0 <= y < rows().
// Where the block's or the template's variance is nil the score follows
// cv::matchTemplate: num / den while |num| < den, +-1 up to 1.125 den, else 0.
class BlockNcc {
 public:
  // A block whose grey levels scatter by less than this RMS (below a
  // camera's noise) scores 0: it holds no structure to match, and the
  // quotient's rounding would otherwise score it +-1 (cv::matchTemplate
  // does: a saturated area of a real photo matched a site at 1.000).
  static constexpr double kMinRms = 1.0;

  BlockNcc(const cv::Mat& image, int t);
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  // One offset: the dot product with the block.
  double score(const NccTemplate& tmpl, int x, int y) const;
  // Every offset (rows() x cols(), CV_32FC1), by DFT; the image's
  // spectrum is computed on the first call.
  cv::Mat scores(const NccTemplate& tmpl);

 private:
  double block_deviation(int x, int y) const;  // sqrt(sum (I - mean)^2) over the block

  cv::Mat image_;
  int t_, cols_, rows_;
  cv::Mat sum_, sqsum_;  // integral images, CV_64F
  cv::Size dft_size_;
  cv::Mat spectrum_;   // of the image zero-padded to dft_size_ (CCS)
  cv::Mat deviation_;  // block_deviation of every offset, CV_64F
};

}  // namespace ceilnav::host::homing
