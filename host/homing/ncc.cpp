#include "host/homing/ncc.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace ceilnav::host::homing {
namespace {

// cv::matchTemplate's TM_CCOEFF_NORMED quotient (templmatch.cpp), which
// keeps a nil denominator's rounding noise from scoring.
double quotient(double num, double den) {
  if (std::abs(num) < den) return num / den;
  if (std::abs(num) < den * 1.125) return num > 0.0 ? 1.0 : -1.0;
  return 0.0;
}

}  // namespace

NccTemplate ncc_template(const cv::Mat& tmpl) {
  NccTemplate out;
  tmpl.convertTo(out.zero_mean, CV_32F, 1.0, -cv::mean(tmpl)[0]);
  out.norm2 = out.zero_mean.dot(out.zero_mean);
  return out;
}

BlockNcc::BlockNcc(const cv::Mat& image, int t)
    : image_(image), t_(t), cols_(image.cols - t + 1), rows_(image.rows - t + 1) {
  if (image.type() != CV_32FC1 || t < 1 || cols_ < 1 || rows_ < 1) {
    throw std::invalid_argument("BlockNcc: a CV_32FC1 image at least t x t");
  }
  cv::integral(image, sum_, sqsum_, CV_64F, CV_64F);
}

double BlockNcc::block_deviation(int x, int y) const {
  const auto block = [&](const cv::Mat& s) {
    return s.at<double>(y + t_, x + t_) - s.at<double>(y, x + t_) - s.at<double>(y + t_, x) +
           s.at<double>(y, x);
  };
  const double s1 = block(sum_), s2 = block(sqsum_);
  return std::sqrt(std::max(0.0, s2 - s1 * s1 / (static_cast<double>(t_) * t_)));
}

double BlockNcc::score(const NccTemplate& tmpl, int x, int y) const {
  const double dev = block_deviation(x, y);
  if (dev < kMinRms * t_) return 0.0;  // a flat block: no evidence
  const double num = tmpl.zero_mean.dot(image_(cv::Rect(x, y, t_, t_)));
  return quotient(num, std::sqrt(tmpl.norm2) * dev);
}

cv::Mat BlockNcc::scores(const NccTemplate& tmpl) {
  if (spectrum_.empty()) {
    // Circular correlation: offsets up to cols() - 1 reach the image's last
    // column without wrapping, so no padding beyond the image is needed.
    dft_size_ = cv::Size(cv::getOptimalDFTSize(image_.cols), cv::getOptimalDFTSize(image_.rows));
    cv::Mat padded = cv::Mat::zeros(dft_size_, CV_32FC1);
    image_.copyTo(padded(cv::Rect(0, 0, image_.cols, image_.rows)));
    cv::dft(padded, spectrum_, 0, image_.rows);
    deviation_.create(rows_, cols_, CV_64FC1);
    for (int y = 0; y < rows_; ++y) {
      for (int x = 0; x < cols_; ++x) deviation_.at<double>(y, x) = block_deviation(x, y);
    }
  }
  cv::Mat padded = cv::Mat::zeros(dft_size_, CV_32FC1);
  tmpl.zero_mean.copyTo(padded(cv::Rect(0, 0, t_, t_)));
  cv::Mat t_spectrum, product, corr;
  cv::dft(padded, t_spectrum, 0, t_);
  cv::mulSpectrums(spectrum_, t_spectrum, product, 0, true);
  cv::dft(product, corr, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT, rows_);
  const double norm = std::sqrt(tmpl.norm2);
  cv::Mat out(rows_, cols_, CV_32FC1);
  for (int y = 0; y < rows_; ++y) {
    const float* c = corr.ptr<float>(y);
    const double* d = deviation_.ptr<double>(y);
    float* o = out.ptr<float>(y);
    for (int x = 0; x < cols_; ++x) {
      o[x] = d[x] < kMinRms * t_ ? 0.0f : static_cast<float>(quotient(c[x], norm * d[x]));
    }
  }
  return out;
}

}  // namespace ceilnav::host::homing
