#include "host/camera_config_io.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <opencv2/core.hpp>

namespace ceilnav::host {
namespace {

namespace fs = std::filesystem;

class ConfigIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ceilnav_cfg_io_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string p = path(name);
    std::ofstream(p) << text;
    return p;
  }
  fs::path dir_;
};

// Key -> YAML value text; a complete valid file by default.
std::map<std::string, std::string> valid_keys() {
  return {
      {"image_width", "640"},
      {"image_height", "480"},
      {"camera_matrix",
       "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 510.5, 0., 321.25, 0., "
       "505.75, "
       "238.5, 0., 0., 1. ]"},
      {"distortion_coefficients",
       "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ -0.1, 0.02, 0.001, -0.002, "
       "0.003 ]"},
      {"camera_pitch_deg", "45."},
      {"camera_height_m", "0.5"},
      {"ceiling_height_m", "3.0"},
      {"tape_width_m", "0.05"},
  };
}

std::string yaml(const std::map<std::string, std::string>& keys) {
  std::string s = "%YAML:1.0\n---\n";
  for (const auto& [k, v] : keys) s += k + ": " + v + "\n";
  return s;
}

// Expects ConfigError whose message contains every string in `needles`.
template <typename F>
void expect_config_error(F&& f, std::initializer_list<std::string> needles) {
  try {
    f();
    ADD_FAILURE() << "no ConfigError thrown";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    for (const auto& n : needles)
      EXPECT_NE(msg.find(n), std::string::npos) << msg << " lacks " << n;
  }
}

TEST_F(ConfigIoTest, ReadsValidFile) {
  const std::string p = write("ok.yaml", yaml(valid_keys()));
  const CameraConfig c = load_camera_config(p);
  EXPECT_EQ(c.image_width, 640);
  EXPECT_EQ(c.image_height, 480);
  EXPECT_EQ(c.fx(), 510.5);
  EXPECT_EQ(c.fy(), 505.75);
  EXPECT_EQ(c.cx(), 321.25);
  EXPECT_EQ(c.cy(), 238.5);
  EXPECT_EQ(c.distortion_coefficients[0], -0.1);
  EXPECT_EQ(c.distortion_coefficients[4], 0.003);
  EXPECT_EQ(c.camera_pitch_deg, 45.0);
  EXPECT_EQ(c.camera_height_m, 0.5);
  EXPECT_EQ(c.ceiling_height_m, 3.0);
  EXPECT_EQ(c.tape_width_m, 0.05);
}

TEST_F(ConfigIoTest, RoundTripIsExact) {
  CameraConfig c;
  c.image_width = 1280;
  c.image_height = 960;
  c.camera_matrix = {
      1012.3456789012345, 0, 641.123456789, 0, 1009.87654321, 477.000000001, 0, 0, 1};
  c.distortion_coefficients = {-0.2876543210987, 0.0912345678, 1.234e-4, -5.678e-5, -0.0123456789};
  c.camera_pitch_deg = 37.123456789;
  c.camera_height_m = 0.4321;
  c.ceiling_height_m = 2.987654321;
  c.tape_width_m = 0.0254;
  const std::string p = path("rt.yaml");
  save_camera_config(c, p);
  const CameraConfig r = load_camera_config(p);
  EXPECT_EQ(r.image_width, c.image_width);
  EXPECT_EQ(r.image_height, c.image_height);
  EXPECT_EQ(r.camera_matrix, c.camera_matrix);
  EXPECT_EQ(r.distortion_coefficients, c.distortion_coefficients);
  EXPECT_EQ(r.camera_pitch_deg, c.camera_pitch_deg);
  EXPECT_EQ(r.camera_height_m, c.camera_height_m);
  EXPECT_EQ(r.ceiling_height_m, c.ceiling_height_m);
  EXPECT_EQ(r.tape_width_m, c.tape_width_m);

  // The file is what a cv::calibrateCamera user writes: 3x3 and 1x5 CV_64F matrices.
  cv::FileStorage fsr(p, cv::FileStorage::READ);
  cv::Mat k, d;
  fsr["camera_matrix"] >> k;
  fsr["distortion_coefficients"] >> d;
  EXPECT_EQ(k.type(), CV_64F);
  EXPECT_EQ(k.rows, 3);
  EXPECT_EQ(k.cols, 3);
  EXPECT_EQ(d.rows, 1);
  EXPECT_EQ(d.cols, 5);
  EXPECT_EQ(d.at<double>(0, 0), c.distortion_coefficients[0]);
  EXPECT_EQ(static_cast<int>(fsr["image_width"]), 1280);
}

