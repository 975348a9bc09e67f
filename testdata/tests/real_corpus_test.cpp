// The corpus loader: every frame there, of the right size, not blank, named
// uniquely; bad files are errors, never a short corpus.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <opencv2/core.hpp>

#include "real_corpus.hpp"

namespace ts = ceilnav::test_support;
namespace fs = std::filesystem;

TEST(RealCorpus, AllFramesLoadAt640x480) {
  const std::vector<ts::RealFrame> frames = ts::load_real_corpus();
  std::set<std::string> names;
  int cycloid = 0, photos = 0;
  for (const auto& f : frames) {
    ASSERT_EQ(f.grey.type(), CV_8UC1) << f.name;
    ASSERT_EQ(f.grey.cols, 640) << f.name;
    ASSERT_EQ(f.grey.rows, 480) << f.name;
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(f.grey, &lo, &hi);
    EXPECT_GT(hi - lo, 20.0) << f.name << ": a real frame has contrast";
    EXPECT_TRUE(names.insert(f.name).second) << "duplicate name " << f.name;
    if (f.name.rfind("cycloid/", 0) == 0) ++cycloid;
    if (f.name.rfind("opencv-doc/", 0) == 0) ++photos;
  }
  EXPECT_EQ(cycloid, 200);
  // opencv-doc 4.6 installs 91 photos; a later version may add some.
  EXPECT_GE(photos, 80);
}

TEST(RealCorpus, CycloidFramesAreTheRecording) {
  const auto frames =
      ts::cycloid_ceiltrack_frames(ts::real_corpus_dir() / "cycloid_ceiltrack" / "data.raw.gz");
  ASSERT_EQ(frames.size(), 200u);
  // Ceiling lights: a few saturated pixels in a darker ceiling, in every frame.
  for (const auto& f : frames) {
    const int bright = cv::countNonZero(f.grey >= 250);
    EXPECT_GT(bright, 0) << f.name;
    EXPECT_LT(bright, static_cast<int>(f.grey.total() / 4)) << f.name;
  }
  // Consecutive frames of a moving car differ.
  EXPECT_GT(cv::norm(frames[0].grey, frames[100].grey, cv::NORM_L1), 0.0);
}

TEST(RealCorpus, ShortOrCorruptRecordingIsAnError) {
  const fs::path dir = fs::temp_directory_path() / "ceilnav_real_corpus_test";
  fs::create_directories(dir);
  const fs::path missing = dir / "missing.raw.gz";
  fs::remove(missing);
  EXPECT_THROW(ts::cycloid_ceiltrack_frames(missing), ts::CorpusError);
  const fs::path junk = dir / "junk.raw.gz";
  std::ofstream(junk) << "not gzip, and far too short";
  EXPECT_THROW(ts::cycloid_ceiltrack_frames(junk), ts::CorpusError);
  EXPECT_THROW(ts::photo_frames(dir / "no_such_folder", "x", 640, 480), ts::CorpusError);
  EXPECT_THROW(ts::photo_frames(dir, "x", 640, 480), ts::CorpusError);  // no images in it
  fs::remove_all(dir);
}

TEST(RealCorpus, CoverAndCropKeepsAspectAndCentre) {
  // A 100 x 50 image with a bright centre column: covering 640 x 480 scales by
  // 9.6 and crops the sides; the column stays in the middle.
  cv::Mat m(50, 100, CV_8UC1, cv::Scalar(10));
  m.col(50).setTo(200);
  const cv::Mat c = ts::cover_and_crop(m, 640, 480);
  ASSERT_EQ(c.cols, 640);
  ASSERT_EQ(c.rows, 480);
  cv::Point hi;
  cv::minMaxLoc(c.row(240), nullptr, nullptr, nullptr, &hi);
  EXPECT_NEAR(hi.x, 320, 8);
}
