// The real-image corpus (testdata/real/README.md): frames no one here rendered,
// none showing tape or the standard pattern. Tests run every detector over
// them and require "not found".
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace ceilnav::test_support {

struct RealFrame {
  std::string name;    // "<set>/<item>", unique, usable as a file stem after '/' -> '_'
  std::string origin;  // where the pixels come from (file, frame index)
  cv::Mat grey;        // CV_8UC1
};

struct CorpusError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// testdata/real of the source tree, and the photos of the opencv-doc package.
std::filesystem::path real_corpus_dir();
std::filesystem::path opencv_doc_data_dir();

// The 200 frames of cycloid's ceiling recording (640 x 480). Throws
// CorpusError when the file is missing, short or corrupt.
std::vector<RealFrame> cycloid_ceiltrack_frames(const std::filesystem::path& file);

// Every *.jpg / *.png of `dir` (sorted by name), as grey, scaled with area
// averaging to cover width x height (aspect kept) and cropped about the
// centre. Throws CorpusError for a missing folder, no images, or a file
// OpenCV cannot decode.
std::vector<RealFrame> photo_frames(const std::filesystem::path& dir, const std::string& set,
                                    int width, int height);

// Both sets at 640 x 480 (cycloid first).
std::vector<RealFrame> load_real_corpus();

// Grey image covering width x height: area-averaged scale, centre crop.
cv::Mat cover_and_crop(const cv::Mat& grey, int width, int height);

}  // namespace ceilnav::test_support
