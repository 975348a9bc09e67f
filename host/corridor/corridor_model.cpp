#include "host/corridor/corridor_model.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace ceilnav::host::corridor {
namespace {

constexpr double kPi = std::numbers::pi;

double median_of(std::vector<double> v) {
  // The lower middle for an even count (an element, as seed step 11 wants a line).
  std::sort(v.begin(), v.end());
  return v[(v.size() - 1) / 2];
}

// (theta, rho) of `line` written near the reference theta: theta - pi with
// -rho, or theta + pi with -rho, is the same line (normal form wrap).
std::pair<double, double> unwrap_near(const ImageLine& line, double ref_theta) {
  double t = line.theta_rad, r = line.rho_px;
  if (t - ref_theta > 0.5 * kPi) {
    t -= kPi;
    r = -r;
  } else if (t - ref_theta < -0.5 * kPi) {
    t += kPi;
    r = -r;
  }
  return {t, r};
}

// Moves a line seen at pan `from` to the image of the same plane at pan `to`
// (a rotation about the vertical through the camera centre: the homography
// K R(to) R(from)^T K^-1, applied to lines as l' = K^-T R(to) R(from)^T K^T l).
ImageLine to_pan(const ImageLine& line, const ModelCamera& camera, double from_rad, double to_rad) {
  const Eigen::Vector3d n_w = plane_normal(line, camera, from_rad);
  const Eigen::Vector3d l = camera.k().transpose().inverse() *
                            world_to_camera(to_rad, camera.tilt_rad, camera.swing_rad) * n_w;
  return line_from_homogeneous(l, line.strength);
}

struct Group {
  std::vector<double> angles;    // atan(q) of its members
  std::vector<ImageLine> lines;  // at the model pan
  int last_image = -1;
  double median_angle() const { return median_of(angles); }
};

}  // namespace

Eigen::Matrix3d ModelCamera::k() const {
  Eigen::Matrix3d m;
  m << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return m;
}

ModelCamera model_camera(const CameraConfig& camera, const CameraMount& mount) {
  ModelCamera m;
  m.image_width = camera.image_width;
  m.image_height = camera.image_height;
  m.fx = camera.fx();
  m.fy = camera.fy();
  m.cx = camera.cx();
  m.cy = camera.cy();
  m.tilt_rad = mount.tilt_rad;
  m.swing_rad = mount.swing_rad;
  return m;
}

Eigen::Matrix3d world_to_camera(double pan_rad, double tilt_rad, double swing_rad) {
  // Rows: right = heading turned -90 deg about Z, down = forward x right,
  // forward = heading tilted up; then the swing about the optical axis turns
  // the x axis toward y (golden/scene.cpp, world_to_camera_rotation).
  const double cp = std::cos(pan_rad), sp = std::sin(pan_rad);
  const double ct = std::cos(tilt_rad), st = std::sin(tilt_rad);
  Eigen::Matrix3d r;
  r << sp, -cp, 0.0,          //
      st * cp, st * sp, -ct,  //
      ct * cp, ct * sp, st;
  const double cs = std::cos(swing_rad), ss = std::sin(swing_rad);
  Eigen::Matrix3d s;
  s << cs, ss, 0.0, -ss, cs, 0.0, 0.0, 0.0, 1.0;
  return s * r;
}

Eigen::Vector3d plane_normal(const ImageLine& line, const ModelCamera& camera, double pan_rad) {
  // l ~ K^-T R n_w (corridor_model.hpp), so n_w = R^T K^T l.
  const Eigen::Matrix3d r = world_to_camera(pan_rad, camera.tilt_rad, camera.swing_rad);
  return (r.transpose() * camera.k().transpose() * line.homogeneous()).normalized();
}

