// Course files: the format's round trip and errors, junctions from the
// geometry, the renderer's strips, the default and random courses.
#include "sim/course.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

namespace ceilnav::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("ceilnav_course_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

const Junction* junction_at(const std::vector<Junction>& js, double x, double y) {
  for (const Junction& j : js) {
    if (std::hypot(j.position.x_m - x, j.position.y_m - y) < 1e-9) return &j;
  }
  return nullptr;
}

std::vector<double> degrees(const std::vector<double>& rad) {
  std::vector<double> out;
  for (double r : rad) out.push_back(std::round(r / kDeg * 1e6) / 1e6);
  return out;
}

TEST(DefaultCourse, HasTheBriefsFeatures) {
  const Course c = default_course();
  EXPECT_NO_THROW(validate(c));
  EXPECT_GE(c.tape_length_m(), 100.0);
  EXPECT_DOUBLE_EQ(c.tape_length_m(), 142.0);
  int gaps = 0;
  for (const TapePolyline& t : c.tapes) {
    for (const auto& [g0, g1] : t.gaps_m) {
      EXPECT_LE(g1 - g0, 1.0 + 1e-12);
      ++gaps;
    }
  }
  EXPECT_GE(gaps, 5);
  const std::vector<Junction> js = junctions(c);
  int tees = 0, ls = 0, crossings = 0;
  for (const Junction& j : js) {
    tees += j.kind == Junction::Kind::tee;
    ls += j.kind == Junction::Kind::l_turn;
    crossings += j.kind == Junction::Kind::crossing;
  }
  EXPECT_EQ(tees, 3);
  EXPECT_EQ(ls, 2);
  EXPECT_EQ(crossings, 0);
  const Junction* t1 = junction_at(js, 40.0, 20.0);  // B leaves A to the left
  ASSERT_NE(t1, nullptr);
  EXPECT_EQ(t1->kind, Junction::Kind::tee);
  EXPECT_EQ(degrees(t1->headings_rad), (std::vector<double>{-180.0, -90.0, 90.0}));
  const Junction* t2 = junction_at(js, 20.0, 20.0);  // C leaves B downward
  ASSERT_NE(t2, nullptr);
  EXPECT_EQ(degrees(t2->headings_rad), (std::vector<double>{-180.0, -90.0, 0.0}));
  const Junction* t3 = junction_at(js, 20.0, 0.0);  // C's start on A
  ASSERT_NE(t3, nullptr);
  EXPECT_EQ(degrees(t3->headings_rad), (std::vector<double>{-180.0, 0.0, 90.0}));
  const Junction* l1 = junction_at(js, 40.0, 0.0);
  ASSERT_NE(l1, nullptr);
  EXPECT_EQ(l1->kind, Junction::Kind::l_turn);
  EXPECT_EQ(degrees(l1->headings_rad), (std::vector<double>{-180.0, 90.0}));
  // The route turns left at both T-branches of the loop.
  EXPECT_GE(std::count(c.route.begin(), c.route.end(), Turn::left), 2);
  ASSERT_EQ(c.patterns.size(), 1u);
  EXPECT_EQ(c.ceiling_height_at(10.0, 0.0), 2.5);
  EXPECT_EQ(c.ceiling_height_at(30.0, 0.0), 2.8);
  EXPECT_EQ(c.ceiling_height_at(40.0, 15.0), 2.5);
  EXPECT_EQ(c.zone_at(10.0, 0.0), -1);
  EXPECT_EQ(c.zone_at(30.0, 0.0), 0);
  EXPECT_EQ(c.zone_at(40.0, 15.0), -1);
}

TEST(CourseFile, YamlAndJsonRoundTripExactly) {
  Course c = random_course(3, 120.0);  // rotated: nothing is round
  c.zones.push_back({{{0.1, 0.2}, {3.3, 0.25}, {1.7, 2.9}}, 3.1});
  for (const std::string ext : {".yaml", ".json"}) {
    const std::string path = temp_path("round" + ext);
    save_course(c, path);
    const Course back = load_course(path);
    EXPECT_EQ(back, c) << ext;
    std::filesystem::remove(path);
  }
}

TEST(CourseFile, TheExampleFileIsTheBuiltInCourse) {
  const std::string path = std::string(CEILNAV_SOURCE_DIR) + "/sim/courses/default.yaml";
  const Course c = load_course(path);
  EXPECT_EQ(c, default_course());
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), course_to_yaml(default_course()))
      << "regenerate sim/courses/default.yaml from course_to_yaml(default_course())";
}

