// The topological site map (host/homing/site_map.hpp): paths between poses,
// a map written and read back (patches to 1/256 grey), and every kind of
// bad map file refused with the file and key named.
#include "host/homing/site_map.hpp"

#include <cmath>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "host/tests/temp_dir.hpp"

namespace ceilnav::host::homing {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(SiteMap, PathBetweenPosesTurnsDrivesAndTurns) {
  const OdometricPath p = path_between({1.0, 1.0, 0.5}, {1.0, 3.0, -2.0}, 0, 1);
  EXPECT_NEAR(p.distance_m, 2.0, 1e-12);
  EXPECT_NEAR(p.turn_rad, kPi / 2 - 0.5, 1e-12);
  // Turns wrap: -2 - pi/2 is -3.57, more than half a turn.
  EXPECT_NEAR(p.final_turn_rad, -2.0 - kPi / 2 + 2 * kPi, 1e-12);
  const OdometricPath q = path_between({0, 0, 3.0}, {-1.0, 0.0, -3.0}, 1, 0);
  EXPECT_NEAR(q.turn_rad, std::remainder(kPi - 3.0, 2 * kPi), 1e-12);
  EXPECT_NEAR(q.final_turn_rad, std::remainder(-3.0 - kPi, 2 * kPi), 1e-12);
}

SiteMap small_map() {
  SiteMap m;
  for (int k = 0; k < 2; ++k) {
    MapSite s;
    s.name = "site " + std::to_string(k + 1);
    s.pose = {1.0 * k, -0.5 * k, 0.3 * k};
    s.look_forward_m = 0.11;
    s.look_left_m = -0.01 * k;
    if (k == 1) s.unusable = "found again at 1 of 6 turns";
    s.site.options.template_px = 32;
    const int side = static_cast<int>(std::ceil(32 * std::sqrt(2.0))) + 4;
    s.site.patch = cv::Mat(side, side, CV_32FC1);
    cv::randu(s.site.patch, 0.0, 255.0);
    s.site.major_orientation_deg = 12.5 * k;
    s.site.self_similarity = 0.3;
    s.site.rotational_similarity = 0.05;
    m.sites.push_back(s);
  }
  m.paths = {path_between(m.sites[0].pose, m.sites[1].pose, 0, 1),
             path_between(m.sites[1].pose, m.sites[0].pose, 1, 0)};
  return m;
}

TEST(SiteMap, ReadsBackWhatItWrote) {
  const test::TempDir dir("site_map");
  const SiteMap m = small_map();
  save_site_map(m, dir.path().string());
  const SiteMap r = load_site_map((dir.path() / "map.json").string());
  ASSERT_EQ(r.sites.size(), 2u);
  ASSERT_EQ(r.paths.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(r.sites[k].name, m.sites[k].name);
    EXPECT_EQ(r.sites[k].pose.x_m, m.sites[k].pose.x_m);
    EXPECT_EQ(r.sites[k].pose.yaw_rad, m.sites[k].pose.yaw_rad);
    EXPECT_EQ(r.sites[k].look_left_m, m.sites[k].look_left_m);
    EXPECT_EQ(r.sites[k].unusable, m.sites[k].unusable);
    EXPECT_EQ(r.sites[k].site.options.template_px, 32);
    EXPECT_EQ(r.sites[k].site.major_orientation_deg, m.sites[k].site.major_orientation_deg);
    double worst = 0.0;
    cv::minMaxLoc(cv::abs(r.sites[k].site.patch - m.sites[k].site.patch), nullptr, &worst);
    EXPECT_LE(worst, 0.5 / 256.0 + 1e-6);
  }
  EXPECT_EQ(r.paths[1].from, 1);
  EXPECT_EQ(r.paths[1].distance_m, m.paths[1].distance_m);
  ASSERT_NE(r.path_from(1), nullptr);
  EXPECT_EQ(r.path_from(1)->to, 0);
  EXPECT_EQ(r.path_from(5), nullptr);
}

void expect_refused(const std::string& json_text, const std::string& words,
                    const std::filesystem::path& dir) {
  {
    std::ofstream f(dir / "map.json");
    f << json_text;
  }
  try {
    load_site_map((dir / "map.json").string());
    ADD_FAILURE() << "accepted: " << json_text;
  } catch (const SiteMapError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(SiteMap, BadFilesAreRefusedWithTheKeyNamed) {
  const test::TempDir dir("site_map_bad");
  save_site_map(small_map(), dir.path().string());
  std::ifstream in(dir.path() / "map.json");
  const std::string good((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  expect_refused("{not json", "not JSON", dir.path());
  expect_refused(with("ceilnav_site_map", "other"), "format", dir.path());
  expect_refused(with("\"version\": 1", "\"version\": 2"), "version", dir.path());
  expect_refused(with("\"to\": 0", "\"to\": 7"), "paths[1]", dir.path());
  expect_refused(with("\"x_m\": 0.0", "\"x_m\": \"a\""), "sites[0].x_m", dir.path());
  expect_refused(with("site_1.png", "missing.png"), "missing.png", dir.path());
  expect_refused(with("\"template_px\": 32", "\"template_px\": 40"), "px square", dir.path());
  EXPECT_THROW(load_site_map((dir.path() / "absent.json").string()), SiteMapError);
}

}  // namespace
}  // namespace ceilnav::host::homing