std::optional<double> inclination(const ImageLine& line, const ModelCamera& camera,
                                  double pan_rad) {
  const Eigen::Vector3d n = plane_normal(line, camera, pan_rad);
  const double horizontal = std::hypot(n.x(), n.y());
  if (horizontal < 1e-9) return std::nullopt;
  // M1 with n_w.y -> sign(n_w.y) |n_w.xy| (pan errors enter at second order).
  return -n.z() / std::copysign(horizontal, n.y());
}

Eigen::Vector2d inclination_gradient(const ImageLine& line, const ModelCamera& camera,
                                     double pan_rad) {
  // q = -m_z / (s |m_xy|) with m = A l, A = R^T K^T, l = (cos t, sin t, -rho)
  // (the normalisation of n cancels in the ratio), s = sign(m_y). With
  // dm = A dl:
  //   dq = -(dm_z |m_xy| - m_z (m_x dm_x + m_y dm_y) / |m_xy|) / (s |m_xy|^2),
  // dl/dt = (-sin t, cos t, 0), dl/drho = (0, 0, -1).
  const Eigen::Matrix3d a =
      world_to_camera(pan_rad, camera.tilt_rad, camera.swing_rad).transpose() *
      camera.k().transpose();
  const Eigen::Vector3d m = a * line.homogeneous();
  const double h = std::hypot(m.x(), m.y());
  const double s = m.y() < 0.0 ? -1.0 : 1.0;
  auto dq = [&](const Eigen::Vector3d& dl) {
    const Eigen::Vector3d dm = a * dl;
    const double dh = (m.x() * dm.x() + m.y() * dm.y()) / h;
    return -(dm.z() * h - m.z() * dh) / (s * h * h);
  };
  const double t = line.theta_rad;
  return {dq({-std::sin(t), std::cos(t), 0.0}), dq({0.0, 0.0, -1.0})};
}

ImageLine line_of_inclination(double q, const ModelCamera& camera, double pan_rad,
                              double strength) {
  const Eigen::Vector3d n_w(0.0, 1.0, -q);
  const Eigen::Vector3d l = camera.k().transpose().inverse() *
                            world_to_camera(pan_rad, camera.tilt_rad, camera.swing_rad) * n_w;
  return line_from_homogeneous(l, strength);
}

