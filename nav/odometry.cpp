#include "nav/odometry.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace ceilnav::nav {
namespace {

std::string trim(std::string_view s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t");
  return std::string(s.substr(b, e - b + 1));
}

// Reads lines, dropping a trailing '\r', counting line numbers from 1.
class LineReader {
 public:
  LineReader(std::istream& in, std::string name) : in_(in), name_(std::move(name)) {}
  // The next non-blank line; false at the end.
  bool next(std::string& line) {
    while (std::getline(in_, line)) {
      ++number_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!trim(line).empty()) return true;
    }
    if (in_.bad()) fail("read error");
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw OdometryFileError(name_ + ":" + std::to_string(number_) + ": " + what);
  }
  const std::string& name() const { return name_; }

 private:
  std::istream& in_;
  std::string name_;
  int number_ = 0;
};

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> out;
  std::string_view rest(line);
  while (true) {
    const auto comma = rest.find(',');
    out.push_back(trim(rest.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return out;
}

double parse_real(const LineReader& r, const std::string& field, const std::string& column) {
  double v = 0.0;
  const char* b = field.data();
  const char* e = b + field.size();
  const auto [ptr, ec] = std::from_chars(b, e, v);
  if (field.empty() || ec != std::errc() || ptr != e) {
    r.fail(column + " '" + field + "' is not a number");
  }
  if (!std::isfinite(v)) r.fail(column + " '" + field + "' is not finite");
  return v;
}

long long parse_count(const LineReader& r, const std::string& field, const std::string& column) {
  long long v = 0;
  const char* b = field.data();
  const char* e = b + field.size();
  const auto [ptr, ec] = std::from_chars(b, e, v);
  if (field.empty() || ec != std::errc() || ptr != e) {
    r.fail(column + " '" + field + "' is not an integer count");
  }
  return v;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& f : v) s += (s.empty() ? "" : ",") + f;
  return s;
}

void check_robot(const RobotParams& p, const std::string& name) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(p.wheel_base_m) || !positive(p.left_m_per_count) ||
      !positive(p.right_m_per_count)) {
    throw OdometryFileError(name +
                            ": wheel_base_m, left_m_per_count, right_m_per_count must be "
                            "finite and > 0");
  }
}

std::ifstream open_or_throw(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw OdometryFileError(path + ": cannot open");
  return in;
}

}  // namespace

RobotParams parse_robot_params(std::istream& in, const std::string& name) {
  LineReader r(in, name);
  std::map<std::string, double> values;
  std::string line;
  while (r.next(line)) {
    const std::string body = trim(line.substr(0, line.find('#')));
    if (body.empty()) continue;
    if (body == "---" || body.rfind("%YAML", 0) == 0) continue;  // document markers
    const auto colon = body.find(':');
    if (colon == std::string::npos) r.fail("expected 'key: value', got '" + body + "'");
    const std::string key = trim(body.substr(0, colon));
    const std::string value = trim(body.substr(colon + 1));
    if (key != "wheel_base_m" && key != "left_m_per_count" && key != "right_m_per_count") {
      r.fail("unknown key '" + key + "'");
    }
    if (values.count(key)) r.fail("key '" + key + "' given twice");
    const double v = parse_real(r, value, key);
    if (!(v > 0.0)) r.fail(key + " must be > 0");
    values[key] = v;
  }
  for (const char* k : {"wheel_base_m", "left_m_per_count", "right_m_per_count"}) {
    if (!values.count(k)) throw OdometryFileError(name + ": missing key '" + k + "'");
  }
  RobotParams p;
  p.wheel_base_m = values["wheel_base_m"];
  p.left_m_per_count = values["left_m_per_count"];
  p.right_m_per_count = values["right_m_per_count"];
  return p;
}

RobotParams load_robot_params(const std::string& path) {
  std::ifstream in = open_or_throw(path);
  return parse_robot_params(in, path);
}

OdometryTrack::OdometryTrack(std::vector<OdometrySample> samples) : samples_(std::move(samples)) {
  if (samples_.size() < 2) throw std::invalid_argument("an odometry track needs two samples");
}