TEST_F(ConfigIoTest, AcceptsColumnAndFourCoefficientDistortion) {
  auto keys = valid_keys();
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n   data: [ -0.1, 0.02, 0.003, 0.004, "
      "0.05 ]";
  CameraConfig c = load_camera_config(write("col.yaml", yaml(keys)));
  EXPECT_EQ(c.distortion_coefficients, (std::array<double, 5>{-0.1, 0.02, 0.003, 0.004, 0.05}));
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: f\n   data: [ -0.125, 0.0625, 0.0009765625, "
      "-0.001953125 ]";
  c = load_camera_config(write("four.yaml", yaml(keys)));
  EXPECT_EQ(c.distortion_coefficients,
            (std::array<double, 5>{-0.125, 0.0625, 0.0009765625, -0.001953125, 0.0}));
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]";
  c = load_camera_config(write("zero.yaml", yaml(keys)));
  EXPECT_FALSE(c.has_distortion());
}

TEST_F(ConfigIoTest, EightCoefficientsOnlyWithTheExtraTermsZero) {
  auto keys = valid_keys();
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 1\n   cols: 8\n   dt: d\n   data: [ -0.1, 0.02, 0.003, 0.004, "
      "0.05, "
      "0., 0., 0. ]";
  const CameraConfig c = load_camera_config(write("eight.yaml", yaml(keys)));
  EXPECT_EQ(c.distortion_coefficients, (std::array<double, 5>{-0.1, 0.02, 0.003, 0.004, 0.05}));
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 1\n   cols: 8\n   dt: d\n   data: [ 0.1, 0.2, 0.3, 0.4, 0.5, "
      "0.01, 0., 0. ]";
  const std::string p = write("rational.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(p); },
                      {"rational.yaml", "distortion_coefficients", "beyond k3"});
  keys["distortion_coefficients"] =
      "!!opencv-matrix\n   rows: 1\n   cols: 6\n   dt: d\n   data: [ 0.1, 0.2, 0.3, 0.4, 0.5, "
      "0. ]";
  const std::string p6 = write("six.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(p6); }, {"six.yaml", "distortion_coefficients"});
}

TEST_F(ConfigIoTest, EveryMissingKeyIsNamed) {
  for (const auto& [key, value] : valid_keys()) {
    auto keys = valid_keys();
    keys.erase(key);
    const std::string p = write("missing_" + key + ".yaml", yaml(keys));
    expect_config_error([&] { load_camera_config(p); }, {p, key, "missing"});
  }
}

TEST_F(ConfigIoTest, WrongTypesAreNamed) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"image_width", "abc"},
      {"image_width", "640.5"},
      {"image_height", "[ 1, 2 ]"},
      {"camera_matrix", "500."},
      {"camera_matrix",
       "!!opencv-matrix\n   rows: 2\n   cols: 3\n   dt: d\n   data: [ 1., 0., 1., 0., 1., 1. ]"},
      {"camera_matrix", "{ a: 1 }"},
      {"distortion_coefficients",
       "!!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   data: [ 0., 0., 0. ]"},
      {"distortion_coefficients",
       "!!opencv-matrix\n   rows: 2\n   cols: 4\n   dt: d\n   data: [ 0., 0., 0., 0., 0., 0., 0., "
       "0. ]"},
      {"camera_pitch_deg", "steep"},
      {"camera_height_m", "[ 0.5 ]"},
      {"ceiling_height_m", "\"3.0\""},
      {"tape_width_m", "{ w: 0.05 }"},
  };
  int i = 0;
  for (const auto& [key, value] : cases) {
    auto keys = valid_keys();
    keys[key] = value;
    const std::string p = write("type_" + std::to_string(i++) + ".yaml", yaml(keys));
    expect_config_error([&] { load_camera_config(p); }, {p, key});
  }
}

TEST_F(ConfigIoTest, OutOfRangeValuesAreNamed) {
  const std::string k_head = "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: ";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"image_width", "0"},
      {"image_width", "2049"},
      {"image_height", "-480"},
      {"image_height", "4096"},
      {"camera_matrix", k_head + "[ -500., 0., 320., 0., 500., 240., 0., 0., 1. ]"},
      {"camera_matrix", k_head + "[ 500., 0., 320., 0., 0., 240., 0., 0., 1. ]"},
      {"camera_matrix", k_head + "[ 500., 0., 700., 0., 500., 240., 0., 0., 1. ]"},
      {"camera_matrix", k_head + "[ 500., 0., 320., 0., 500., -3., 0., 0., 1. ]"},
      {"camera_matrix", k_head + "[ 500., 2., 320., 0., 500., 240., 0., 0., 1. ]"},
      {"camera_matrix", k_head + "[ 500., 0., 320., 0., 500., 240., 0., 0., 2. ]"},
      {"camera_pitch_deg", "0."},
      {"camera_pitch_deg", "-10."},
      {"camera_pitch_deg", "90.5"},
      {"camera_pitch_deg", ".nan"},
      {"ceiling_height_m", "0.5"},
      {"ceiling_height_m", "0.2"},
      {"tape_width_m", "0."},
      {"tape_width_m", "-0.05"},
  };
  int i = 0;
  for (const auto& [key, value] : cases) {
    auto keys = valid_keys();
    keys[key] = value;
    const std::string p = write("range_" + std::to_string(i++) + ".yaml", yaml(keys));
    expect_config_error([&] { load_camera_config(p); }, {p, key});
  }
  // Edge of the ranges: accepted.
  auto keys = valid_keys();
  keys["camera_pitch_deg"] = "90.";
  keys["image_width"] = "2048";
  keys["image_height"] = "1";
  keys["camera_matrix"] = k_head + "[ 500., 0., 2047.5, 0., 500., -0.5, 0., 0., 1. ]";
  EXPECT_NO_THROW(load_camera_config(write("edge.yaml", yaml(keys))));
}

