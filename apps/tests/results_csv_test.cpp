// The results table of `ceilnav run`: pose columns only for ok results, the
// zenith's by its own status, evidence columns whenever a line was fitted.
#include "apps/results_csv.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace ceilnav::app {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string f;
  while (std::getline(ss, f, ',')) out.push_back(f);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// Header and row as name -> field.
std::vector<std::pair<std::string, std::string>> table(
    const host::FrameOutcome& o, const std::vector<host::Junction>& junctions = {},
    const OdometryColumns& odo = {}) {
  std::ostringstream out;
  write_results_header(out);
  write_results_row(out, "f.png", o, junctions, odo);
  std::istringstream in(out.str());
  std::string h, r;
  std::getline(in, h);
  std::getline(in, r);
  const auto hs = split(h), rs = split(r);
  EXPECT_EQ(hs.size(), rs.size()) << r;
  std::vector<std::pair<std::string, std::string>> t;
  for (size_t i = 0; i < hs.size() && i < rs.size(); ++i) t.emplace_back(hs[i], rs[i]);
  return t;
}

std::string field(const std::vector<std::pair<std::string, std::string>>& t,
                  const std::string& name) {
  for (const auto& [k, v] : t) {
    if (k == name) return v;
  }
  ADD_FAILURE() << "no column " << name;
  return "?";
}

host::FrameOutcome outcome(host::Status pose, std::optional<host::Status> zenith) {
  host::FrameOutcome o;
  o.results.valid = true;
  o.pose.status = pose;
  o.pose.yaw_rad = 0.1;
  o.pose.offset_m = 0.2;
  o.pose.evidence.runs = 50;
  o.pose.evidence.span_m = 2.0;
  o.pose.evidence.visible_length_m = 1.5;
  o.pose.evidence.width_sampled = 40;
  o.pose.evidence.width_consistent = 12;
  o.pose.evidence.ends_at_border = 1;
  if (zenith) {
    o.zenith = host::TapePose{};
    o.zenith->status = *zenith;
    o.zenith->yaw_rad = 0.3;
    o.zenith->offset_m = 0.4;
  }
  return o;
}

TEST(ResultsCsv, ZenithColumnsOnlyForAnOkZenithResult) {
  const auto ok = table(outcome(host::Status::ok, host::Status::ok));
  EXPECT_EQ(field(ok, "zenith_status"), "ok");
  EXPECT_EQ(field(ok, "zenith_yaw_rad"), "0.3");
  EXPECT_EQ(field(ok, "zenith_offset_m"), "0.4");
  // The zenith result's own status empties its columns, whatever the centre line says.
  const auto bad = table(outcome(host::Status::ok, host::Status::inconsistent));
  EXPECT_EQ(field(bad, "status"), "ok");
  EXPECT_EQ(field(bad, "yaw_rad"), "0.1");
  EXPECT_EQ(field(bad, "zenith_status"), "inconsistent");
  EXPECT_EQ(field(bad, "zenith_yaw_rad"), "");
  EXPECT_EQ(field(bad, "zenith_offset_m"), "");
  const auto none = table(outcome(host::Status::ok, std::nullopt));
  EXPECT_EQ(field(none, "zenith_status"), "");
}

TEST(ResultsCsv, PoseColumnsEmptyWhenNotOkEvidenceKept) {
  const auto t = table(outcome(host::Status::inconsistent, host::Status::degenerate));
  EXPECT_EQ(field(t, "status"), "inconsistent");
  for (const char* c : {"yaw_rad", "offset_m", "pitch_rad", "vp_u", "vp_v", "pitch_est_rad",
                        "residual_px", "zenith_yaw_rad", "zenith_offset_m"}) {
    EXPECT_EQ(field(t, c), "") << c;
  }
  EXPECT_EQ(field(t, "visible_length_m"), "1.5");
  EXPECT_EQ(field(t, "coverage"), "0.75");
  EXPECT_EQ(field(t, "width_consistent"), "12/40");
  EXPECT_EQ(field(t, "ends_at_border"), "1");
}

