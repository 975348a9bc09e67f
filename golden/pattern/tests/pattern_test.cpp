#include "golden/pattern/pattern.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

namespace ceilnav::golden::pattern {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

host::CameraConfig plain_camera() {
  host::CameraConfig c;
  c.camera_matrix = {500.0, 0.0, 319.5, 0.0, 500.0, 239.5, 0.0, 0.0, 1.0};
  return c;
}

TEST(PatternCode, BlockValuesRoundTripAndSingleErrorsAreRejected) {
  for (int v = 0; v < kBlockValues; ++v) {
    const auto w = block_widths(v);
    ASSERT_EQ(block_value(w), v);
    for (std::size_t k = 0; k < w.size(); ++k) {  // any one width misread breaks the weight
      auto bad = w;
      bad[k] = 3 - bad[k];
      EXPECT_FALSE(block_value(bad).has_value());
    }
  }
  for (int id = 0; id < kIdentityCount; ++id) {
    const auto [l, r] = block_values(id);
    ASSERT_EQ(identity_from_blocks(l, r), id);
  }
  // The parity bit: exactly half of all value pairs are identities.
  int valid = 0;
  for (int l = 0; l < kBlockValues; ++l) {
    for (int r = 0; r < kBlockValues; ++r) valid += identity_from_blocks(l, r).has_value();
  }
  EXPECT_EQ(valid, kIdentityCount);
  EXPECT_THROW(block_values(kIdentityCount), std::invalid_argument);
}

TEST(PatternCode, LayoutIsMirroredWithFixedBlockLength) {
  const PatternGeometry g;
  const auto bars = bar_layout(g, 17);
  ASSERT_EQ(bars.size(), 12u);
  EXPECT_NEAR(bars.front().x0_m, block_outer_x_m(g), 1e-12);
  EXPECT_NEAR(bars.front().x1_m - bars.front().x0_m, 3 * g.bar_unit_m, 1e-12);
  EXPECT_NEAR(bars[5].x1_m, block_inner_x_m(g), 1e-12);
  EXPECT_NEAR(bars[6].x0_m, -block_inner_x_m(g), 1e-12);
  EXPECT_NEAR(bars.back().x1_m, -block_outer_x_m(g), 1e-12);
  for (std::size_t k = 1; k < bars.size(); ++k) EXPECT_GT(bars[k].x0_m, bars[k - 1].x1_m);
}

TEST(PatternCode, MirroredPrintIsAnotherIdentitysPrintOrFailsTheParity) {
  // The pattern's texture mirrored (x -> -x, bars then listed left to right):
  // where mirrored_identity has a value it is exactly that identity's layout;
  // where not, no identity has that layout (the swapped blocks fail the parity).
  const PatternGeometry g;
  int self = 0, other = 0, unreadable = 0;
  for (int id = 0; id < kIdentityCount; ++id) {
    std::vector<BarSpan> mirrored;
    for (const BarSpan& b : bar_layout(g, id))
      mirrored.insert(mirrored.begin(), {-b.x1_m, -b.x0_m});
    const auto [left, right] = block_values(id);
    const std::optional<int> m = mirrored_identity(id);
    EXPECT_EQ(m, identity_from_blocks(right, left)) << id;
    int same_layout = -1;
    for (int other_id = 0; other_id < kIdentityCount; ++other_id) {
      const auto bars = bar_layout(g, other_id);
      bool same = true;
      for (std::size_t k = 0; k < bars.size(); ++k) {
        same = same && std::abs(bars[k].x0_m - mirrored[k].x0_m) < 1e-12 &&
               std::abs(bars[k].x1_m - mirrored[k].x1_m) < 1e-12;
      }
      if (same) same_layout = other_id;
    }
    EXPECT_EQ(same_layout, m.value_or(-1)) << id;
    if (!m) {
      ++unreadable;
    } else if (*m == id) {
      ++self;
    } else {
      ++other;
      EXPECT_EQ(mirrored_identity(*m), id);  // mirroring twice gives the print back
    }
  }
  // docs/pattern.md, "Mirrored print": 6 identities (L == V) are their own
  // mirror image, 20 read as another identity, 24 are unreadable mirrored.
  EXPECT_EQ(self, 6);
  EXPECT_EQ(other, 20);
  EXPECT_EQ(unreadable, 24);
  EXPECT_EQ(mirrored_identity(13), 36);
}

TEST(PatternLut, NominalLevelsAndFalloffRangeMapToTheirClasses) {
  const Radiometry r;
  const auto lut = class_lut(r);
  for (PixelClass c :
       {PixelClass::background, PixelClass::pattern, PixelClass::shadow, PixelClass::bar}) {
    // +-3 sigma of noise 3 over the falloff of the wall panel (lamp 6 m in
    // front, panel +-3 m x +-1.5 m: 0.78) to the disc face (1.0).
    const double f_min = 36.0 / (36.0 + 9.0 + 2.25);
    for (double f : {f_min, 1.0}) {
      if (c != PixelClass::background && f < 1.0) continue;  // only the wall spans the panel
      for (double n : {-9.0, 0.0, 9.0}) {
        const double grey = r.black_level + (r.level(c) - r.black_level) * f + n;
        const int g = static_cast<int>(std::lround(std::clamp(grey, 0.0, 255.0)));
        EXPECT_EQ(lut[static_cast<std::size_t>(g)], static_cast<uint8_t>(c))
            << "class " << static_cast<int>(c) << " f " << f << " n " << n;
      }
    }
  }
  const auto mask = bar_mask_lut(r);
  for (unsigned g = 0; g < 256; ++g) {
    EXPECT_EQ((mask[g] & stream::kLutMaskBit) != 0, lut[g] == 3 || lut[g] == 1);
    // Remap: 255 - grey up to wall + dead zone (bar ink), then background +
    // the disc's coverage, rising to the full weight at the disc level.
    const unsigned remap = mask[g] & stream::kLutRemapMask;
    const double grey = static_cast<double>(g), wall = r.level(PixelClass::background);
    if (grey < wall + kCoverageDeadZone) {
      EXPECT_EQ(remap, 255 - g) << g;
    } else if (grey >= r.level(PixelClass::pattern) - kCoverageDeadZone) {
      EXPECT_EQ(remap, 255u) << g;
    } else {
      const double c = (grey - wall) / (r.level(PixelClass::pattern) - wall);
      EXPECT_NEAR(remap, bar_run_background(r) + disc_coverage_weight(r) * c, 0.5) << g;
    }
    EXPECT_EQ(stream::lut_class(mask[g]), lut[g]);
  }
  Radiometry bad;
  bad.albedo_shadow = 0.1;  // darker than the wall: order broken
  EXPECT_THROW(class_lut(bad), std::invalid_argument);
}

TEST(PatternRender, FrontalDiscMatchesTheAnalyticProjection) {
  // theta = 0: the disc projects to a circle of radius f R / D centred on the
  // principal point; its class area and centroid match to sub-pixel.
  const auto cam = plain_camera();
  const PatternGeometry g;
  PatternRenderParams p;
  p.noise_sigma_grey = 0.0;
  p.blur_sigma_px = 0.0;
  p.supersample = 8;
  for (double d : {1.5, 3.0}) {
    const PatternView v = spherical_view(d, 0.0, 0.0);
    const cv::Mat cls = classify(render_pattern(cam, g, Radiometry{}, 3, v, p), class_lut({}));
    const cv::Moments m = cv::moments(cls == 1, true);
    const double rpx = 500.0 * g.radius_m / d;
    EXPECT_NEAR(m.m00, std::numbers::pi * rpx * rpx, 0.002 * std::numbers::pi * rpx * rpx);
    EXPECT_NEAR(m.m10 / m.m00, 319.5, 0.02);
    EXPECT_NEAR(m.m01 / m.m00, 239.5, 0.02);
    // No side wall is visible head-on: the only shadow-class pixels are the
    // mixed disc/wall pixels on the rim (fewer than the perimeter).
    EXPECT_LT(cv::countNonZero(cls == 2), 2.0 * std::numbers::pi * rpx);
  }
}

TEST(PatternRender, ClassesAgreeWithTheExactSceneAwayFromEdges) {
  const auto cam = plain_camera();
  const PatternGeometry g;
  PatternRenderParams p;
  p.noise_sigma_grey = 3.0;
  p.blur_sigma_px = 0.5;
  const PatternView v = spherical_view(2.0, 40 * kDeg, 60 * kDeg, 5 * kDeg);
  const cv::Mat cls = classify(render_pattern(cam, g, Radiometry{}, 21, v, p), class_lut({}));
  const auto rays = pixel_rays(cam, false);
  int checked = 0, wrong = 0, counts[4] = {0, 0, 0, 0};
  for (int j = 2; j < cam.image_height - 2; ++j) {
    for (int i = 2; i < cam.image_width - 2; ++i) {
      // Only pixels whose 5 x 5 neighbourhood has one exact class.
      const PixelClass c0 = class_along_ray(g, 21, v, (i - 319.5) / 500.0, (j - 239.5) / 500.0);
      bool same = true;
      for (int dj = -2; dj <= 2 && same; dj += 2) {
        for (int di = -2; di <= 2 && same; di += 2) {
          same =
              class_along_ray(g, 21, v, (i + di - 319.5) / 500.0, (j + dj - 239.5) / 500.0) == c0;
        }
      }
      if (!same) continue;
      ++checked;
      ++counts[static_cast<int>(c0)];
      wrong += cls.at<uint8_t>(j, i) != static_cast<uint8_t>(c0);
    }
  }
  EXPECT_GT(checked, 200000);
  for (int c = 0; c < 4; ++c) EXPECT_GT(counts[c], 50) << "class " << c;
  EXPECT_EQ(wrong, 0);
}

TEST(PatternRender, ShadowLiesOnTheCameraSide) {
  // The visible side wall is on the side of the disc toward the camera's foot
  // on the wall: image direction (sin beta, -cos beta) at zero swing.
  const auto cam = plain_camera();
  PatternRenderParams p;
  p.noise_sigma_grey = 0.0;
  for (double beta_deg : {-150.0, -90.0, -30.0, 0.0, 45.0, 120.0, 180.0}) {
    const PatternView v = spherical_view(2.0, 45 * kDeg, beta_deg * kDeg);
    const cv::Mat cls = classify(render_pattern(cam, {}, {}, 0, v, p), class_lut({}));
    const cv::Moments md = cv::moments(cls == 1, true), ms = cv::moments(cls == 2, true);
    ASSERT_GT(ms.m00, 100.0);
    const double du = ms.m10 / ms.m00 - md.m10 / md.m00, dv = ms.m01 / ms.m00 - md.m01 / md.m00;
    // Perspective skews the crescent's centroid by up to ~10 deg; the side is what counts.
    const double cos_angle =
        (du * std::sin(beta_deg * kDeg) - dv * std::cos(beta_deg * kDeg)) / std::hypot(du, dv);
    EXPECT_GT(cos_angle, 0.95) << beta_deg;
  }
}

TEST(PatternTruth, SphericalViewTruthAndRobotView) {
  const PatternView v = spherical_view(3.0, 30 * kDeg, -70 * kDeg, 4 * kDeg);
  const PatternTruth t = pattern_truth(plain_camera(), {}, 5, v);
  EXPECT_NEAR(t.d_m, 3.0, 1e-12);
  EXPECT_NEAR(t.theta_rad, 30 * kDeg, 1e-12);
  EXPECT_NEAR(t.beta_rad, -70 * kDeg, 1e-12);
  EXPECT_NEAR(t.swing_rad, 4 * kDeg, 1e-12);
  EXPECT_NEAR(t.centre_px.x(), 319.5, 1e-9);
  EXPECT_NEAR(t.centre_px.y(), 239.5, 1e-9);
  // A robot camera at the pattern's height, 2 m in front, looking at it.
  PatternPlacement pl{7, 4.0, 1.0, 1.2, 180 * kDeg};
  RobotCamera rc{2.0, 1.0, 1.2, 0.0, 0.0, 0.0};
  const PatternView rv = robot_view(pl, rc);
  EXPECT_NEAR((rv.centre - Eigen::Vector3d(0, 0, 2.0)).norm(), 0.0, 1e-12);
  const PatternView lv = look_at(rv.centre, Eigen::Vector3d::Zero(), 0.0);
  EXPECT_NEAR((rv.rotation - lv.rotation).norm(), 0.0, 1e-12);
  EXPECT_NEAR(
      (pattern_to_world(pl, world_to_pattern(pl, {1, 2, 3})) - Eigen::Vector3d(1, 2, 3)).norm(),
      0.0, 1e-12);
}

TEST(PatternDatabaseIo, RoundTripAndErrors) {
  const auto dir = std::filesystem::temp_directory_path() / "ceilnav_pattern_db_test";
  std::filesystem::create_directories(dir);
  PatternDatabase db;
  db.geometry.radius_m = 0.2;
  db.patterns.push_back({3, 1.0, 2.0, 1.1, 90 * kDeg});
  db.patterns.push_back({44, -1.0, 0.5, 1.3, -45 * kDeg});
  const std::string path = (dir / "db.yaml").string();
  save_pattern_database(path, db);
  const PatternDatabase back = load_pattern_database(path);
  ASSERT_EQ(back.patterns.size(), 2u);
  EXPECT_DOUBLE_EQ(back.geometry.radius_m, 0.2);
  ASSERT_NE(back.find(44), nullptr);
  EXPECT_NEAR(back.find(44)->facing_rad, -45 * kDeg, 1e-12);
  EXPECT_EQ(back.find(5), nullptr);
  const std::string bad = (dir / "bad.yaml").string();
  std::ofstream(bad) << "%YAML:1.0\npatterns:\n  - { identity: 3, x_m: 1.0, y_m: 2.0 }\n";
  EXPECT_THROW(load_pattern_database(bad), std::runtime_error);
  std::ofstream(bad) << "%YAML:1.0\npatterns:\n  - { identity: 60, x_m: 1, y_m: 2, z_m: 1, "
                        "facing_deg: 0 }\n";
  EXPECT_THROW(load_pattern_database(bad), std::runtime_error);
  EXPECT_THROW(load_pattern_database((dir / "missing.yaml").string()), std::runtime_error);
  std::filesystem::remove_all(dir);
}

// The message of a database without patterns: an empty list, written by
// save_pattern_database or by hand, a missing key, a key of the wrong kind.
TEST(PatternDatabaseIo, EmptyDatabaseIsNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "ceilnav_pattern_db_empty_test";
  std::filesystem::create_directories(dir);
  const auto message = [](const std::string& path) -> std::string {
    try {
      load_pattern_database(path);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string saved = (dir / "saved.yaml").string();
  save_pattern_database(saved, PatternDatabase{});
  const std::string empty = (dir / "empty.yaml").string();
  std::ofstream(empty) << "%YAML:1.0\npatterns: []\n";
  for (const std::string& p : {saved, empty}) {
    const std::string m = message(p);
    EXPECT_NE(m.find(p), std::string::npos) << m;
    EXPECT_NE(m.find("has no patterns (key patterns is an empty sequence)"), std::string::npos)
        << m;
  }
  const std::string none = (dir / "none.yaml").string();
  std::ofstream(none) << "%YAML:1.0\ngeometry: { radius_m: 0.2 }\n";
  EXPECT_NE(message(none).find("missing key patterns"), std::string::npos) << message(none);
  const std::string map = (dir / "map.yaml").string();
  std::ofstream(map) << "%YAML:1.0\npatterns: { identity: 3 }\n";
  EXPECT_NE(message(map).find("key patterns is not a sequence"), std::string::npos) << message(map);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ceilnav::golden::pattern