TEST(CourseFile, ReadsRectanglesDegreesAndDefaults) {
  const Course c = parse_course(R"(
format: ceilnav_course
version: 1
ceiling:
  height_m: 2.5
  zones:
    - {height_m: 2.8, rectangle: [1, 2, 3, 4]}
tapes:
  - points: [[0, 0], [10, 0]]
    width_m: 0.05
start: {x_m: 1, y_m: 0, yaw_deg: 90}
)");
  ASSERT_EQ(c.zones.size(), 1u);
  EXPECT_EQ(c.zones[0].polygon, (std::vector<Point2>{{1, 2}, {3, 2}, {3, 4}, {1, 4}}));
  EXPECT_EQ(c.tapes[0].reflectance, 1.0);
  EXPECT_TRUE(c.tapes[0].gaps_m.empty());
  EXPECT_NEAR(c.start.yaw_rad, std::numbers::pi / 2, 1e-15);
  EXPECT_TRUE(c.route.empty());
  EXPECT_TRUE(c.patterns.empty());
  // JSON is read by the same parser.
  const Course j = parse_course(
      R"({"format": "ceilnav_course", "version": 1, "ceiling": {"height_m": 2.5},
          "tapes": [{"points": [[0, 0], [10, 0]], "width_m": 0.05}],
          "start": {"x_m": 1, "y_m": 0, "yaw_rad": 0}, "route": ["left", "straight"]})");
  EXPECT_EQ(j.route, (std::vector<Turn>{Turn::left, Turn::straight}));
}

void expect_error(const std::string& from, const std::string& to, const std::string& message) {
  std::string text = course_to_yaml(default_course());
  const std::size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
  try {
    parse_course(text, "f.yaml");
    ADD_FAILURE() << "no error for " << to;
  } catch (const CourseError& e) {
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos)
        << "'" << e.what() << "' lacks '" << message << "'";
  }
}

TEST(CourseFile, ErrorsNameTheKeyAndTheProblem) {
  expect_error("format: ceilnav_course", "format: other",
               "f.yaml: format: must be 'ceilnav_course'");
  expect_error("version: 1", "version: 2", "version: must be 1");
  expect_error("width_m: 0.05", "width_m: -1", "tapes[0].width_m: must be > 0");
  expect_error("width_m: 0.05", "width_m: wide", "tapes[0].width_m: 'wide' is not a number");
  expect_error("width_m: 0.05", "widht_m: 0.05", "tapes[0].widht_m: unknown key");
  expect_error("[8, 8.8]", "[9, 8]", "tapes[0].gaps[0]: needs end > start");
  expect_error("[8, 8.8]", "[8, 80]", "tapes[0].gaps[0]: must lie inside");
  expect_error("[8, 8.8], [47, 48]", "[47, 48], [8, 8.8]",
               "tapes[0].gaps[1]: gaps must be sorted and disjoint");
  expect_error("{id: 7,", "{id: 70,", "patterns[0].id: must be in [0, 50)");
  expect_error("[straight,", "[sideways,", "route[0]: 'sideways' is not left, right or straight");
  expect_error("height_m: 2.5", "height: 2.5", "ceiling.height: unknown key");
  expect_error("start: {x_m: 0, y_m: 0, yaw_rad: 0}", "start: {x_m: 0, y_m: 0}",
               "start: needs exactly one of yaw_rad and yaw_deg");
  expect_error("points: [[-2, 0], [40, 0], [40, 22]]", "points: [[-2, 0]]",
               "tapes[0].points: needs at least 2 points");
  expect_error("format: ceilnav_course", "format: [", "f.yaml: not YAML or JSON");
  EXPECT_THROW(load_course(temp_path("absent.yaml")), CourseError);
}

TEST(Junctions, CrossingsTeesLTurnsAndBends) {
  Course c;
  c.tapes.push_back({"x", {{0, 0}, {10, 0}}, 0.05, 1.0, {}});
  c.tapes.push_back({"y", {{5, -5}, {5, 5}}, 0.05, 1.0, {}});    // crosses x at (5, 0)
  c.tapes.push_back({"t", {{8, 0.01}, {8, 3}}, 0.05, 1.0, {}});  // ends on x (within 2.5 cm)
  c.tapes.push_back({"b", {{0, 10}, {5, 10}, {10, 13}}, 0.05, 1.0, {}});  // 31 deg bend
  c.tapes.push_back({"l", {{0, 20}, {5, 20}, {5, 25}, {9, 29}}, 0.05, 1.0, {}});
  c.tapes[0].gaps_m = {{4.5, 5.5}};  // a junction stays one where the tape is cut
  const std::vector<Junction> js = junctions(c);
  ASSERT_EQ(js.size(), 3u);
  const Junction* x = junction_at(js, 5.0, 0.0);
  ASSERT_NE(x, nullptr);
  EXPECT_EQ(x->kind, Junction::Kind::crossing);
  EXPECT_EQ(degrees(x->headings_rad), (std::vector<double>{-180.0, -90.0, 0.0, 90.0}));
  const Junction* t = junction_at(js, 8.0, 0.0);
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->kind, Junction::Kind::tee);
  EXPECT_EQ(t->tapes, (std::vector<int>{2, 0}));
  const Junction* l = junction_at(js, 5.0, 20.0);
  ASSERT_NE(l, nullptr);
  EXPECT_EQ(l->kind, Junction::Kind::l_turn);
  EXPECT_EQ(degrees(l->headings_rad), (std::vector<double>{-180.0, 90.0}));
  // (5, 25) turns by 45 deg and (5, 10) by 31 deg: bends, not junctions.
  EXPECT_EQ(junction_at(js, 5.0, 25.0), nullptr);
}

