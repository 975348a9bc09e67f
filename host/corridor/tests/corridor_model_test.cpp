#include "host/corridor/corridor_model.hpp"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "golden/scene.hpp"
#include "host/corridor/tests/corridor_scene.hpp"

namespace ceilnav::host::corridor {
namespace {

using testing::ceiling_lines;
using testing::corridor_camera;
using testing::corridor_mount;
using testing::kDeg;
using testing::pose_at;

TEST(CorridorModel, RotationIsTheGoldenOne) {
  for (double pan : {-0.3, 0.0, 0.07, 1.2}) {
    for (double tilt : {0.0, 0.61, 1.2}) {
      for (double swing : {-0.05, 0.0, 0.2}) {
        const Eigen::Matrix3d a = world_to_camera(pan, tilt, swing);
        const Eigen::Matrix3d b = golden::world_to_camera_rotation(pan, tilt, swing);
        EXPECT_LT((a - b).norm(), 1e-15);
      }
    }
  }
}

// M1: the inclination of a truth line is dy / h whatever the pan, tilt,
// swing and camera position along the axis; line_of_inclination is its inverse.
TEST(CorridorModel, InclinationOfTruthLinesIsLateralOffsetOverHeight) {
  const CameraConfig camera = corridor_camera();
  const golden::corridor::Corridor corridor = golden::corridor::default_corridor();
  std::mt19937_64 rng(1);
  int checked = 0;
  for (double y : {-0.8, 0.0, 0.3, 0.75}) {
    for (double pan : {-10.0 * kDeg, 0.0, 4.0 * kDeg, 10.0 * kDeg}) {
      for (double swing : {0.0, 2.0 * kDeg}) {
        golden::corridor::Pose pose = pose_at(y, pan);
        pose.swing_rad = swing;
        const ModelCamera mc = model_camera(camera, corridor_mount(swing));
        for (const auto& t : ceiling_lines(camera, corridor, pose, 0.0, 0.0, rng)) {
          const std::optional<double> q = inclination(t.line, mc, pan);
          ASSERT_TRUE(q.has_value());
          EXPECT_NEAR(*q, (t.y_m - y) / 1.8, 1e-9);
          const ImageLine back = line_of_inclination(*q, mc, pan);
          EXPECT_NEAR(back.theta_rad, t.line.theta_rad, 1e-9);
          EXPECT_NEAR(back.rho_px, t.line.rho_px, 1e-6);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 100);
}

// A pan error turns n_w about Z and leaves |n_w.xy| and n_w.z: the
// inclination does not move (exactly, noise-free).
TEST(CorridorModel, InclinationDoesNotDependOnThePan) {
  const ModelCamera mc = model_camera(corridor_camera(), corridor_mount());
  const ImageLine l = line_of_inclination(0.3, mc, 3.0 * kDeg);
  for (double wrong : {-5.0, 0.0, 3.0, 8.0})
    EXPECT_NEAR(*inclination(l, mc, wrong * kDeg), 0.3, 1e-12);
}

// S2: the gradient against central differences everywhere, and against the
// closed form for pan 0, swing 0.
TEST(CorridorModel, InclinationGradientMatchesDifferencesAndTheClosedForm) {
  const ModelCamera mc = model_camera(corridor_camera(), corridor_mount());
  for (double pan : {0.0, 6.0 * kDeg}) {
    for (double q : {-0.7, -0.1, 0.25, 0.6}) {
      const ImageLine l = line_of_inclination(q, mc, pan);
      const Eigen::Vector2d g = inclination_gradient(l, mc, pan);
      const double e = 1e-6;
      auto at = [&](double dt, double dr) {
        return *inclination(line_from_homogeneous({std::cos(l.theta_rad + dt),
                                                   std::sin(l.theta_rad + dt), -(l.rho_px + dr)}),
                            mc, pan);
      };
      EXPECT_NEAR(g.x(), (at(e, 0) - at(-e, 0)) / (2 * e), 1e-5 * std::max(1.0, std::abs(g.x())));
      EXPECT_NEAR(g.y(), (at(0, e) - at(0, -e)) / (2 * e), 1e-6);
      if (pan == 0.0) {
        const double t = l.theta_rad, c = std::cos(mc.tilt_rad), s = std::sin(mc.tilt_rad),
                     f = mc.fx;
        const double dq_drho = -s / (f * std::cos(t));
        const double dq_dtheta =
            (s * (mc.cy * std::cos(t) - mc.cx * std::sin(t)) - c * f * std::cos(t)) /
                (f * std::cos(t)) +
            q * std::tan(t);
        EXPECT_NEAR(g.y(), dq_drho, 1e-9);
        EXPECT_NEAR(g.x(), dq_dtheta, 1e-9);
      }
    }
  }
}

std::vector<LearningImage> learning_drive(double path_y, double sigma_theta, double sigma_rho,
                                          int n, std::mt19937_64& rng, bool drop_lines) {
  const CameraConfig camera = corridor_camera();
  const golden::corridor::Corridor corridor = golden::corridor::default_corridor();
  std::normal_distribution<double> wander(0.0, 0.01), pan_noise(0.0, 1.0 * kDeg);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<LearningImage> images;
  for (int i = 0; i < n; ++i) {
    const double pan = pan_noise(rng);
    const auto pose = pose_at(path_y + wander(rng), pan, 1.0 + 0.25 * i);
    LearningImage im;
    im.pan_rad = pan;
    for (const auto& t : ceiling_lines(camera, corridor, pose, sigma_theta, sigma_rho, rng)) {
      if (drop_lines && u01(rng) < 0.2) continue;  // missed by the line finder
      im.lines.push_back(t.line);
    }
    if (drop_lines && i % 4 == 1) {
      // A spurious line (a door edge, a reflection) once in a while.
      im.lines.push_back({0.4 + 0.1 * u01(rng), 200.0 * u01(rng), 30.0});
    }
    images.push_back(im);
  }
  return images;
}

// Steps 9-11 with the nearest-median grouping: 17 images with 20 % of the
// lines missing, spurious lines and a wandering pan give one model line per
// ceiling line seen in most images, at its true inclination.
TEST(CorridorModel, LearnsEveryCeilingLineDespiteMissingAndSpuriousLines) {
  const CameraConfig camera = corridor_camera();
  const ModelCamera mc = model_camera(camera, corridor_mount());
  std::mt19937_64 rng(7);
  const double path_y = 0.0;
  const std::vector<LearningImage> images = learning_drive(path_y, 0.1 * kDeg, 0.5, 17, rng, true);
  LearnOptions opt;
  opt.line_height_m = camera.ceiling_above_camera_m();
  const CorridorModel model = learn_model(images, mc, opt);
  // The ceiling lines in view from the path.
  std::mt19937_64 rng2(1);
  const auto truth = ceiling_lines(camera, golden::corridor::default_corridor(),
                                   pose_at(path_y, 0.0), 0.0, 0.0, rng2);
  ASSERT_GE(truth.size(), 6u);
  EXPECT_EQ(model.lines.size(), truth.size());
  EXPECT_EQ(model.images, 17);
  for (const auto& t : truth) {
    const double q = (t.y_m - path_y) / 1.8;
    const auto it = std::min_element(
        model.lines.begin(), model.lines.end(), [&](const ModelLine& a, const ModelLine& b) {
          return std::abs(a.inclination - q) < std::abs(b.inclination - q);
        });
    // A model line is one image's line: its error is one line's (~2 cm at
    // 0.1 deg, 0.5 px) plus the path's wander (1 cm), far below the 0.15 m
    // between neighbouring ceiling lines.
    EXPECT_NEAR(it->inclination * 1.8, q * 1.8, 0.06) << "line at y = " << t.y_m;
    EXPECT_GE(it->support, 9);
    EXPECT_DOUBLE_EQ(it->height_m, 1.8);
  }
  for (std::size_t i = 1; i < model.lines.size(); ++i) {
    EXPECT_GT(model.lines[i - 1].inclination, model.lines[i].inclination);  // left to right
  }
  // The vanishing point of the model lines is the axis' at the model pan.
  const Eigen::Vector3d expected =
      (mc.k() * world_to_camera(model.pan_rad, mc.tilt_rad, mc.swing_rad) *
       Eigen::Vector3d::UnitX())
          .normalized();
  const Eigen::Vector2d vp = model.axis_vp.head<2>() / model.axis_vp.z();
  const Eigen::Vector2d ev = expected.head<2>() / expected.z();
  EXPECT_LT((vp - ev).norm(), 5.0) << vp.transpose() << " vs " << ev.transpose();
  EXPECT_NEAR(model.pan_rad, 0.0, 1.0 * kDeg);
}

// The seed's rank grouping (the k-th line of every image is group k) on the
// same drive mixes different ceiling lines in a group as soon as one image
// misses a line; the nearest-median grouping does not. This pins down why
// the deviation exists.
TEST(CorridorModel, RankGroupingWouldMixLinesWhereTheNearestMedianDoesNot) {
  const ModelCamera mc = model_camera(corridor_camera(), corridor_mount());
  std::mt19937_64 rng(11);
  const std::vector<LearningImage> images = learning_drive(0.0, 0.0, 0.0, 17, rng, true);
  // Rank grouping: sort each image's lines by inclination; group k = k-th.
  std::size_t mixed = 0;
  std::vector<std::vector<double>> rank_groups;
  for (const LearningImage& im : images) {
    std::vector<double> qs;
    for (const ImageLine& l : im.lines) qs.push_back(*inclination(l, mc, im.pan_rad));
    std::sort(qs.rbegin(), qs.rend());
    for (std::size_t k = 0; k < qs.size(); ++k) {
      if (rank_groups.size() <= k) rank_groups.emplace_back();
      rank_groups[k].push_back(qs[k]);
    }
  }
  for (const auto& g : rank_groups) {
    const auto [lo, hi] = std::minmax_element(g.begin(), g.end());
    if ((*hi - *lo) * 1.8 > 0.1) ++mixed;
  }
  EXPECT_GT(mixed, 0u);
  const CorridorModel model = learn_model(images, mc, {});
  std::mt19937_64 rng2(1);
  const auto truth = ceiling_lines(corridor_camera(), golden::corridor::default_corridor(),
                                   pose_at(0.0, 0.0), 0, 0, rng2);
  ASSERT_EQ(model.lines.size(), truth.size());
  std::vector<double> qs;
  for (const auto& t : truth) qs.push_back(t.y_m / 1.8);
  std::sort(qs.rbegin(), qs.rend());
  for (std::size_t i = 0; i < qs.size(); ++i) EXPECT_NEAR(model.lines[i].inclination, qs[i], 0.012);
}

TEST(CorridorModel, KeepsTheBestSupportedLinesAndRejectsBadInput) {
  const ModelCamera mc = model_camera(corridor_camera(), corridor_mount());
  std::mt19937_64 rng(3);
  const std::vector<LearningImage> images = learning_drive(0.2, 0.05 * kDeg, 0.3, 9, rng, false);
  LearnOptions opt;
  opt.max_lines = 2;  // the seed's i = 2
  EXPECT_EQ(learn_model(images, mc, opt).lines.size(), 2u);
  EXPECT_THROW(learn_model({}, mc), std::invalid_argument);
  opt.line_height_m = 0.0;
  EXPECT_THROW(learn_model(images, mc, opt), std::invalid_argument);
}

CorridorModel small_model() {
  const ModelCamera mc = model_camera(corridor_camera(), corridor_mount());
  std::mt19937_64 rng(5);
  return learn_model(learning_drive(0.0, 0.1 * kDeg, 0.5, 17, rng, true), mc, {});
}

TEST(CorridorModel, FileRoundTrips) {
  const CorridorModel m = small_model();
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("corridor_model_test_" + std::to_string(::getpid()) + ".json"))
                               .string();
  write_model_file(path, m);
  const CorridorModel r = read_model_file(path);
  std::filesystem::remove(path);
  EXPECT_EQ(r.camera, m.camera);
  EXPECT_EQ(r.pan_rad, m.pan_rad);
  EXPECT_EQ(r.images, m.images);
  EXPECT_TRUE(r.axis_vp.isApprox(m.axis_vp, 1e-15));
  EXPECT_TRUE(r.cross_vp.isApprox(m.cross_vp, 1e-15));
  ASSERT_EQ(r.lines.size(), m.lines.size());
  for (std::size_t i = 0; i < m.lines.size(); ++i) {
    EXPECT_EQ(r.lines[i].line.theta_rad, m.lines[i].line.theta_rad);
    EXPECT_EQ(r.lines[i].line.rho_px, m.lines[i].line.rho_px);
    EXPECT_EQ(r.lines[i].line.strength, m.lines[i].line.strength);
    EXPECT_EQ(r.lines[i].inclination, m.lines[i].inclination);
    EXPECT_EQ(r.lines[i].height_m, m.lines[i].height_m);
    EXPECT_EQ(r.lines[i].support, m.lines[i].support);
  }
}

void expect_rejected(const std::string& text, const std::string& key) {
  try {
    model_from_json(text, "m.json");
    ADD_FAILURE() << "accepted; expected an error naming " << key;
  } catch (const CorridorModelError& e) {
    EXPECT_NE(std::string(e.what()).find("m.json: " + key), std::string::npos) << e.what();
  }
}

TEST(CorridorModel, ReaderRejectsMalformedFilesNamingTheKey) {
  const std::string good = model_to_json(small_model());
  EXPECT_NO_THROW(model_from_json(good));
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const std::size_t p = s.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    return s.replace(p, from.size(), to);
  };
  expect_rejected("{", "not JSON");
  expect_rejected("[1, 2]", "(top level)");
  expect_rejected(replaced("\"ceilnav_corridor_model\"", "\"other\""), "format");
  expect_rejected(replaced("\"version\": 1", "\"version\": 2"), "version");
  expect_rejected(replaced("\"fx_px\"", "\"fx\""), "camera.fx_px: missing");
  expect_rejected(replaced("\"image_width\": 640", "\"image_width\": 0"), "camera.image_width");
  expect_rejected(replaced("\"pan_rad\"", "\"pan\""), "pan_rad");
  expect_rejected(replaced("\"axis\": [", "\"axis\": [1.0, "), "vanishing_points.axis");
  auto value = [&](const std::string& key, const std::string& to) {
    return std::regex_replace(good, std::regex("\"" + key + "\": [^,\\n]+"),
                              "\"" + key + "\": " + to, std::regex_constants::format_first_only);
  };
  expect_rejected(value("theta_rad", "4.0"), "lines[0].theta_rad");
  expect_rejected(value("theta_rad", "\"x\""), "lines[0].theta_rad");
  expect_rejected(replaced("\"rho_px\"", "\"rho\""), "lines[0].rho_px: missing");
  expect_rejected(replaced("\"support\"", "\"odd\": 0, \"support\""), "lines[0].odd: unknown key");
  expect_rejected(value("height_m", "-1.0"), "lines[0].height_m");
  expect_rejected(value("support", "\"many\""), "lines[0].support");
  expect_rejected(value("support", "1000"), "lines[0].support");
  expect_rejected(value("tilt_rad", "2.0"), "camera.tilt_rad");
  expect_rejected(replaced("\"pan_rad\"", "\"extra\": 1, \"pan_rad\""), "extra: unknown key");
  {
    std::string s = good;
    s.replace(s.find("\"lines\": ["), std::string("\"lines\": [").size(),
              "\"lines\": [], \"old\": [");
    expect_rejected(s, "lines");
  }
}

}  // namespace
}  // namespace ceilnav::host::corridor