OdometryTrack OdometryTrack::parse(std::istream& in, const std::string& name,
                                   const RobotParams* robot) {
  LineReader r(in, name);
  std::string line;
  if (!r.next(line))
    r.fail(
        "empty file: expected the header t_s,left_ticks,right_ticks or "
        "t_s,v_mps,omega_radps");
  const std::vector<std::string> header = split_fields(line);
  OdometryFormat format;
  if (header == std::vector<std::string>{"t_s", "left_ticks", "right_ticks"}) {
    format = OdometryFormat::encoder_counts;
    if (robot == nullptr) r.fail("encoder counts need the robot's parameters (--robot FILE)");
    check_robot(*robot, name);
  } else if (header == std::vector<std::string>{"t_s", "v_mps", "omega_radps"}) {
    format = OdometryFormat::body_velocity;
  } else {
    r.fail("header '" + join(header) +
           "' is neither t_s,left_ticks,right_ticks nor t_s,v_mps,omega_radps");
  }

  std::vector<OdometrySample> samples;
  long long prev_left = 0, prev_right = 0;
  double prev_v = 0.0, prev_omega = 0.0;
  while (r.next(line)) {
    const std::vector<std::string> f = split_fields(line);
    if (f.size() != 3) r.fail("expected 3 fields, got " + std::to_string(f.size()));
    OdometrySample s;
    s.t_s = parse_real(r, f[0], "t_s");
    if (!samples.empty() && !(s.t_s > samples.back().t_s)) {
      r.fail("time " + f[0] + " is not after the previous row's");
    }
    if (format == OdometryFormat::encoder_counts) {
      const long long left = parse_count(r, f[1], "left_ticks");
      const long long right = parse_count(r, f[2], "right_ticks");
      if (!samples.empty()) {
        const OdometryStep step{s.t_s,
                                static_cast<double>(left - prev_left) * robot->left_m_per_count,
                                static_cast<double>(right - prev_right) * robot->right_m_per_count};
        s.pose = advance(samples.back().pose, motion_of(step, robot->wheel_base_m));
      }
      prev_left = left;
      prev_right = right;
    } else {
      const double v = parse_real(r, f[1], "v_mps");
      const double omega = parse_real(r, f[2], "omega_radps");
      if (!samples.empty()) {
        const double dt = s.t_s - samples.back().t_s;
        s.pose = advance(samples.back().pose, {prev_v * dt, prev_omega * dt});
      }
      prev_v = v;
      prev_omega = omega;
    }
    samples.push_back(s);
  }
  if (samples.size() < 2) r.fail("needs at least two rows of odometry");
  OdometryTrack track(std::move(samples));
  track.format_ = format;
  return track;
}

OdometryTrack OdometryTrack::load(const std::string& path, const RobotParams* robot) {
  std::ifstream in = open_or_throw(path);
  return parse(in, path, robot);
}

Pose2 OdometryTrack::pose_at(double t_s) const {
  if (!covers(t_s)) {
    throw std::out_of_range("time " + std::to_string(t_s) + " s is outside the odometry's span [" +
                            std::to_string(t_begin()) + ", " + std::to_string(t_end()) + "] s");
  }
  // The segment [k-1, k] holding t_s.
  const auto it = std::lower_bound(samples_.begin(), samples_.end(), t_s,
                                   [](const OdometrySample& s, double t) { return s.t_s < t; });
  if (it == samples_.begin()) return it->pose;
  const OdometrySample& a = *(it - 1);
  const OdometrySample& b = *it;
  const double f = (t_s - a.t_s) / (b.t_s - a.t_s);
  // The segment's arc from its end poses: heading change and arc length of the
  // constant-curvature step that joins them (advance() inverted).
  const double dyaw = wrap_angle(b.pose.yaw_rad - a.pose.yaw_rad);
  const double chord = std::hypot(b.pose.x_m - a.pose.x_m, b.pose.y_m - a.pose.y_m);
  const double half = 0.5 * dyaw;
  const double sinc = std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
  // Backward travel: the chord points against the mid heading.
  const double mid = a.pose.yaw_rad + half;
  const double along =
      (b.pose.x_m - a.pose.x_m) * std::cos(mid) + (b.pose.y_m - a.pose.y_m) * std::sin(mid);
  const double distance = (along < 0.0 ? -chord : chord) / sinc;
  return advance(a.pose, {f * distance, f * dyaw});
}

Pose2 OdometryTrack::relative(double t1_s, double t2_s) const {
  return relative_pose(pose_at(t1_s), pose_at(t2_s));
}

Pose2 relative_pose(const Pose2& a, const Pose2& b) {
  const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
  const double c = std::cos(a.yaw_rad), s = std::sin(a.yaw_rad);
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(b.yaw_rad - a.yaw_rad)};
}

std::vector<FrameTime> parse_frame_times(std::istream& in, const std::string& name) {
  LineReader r(in, name);
  std::string line;
  if (!r.next(line)) r.fail("empty file: expected the header frame,t_s");
  if (split_fields(line) != std::vector<std::string>{"frame", "t_s"}) {
    r.fail("header '" + join(split_fields(line)) + "' is not frame,t_s");
  }
  std::vector<FrameTime> out;
  std::set<std::string> seen;
  while (r.next(line)) {
    const std::vector<std::string> f = split_fields(line);
    if (f.size() != 2) r.fail("expected 2 fields, got " + std::to_string(f.size()));
    if (f[0].empty()) r.fail("empty frame name");
    if (!seen.insert(f[0]).second) r.fail("frame '" + f[0] + "' listed twice");
    FrameTime ft{f[0], parse_real(r, f[1], "t_s")};
    if (!out.empty() && !(ft.t_s > out.back().t_s)) {
      r.fail("time " + f[1] + " is not after the previous row's");
    }
    out.push_back(std::move(ft));
  }
  if (out.empty()) r.fail("no frames listed");
  return out;
}

std::vector<FrameTime> load_frame_times(const std::string& path) {
  std::ifstream in = open_or_throw(path);
  return parse_frame_times(in, path);
}

}  // namespace ceilnav::nav