TEST(ResultsCsv, OdometryColumnsEmptyUnlessMeasured) {
  const char* cols[] = {"flow_ceiling_m", "flow_ceiling_se_m", "flow_range_m",
                        "flow_frames",    "width_ceiling_m",   "odometry_scale"};
  const auto none = table(outcome(host::Status::ok, std::nullopt));
  for (const char* c : cols) EXPECT_EQ(field(none, c), "") << c;
  OdometryColumns odo;
  odo.flow_ceiling_m = 2.3125;
  odo.flow_ceiling_se_m = 0.004;
  odo.flow_range_m = 4.5;
  odo.flow_frames = 12;
  odo.width_ceiling_m = 2.299;
  odo.odometry_scale = 1.01;
  const auto t = table(outcome(host::Status::ok, std::nullopt), {}, odo);
  EXPECT_EQ(field(t, "flow_ceiling_m"), "2.3125");
  EXPECT_EQ(field(t, "flow_ceiling_se_m"), "0.004");
  EXPECT_EQ(field(t, "flow_range_m"), "4.5");
  EXPECT_EQ(field(t, "flow_frames"), "12");
  EXPECT_EQ(field(t, "width_ceiling_m"), "2.299");
  EXPECT_EQ(field(t, "odometry_scale"), "1.01");
  // Only the width measured (no tape end tracked): the flow columns stay empty.
  OdometryColumns width_only;
  width_only.width_ceiling_m = 2.3;
  const auto w = table(outcome(host::Status::ok, std::nullopt), {}, width_only);
  EXPECT_EQ(field(w, "flow_ceiling_m"), "");
  EXPECT_EQ(field(w, "flow_frames"), "");
  EXPECT_EQ(field(w, "width_ceiling_m"), "2.3");
}

host::Junction junction(host::JunctionKind kind, host::JunctionSide side, double distance_m) {
  host::Junction j;
  j.kind = kind;
  j.side = side;
  j.distance_m = distance_m;
  j.branch_angle_rad = kind == host::JunctionKind::tape_end ? 0.0 : std::numbers::pi / 2;
  return j;
}

// The nearest junction (the first) for an ok pose; none when there is none;
// empty columns when the pose is not ok.
TEST(ResultsCsv, JunctionColumnsOnlyForAnOkPose) {
  const std::vector<host::Junction> js = {
      junction(host::JunctionKind::t_branch, host::JunctionSide::right, 2.5),
      junction(host::JunctionKind::tape_end, host::JunctionSide::none, 4.0)};
  const auto t = table(outcome(host::Status::ok, std::nullopt), js);
  EXPECT_EQ(field(t, "junction"), "t_branch");
  EXPECT_EQ(field(t, "junction_side"), "right");
  EXPECT_EQ(field(t, "junction_distance_m"), "2.5");
  EXPECT_EQ(field(t, "junction_angle_deg"), "90");
  const auto l = table(outcome(host::Status::ok, std::nullopt),
                       {junction(host::JunctionKind::l_turn, host::JunctionSide::both, -0.25)});
  EXPECT_EQ(field(l, "junction"), "l_turn");
  EXPECT_EQ(field(l, "junction_side"), "both");
  EXPECT_EQ(field(l, "junction_distance_m"), "-0.25");
  const auto e = table(outcome(host::Status::ok, std::nullopt),
                       {junction(host::JunctionKind::tape_end, host::JunctionSide::none, 1.75)});
  EXPECT_EQ(field(e, "junction"), "tape_end");
  EXPECT_EQ(field(e, "junction_side"), "");
  EXPECT_EQ(field(e, "junction_distance_m"), "1.75");
  EXPECT_EQ(field(e, "junction_angle_deg"), "");
  const auto none = table(outcome(host::Status::ok, std::nullopt));
  EXPECT_EQ(field(none, "junction"), "none");
  EXPECT_EQ(field(none, "junction_side"), "");
  EXPECT_EQ(field(none, "junction_distance_m"), "");
  const auto bad = table(outcome(host::Status::inconsistent, std::nullopt), js);
  for (const char* c : {"junction", "junction_side", "junction_distance_m", "junction_angle_deg"}) {
    EXPECT_EQ(field(bad, c), "") << c;
  }
}

}  // namespace
}  // namespace ceilnav::app
