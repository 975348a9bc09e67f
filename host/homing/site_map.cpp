#include "host/homing/site_map.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

namespace ceilnav::host::homing {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kFormat = "ceilnav_site_map";

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  throw SiteMapError(source + ": " + (key.empty() ? "" : key + ": ") + what);
}

double number(const json& j, const std::string& name, const std::string& source,
              const std::string& key) {
  if (!j.contains(name) || !j[name].is_number()) fail(source, key + "." + name, "must be a number");
  const double v = j[name].get<double>();
  if (!std::isfinite(v)) fail(source, key + "." + name, "must be finite");
  return v;
}

int integer(const json& j, const std::string& name, const std::string& source,
            const std::string& key) {
  if (!j.contains(name) || !j[name].is_number_integer()) {
    fail(source, key + "." + name, "must be an integer");
  }
  return j[name].get<int>();
}

}  // namespace

OdometricPath path_between(const nav::Pose2& a, const nav::Pose2& b, int from, int to) {
  OdometricPath p;
  p.from = from;
  p.to = to;
  const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
  p.distance_m = std::hypot(dx, dy);
  const double bearing = p.distance_m > 0.0 ? std::atan2(dy, dx) : a.yaw_rad;
  p.turn_rad = nav::wrap_angle(bearing - a.yaw_rad);
  p.final_turn_rad = nav::wrap_angle(b.yaw_rad - bearing);
  return p;
}

const OdometricPath* SiteMap::path_from(int from) const {
  for (const OdometricPath& p : paths) {
    if (p.from == from) return &p;
  }
  return nullptr;
}

void save_site_map(const SiteMap& map, const std::string& folder) {
  json j;
  j["format"] = kFormat;
  j["version"] = 1;
  j["sites"] = json::array();
  for (std::size_t k = 0; k < map.sites.size(); ++k) {
    const MapSite& s = map.sites[k];
    const std::string png = "site_" + std::to_string(k) + ".png";
    cv::Mat patch16;
    s.site.patch.convertTo(patch16, CV_16UC1, 256.0);
    if (!cv::imwrite((fs::path(folder) / png).string(), patch16)) {
      fail(folder, png, "cannot be written");
    }
    j["sites"].push_back({{"name", s.name},
                          {"x_m", s.pose.x_m},
                          {"y_m", s.pose.y_m},
                          {"yaw_rad", s.pose.yaw_rad},
                          {"look_forward_m", s.look_forward_m},
                          {"look_left_m", s.look_left_m},
                          {"unusable", s.unusable},
                          {"patch", png},
                          {"template_px", s.site.options.template_px},
                          {"bank_size", s.site.options.bank_size},
                          {"orientation_bins", s.site.options.orientation_bins},
                          {"min_magnitude", s.site.options.min_magnitude},
                          {"major_orientation_deg", s.site.major_orientation_deg},
                          {"self_similarity", s.site.self_similarity},
                          {"rotational_similarity", s.site.rotational_similarity}});
  }
  j["paths"] = json::array();
  for (const OdometricPath& p : map.paths) {
    j["paths"].push_back({{"from", p.from},
                          {"to", p.to},
                          {"turn_rad", p.turn_rad},
                          {"distance_m", p.distance_m},
                          {"final_turn_rad", p.final_turn_rad}});
  }
  const fs::path path = fs::path(folder) / "map.json";
  std::ofstream out(path);
  if (!out) fail(path.string(), "", "cannot be written");
  out << j.dump(2) << "\n";
  if (!out) fail(path.string(), "", "writing failed");
}

