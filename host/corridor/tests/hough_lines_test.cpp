// Steps 4-9 of seed 002's line extraction (eq. 19-20) on synthetic
// accumulators: plateau marks, hole filling (and its wrap at theta 0/180),
// plateau removal, the repeat and the order; the sub-bin estimate on the
// golden accumulator of known lines; the distorted -> undistorted line.
#include "host/corridor/hough_lines.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "golden/hough_ref.hpp"

namespace ceilnav::host::corridor {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::vector<bool> bits(const std::string& s) {
  std::vector<bool> out;
  for (char c : s) out.push_back(c == '1');
  return out;
}

std::string str(const std::vector<bool>& b) {
  std::string s;
  for (bool x : b) s += x ? '1' : '0';
  return s;
}

// An empty accumulator of a shape with the full theta range.
Accumulator empty(int theta_step = 4, int rho_bits = 6) {
  Accumulator acc;
  acc.shape.theta_step = theta_step;
  acc.shape.rho_bits = rho_bits;
  acc.config.width = 640;
  acc.config.rho_shift = static_cast<uint8_t>(11 - rho_bits);
  acc.cells.assign(static_cast<size_t>(acc.shape.n_theta()) * acc.shape.rho_bins(), 0);
  return acc;
}

void set(Accumulator& acc, int j, int r, uint64_t v) {
  acc.cells[static_cast<size_t>(j) * acc.shape.rho_bins() + static_cast<size_t>(r)] = v;
}

TEST(HoughLines, PlateauMarksAreStrictlyAboveCTimesMax) {
  Accumulator acc = empty();
  set(acc, 3, 10, 100);
  set(acc, 4, 11, 81);  // > 80: marked
  set(acc, 5, 12, 80);  // == 0.8 max: not (eq. 19 is strict)
  set(acc, 9, 40, 79);
  const std::vector<bool> m = plateau_marks(acc, 100, 0.8);
  ASSERT_EQ(m.size(), 45u);
  for (int j = 0; j < 45; ++j) EXPECT_EQ(m[static_cast<size_t>(j)], j == 3 || j == 4) << j;
}

TEST(HoughLines, HoleFillingPatterns) {
  struct Case {
    const char* in;
    const char* no_wrap;
    const char* wrap;
  };
  const Case cases[] = {
      {"0101000000", "0111000000", "0111000000"},  // 101 -> 111
      {"0100100000", "0111100000", "0111100000"},  // 1001 -> 1111
      {"0100010000", "0111110000", "0111110000"},  // 10001 -> 11111
      {"0100001", "0100001", "1100001"},           // 100001 stays; wrap: 1|1 adjacent, "10" + "1"
      {"1000010000", "1000010000", "1000010000"},  // "100001": 4 zeros stay
      {"0010000100", "0010000100", "0010000100"},
      {"1000000100", "1000000100", "1000000111"},  // across the end: 1 0 0 | 1
      {"0000000000", "0000000000", "0000000000"},
      {"1111111111", "1111111111", "1111111111"},
      {"1010101000", "1111111000", "1111111111"},  // wrap: "1000" + "1"
  };
  for (const Case& c : cases) {
    std::vector<bool> a = bits(c.in), b = bits(c.in);
    fill_holes(a, false);
    fill_holes(b, true);
    EXPECT_EQ(str(a), c.no_wrap) << c.in;
    EXPECT_EQ(str(b), c.wrap) << c.in;
  }
}

TEST(HoughLines, PlateauRowsFollowEq20) {
  Accumulator acc = empty();  // 45 rows of 4 deg
  // A run of 5 rows (16 deg wide) > theta_range 12: the run.
  std::vector<bool> m(45, false);
  for (int j = 10; j <= 14; ++j) m[static_cast<size_t>(j)] = true;
  RowRange r = plateau_rows(acc, m, 12, 12.0, true);
  EXPECT_EQ(r.first, 10);
  EXPECT_EQ(r.last, 14);
  // A run of 3 rows (8 deg) <= 12: theta_max +- 6 deg = rows 11 .. 13 (one
  // row is 4 deg: floor(6 / 4) = 1 row each side).
  std::fill(m.begin(), m.end(), false);
  for (int j = 20; j <= 22; ++j) m[static_cast<size_t>(j)] = true;
  r = plateau_rows(acc, m, 20, 12.0, true);
  EXPECT_EQ(r.first, 19);
  EXPECT_EQ(r.last, 21);
  // Across the end (wrap): rows 43, 44, 0, 1, 2.
  std::fill(m.begin(), m.end(), false);
  for (int j : {43, 44, 0, 1, 2}) m[static_cast<size_t>(j)] = true;
  r = plateau_rows(acc, m, 0, 12.0, true);
  EXPECT_EQ(r.first, 43);
  EXPECT_EQ(r.last, 2);
  // Without the wrap the run stops at the end.
  r = plateau_rows(acc, m, 0, 4.0, false);
  EXPECT_EQ(r.first, 0);
  EXPECT_EQ(r.last, 2);
  // theta_max +- theta_range / 2 across the end.
  std::fill(m.begin(), m.end(), false);
  m[44] = true;
  r = plateau_rows(acc, m, 44, 8.0, true);
  EXPECT_EQ(r.first, 43);
  EXPECT_EQ(r.last, 0);
}

TEST(HoughLines, PlateauRemovalRemovesExactlyThePlateau) {
  Accumulator acc = empty();
  // A plateau over rows 5..9 (with a hole at 7), a second peak elsewhere,
  // and low cells everywhere.
  for (int j = 0; j < 45; ++j) {
    for (int r = 0; r < 64; ++r) set(acc, j, r, static_cast<uint64_t>((j * 7 + r * 3) % 11));
  }
  for (int j : {5, 6, 8, 9}) set(acc, j, 30, 900 + static_cast<uint64_t>(j));
  set(acc, 7, 30, 500);  // a hole: below 0.8 max
  set(acc, 30, 12, 850);
  const Accumulator before = acc;
  const uint64_t max = 909;
  std::vector<bool> m = plateau_marks(acc, max, 0.8);
  EXPECT_EQ(str(m).substr(0, 12), "000001101100");
  fill_holes(m, true);
  EXPECT_EQ(str(m).substr(0, 12), "000001111100");
  const RowRange range = plateau_rows(acc, m, 9, 12.0, true);  // 16 deg > 12: the run
  EXPECT_EQ(range.first, 5);
  EXPECT_EQ(range.last, 9);
  remove_rows(acc, range);
  for (int j = 0; j < 45; ++j) {
    for (int r = 0; r < 64; ++r) {
      if (j >= 5 && j <= 9) {
        EXPECT_EQ(acc.at(j, r), 0u);
      } else {
        EXPECT_EQ(acc.at(j, r), before.at(j, r)) << j << " " << r;
      }
    }
  }
  // Circular range: rows 44 and 0 only.
  Accumulator w = before;
  remove_rows(w, {44, 0});
  for (int j = 0; j < 45; ++j) {
    for (int r = 0; r < 64; ++r) {
      EXPECT_EQ(w.at(j, r), (j == 44 || j == 0) ? 0u : before.at(j, r));
    }
  }
}

// The golden accumulator of known lines (unit weights), a 1-deg / 512-bin
// shape with 4-px bins.
Accumulator of_lines(const std::vector<std::pair<double, double>>& lines, int theta_step,
                     int rho_bits) {
  std::vector<golden::EdgePoint> pts;
  for (const auto& [rho, theta_deg] : lines) {
    const std::vector<golden::EdgePoint> p = golden::line_points(rho, theta_deg, 640, 480);
    pts.insert(pts.end(), p.begin(), p.end());
  }
  Accumulator acc = empty(theta_step, rho_bits);
  acc.config.unit_weight = true;
  acc.cells = golden::hough_ref(acc.shape, acc.config, pts);
  return acc;
}

double line_distance_at(const ImageLine& a, double theta_deg, double rho, double u, double v) {
  // |distance of a's point nearest (u, v) on the true line from the true line|
  (void)theta_deg;
  const double t = theta_deg * kDeg;
  // The point of the true line nearest (u, v).
  const double d = u * std::cos(t) + v * std::sin(t) - rho;
  const double pu = u - d * std::cos(t), pv = v - d * std::sin(t);
  return std::abs(pu * std::cos(a.theta_rad) + pv * std::sin(a.theta_rad) - a.rho_px);
}

TEST(HoughLines, ExtractsKnownLinesOrderedByThetaWithSubBinPrecision) {
  const std::vector<std::pair<double, double>> truth = {
      {101.7, 23.4}, {380.2, 61.8}, {-140.6, 131.3}, {200.9, 96.6}};
  for (const auto& [step, bits] : {std::pair{1, 9}, std::pair{2, 8}, std::pair{4, 6}}) {
    const Accumulator acc = of_lines(truth, step, bits);
    LineExtractionParams p;
    p.max_lines = 4;
    // Long lines leave side peaks a few rows off (their votes' rho spread
    // is below one bin there): theta_range of 4 rows removes them. (With
    // 12 deg on the default shape, side peaks 7 deg from the 61.8 and 96.6
    // deg lines outrank the short 23.4 deg line.)
    p.theta_range_deg = 4.0 * step;
    p.min_strength_ratio = 0.3;
    const std::vector<HoughLine> lines = extract_lines(acc, p);
    ASSERT_EQ(lines.size(), static_cast<size_t>(p.max_lines)) << step;
    for (size_t i = 1; i < lines.size(); ++i) {
      EXPECT_LT(lines[i - 1].line.theta_rad, lines[i].line.theta_rad);  // step 9
    }
    const double bin = std::ldexp(1.0, acc.config.rho_shift);
    for (const auto& [rho, theta] : truth) {
      bool matched = false;
      for (const HoughLine& h : lines) {
        if (std::abs(h.line.theta_rad / kDeg - theta) > step) continue;
        matched = true;
        // Sub-bin on the finer shapes: theta within half a row, the line
        // within a quarter bin of the truth at the frame's centre. On the
        // default shape (4 deg, 32-px bins) within a row and a bin.
        const bool fine = step <= 2;
        EXPECT_LE(std::abs(h.line.theta_rad / kDeg - theta), (fine ? 0.5 : 1.0) * step) << theta;
        EXPECT_LE(line_distance_at(h.line, theta, rho, 320, 240), fine ? 0.25 * bin + 0.5 : bin)
            << theta;
        EXPECT_GT(h.votes, 0u);
        EXPECT_EQ(h.line.strength, static_cast<double>(h.votes));
      }
      EXPECT_TRUE(matched) << theta << " step " << step;
    }
  }
}

// A line near vertical in the image (theta 179 deg) votes near theta 180
// at rho and near theta 0 at -rho: with the wrap (full range) one plateau,
// one line; without it the seed's string finds it twice.
TEST(HoughLines, WrapMakesANearVerticalLineOnePlateau) {
  const Accumulator acc = of_lines({{-300.0, 179.0}, {150.0, 60.0}}, 1, 9);
  LineExtractionParams p;
  p.max_lines = 3;
  p.min_strength_ratio = 0.3;
  p.theta_range_deg = 6.0;
  p.wrap = true;
  const std::vector<HoughLine> wrapped = extract_lines(acc, p);
  p.wrap = false;
  const std::vector<HoughLine> unwrapped = extract_lines(acc, p);
  ASSERT_EQ(wrapped.size(), 2u);
  EXPECT_NEAR(wrapped[1].line.theta_rad / kDeg, 179.0, 0.5);
  EXPECT_NEAR(wrapped[1].line.rho_px, -300.0, 2.0);
  ASSERT_EQ(unwrapped.size(), 3u);
  // The duplicate: peak cell in row 0 (theta 0, rho near +300), the same
  // line; its sub-bin estimate (rows 179, 0, 1) gives it in [0, 180) again.
  int near_vertical = 0;
  for (const HoughLine& h : unwrapped) {
    if (std::abs(h.line.theta_rad / kDeg - 179.0) < 1.0) {
      ++near_vertical;
      EXPECT_NEAR(h.line.rho_px, -300.0, 4.0);
    }
  }
  EXPECT_EQ(near_vertical, 2);
  EXPECT_TRUE(unwrapped[0].row == 0 || unwrapped[1].row == 0 || unwrapped[2].row == 0);
}

TEST(HoughLines, StopsAtMaxLinesAndTheStrengthRatio) {
  const Accumulator acc = of_lines({{101.7, 23.4}, {380.2, 61.8}, {-140.6, 131.3}}, 1, 9);
  LineExtractionParams p;
  p.max_lines = 2;
  p.min_strength_ratio = 0.0;
  EXPECT_EQ(extract_lines(acc, p).size(), 2u);
  p.max_lines = 50;
  p.min_strength_ratio = 0.99;  // only the strongest
  EXPECT_EQ(extract_lines(acc, p).size(), 1u);
  Accumulator zero = empty();
  EXPECT_TRUE(extract_lines(zero, p).empty());
}

TEST(HoughLines, UndistortLine) {
  CameraConfig cam;
  ImageLine raw{0.7, 210.0, 5.0};
  ImageLine out;
  // No distortion: the same line.
  ASSERT_TRUE(undistort_line(raw, CameraModel(cam), 640, 480, out));
  EXPECT_EQ(out.theta_rad, raw.theta_rad);
  EXPECT_EQ(out.rho_px, raw.rho_px);
  // A line missing the frame.
  EXPECT_FALSE(undistort_line({0.0, -50.0}, CameraModel(cam), 640, 480, out));
  // Radial distortion keeps a line through the principal point: it maps to
  // itself.
  cam.distortion_coefficients = {-0.2, 0.05, 0.0, 0.0, 0.0};
  const CameraModel model(cam);
  const double t = 0.9;
  const ImageLine radial{t, cam.cx() * std::cos(t) + cam.cy() * std::sin(t), 1.0};
  ASSERT_TRUE(undistort_line(radial, model, 640, 480, out));
  EXPECT_NEAR(out.theta_rad, t, 1e-9);
  EXPECT_NEAR(out.rho_px, radial.rho_px, 1e-6);
  EXPECT_EQ(out.strength, 1.0);
  // A straight line of the undistorted image is a curve of the raw one: the
  // raw chord through two of its distorted points, undistorted, passes
  // through the undistorted points at the chord's ends.
  const Eigen::Vector2d a(100.0, 60.0), b(560.0, 130.0);
  auto distorted = [&](const Eigen::Vector2d& p) {
    return model.distort_to_pixel({(p.x() - cam.cx()) / cam.fx(), (p.y() - cam.cy()) / cam.fy()});
  };
  const Eigen::Vector2d da = distorted(a), db = distorted(b);
  const Eigen::Vector3d h =
      Eigen::Vector3d(da.x(), da.y(), 1.0).cross(Eigen::Vector3d(db.x(), db.y(), 1.0));
  ASSERT_TRUE(undistort_line(line_from_homogeneous(h), model, 640, 480, out));
  // The chord's ends undistort onto the curve's image: within a few pixels
  // of the true line (the raw chord is not the raw curve).
  for (const Eigen::Vector2d& p : {a, b}) {
    EXPECT_LT(
        std::abs(p.x() * std::cos(out.theta_rad) + p.y() * std::sin(out.theta_rad) - out.rho_px),
        6.0);
  }
}

}  // namespace
}  // namespace ceilnav::host::corridor