TEST_F(ConfigIoTest, UnreadableFilesAreNamed) {
  const std::string none = path("does_not_exist.yaml");
  expect_config_error([&] { load_camera_config(none); }, {none, "no such file"});
  const std::string empty = write("empty.yaml", "");
  expect_config_error([&] { load_camera_config(empty); }, {empty, "empty"});
  const std::string garbage = write("garbage.yaml", "%YAML:1.0\n{{{: [ ]] :\x01\x02 \n");
  expect_config_error([&] { load_camera_config(garbage); }, {garbage});
  const std::string text = write("text.yaml", "this is not a configuration\n");
  expect_config_error([&] { load_camera_config(text); }, {text});
  const std::string scalar = write("scalar.yaml", "%YAML:1.0\n--- 42\n");
  expect_config_error([&] { load_camera_config(scalar); }, {scalar});
  expect_config_error([&] { load_camera_config(dir_.string()); }, {dir_.string()});
}

TEST_F(ConfigIoTest, SaveRejectsBadConfigAndUnwritablePath) {
  CameraConfig bad;
  bad.tape_width_m = -1.0;
  const std::string p = path("bad.yaml");
  expect_config_error([&] { save_camera_config(bad, p); }, {p, "tape_width_m"});
  EXPECT_FALSE(fs::exists(p));
  const std::string q = (dir_ / "no_such_dir" / "x.yaml").string();
  expect_config_error([&] { save_camera_config(CameraConfig{}, q); }, {q});
}

