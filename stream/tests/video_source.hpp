// Test helper: grey images -> AXI4-Stream video beat sequences with random
// gaps, malformed-stream injection, and the real photos shipped with
// opencv-doc as test images.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "stream/beat.hpp"

namespace ceilnav::stream::test {

inline cv::Mat random_image(std::mt19937& rng, int width, int height) {
  cv::Mat img(height, width, CV_8UC1);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      img.at<uchar>(y, x) = static_cast<uchar>(byte(rng));
    }
  }
  return img;
}

// Random blobs on a dim background: long runs of bright pixels, unlike noise.
inline cv::Mat blob_image(std::mt19937& rng, int width, int height) {
  cv::Mat img(height, width, CV_8UC1);
  std::uniform_int_distribution<int> dim(0, 60);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      img.at<uchar>(y, x) = static_cast<uchar>(dim(rng));
    }
  }
  std::uniform_int_distribution<int> cx(0, width - 1);
  std::uniform_int_distribution<int> cy(0, height - 1);
  std::uniform_int_distribution<int> radius(1, std::max(1, std::min(width, height) / 6));
  std::uniform_int_distribution<int> bright(120, 255);
  for (int i = 0; i < 6; ++i) {
    cv::circle(img, {cx(rng), cy(rng)}, radius(rng), cv::Scalar(bright(rng)), cv::FILLED);
  }
  return img;
}

// A photo from opencv-doc as grey, shrunk (aspect kept) to fit max_w x max_h.
inline std::optional<cv::Mat> load_photo(const std::string& name, int max_w = 1280,
                                         int max_h = 960) {
  const std::string path = "/usr/share/doc/opencv-doc/examples/data/" + name;
  cv::Mat img = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (img.empty()) {
    return std::nullopt;
  }
  const double scale =
      std::min({1.0, static_cast<double>(max_w) / img.cols, static_cast<double>(max_h) / img.rows});
  if (scale < 1.0) {
    cv::resize(img, img, cv::Size(), scale, scale, cv::INTER_AREA);
  }
  return img;
}

inline const std::vector<std::string>& photo_names() {
  static const std::vector<std::string> names = {"building.jpg", "messi5.jpg", "baboon.jpg",
                                                 "fruits.jpg", "home.jpg"};
  return names;
}

inline VideoBeat gap_beat() {
  return VideoBeat{};
}

inline VideoBeat pixel_beat(uint8_t grey, bool sof, bool eol) {
  return VideoBeat{grey, true, sof, eol};
}

// Appends the well-formed beats of img to out; before every pixel, a gap is
// inserted with probability gap_prob (several in a row possible).
inline void append_frame(std::vector<VideoBeat>& out, const cv::Mat& img, std::mt19937& rng,
                         double gap_prob) {
  std::bernoulli_distribution gap(gap_prob);
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      while (gap_prob > 0.0 && gap(rng)) {
        out.push_back(gap_beat());
      }
      out.push_back(pixel_beat(img.at<uchar>(y, x), x == 0 && y == 0, x == img.cols - 1));
    }
  }
}

inline void append_gaps(std::vector<VideoBeat>& out, int count) {
  for (int i = 0; i < count; ++i) {
    out.push_back(gap_beat());
  }
}

}  // namespace ceilnav::stream::test
