#include "real_corpus.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace ceilnav::test_support {

namespace fs = std::filesystem;

fs::path real_corpus_dir() {
  return CEILNAV_REAL_CORPUS_DIR;
}
fs::path opencv_doc_data_dir() {
  return CEILNAV_OPENCV_DOC_DATA_DIR;
}

std::vector<RealFrame> cycloid_ceiltrack_frames(const fs::path& file) {
  constexpr int kWidth = 640, kHeight = 480, kFrames = 200;
  if (!fs::is_regular_file(file)) {
    throw CorpusError(fmt::format("real corpus: {} is missing", file.string()));
  }
  const std::unique_ptr<gzFile_s, int (*)(gzFile)> gz(gzopen(file.c_str(), "rb"), gzclose);
  if (!gz) throw CorpusError(fmt::format("real corpus: cannot open {}", file.string()));
  std::vector<RealFrame> frames;
  frames.reserve(kFrames);
  for (int i = 0; i < kFrames; ++i) {
    cv::Mat m(kHeight, kWidth, CV_8UC1);
    const auto want = static_cast<unsigned>(m.total());
    const int got = gzread(gz.get(), m.data, want);
    if (got < 0 || static_cast<unsigned>(got) != want) {
      throw CorpusError(
          fmt::format("real corpus: {} ends or is corrupt at frame {}", file.string(), i));
    }
    frames.push_back(RealFrame{fmt::format("cycloid/{:03d}", i),
                               fmt::format("{} frame {}", file.filename().string(), i), m});
  }
  unsigned char extra = 0;
  if (gzread(gz.get(), &extra, 1) != 0) {
    throw CorpusError(
        fmt::format("real corpus: {} holds more than {} frames", file.string(), kFrames));
  }
  return frames;
}

cv::Mat cover_and_crop(const cv::Mat& grey, int width, int height) {
  const double s =
      std::max(static_cast<double>(width) / grey.cols, static_cast<double>(height) / grey.rows);
  const int w = std::max(width, static_cast<int>(std::ceil(grey.cols * s)));
  const int h = std::max(height, static_cast<int>(std::ceil(grey.rows * s)));
  cv::Mat scaled;
  cv::resize(grey, scaled, cv::Size(w, h), 0, 0, s < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  const cv::Rect roi((w - width) / 2, (h - height) / 2, width, height);
  return scaled(roi).clone();
}

std::vector<RealFrame> photo_frames(const fs::path& dir, const std::string& set, int width,
                                    int height) {
  if (!fs::is_directory(dir)) {
    throw CorpusError(
        fmt::format("real corpus: {} is not a folder (install opencv-doc: "
                    "scripts/setup)",
                    dir.string()));
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string ext = e.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (e.is_regular_file() && (ext == ".jpg" || ext == ".png")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    throw CorpusError(fmt::format("real corpus: no *.jpg or *.png in {}", dir.string()));
  }
  std::vector<RealFrame> frames;
  frames.reserve(files.size());
  for (const fs::path& f : files) {
    const cv::Mat grey = cv::imread(f.string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) {
      throw CorpusError(fmt::format("real corpus: OpenCV cannot read {}", f.string()));
    }
    frames.push_back(RealFrame{set + "/" + f.filename().string(), f.string(),
                               cover_and_crop(grey, width, height)});
  }
  return frames;
}

std::vector<RealFrame> load_real_corpus() {
  std::vector<RealFrame> all =
      cycloid_ceiltrack_frames(real_corpus_dir() / "cycloid_ceiltrack" / "data.raw.gz");
  std::vector<RealFrame> photos = photo_frames(opencv_doc_data_dir(), "opencv-doc", 640, 480);
  all.insert(all.end(), std::make_move_iterator(photos.begin()),
             std::make_move_iterator(photos.end()));
  return all;
}

}  // namespace ceilnav::test_support