// A 640x480 sensor with its principal point at the centre and focal length f.
CameraConfig lens(double f, std::array<double, 5> k) {
  CameraConfig c;
  c.camera_matrix = {f, 0.0, 319.5, 0.0, f, 239.5, 0.0, 0.0, 1.0};
  c.distortion_coefficients = k;
  return c;
}

std::string matrix_yaml(const std::array<double, 5>& k) {
  std::string s = "!!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ ";
  for (size_t i = 0; i < k.size(); ++i) s += (i ? ", " : "") + std::to_string(k[i]);
  return s + " ]";
}

TEST_F(ConfigIoTest, InvertibleLensesPass) {
  // A wide-angle lens (90 deg across at f = 400 px): its radial map
  // rises past the corner's r_d = 1.0 before it turns back (r = 1.86, r_d = 1.14).
  const std::array<double, 5> wide{-0.28, 0.09, 0.0012, -0.0008, -0.012};
  EXPECT_FALSE(distortion_fold(lens(400.0, wide)).has_value());
  EXPECT_NO_THROW(validate_camera_config(lens(400.0, wide), "wide"));
  // The same lens, narrower sensor view, and the project's cameras.
  EXPECT_FALSE(distortion_fold(lens(520.0, wide)).has_value());
  EXPECT_FALSE(distortion_fold(lens(500.0, {-0.25, 0.08, 8e-4, -6e-4, -0.01})).has_value());
  EXPECT_FALSE(distortion_fold(lens(500.0, {-0.08, 0.015, 4e-4, -3e-4, 0.0})).has_value());
  EXPECT_FALSE(distortion_fold(lens(500.0, {0.3, 0.1, 0.0, 0.0, 0.0})).has_value());  // pincushion
  EXPECT_FALSE(distortion_fold(lens(500.0, {})).has_value());
  auto keys = valid_keys();
  keys["camera_matrix"] =
      "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 400., 0., 319.5, 0., "
      "400., 239.5, 0., 0., 1. ]";
  keys["distortion_coefficients"] = matrix_yaml(wide);
  EXPECT_NO_THROW(load_camera_config(write("wide.yaml", yaml(keys))));
}

TEST_F(ConfigIoTest, NonInvertibleDistortionIsRefused) {
  // k1 = -0.5: d r_d / d r = 1 - 1.5 r^2 = 0 at r = 0.816, where r_d = 0.544,
  // short of the corner's r_d = sqrt(320^2 + 240^2) / 500 = 0.8.
  const std::array<double, 5> barrel{-0.5, 0.0, 0.0, 0.0, 0.0};
  const auto why = distortion_fold(lens(500.0, barrel));
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("turns back at r = 0.816 (r_d = 0.544), inside the image corner r_d = 0.800"),
            std::string::npos)
      << *why;
  auto keys = valid_keys();
  keys["camera_matrix"] =
      "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 319.5, 0., "
      "500., 239.5, 0., 0., 1. ]";
  keys["distortion_coefficients"] = matrix_yaml(barrel);
  const std::string p = write("fold.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(p); },
                      {p, "distortion_coefficients", "not invertible over the image",
                       "turns back at r = 0.816", "inside the image corner r_d = 0.800"});
  // camera_only reads the lens all the same.
  expect_config_error([&] { load_camera_config(p, ConfigKeys::camera_only); },
                      {p, "distortion_coefficients", "not invertible"});
  // Nor is such a lens written.
  const std::string q = path("fold_out.yaml");
  expect_config_error([&] { save_camera_config(lens(500.0, barrel), q); },
                      {q, "distortion_coefficients", "not invertible"});
  EXPECT_FALSE(fs::exists(q));
  // The same lens behind a longer focal length sees only r_d <= 0.5: accepted.
  EXPECT_FALSE(distortion_fold(lens(800.0, barrel)).has_value());
  // A lens that turns back outside the image but below the corner radius:
  // k1 = -0.25 at f = 500 peaks at r_d = 0.770 < 0.8.
  const auto near = distortion_fold(lens(500.0, {-0.25, 0.0, 0.0, 0.0, 0.0}));
  ASSERT_TRUE(near.has_value());
  EXPECT_NE(near->find("turns back at r = 1.155 (r_d = 0.770)"), std::string::npos) << *near;
  // Pincushion that falls back: k1 = 0.2, k3 = -1 turns at r = 0.760 (r_d =
  // 0.701); with k3 = -0.5 it turns at r = 0.863, past the corner (r_d = 0.813).
  const auto pincushion = distortion_fold(lens(500.0, {0.2, 0.0, 0.0, 0.0, -1.0}));
  ASSERT_TRUE(pincushion.has_value());
  EXPECT_NE(pincushion->find("turns back at r = 0.760 (r_d = 0.701)"), std::string::npos)
      << *pincushion;
  EXPECT_FALSE(distortion_fold(lens(500.0, {0.2, 0.0, 0.0, 0.0, -0.5})).has_value());
  // Radially fine but the tangential terms fold the map inside the image.
  const auto tangential = distortion_fold(lens(500.0, {-0.05, 0.0, 0.3, 0.0, 0.0}));
  ASSERT_TRUE(tangential.has_value());
  EXPECT_NE(tangential->find("folds"), std::string::npos) << *tangential;
  EXPECT_NE(tangential->find("p1, p2"), std::string::npos) << *tangential;
  // A positive k2 does not save k1 = -0.5 at f = 500: d r_d / d r =
  // 1 - 1.5 r^2 + 0.5 r^4 = 0 at r = 1, where r_d = 0.6 < 0.8.
  EXPECT_TRUE(distortion_fold(lens(500.0, {-0.5, 0.1, 0.0, 0.0, 0.0})).has_value());
}

