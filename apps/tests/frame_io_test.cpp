// Frame reading and atomic output: every bad input is a clear error.
#include "apps/frame_io.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "apps/atomic_file.hpp"

namespace fs = std::filesystem;
using ceilnav::app::AtomicFile;
using ceilnav::app::InputError;
using ceilnav::app::list_png_frames;
using ceilnav::app::OutputFolder;
using ceilnav::app::read_grey_frame;

namespace {

class TempDir {
 public:
  TempDir() {
    path_ =
        fs::temp_directory_path() /
        ("ceilnav_frame_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
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

TEST(AtomicFile, NothingAppearsUntilCommit) {
  TempDir d;
  const fs::path dest = d.path() / "out.csv";
  {
    AtomicFile f(dest);
    f.stream() << "partial";
    EXPECT_FALSE(fs::exists(dest));
  }  // destroyed without commit
  EXPECT_FALSE(fs::exists(dest));
  EXPECT_TRUE(fs::is_empty(d.path()));  // no temporary left behind
  {
    AtomicFile f(dest);
    f.stream() << "whole\n";
    f.commit();
  }
  std::ifstream in(dest);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "whole");
}

TEST(AtomicFile, UnwritableDestinations) {
  TempDir d;
  EXPECT_THROW(AtomicFile(d.path() / "missing" / "x.csv"), std::runtime_error);
  EXPECT_THROW(AtomicFile(d.path()), std::runtime_error);  // a folder
  std::ofstream(d.path() / "file") << "x";
  EXPECT_THROW(AtomicFile(d.path() / "file" / "x.csv"), std::runtime_error);
}

TEST(OutputFolder, FilesAppearOnlyOnCommit) {
  TempDir d;
  const fs::path out = d.path() / "a" / "b";
  {
    OutputFolder f(out);
    std::ofstream(f.path("x.csv")) << "x";
    std::ofstream(f.path(fs::path("frames") / "y.png")) << "y";
    EXPECT_FALSE(fs::exists(out / "x.csv"));
  }  // destroyed without commit: the folders it created are gone too
  EXPECT_FALSE(fs::exists(d.path() / "a"));
  {
    OutputFolder f(out);
    std::ofstream(f.path("x.csv")) << "x";
    std::ofstream(f.path(fs::path("frames") / "y.png")) << "y";
    f.commit();
  }
  EXPECT_TRUE(fs::is_regular_file(out / "x.csv"));
  EXPECT_TRUE(fs::is_regular_file(out / "frames" / "y.png"));
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(out)) entries += e.path().filename() != "" ? 1u : 0u;
  EXPECT_EQ(entries, 2u);  // x.csv and frames/, no staging folder
  {
    OutputFolder f(out);  // exists: kept as it was without commit
    std::ofstream(f.path("z.csv")) << "z";
  }
  EXPECT_TRUE(fs::exists(out / "x.csv"));
  EXPECT_FALSE(fs::exists(out / "z.csv"));
  {
    // "..", "." and a trailing separator: only "c" is created, and removed.
    OutputFolder f(d.path() / "x" / ".." / "c" / "." / "");
    std::ofstream(f.path("x.csv")) << "x";
  }
  EXPECT_FALSE(fs::exists(d.path() / "x"));
  EXPECT_FALSE(fs::exists(d.path() / "c"));
  std::ofstream(d.path() / "file") << "f";
  EXPECT_THROW(OutputFolder(d.path() / "file"), std::runtime_error);
  EXPECT_THROW(OutputFolder(d.path() / "file" / "sub"), std::runtime_error);
}
