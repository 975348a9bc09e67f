// Charts through gnuplot: a PNG with its data file and script beside it, and a
// clear error naming the package when gnuplot is missing.
#include "apps/plot.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "host/tests/temp_dir.hpp"

namespace fs = std::filesystem;
using ceilnav::app::PlotPanel;
using ceilnav::app::write_plots;

namespace {

class TempDir : public ceilnav::test::TempDir {
 public:
  TempDir() : ceilnav::test::TempDir("ceilnav_plot") {}
};

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<PlotPanel> two_panels() {
  return {{"Quadratic, it's squared", "x", "y", {{"x^2", {0, 1, 2, 3}, {0, 1, 4, 9}}}},
          {"Two lines",
           "x",
           "y",
           {{"up", {0, 1, 2}, {-1, 0, 1}, {40, 40, 210}}, {"flat", {0, 2}, {0.5, 0.5}}}}};
}

}  // namespace

TEST(Plot, WritesPngWithDataAndScriptBeside) {
  TempDir d;
  const fs::path png = d.path() / "chart.png";
  write_plots(png, two_panels());
  const std::string bytes = read_all(png);
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_FALSE(fs::exists(d.path() / "chart.png.tmp"));

  const std::string dat = read_all(d.path() / "chart.dat");
  EXPECT_NE(dat.find("# panel 1 (Quadratic, it's squared): x^2\n0 0\n1 1\n2 4\n3 9\n"),
            std::string::npos);
  EXPECT_NE(dat.find("\n\n\n# panel 2 (Two lines): up\n0 -1\n"), std::string::npos);
  EXPECT_NE(dat.find("# panel 2 (Two lines): flat\n0 0.5\n2 0.5\n"), std::string::npos);

  const std::string gp = read_all(d.path() / "chart.gp");
  EXPECT_NE(gp.find("set output 'chart.png'"), std::string::npos);
  EXPECT_NE(gp.find("'chart.dat' index 2"), std::string::npos);
  EXPECT_NE(gp.find("lc rgb '#d22828'"), std::string::npos);
  EXPECT_NE(gp.find("'Quadratic, it''s squared'"), std::string::npos);
}

TEST(Plot, NonFinitePointsAreLeftOut) {
  TempDir d;
  const fs::path png = d.path() / "gaps.png";
  write_plots(png, {{"t", "x", "y", {{"s", {0, 1, 2}, {1, std::nan(""), 3}}}}});
  EXPECT_EQ(read_all(d.path() / "gaps.dat"), "# panel 1 (t): s\n0 1\n2 3\n");
  EXPECT_GT(fs::file_size(png), 0u);
}

TEST(Plot, MissingGnuplotNamesThePackage) {
  TempDir d;
  try {
    write_plots(d.path() / "none.png", two_panels(), 960, 360, "ceilnav-no-such-gnuplot");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("gnuplot-nox"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(d.path() / "none.png"));
}

TEST(Plot, MismatchedSeriesIsAnError) {
  TempDir d;
  EXPECT_THROW(write_plots(d.path() / "bad.png", {{"t", "x", "y", {{"s", {0, 1}, {1}}}}}),
               std::runtime_error);
}

TEST(Plot, DrawsSeriesInTheirColourAtTheAskedSize) {
  TempDir d;
  const fs::path png = d.path() / "blue.png";
  write_plots(png, {{"t", "x", "y", {{"a", {0, 1, 2}, {5, 7, 6}, cv::Scalar(255, 0, 0)}}}}, 400,
              300);
  const cv::Mat img = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  ASSERT_EQ(img.size(), cv::Size(400, 300));
  int blue = 0;
  for (int y = 0; y < img.rows; ++y) {
    for (int x = 0; x < img.cols; ++x) {
      const auto p = img.at<cv::Vec3b>(y, x);
      blue += p[0] > 200 && p[1] < 80 && p[2] < 80 ? 1 : 0;
    }
  }
  EXPECT_GT(blue, 50);
}