TEST_F(ConfigIoTest, CameraOnlyNeedsNoSceneKeys) {
  auto keys = valid_keys();
  for (const char* k :
       {"camera_pitch_deg", "camera_height_m", "ceiling_height_m", "tape_width_m"}) {
    keys.erase(k);
  }
  const std::string p = write("lens_only.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(p); }, {p, "missing"});
  const CameraConfig c = load_camera_config(p, ConfigKeys::camera_only);
  const CameraConfig defaults;
  EXPECT_EQ(c.image_width, 640);
  EXPECT_EQ(c.fx(), 510.5);
  EXPECT_EQ(c.distortion_coefficients[0], -0.1);
  EXPECT_EQ(c.camera_pitch_deg, defaults.camera_pitch_deg);
  EXPECT_EQ(c.camera_height_m, defaults.camera_height_m);
  EXPECT_EQ(c.ceiling_height_m, defaults.ceiling_height_m);
  EXPECT_EQ(c.tape_width_m, defaults.tape_width_m);
  // A present scene key is still read and checked.
  keys["tape_width_m"] = "0.025";
  EXPECT_EQ(
      load_camera_config(write("tape.yaml", yaml(keys)), ConfigKeys::camera_only).tape_width_m,
      0.025);
  keys["tape_width_m"] = "-1.";
  const std::string bad = write("bad_tape.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(bad, ConfigKeys::camera_only); },
                      {bad, "tape_width_m"});
  keys["tape_width_m"] = "wide";
  const std::string typo = write("typo_tape.yaml", yaml(keys));
  expect_config_error([&] { load_camera_config(typo, ConfigKeys::camera_only); },
                      {typo, "tape_width_m"});
  // The camera keys stay required.
  for (const char* k :
       {"image_width", "image_height", "camera_matrix", "distortion_coefficients"}) {
    auto lens_keys = valid_keys();
    lens_keys.erase(k);
    const std::string q = write(std::string("no_") + k + ".yaml", yaml(lens_keys));
    expect_config_error([&] { load_camera_config(q, ConfigKeys::camera_only); }, {q, k, "missing"});
  }
}

// The reader parses the file itself (yaml-cpp, pugixml), not through
// cv::FileStorage: on every valid file of the fuzz corpus, in YAML, JSON and
// XML, and on files written by cv::FileStorage in each format, it must read
// exactly what cv::FileStorage reads.
CameraConfig read_with_opencv(const std::string& p) {
  cv::FileStorage in(p, cv::FileStorage::READ);
  EXPECT_TRUE(in.isOpened()) << p;
  CameraConfig c;
  c.image_width = static_cast<int>(in["image_width"]);
  c.image_height = static_cast<int>(in["image_height"]);
  cv::Mat k, d;
  in["camera_matrix"] >> k;
  in["distortion_coefficients"] >> d;
  k.convertTo(k, CV_64F);
  d.convertTo(d, CV_64F);
  for (int i = 0; i < 9; ++i) c.camera_matrix[static_cast<size_t>(i)] = k.at<double>(i / 3, i % 3);
  c.distortion_coefficients = {};
  for (int i = 0; i < std::min(5, static_cast<int>(d.total())); ++i) {
    c.distortion_coefficients[static_cast<size_t>(i)] = d.at<double>(i);
  }
  c.camera_pitch_deg = static_cast<double>(in["camera_pitch_deg"]);
  c.camera_height_m = static_cast<double>(in["camera_height_m"]);
  c.ceiling_height_m = static_cast<double>(in["ceiling_height_m"]);
  c.tape_width_m = static_cast<double>(in["tape_width_m"]);
  return c;
}

void expect_same(const CameraConfig& a, const CameraConfig& b, const std::string& what) {
  EXPECT_EQ(a.image_width, b.image_width) << what;
  EXPECT_EQ(a.image_height, b.image_height) << what;
  EXPECT_EQ(a.camera_matrix, b.camera_matrix) << what;
  EXPECT_EQ(a.distortion_coefficients, b.distortion_coefficients) << what;
  EXPECT_EQ(a.camera_pitch_deg, b.camera_pitch_deg) << what;
  EXPECT_EQ(a.camera_height_m, b.camera_height_m) << what;
  EXPECT_EQ(a.ceiling_height_m, b.ceiling_height_m) << what;
  EXPECT_EQ(a.tape_width_m, b.tape_width_m) << what;
}

TEST_F(ConfigIoTest, ReadsWhatOpenCvReadsInYamlJsonAndXml) {
  int files = 0;
  for (const auto& e :
       fs::directory_iterator(fs::path(CEILNAV_SOURCE_DIR) / "fuzz/corpus/scene_yaml")) {
    if (e.path().filename().string().rfind("valid", 0) != 0) continue;
    expect_same(load_camera_config(e.path().string()), read_with_opencv(e.path().string()),
                e.path().string());
    ++files;
  }
  EXPECT_GE(files, 5);
  // Written by cv::FileStorage itself, one file per format, with values
  // that print with many digits.
  CameraConfig c = load_camera_config(write("v.yaml", yaml(valid_keys())));
  c.camera_matrix[0] = 512.0 / 3.0;
  c.distortion_coefficients[0] = -1e-7 / 3.0;
  c.tape_width_m = 0.1 + 0.2;
  for (const char* ext : {".yaml", ".json", ".xml"}) {
    const std::string p = path(std::string("opencv") + ext);
    {
      cv::FileStorage out(p, cv::FileStorage::WRITE);
      const cv::Mat k(3, 3, CV_64F, c.camera_matrix.data());
      const cv::Mat d(1, 5, CV_64F, c.distortion_coefficients.data());
      out << "image_width" << c.image_width << "image_height" << c.image_height;
      out << "camera_matrix" << k << "distortion_coefficients" << d;
      out << "camera_pitch_deg" << c.camera_pitch_deg << "camera_height_m" << c.camera_height_m;
      out << "ceiling_height_m" << c.ceiling_height_m << "tape_width_m" << c.tape_width_m;
    }
    expect_same(load_camera_config(p), c, p);
    expect_same(load_camera_config(p), read_with_opencv(p), p);
  }
}

}  // namespace
}  // namespace ceilnav::host