CorridorModel learn_model(const std::vector<LearningImage>& images, const ModelCamera& camera,
                          const LearnOptions& options) {
  if (images.empty()) throw std::invalid_argument("learn_model: no learning images");
  if (!(options.line_height_m > 0.0)) {
    throw std::invalid_argument("learn_model: line_height_m must be > 0");
  }
  if (!(options.gate_rad > 0.0) || !(options.same_theta_rad >= 0.0) ||
      !(options.min_support_fraction >= 0.0 && options.min_support_fraction <= 1.0) ||
      options.max_lines < 0) {
    throw std::invalid_argument(
        "learn_model: bad option (gate_rad, same_theta_rad, "
        "min_support_fraction or max_lines)");
  }
  CorridorModel model;
  model.camera = camera;
  model.images = static_cast<int>(images.size());
  {
    std::vector<double> pans;
    for (const LearningImage& im : images) pans.push_back(im.pan_rad);
    model.pan_rad = median_of(pans);
  }

  // Grouping (deviation from steps 9-10, which take the k-th line of every
  // image as group k and so shift every later group when an image misses a
  // line): each line joins the group whose running median of atan(q) is
  // nearest within the gate, one line per group and image, strongest lines
  // first; otherwise it starts a group. atan(q) is the angle of the line's
  // plane from the vertical: pan-free, without the theta wrap at 0 / pi.
  std::vector<Group> groups;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const LearningImage& im = images[i];
    std::vector<ImageLine> lines = im.lines;
    std::stable_sort(lines.begin(), lines.end(), [](const ImageLine& a, const ImageLine& b) {
      return a.strength > b.strength;
    });
    for (const ImageLine& line : lines) {
      const std::optional<double> q = inclination(line, camera, im.pan_rad);
      if (!q) continue;
      const double angle = std::atan(*q);
      Group* best = nullptr;
      double best_d = options.gate_rad;
      for (Group& g : groups) {
        if (g.last_image == static_cast<int>(i)) continue;
        const double d = std::abs(angle - g.median_angle());
        if (d <= best_d) {
          best_d = d;
          best = &g;
        }
      }
      if (best == nullptr) {
        groups.emplace_back();
        best = &groups.back();
      }
      best->angles.push_back(angle);
      best->lines.push_back(to_pan(line, camera, im.pan_rad, model.pan_rad));
      best->last_image = static_cast<int>(i);
    }
  }

  // Spurious groups (a door edge, a glare) are seen in few images.
  const double min_support = options.min_support_fraction * static_cast<double>(images.size());
  std::erase_if(groups,
                [&](const Group& g) { return static_cast<double>(g.angles.size()) < min_support; });
  std::stable_sort(groups.begin(), groups.end(), [](const Group& a, const Group& b) {
    return a.angles.size() > b.angles.size();
  });
  if (options.max_lines > 0 && groups.size() > static_cast<std::size_t>(options.max_lines)) {
    groups.resize(static_cast<std::size_t>(options.max_lines));
  }

  // Step 11: sort a group by theta, average the rho of equal thetas, keep the
  // median-theta line. Thetas are unwrapped near the group's first line.
  for (const Group& g : groups) {
    const double ref = g.lines.front().theta_rad;
    std::vector<std::pair<double, double>> tr;
    for (const ImageLine& l : g.lines) tr.push_back(unwrap_near(l, ref));
    std::sort(tr.begin(), tr.end());
    const double theta = tr[(tr.size() - 1) / 2].first;
    double rho_sum = 0.0, strength_sum = 0.0;
    int n = 0;
    for (const auto& [t, r] : tr) {
      if (std::abs(t - theta) <= options.same_theta_rad) {
        rho_sum += r;
        ++n;
      }
    }
    for (const ImageLine& l : g.lines) strength_sum += l.strength;
    const double rho = rho_sum / n;
    ModelLine ml;
    ml.line = line_from_homogeneous({std::cos(theta), std::sin(theta), -rho},
                                    strength_sum / static_cast<double>(g.lines.size()));
    const std::optional<double> q = inclination(ml.line, camera, model.pan_rad);
    if (!q) continue;
    ml.inclination = *q;
    ml.height_m = options.line_height_m;
    ml.support = static_cast<int>(g.lines.size());
    model.lines.push_back(ml);
  }
  // Left to right: a line further left has a larger dy, so a larger q.
  std::sort(model.lines.begin(), model.lines.end(),
            [](const ModelLine& a, const ModelLine& b) { return a.inclination > b.inclination; });

  // Vanishing points. The axis one is where the model lines meet (least
  // squares: the smallest right singular vector of the stacked unit lines);
  // with fewer than two lines, and for the cross direction (no cross lines
  // in the model), K R e at the model pan.
  const Eigen::Matrix3d kr =
      camera.k() * world_to_camera(model.pan_rad, camera.tilt_rad, camera.swing_rad);
  model.axis_vp = (kr * Eigen::Vector3d::UnitX()).normalized();
  model.cross_vp = (kr * Eigen::Vector3d::UnitY()).normalized();
  if (model.lines.size() >= 2) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(model.lines.size()), 3);
    for (std::size_t i = 0; i < model.lines.size(); ++i) {
      a.row(static_cast<Eigen::Index>(i)) =
          model.lines[i].line.homogeneous().normalized().transpose();
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
    Eigen::Vector3d vp = svd.matrixV().col(2);
    if (vp.dot(model.axis_vp) < 0.0) vp = -vp;
    model.axis_vp = vp.normalized();
  }
  return model;
}

// ---------------------------------------------------------------------------
// Model files.

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& source, const std::string& key, const std::string& what) {
  throw CorridorModelError(source + ": " + key + ": " + what);
}