SiteMap load_site_map(const std::string& map_json) {
  std::ifstream in(map_json);
  if (!in) fail(map_json, "", "cannot be opened");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {
    fail(map_json, "", std::string("not JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != kFormat) {
    fail(map_json, "format", std::string("must be '") + kFormat + "'");
  }
  if (!j.contains("version") || j["version"] != 1) fail(map_json, "version", "must be 1");
  if (!j.contains("sites") || !j["sites"].is_array()) fail(map_json, "sites", "must be a list");
  if (!j.contains("paths") || !j["paths"].is_array()) fail(map_json, "paths", "must be a list");
  SiteMap map;
  const fs::path dir = fs::path(map_json).parent_path();
  for (std::size_t k = 0; k < j["sites"].size(); ++k) {
    const json& s = j["sites"][k];
    const std::string key = "sites[" + std::to_string(k) + "]";
    if (!s.is_object()) fail(map_json, key, "must be an object");
    MapSite m;
    if (!s.contains("name") || !s["name"].is_string())
      fail(map_json, key + ".name", "must be text");
    m.name = s["name"].get<std::string>();
    m.pose = {number(s, "x_m", map_json, key), number(s, "y_m", map_json, key),
              number(s, "yaw_rad", map_json, key)};
    m.look_forward_m = number(s, "look_forward_m", map_json, key);
    m.look_left_m = number(s, "look_left_m", map_json, key);
    if (!s.contains("unusable") || !s["unusable"].is_string()) {
      fail(map_json, key + ".unusable", "must be text (empty: usable)");
    }
    m.unusable = s["unusable"].get<std::string>();
    m.site.options.template_px = integer(s, "template_px", map_json, key);
    m.site.options.bank_size = integer(s, "bank_size", map_json, key);
    m.site.options.orientation_bins = integer(s, "orientation_bins", map_json, key);
    m.site.options.min_magnitude = number(s, "min_magnitude", map_json, key);
    m.site.major_orientation_deg = number(s, "major_orientation_deg", map_json, key);
    m.site.self_similarity = number(s, "self_similarity", map_json, key);
    m.site.rotational_similarity = number(s, "rotational_similarity", map_json, key);
    if (m.site.options.template_px < 8 || m.site.options.template_px > 1024 ||
        m.site.options.bank_size < 4 || m.site.options.orientation_bins < 4) {
      fail(map_json, key, "template_px, bank_size or orientation_bins out of range");
    }
    if (!s.contains("patch") || !s["patch"].is_string()) {
      fail(map_json, key + ".patch", "must be a file name");
    }
    const fs::path png = dir / s["patch"].get<std::string>();
    const cv::Mat patch16 = cv::imread(png.string(), cv::IMREAD_ANYDEPTH);
    if (patch16.empty() || patch16.type() != CV_16UC1) {
      fail(png.string(), "", "not a 16-bit grey PNG");
    }
    const int side = static_cast<int>(std::ceil(m.site.options.template_px * std::sqrt(2.0))) + 4;
    if (patch16.rows != side || patch16.cols != side) {
      fail(png.string(), "",
           "must be " + std::to_string(side) + " px square for template_px " +
               std::to_string(m.site.options.template_px));
    }
    patch16.convertTo(m.site.patch, CV_32FC1, 1.0 / 256.0);
    map.sites.push_back(std::move(m));
  }
  for (std::size_t k = 0; k < j["paths"].size(); ++k) {
    const json& p = j["paths"][k];
    const std::string key = "paths[" + std::to_string(k) + "]";
    if (!p.is_object()) fail(map_json, key, "must be an object");
    OdometricPath path;
    path.from = integer(p, "from", map_json, key);
    path.to = integer(p, "to", map_json, key);
    const int n = static_cast<int>(map.sites.size());
    if (path.from < 0 || path.from >= n || path.to < 0 || path.to >= n) {
      fail(map_json, key, "names a site that is not in the map");
    }
    path.turn_rad = number(p, "turn_rad", map_json, key);
    path.distance_m = number(p, "distance_m", map_json, key);
    path.final_turn_rad = number(p, "final_turn_rad", map_json, key);
    if (path.distance_m < 0.0) fail(map_json, key + ".distance_m", "must be >= 0");
    map.paths.push_back(path);
  }
  return map;
}

}  // namespace ceilnav::host::homing
