#include "nav/odometry.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ceilnav::nav {
namespace {

constexpr RobotParams kRobot{0.4, 1e-4, 1e-4};

OdometryTrack parse(const std::string& text, const RobotParams* robot = &kRobot) {
  std::istringstream in(text);
  return OdometryTrack::parse(in, "odo.csv", robot);
}

// The message of the OdometryFileError that `parse_fn(stream)` throws for
// `text` ("" if none).
template <class ParseFn>
std::string error_of(const std::string& text, ParseFn parse_fn) {
  std::istringstream in(text);
  try {
    parse_fn(in);
  } catch (const OdometryFileError& e) {
    return e.what();
  }
  return "";
}

std::string parse_error(const std::string& text, const RobotParams* robot = &kRobot) {
  return error_of(text, [&](std::istream& in) { OdometryTrack::parse(in, "odo.csv", robot); });
}

struct ErrorCase {
  std::string text;
  std::string want;  // the message's start
};

template <class ParseFn>
void expect_errors(const std::vector<ErrorCase>& cases, ParseFn parse_fn) {
  for (const auto& c : cases) {
    const std::string got = error_of(c.text, parse_fn);
    EXPECT_EQ(got.rfind(c.want, 0), 0u) << "file:\n" << c.text << "\nmessage: " << got;
  }
}

TEST(OdometryFile, CountsIntegrateToThePose) {
  // 1 m straight (10000 counts each), then a quarter turn in place
  // (wheels -/+ b pi/4 = 0.1 pi m = 3141.59 counts).
  const OdometryTrack t =
      parse("t_s,left_ticks,right_ticks\n0,100,200\n1.0,10100,10200\n2.0,6958,13342\n");
  EXPECT_EQ(t.format(), OdometryFormat::encoder_counts);
  ASSERT_EQ(t.samples().size(), 3u);
  EXPECT_NEAR(t.samples()[1].pose.x_m, 1.0, 1e-12);
  EXPECT_NEAR(t.samples()[1].pose.y_m, 0.0, 1e-12);
  EXPECT_NEAR(t.samples()[2].pose.x_m, 1.0, 1e-12);
  EXPECT_NEAR(t.samples()[2].pose.yaw_rad, 6284e-4 / 0.4, 1e-12);
}

TEST(OdometryFile, PerWheelScaleAndWheelBaseApply) {
  const RobotParams robot{0.5, 2e-4, 1e-4};
  // Left 1000 counts = 0.2 m, right 3000 = 0.3 m: ds 0.25, dpsi 0.2 rad.
  const OdometryTrack t = parse("t_s,left_ticks,right_ticks\n0,0,0\n1,1000,3000\n", &robot);
  const Pose2 want = advance({}, {0.25, 0.2});
  EXPECT_NEAR(t.samples()[1].pose.x_m, want.x_m, 1e-15);
  EXPECT_NEAR(t.samples()[1].pose.y_m, want.y_m, 1e-15);
  EXPECT_NEAR(t.samples()[1].pose.yaw_rad, 0.2, 1e-15);
}

TEST(OdometryFile, VelocitiesHoldUntilTheNextRow) {
  // 0.5 m/s for 2 s, then 1 m/s turning at 0.5 rad/s for 1 s; the last row's
  // velocity is never used.
  const OdometryTrack t = parse("t_s,v_mps,omega_radps\r\n0,0.5,0\r\n2,1.0,0.5\r\n\r\n3,9,9\r\n");
  EXPECT_EQ(t.format(), OdometryFormat::body_velocity);
  const Pose2 want = advance({1.0, 0.0, 0.0}, {1.0, 0.5});
  EXPECT_NEAR(t.samples()[1].pose.x_m, 1.0, 1e-15);
  EXPECT_NEAR(t.samples()[2].pose.x_m, want.x_m, 1e-15);
  EXPECT_NEAR(t.samples()[2].pose.y_m, want.y_m, 1e-15);
  EXPECT_NEAR(t.samples()[2].pose.yaw_rad, 0.5, 1e-15);
}

TEST(OdometryFile, WhitespaceAroundFieldsIsAccepted) {
  const OdometryTrack t = parse(" t_s , v_mps,omega_radps \n 0 , 1 , 0\n1,1,0\n");
  EXPECT_NEAR(t.samples()[1].pose.x_m, 1.0, 1e-15);
}

TEST(OdometryFile, EachMalformedFileNamesTheLine) {
  const std::string counts = "t_s,left_ticks,right_ticks\n";
  const std::string vel = "t_s,v_mps,omega_radps\n";
  expect_errors(
      {
          {"", "odo.csv:0: empty file"},
          {"\n\n", "odo.csv:2: empty file"},
          {"t,v,w\n0,1,0\n1,1,0\n", "odo.csv:1: header 't,v,w' is neither"},
          {"t_s,v_mps\n0,1\n", "odo.csv:1: header"},
          {vel + "0,1,0\n1,1\n", "odo.csv:3: expected 3 fields, got 2"},
          {vel + "0,1,0\n1,1,0,4\n", "odo.csv:3: expected 3 fields, got 4"},
          {vel + "0,1,0\nx,1,0\n", "odo.csv:3: t_s 'x' is not a number"},
          {vel + "0,1,0\n1,,0\n", "odo.csv:3: v_mps '' is not a number"},
          {vel + "0,1,0\n1,1,0.5rad\n", "odo.csv:3: omega_radps '0.5rad' is not a number"},
          {vel + "0,1,0\n1,inf,0\n", "odo.csv:3: v_mps 'inf' is not finite"},
          {vel + "0,1,0\nnan,1,0\n", "odo.csv:3: t_s 'nan' is not finite"},
          {vel + "0,1,0\n1,1,0\n1,1,0\n", "odo.csv:4: time 1 is not after"},
          {vel + "0,1,0\n1,1,0\n0.5,1,0\n", "odo.csv:4: time 0.5 is not after"},
          {vel + "0,1,0\n", "odo.csv:2: needs at least two rows"},
          {vel, "odo.csv:1: needs at least two rows"},
          {counts + "0,0,0\n1,10.5,3\n", "odo.csv:3: left_ticks '10.5' is not an integer count"},
          {counts + "0,0,0\n1,10,3e2\n", "odo.csv:3: right_ticks '3e2' is not an integer count"},
      },
      [](std::istream& in) { OdometryTrack::parse(in, "odo.csv", &kRobot); });
}

TEST(OdometryFile, CountsNeedAValidRobot) {
  const std::string text = "t_s,left_ticks,right_ticks\n0,0,0\n1,1,1\n";
  EXPECT_NE(parse_error(text, nullptr).find("--robot"), std::string::npos);
  const RobotParams bad{0.0, 1e-4, 1e-4};
  EXPECT_NE(parse_error(text, &bad).find("must be finite and > 0"), std::string::npos);
  // The velocity format needs no robot.
  EXPECT_EQ(parse_error("t_s,v_mps,omega_radps\n0,1,0\n1,1,0\n", nullptr), "");
}

TEST(OdometryFile, MissingFileIsAnError) {
  EXPECT_THROW(OdometryTrack::load("/nonexistent/odo.csv", &kRobot), OdometryFileError);
}

TEST(OdometryTrack, InterpolatesAlongTheArcOfATick) {
  // One tick of a quarter circle of radius 1 m over 1 s: at 0.5 s the robot is
  // half-way round (45 deg), on the circle.
  const OdometryTrack t(
      {{0.0, {}}, {1.0, advance({}, {std::numbers::pi / 2, std::numbers::pi / 2})}});
  const Pose2 mid = t.pose_at(0.5);
  EXPECT_NEAR(mid.x_m, std::sin(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(mid.y_m, 1.0 - std::cos(std::numbers::pi / 4), 1e-12);
  EXPECT_NEAR(mid.yaw_rad, std::numbers::pi / 4, 1e-12);
  const Pose2 end = t.pose_at(1.0);
  EXPECT_NEAR(end.x_m, 1.0, 1e-12);
  EXPECT_NEAR(end.y_m, 1.0, 1e-12);
  const Pose2 start = t.pose_at(0.0);
  EXPECT_EQ(start.x_m, 0.0);
}

TEST(OdometryTrack, InterpolatesStraightAndBackwardTicksLinearly) {
  const OdometryTrack t({{0.0, {}}, {2.0, {2.0, 0.0, 0.0}}, {4.0, {1.0, 0.0, 0.0}}});
  EXPECT_NEAR(t.pose_at(0.5).x_m, 0.5, 1e-15);
  EXPECT_NEAR(t.pose_at(3.0).x_m, 1.5, 1e-15);  // backing up
  EXPECT_NEAR(t.pose_at(3.0).yaw_rad, 0.0, 1e-15);
}

TEST(OdometryTrack, InterpolationMatchesFinerTicks) {
  // Velocity file at 10 Hz vs the same motion at 1 Hz: equal at any time.
  std::string fine = "t_s,v_mps,omega_radps\n", coarse = fine;
  for (int k = 0; k <= 30; ++k) fine += std::to_string(0.1 * k) + ",0.8,0.3\n";
  for (int k = 0; k <= 3; ++k) coarse += std::to_string(k) + ",0.8,0.3\n";
  const OdometryTrack f = parse(fine), c = parse(coarse);
  for (double t : {0.0, 0.37, 1.0, 1.55, 2.95}) {
    EXPECT_NEAR(f.pose_at(t).x_m, c.pose_at(t).x_m, 1e-9) << t;
    EXPECT_NEAR(f.pose_at(t).y_m, c.pose_at(t).y_m, 1e-9) << t;
    EXPECT_NEAR(f.pose_at(t).yaw_rad, c.pose_at(t).yaw_rad, 1e-9) << t;
  }
}

TEST(OdometryTrack, OutsideTheSpanThrows) {
  const OdometryTrack t({{1.0, {}}, {2.0, {1.0, 0.0, 0.0}}});
  EXPECT_TRUE(t.covers(1.0));
  EXPECT_FALSE(t.covers(0.999));
  EXPECT_THROW(t.pose_at(0.5), std::out_of_range);
  EXPECT_THROW(t.pose_at(2.01), std::out_of_range);
}

TEST(OdometryTrack, RelativeMotionIsInTheFirstPosesFrame) {
  // Heading +90 deg from t = 1 on: moving 1 m along +Y is 1 m forward.
  const OdometryTrack t({{0.0, {}},
                         {1.0, {0.0, 0.0, std::numbers::pi / 2}},
                         {2.0, {0.0, 1.0, std::numbers::pi / 2}}});
  const Pose2 r = t.relative(1.0, 2.0);
  EXPECT_NEAR(r.x_m, 1.0, 1e-12);
  EXPECT_NEAR(r.y_m, 0.0, 1e-12);
  EXPECT_NEAR(r.yaw_rad, 0.0, 1e-12);
  const Pose2 q = relative_pose({1.0, 1.0, std::numbers::pi}, {0.0, 2.0, 0.0});
  EXPECT_NEAR(q.x_m, 1.0, 1e-12);
  EXPECT_NEAR(q.y_m, -1.0, 1e-12);
  EXPECT_NEAR(std::abs(q.yaw_rad), std::numbers::pi, 1e-12);
}

TEST(RobotFile, ParsesTheKeys) {
  std::istringstream in(
      "%YAML:1.0\n---\n# robot\nwheel_base_m: 0.42  # axle\nleft_m_per_count: 1.5e-4\n\n"
      "right_m_per_count: 1.6e-4\n");
  const RobotParams p = parse_robot_params(in, "robot.yaml");
  EXPECT_EQ(p.wheel_base_m, 0.42);
  EXPECT_EQ(p.left_m_per_count, 1.5e-4);
  EXPECT_EQ(p.right_m_per_count, 1.6e-4);
}

TEST(RobotFile, EachMalformedFileIsRejected) {
  const std::string ok = "wheel_base_m: 0.4\nleft_m_per_count: 1e-4\nright_m_per_count: 1e-4\n";
  expect_errors(
      {
          {"wheel_base_m: 0.4\nleft_m_per_count: 1e-4\n",
           "robot.yaml: missing key 'right_m_per_count'"},
          {ok + "wheel_base: 1\n", "robot.yaml:4: unknown key 'wheel_base'"},
          {ok + "wheel_base_m: 0.5\n", "robot.yaml:4: key 'wheel_base_m' given twice"},
          {"wheel_base_m 0.4\n", "robot.yaml:1: expected 'key: value'"},
          {"wheel_base_m: -0.4\n", "robot.yaml:1: wheel_base_m must be > 0"},
          {"wheel_base_m: wide\n", "robot.yaml:1: wheel_base_m 'wide' is not a number"},
      },
      [](std::istream& in) { parse_robot_params(in, "robot.yaml"); });
}

TEST(FrameTimes, ParsesAndRejects) {
  std::istringstream good("frame,t_s\nframe_000.png,0.05\nframe_001.png,0.15\n");
  const auto ft = parse_frame_times(good, "times.csv");
  ASSERT_EQ(ft.size(), 2u);
  EXPECT_EQ(ft[1].frame, "frame_001.png");
  EXPECT_EQ(ft[1].t_s, 0.15);
  expect_errors(
      {
          {"", "times.csv:0: empty file"},
          {"name,t\na.png,1\n", "times.csv:1: header 'name,t' is not frame,t_s"},
          {"frame,t_s\n", "times.csv:1: no frames listed"},
          {"frame,t_s\na.png,1\na.png,2\n", "times.csv:3: frame 'a.png' listed twice"},
          {"frame,t_s\na.png,1\nb.png,1\n", "times.csv:3: time 1 is not after"},
          {"frame,t_s\na.png\n", "times.csv:2: expected 2 fields, got 1"},
          {"frame,t_s\n,1\n", "times.csv:2: empty frame name"},
          {"frame,t_s\na.png,soon\n", "times.csv:2: t_s 'soon' is not a number"},
      },
      [](std::istream& in) { parse_frame_times(in, "times.csv"); });
}

}  // namespace
}  // namespace ceilnav::nav