TEST(CeilingScene, StripsSkipGapsCloseCornersAndSplitAtZoneBorders) {
  const Course c = default_course();
  const golden::CeilingScene scene = ceiling_scene(c);
  auto covered = [&](double x, double y) {
    int n = 0;
    for (const golden::TapeSegment& s : scene.tapes) {
      const double dx = s.x1_m - s.x0_m, dy = s.y1_m - s.y0_m, len = std::hypot(dx, dy);
      const double along = ((x - s.x0_m) * dx + (y - s.y0_m) * dy) / len;
      const double across = ((y - s.y0_m) * dx - (x - s.x0_m) * dy) / len;
      n += along >= 0 && along <= len && std::abs(across) <= 0.5 * s.width_m;
    }
    return n;
  };
  EXPECT_EQ(covered(6.4, 0.0), 0);  // A's first gap: arc 8..8.8 = x 6..6.8
  EXPECT_EQ(covered(5.9, 0.0), 1);
  EXPECT_EQ(covered(20.0, 10.0), 0);    // C's gap at 9.5..10.3
  EXPECT_GE(covered(40.02, -0.02), 1);  // the L-turn's outer corner is closed
  // Strips cross no zone border; each has its zone's height.
  double length = 0.0;
  for (const golden::TapeSegment& s : scene.tapes) {
    const double mx = 0.5 * (s.x0_m + s.x1_m), my = 0.5 * (s.y0_m + s.y1_m);
    EXPECT_EQ(s.ceiling_height_m, c.ceiling_height_at(mx, my));
    EXPECT_EQ(
        c.ceiling_height_at(s.x0_m + 1e-9 * (s.x1_m - s.x0_m), s.y0_m + 1e-9 * (s.y1_m - s.y0_m)),
        c.ceiling_height_at(s.x1_m - 1e-9 * (s.x1_m - s.x0_m), s.y1_m - 1e-9 * (s.y1_m - s.y0_m)));
    length += std::hypot(s.x1_m - s.x0_m, s.y1_m - s.y0_m);
  }
  double gaps = 0.0;
  for (const TapePolyline& t : c.tapes) {
    for (const auto& [g0, g1] : t.gaps_m) gaps += g1 - g0;
  }
  // Two L-turn corners each lengthen two strips by half the width.
  EXPECT_NEAR(length, c.tape_length_m() - gaps + 4 * 0.025, 1e-9);
  EXPECT_TRUE(std::any_of(scene.tapes.begin(), scene.tapes.end(), [](const golden::TapeSegment& s) {
    return s.x1_m == 25.0 && s.y1_m == 0.0;
  }));
}

TEST(RandomCourse, ValidOfTheDefaultKindsAndReproducible) {
  for (uint64_t seed = 1; seed <= 25; ++seed) {
    const double length = 60.0 + 10.0 * static_cast<double>(seed);
    const Course c = random_course(seed, length);
    EXPECT_NO_THROW(validate(c));
    EXPECT_NEAR(c.tape_length_m(), length, 1e-9) << seed;
    int tees = 0, ls = 0;
    for (const Junction& j : junctions(c)) {
      tees += j.kind == Junction::Kind::tee;
      ls += j.kind == Junction::Kind::l_turn;
    }
    EXPECT_EQ(tees, 3) << seed;
    EXPECT_EQ(ls, 2) << seed;
    int gaps = 0;
    for (const TapePolyline& t : c.tapes) {
      for (const auto& [g0, g1] : t.gaps_m) {
        EXPECT_LE(g1 - g0, 1.0) << seed;
        EXPECT_GE(g1 - g0, 0.2) << seed;
        ++gaps;
      }
    }
    EXPECT_GE(gaps, 1) << seed;
    ASSERT_EQ(c.zones.size(), 1u);
    EXPECT_GE(std::abs(c.zones[0].height_m - c.ceiling_height_m), 0.1 - 1e-12);
    EXPECT_EQ(c.patterns.size(), 1u);
    // The start is on the first tape, heading along it.
    EXPECT_NEAR(
        std::hypot(c.start.x_m - c.tapes[0].points[0].x_m, c.start.y_m - c.tapes[0].points[0].y_m),
        2.0, 1e-9);
    EXPECT_EQ(parse_course(course_to_yaml(c)), c) << seed;
  }
  EXPECT_EQ(random_course(9, 100.0), random_course(9, 100.0));
  EXPECT_NE(random_course(9, 100.0), random_course(10, 100.0));
  EXPECT_THROW(random_course(1, 10.0), std::invalid_argument);
}

}  // namespace
}  // namespace ceilnav::sim
