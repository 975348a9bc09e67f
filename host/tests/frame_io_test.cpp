// Frame reading: every bad input is a clear error.
#include "host/frame_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "host/tests/temp_dir.hpp"

namespace fs = std::filesystem;
using ceilnav::host::InputError;
using ceilnav::host::list_png_frames;
using ceilnav::host::read_grey_frame;

namespace {

// One scratch folder per test.
class TempDir : public ceilnav::test::TempDir {
 public:
  TempDir() : ceilnav::test::TempDir("ceilnav_frame_io") {}
};

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FrameIo, ListsPngsInNameOrderOnly) {
  TempDir d;
  cv::Mat m(4, 5, CV_8UC1, cv::Scalar(7));
  for (const char* n : {"b.png", "a.PNG", "c.png", "z.jpg"}) {
    ASSERT_TRUE(cv::imwrite((d.path() / n).string(), m, {}) || std::string(n) == "z.jpg");
  }
  fs::create_directory(d.path() / "sub.png");
  const auto frames = list_png_frames(d.path());
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].filename(), "a.PNG");
  EXPECT_EQ(frames[1].filename(), "b.png");
  EXPECT_EQ(frames[2].filename(), "c.png");
}

TEST(FrameIo, FolderErrors) {
  TempDir d;
  EXPECT_NE(message_of([&] { list_png_frames(d.path() / "missing"); }).find("does not exist"),
            std::string::npos);
  EXPECT_NE(message_of([&] { list_png_frames(d.path()); }).find("no PNG"), std::string::npos);
  std::ofstream(d.path() / "file.txt") << "x";
  EXPECT_NE(message_of([&] { list_png_frames(d.path() / "file.txt"); }).find("not a folder"),
            std::string::npos);
}

TEST(FrameIo, ColourIsConvertedToGrey) {
  TempDir d;
  cv::Mat bgr(6, 8, CV_8UC3, cv::Scalar(10, 100, 200));
  ASSERT_TRUE(cv::imwrite((d.path() / "c.png").string(), bgr));
  const cv::Mat g = read_grey_frame(d.path() / "c.png", 8, 6);
  cv::Mat expected;
  cv::cvtColor(bgr, expected, cv::COLOR_BGR2GRAY);
  ASSERT_EQ(g.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(g, expected, cv::NORM_INF), 0.0);
  cv::Mat bgra(6, 8, CV_8UC4, cv::Scalar(10, 100, 200, 255));
  ASSERT_TRUE(cv::imwrite((d.path() / "a.png").string(), bgra));
  EXPECT_EQ(cv::norm(read_grey_frame(d.path() / "a.png", 8, 6), expected, cv::NORM_INF), 0.0);
}

TEST(FrameIo, RejectsSixteenBitCorruptTruncatedAndMisSized) {
  TempDir d;
  cv::Mat deep(6, 8, CV_16UC1, cv::Scalar(1000));
  ASSERT_TRUE(cv::imwrite((d.path() / "deep.png").string(), deep));
  EXPECT_NE(message_of([&] { read_grey_frame(d.path() / "deep.png"); }).find("16-bit"),
            std::string::npos);

  std::ofstream(d.path() / "junk.png") << "definitely not a png";
  EXPECT_NE(message_of([&] { read_grey_frame(d.path() / "junk.png"); }).find("cannot decode"),
            std::string::npos);

  cv::Mat big(100, 120, CV_8UC1);
  cv::randu(big, 0, 255);
  std::vector<uchar> buf;
  ASSERT_TRUE(cv::imencode(".png", big, buf));
  std::ofstream(d.path() / "cut.png", std::ios::binary)
      .write(reinterpret_cast<const char*>(buf.data()),
             static_cast<std::streamsize>(buf.size() / 2));
  EXPECT_NE(message_of([&] { read_grey_frame(d.path() / "cut.png"); }).find("cannot decode"),
            std::string::npos);

  ASSERT_TRUE(cv::imwrite((d.path() / "ok.png").string(), big));
  EXPECT_NE(message_of([&] { read_grey_frame(d.path() / "ok.png", 640, 480); }).find("120x100"),
            std::string::npos);
  EXPECT_EQ(read_grey_frame(d.path() / "ok.png", 120, 100).rows, 100);
  EXPECT_NE(message_of([&] { read_grey_frame(d.path() / "missing.png"); }).find("cannot open"),
            std::string::npos);
}