const json& member(const json& obj, const std::string& key, const std::string& path,
                   const std::string& source) {
  if (!obj.is_object()) bad(source, path, "must be an object");
  const auto it = obj.find(key);
  if (it == obj.end()) bad(source, path + (path.empty() ? "" : ".") + key, "missing");
  return *it;
}

double number(const json& obj, const std::string& key, const std::string& path,
              const std::string& source) {
  const json& v = member(obj, key, path, source);
  const std::string name = path + (path.empty() ? "" : ".") + key;
  if (!v.is_number()) bad(source, name, "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) bad(source, name, "must be finite");
  return d;
}

int integer(const json& obj, const std::string& key, const std::string& path,
            const std::string& source, int min) {
  const json& v = member(obj, key, path, source);
  const std::string name = path + (path.empty() ? "" : ".") + key;
  if (!v.is_number_integer()) bad(source, name, "must be an integer");
  const auto i = v.get<long long>();
  if (i < min || i > 1000000000) bad(source, name, "must be an integer >= " + std::to_string(min));
  return static_cast<int>(i);
}

Eigen::Vector3d homogeneous_point(const json& obj, const std::string& key, const std::string& path,
                                  const std::string& source) {
  const json& v = member(obj, key, path, source);
  const std::string name = path + "." + key;
  if (!v.is_array() || v.size() != 3) bad(source, name, "must be an array of 3 numbers");
  Eigen::Vector3d p;
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>())) {
      bad(source, name, "must be an array of 3 finite numbers");
    }
    p[static_cast<Eigen::Index>(i)] = v[i].get<double>();
  }
  if (!(p.norm() > 1e-12)) bad(source, name, "must not be (0, 0, 0)");
  return p.normalized();
}

// Unknown keys are errors (as in the corridor and course files).
void only_keys(const json& obj, std::initializer_list<const char*> keys, const std::string& path,
               const std::string& source) {
  for (const auto& item : obj.items()) {
    if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return item.key() == k; })) {
      bad(source, path + (path.empty() ? "" : ".") + item.key(), "unknown key");
    }
  }
}

}  // namespace

std::string model_to_json(const CorridorModel& model) {
  json j;
  j["format"] = "ceilnav_corridor_model";
  j["version"] = CorridorModel::kVersion;
  const ModelCamera& c = model.camera;
  j["camera"] = {{"image_width", c.image_width},
                 {"image_height", c.image_height},
                 {"fx_px", c.fx},
                 {"fy_px", c.fy},
                 {"cx_px", c.cx},
                 {"cy_px", c.cy},
                 {"tilt_rad", c.tilt_rad},
                 {"swing_rad", c.swing_rad}};
  j["pan_rad"] = model.pan_rad;
  j["images"] = model.images;
  j["vanishing_points"] = {{"axis", {model.axis_vp.x(), model.axis_vp.y(), model.axis_vp.z()}},
                           {"cross", {model.cross_vp.x(), model.cross_vp.y(), model.cross_vp.z()}}};
  json lines = json::array();
  for (const ModelLine& l : model.lines) {
    lines.push_back({{"theta_rad", l.line.theta_rad},
                     {"rho_px", l.line.rho_px},
                     {"strength", l.line.strength},
                     {"height_m", l.height_m},
                     {"support", l.support}});
  }
  j["lines"] = lines;
  return j.dump(2) + "\n";
}

