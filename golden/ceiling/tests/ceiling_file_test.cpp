// Ceiling files (golden/ceiling/ceiling_file.hpp): the example file is the
// built-in homing world, a ceiling with every kind of feature reads back
// equal, degrees and radians, and bad files are refused naming the key.
#include "golden/ceiling/ceiling_file.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

namespace ceilnav::golden::ceiling {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

TEST(CeilingFile, TheExampleIsTheBuiltInWorld) {
  const CeilingFile f =
      load_ceiling(std::string(CEILNAV_SOURCE_DIR) + "/examples/homing/office.yaml");
  EXPECT_TRUE(f == default_homing_world());
}

TEST(CeilingFile, EveryFeatureReadsBackEqual) {
  CeilingFile f = default_homing_world();
  f.ceiling = hall_ceiling();  // beams, another tile pitch
  f.ceiling.tiles.angle_rad = 0.1;
  f.ceiling.vents[0].slats = 3;
  f.lighting.lamps_on = false;
  f.return_lighting.reset();
  f.camera.left_m = -0.02;
  f.sites.push_back({"a \"quoted\" name", 1.0 / 3.0, -2.0, 1e-17});
  const CeilingFile back = parse_ceiling(ceiling_to_yaml(f));
  EXPECT_TRUE(back == f);
  EXPECT_FALSE(back.return_lighting.has_value());
  EXPECT_TRUE(back.lighting_at_return() == back.lighting);
}

const char* kMinimal = R"(format: ceilnav_ceiling
version: 1
height_m: 3
camera: {height_m: 0.4, pitch_error_deg: 0.5}
sites:
  - {name: a, x_m: 0, y_m: 0, yaw_deg: 90}
  - {name: b, x_m: 2, y_m: 1, yaw_rad: 0.5}
)";

TEST(CeilingFile, DegreesRadiansAndDefaults) {
  const CeilingFile f = parse_ceiling(kMinimal);
  EXPECT_EQ(f.ceiling.height_m, 3.0);
  EXPECT_EQ(f.ceiling.tiles.pitch_x_m, 0.0);  // no tiles key: a plain ceiling
  EXPECT_NEAR(f.camera.pitch_error_rad, 0.5 * kDeg, 1e-15);
  ASSERT_EQ(f.sites.size(), 2u);
  EXPECT_NEAR(f.sites[0].yaw_rad, 90.0 * kDeg, 1e-15);
  EXPECT_EQ(f.sites[1].yaw_rad, 0.5);
  EXPECT_TRUE(f.lighting == Lighting{});
}

void expect_refused(const std::string& text, const std::string& words) {
  try {
    parse_ceiling(text, "test.yaml");
    ADD_FAILURE() << "accepted:\n" << text;
  } catch (const CeilingError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

std::string with(const std::string& from, const std::string& to) {
  std::string s = kMinimal;
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(CeilingFile, BadFilesAreRefusedWithTheKeyNamed) {
  expect_refused("{", "not YAML");
  expect_refused("- 1", "top level");
  expect_refused(with("ceilnav_ceiling", "ceilnav_corridor"), "format");
  expect_refused(with("version: 1", "version: 3"), "version");
  expect_refused(with("height_m: 3\n", ""), "height_m: missing");
  expect_refused(with("height_m: 3\n", "height_m: 3\ncolour: red\n"), "colour: unknown key");
  expect_refused(with("height_m: 0.4", "height_m: 3.2"), "camera.height_m");
  expect_refused(with("name: b", "name: a"), "sites[1].name");
  expect_refused(with("yaw_rad: 0.5", "yaw_rad: 0.5, yaw_deg: 3"), "sites[1].yaw");
  expect_refused(with("y_m: 1,", "y_m: north,"), "sites[1].y_m");
  expect_refused(with("{name: a, ", "{"), "sites[0].name: missing");
  expect_refused(std::string(kMinimal) +
                     "vents:\n  - {x_m: 0, y_m: 0, length_m: 0.5, width_m: "
                     "0.5, slats: 0}\n",
                 "vents[0]");
  expect_refused(
      std::string(kMinimal) + "lamps:\n  - {x_m: 0, y_m: 0, length_m: -1, width_m: 0.3}\n",
      "lamps[0]");
  expect_refused(std::string(kMinimal) + "lighting: {lamps_on: maybe}\n", "lighting.lamps_on");
  expect_refused(std::string(kMinimal) + "beams:\n  - {x0_m: 1, y0_m: 1, x1_m: 1, y1_m: 1}\n",
                 "beams[0]");
  EXPECT_THROW(load_ceiling("/nonexistent/ceiling.yaml"), CeilingError);
}

}  // namespace
}  // namespace ceilnav::golden::ceiling

namespace ceilnav::golden::ceiling {
namespace {

// The study ceilings (docs/homing.md, "Held-out ceilings") load, and each
// has three sites for the race.
TEST(CeilingFile, TheStudyCeilingsLoad) {
  int n = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::string(CEILNAV_SOURCE_DIR) + "/examples/homing")) {
    if (e.path().filename().string().rfind("study_", 0) != 0) continue;
    const CeilingFile f = load_ceiling(e.path().string());
    EXPECT_EQ(f.sites.size(), 3u) << e.path();
    ++n;
  }
  EXPECT_EQ(n, 5);
}

}  // namespace
}  // namespace ceilnav::golden::ceiling