CorridorModel model_from_json(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw CorridorModelError(source + ": not JSON: " + e.what());
  }
  if (!j.is_object()) bad(source, "(top level)", "must be an object");
  const json& format = member(j, "format", "", source);
  if (!format.is_string() || format.get<std::string>() != "ceilnav_corridor_model") {
    bad(source, "format", "must be \"ceilnav_corridor_model\"");
  }
  const json& version = member(j, "version", "", source);
  if (!version.is_number_integer() || version.get<long long>() != CorridorModel::kVersion) {
    bad(source, "version", "must be " + std::to_string(CorridorModel::kVersion));
  }
  CorridorModel m;
  const json& cam = member(j, "camera", "", source);

  m.camera.image_width = integer(cam, "image_width", "camera", source, 1);
  m.camera.image_height = integer(cam, "image_height", "camera", source, 1);
  m.camera.fx = number(cam, "fx_px", "camera", source);
  m.camera.fy = number(cam, "fy_px", "camera", source);
  m.camera.cx = number(cam, "cx_px", "camera", source);
  m.camera.cy = number(cam, "cy_px", "camera", source);
  m.camera.tilt_rad = number(cam, "tilt_rad", "camera", source);
  m.camera.swing_rad = number(cam, "swing_rad", "camera", source);
  only_keys(
      cam,
      {"image_width", "image_height", "fx_px", "fy_px", "cx_px", "cy_px", "tilt_rad", "swing_rad"},
      "camera", source);
  if (!(m.camera.fx > 0.0)) bad(source, "camera.fx_px", "must be > 0");
  if (!(m.camera.fy > 0.0)) bad(source, "camera.fy_px", "must be > 0");
  if (!(std::abs(m.camera.tilt_rad) < 0.5 * kPi))
    bad(source, "camera.tilt_rad", "must be in (-pi/2, pi/2)");
  m.pan_rad = number(j, "pan_rad", "", source);
  if (!(std::abs(m.pan_rad) < 0.5 * kPi)) bad(source, "pan_rad", "must be in (-pi/2, pi/2)");
  m.images = integer(j, "images", "", source, 1);
  const json& vps = member(j, "vanishing_points", "", source);
  m.axis_vp = homogeneous_point(vps, "axis", "vanishing_points", source);
  m.cross_vp = homogeneous_point(vps, "cross", "vanishing_points", source);
  only_keys(vps, {"axis", "cross"}, "vanishing_points", source);
  const json& lines = member(j, "lines", "", source);
  if (!lines.is_array() || lines.empty()) bad(source, "lines", "must be a non-empty array");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string path = "lines[" + std::to_string(i) + "]";
    const json& l = lines[i];
    if (!l.is_object()) bad(source, path, "must be an object");
    ModelLine ml;
    ml.line.theta_rad = number(l, "theta_rad", path, source);
    ml.line.rho_px = number(l, "rho_px", path, source);
    ml.line.strength = number(l, "strength", path, source);
    ml.height_m = number(l, "height_m", path, source);
    ml.support = integer(l, "support", path, source, 1);
    only_keys(l, {"theta_rad", "rho_px", "strength", "height_m", "support"}, path, source);
    if (!(ml.line.theta_rad >= 0.0 && ml.line.theta_rad < kPi))
      bad(source, path + ".theta_rad", "must be in [0, pi)");
    if (!(ml.line.strength >= 0.0)) bad(source, path + ".strength", "must be >= 0");
    if (!(ml.height_m > 0.0)) bad(source, path + ".height_m", "must be > 0");
    if (ml.support > m.images) bad(source, path + ".support", "must be <= images");
    const std::optional<double> q = inclination(ml.line, m.camera, m.pan_rad);
    if (!q) bad(source, path, "its plane is horizontal: not a line along the corridor axis");
    ml.inclination = *q;
    m.lines.push_back(ml);
  }
  only_keys(j, {"format", "version", "camera", "pan_rad", "images", "vanishing_points", "lines"},
            "", source);
  return m;
}

void write_model_file(const std::string& path, const CorridorModel& model) {
  std::ofstream out(path);
  if (!out) throw CorridorModelError(path + ": cannot open for writing");
  out << model_to_json(model);
  if (!out) throw CorridorModelError(path + ": write failed");
}

CorridorModel read_model_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw CorridorModelError(path + ": cannot open");
  std::stringstream ss;
  ss << in.rdbuf();
  return model_from_json(ss.str(), path);
}

}  // namespace ceilnav::host::corridor
