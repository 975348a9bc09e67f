#include "host/camera_config_io.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <variant>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <opencv2/core.hpp>
#include <pugixml.hpp>

namespace ceilnav::host {
namespace {

constexpr int kMaxImageSide = 2048;
constexpr int kMaxMatrixSide = 16;  // camera_matrix 3x3, distortion_coefficients up to 1x14
constexpr std::uintmax_t kMaxFileBytes = 1u << 20;
// distortion_fold: the radial map is sampled every 1/1024 of the corner's
// distorted radius out to 64 times it; the Jacobian on 64 radii x 128 angles.
constexpr int kRadialSteps = 1024;
constexpr int kMaxRadiusRatio = 64;
constexpr int kDiscRadii = 64;
constexpr int kDiscAngles = 128;

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  std::ostringstream msg;
  msg << "camera config '" << source << "'";
  if (!key.empty()) msg << ": key '" << key << "'";
  msg << ": " << what;
  throw ConfigError(msg.str());
}

// The reader does not hand the file to cv::FileStorage: OpenCV 4.6's
// FileStorage parsers crash or loop for ever on some malformed files (found by
// fuzz_scene_yaml, docs/fuzzing.md). The file is read in-process by yaml-cpp
// (YAML and JSON, the FileStorage YAML subset: the "%YAML:1.0" directive, the
// !!opencv-matrix tag) or pugixml (FileStorage XML) into a flat document of
// top-level keys, each an integer, a real, a matrix or something else.

struct Matrix {
  int rows = 0;
  int cols = 0;
  std::vector<double> data;
};
struct Other {
  std::string what;  // e.g. "a string", "a map without rows/cols/data"
};
using Value = std::variant<long long, double, Matrix, Other>;
using Document = std::map<std::string, Value>;

// An integer literal (optional sign, decimal digits), as FileStorage's isInt().
std::optional<long long> parse_int(const std::string& text) {
  long long v = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  if (first != last && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || first == last) return std::nullopt;
  return v;
}

// A real literal (decimal or exponent form; YAML's .inf/.nan as well, so
// that they are refused as non-finite rather than as text).
std::optional<double> parse_real(const std::string& text) {
  std::string t = text;
  if (t == ".inf" || t == ".Inf" || t == "+.inf" || t == "+.Inf") return HUGE_VAL;
  if (t == "-.inf" || t == "-.Inf") return -HUGE_VAL;
  if (t == ".nan" || t == ".NaN") return std::nan("");
  if (!t.empty() && t[0] == '+') t.erase(0, 1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || ptr != t.data() + t.size() || t.empty()) return std::nullopt;
  return v;
}

Value scalar_value(const std::string& text) {
  if (const auto i = parse_int(text)) return *i;
  if (const auto r = parse_real(text)) return *r;
  return Other{"text"};
}

// rows, cols and data (count = rows x cols, every element a number) of an
// opencv-matrix; the header is checked before the data is stored, so a
// corrupt size cannot ask for memory.
Value matrix_value(const std::string& source, const std::string& key, const std::string& rows_text,
                   const std::string& cols_text, const std::vector<std::string>& elements) {
  const auto rows = parse_int(rows_text), cols = parse_int(cols_text);
  if (!rows || !cols) fail(source, key, "rows and cols must be integers and data a sequence");
  if (*rows < 1 || *rows > kMaxMatrixSide || *cols < 1 || *cols > kMaxMatrixSide) {
    fail(source, key, "rows and cols must be in 1.." + std::to_string(kMaxMatrixSide));
  }
  const auto count = static_cast<size_t>(*rows * *cols);
  if (elements.size() != count) {
    fail(source, key,
         "data has " + std::to_string(elements.size()) +
             " elements, rows x cols = " + std::to_string(count));
  }
  Matrix m{static_cast<int>(*rows), static_cast<int>(*cols), {}};
  for (const std::string& e : elements) {
    const Value v = scalar_value(e);
    if (const auto* i = std::get_if<long long>(&v)) {
      m.data.push_back(static_cast<double>(*i));
    } else if (const auto* r = std::get_if<double>(&v)) {
      m.data.push_back(*r);
    } else {
      fail(source, key, "unreadable matrix: element '" + e + "' is not a number");
    }
  }
  return m;
}

Value yaml_value(const std::string& source, const std::string& key, const YAML::Node& node) {
  if (node.IsScalar()) {
    // A quoted scalar ("3.0", tag "!") is text, as in FileStorage.
    return node.Tag() == "!" ? Value{Other{"text"}} : scalar_value(node.Scalar());
  }
  if (node.IsMap()) {
    const YAML::Node rows = node["rows"], cols = node["cols"], data = node["data"];
    if (!rows || !cols || !data) return Other{"a map"};
    if (!rows.IsScalar() || !cols.IsScalar() || !data.IsSequence()) {
      fail(source, key, "rows and cols must be integers and data a sequence");
    }
    std::vector<std::string> elements;
    for (const YAML::Node& e : data) {
      if (!e.IsScalar()) fail(source, key, "unreadable matrix: data holds a non-scalar");
      elements.push_back(e.Scalar());
      if (elements.size() > size_t{kMaxMatrixSide} * kMaxMatrixSide) break;
    }
    return matrix_value(source, key, rows.Scalar(), cols.Scalar(), elements);
  }
  return Other{node.IsSequence() ? "a sequence" : "null"};
}

Document read_yaml(const std::string& source, std::string text) {
  // FileStorage writes the directive as "%YAML:1.0", which is not YAML 1.2:
  // blank it (the line count stays, for yaml-cpp's messages).
  if (text.rfind("%YAML:", 0) == 0) text.replace(0, text.find('\n'), "");
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    fail(source, "", std::string("not a FileStorage YAML file: ") + e.what());
  }
  if (!root.IsMap()) fail(source, "", "top level is not a map of keys");
  Document doc;
  for (const auto& kv : root) {
    if (!kv.first.IsScalar()) fail(source, "", "a key is not a plain name");
    const std::string key = kv.first.Scalar();
    doc.insert_or_assign(key, yaml_value(source, key, kv.second));
  }
  return doc;
}

Document read_xml(const std::string& source, const std::string& text) {
  pugi::xml_document xml;
  const pugi::xml_parse_result parsed = xml.load_buffer(text.data(), text.size());
  if (!parsed) {
    fail(source, "", std::string("not a FileStorage XML file: ") + parsed.description());
  }
  const pugi::xml_node root = xml.child("opencv_storage");
  if (!root) fail(source, "", "XML without an <opencv_storage> element");
  Document doc;
  for (const pugi::xml_node& n : root.children()) {
    if (n.type() != pugi::node_element) continue;
    const std::string key = n.name();
    const pugi::xml_node rows = n.child("rows"), cols = n.child("cols"), data = n.child("data");
    if (rows && cols && data) {
      std::istringstream words(data.text().get());
      std::vector<std::string> elements;
      for (std::string w; words >> w;) {
        elements.push_back(w);
        if (elements.size() > size_t{kMaxMatrixSide} * kMaxMatrixSide) break;
      }
      doc.insert_or_assign(
          key, matrix_value(source, key, rows.text().get(), cols.text().get(), elements));
    } else if (n.first_child().type() == pugi::node_element) {
      doc.insert_or_assign(key, Value{Other{"a map"}});
    } else {
      std::istringstream words(n.text().get());
      std::string word, extra;
      words >> word >> extra;
      doc.insert_or_assign(key, extra.empty() ? scalar_value(word) : Value{Other{"a sequence"}});
    }
  }
  return doc;
}

const Value& require(const Document& doc, const std::string& source, const std::string& key) {
  const auto it = doc.find(key);
  if (it == doc.end()) fail(source, key, "missing");
  return it->second;
}

int read_int(const Document& doc, const std::string& source, const std::string& key) {
  const auto* v = std::get_if<long long>(&require(doc, source, key));
  if (v == nullptr) fail(source, key, "must be an integer");
  if (*v < INT32_MIN || *v > INT32_MAX) fail(source, key, "is out of the int range");
  return static_cast<int>(*v);
}

double read_real(const Document& doc, const std::string& source, const std::string& key) {
  const Value& v = require(doc, source, key);
  double value = 0.0;
  if (const auto* i = std::get_if<long long>(&v)) {
    value = static_cast<double>(*i);
  } else if (const auto* r = std::get_if<double>(&v)) {
    value = *r;
  } else {
    fail(source, key, "must be a number");
  }
  if (!std::isfinite(value)) fail(source, key, "must be finite");
  return value;
}

const Matrix& read_matrix(const Document& doc, const std::string& source, const std::string& key) {
  const auto* m = std::get_if<Matrix>(&require(doc, source, key));
  if (m == nullptr) fail(source, key, "must be an opencv-matrix (rows, cols, dt, data)");
  for (double v : m->data) {
    if (!std::isfinite(v)) fail(source, key, "has a non-finite element");
  }
  return *m;
}

// Screens the file. The scene file must stay readable by cv::FileStorage
// (BRIEF §5), whose YAML parser (OpenCV 4.6) loops for ever on a document
// whose '---' marker line carries content and is followed by certain lines
// ("%YAML:1.0", "--- a: 1", "i-", "-"; found by fuzz_scene_yaml,
// docs/fuzzing.md). cv::FileStorage and cv::calibrateCamera always write the
// marker alone on its line, so such a file is refused. A scene file is a few
// hundred bytes: larger than 1 MB is refused too.
void screen_text(std::ifstream& in, const std::string& source) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(source, ec);
  if (!ec && bytes > kMaxFileBytes) {
    fail(source, "", "is " + std::to_string(bytes) + " bytes; a scene file is at most 1 MB");
  }
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.rfind("---", 0) == 0 && line.find_first_not_of(" \t\r", 3) != std::string::npos) {
      fail(source, "",
           "line " + std::to_string(number) +
               ": the YAML document marker '---' must be alone on its line");
    }
  }
}

std::string fixed3(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << v;
  return s.str();
}

}  // namespace

std::optional<std::string> distortion_fold(const CameraConfig& cfg) {
  if (!cfg.has_distortion()) return std::nullopt;
  const auto& d = cfg.distortion_coefficients;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
  // Distorted normalised radius of the farthest corner of the sensor.
  double corner = 0.0;
  for (const double u : {-0.5, cfg.image_width - 0.5}) {
    for (const double v : {-0.5, cfg.image_height - 0.5}) {
      corner = std::max(corner, std::hypot((u - cfg.cx()) / cfg.fx(), (v - cfg.cy()) / cfg.fy()));
    }
  }
  const auto radial = [&](double r) {
    const double s = r * r;
    return r * (1.0 + s * (k1 + s * (k2 + s * k3)));
  };
  const auto slope = [&](double r) {  // d r_d / d r
    const double s = r * r;
    return 1.0 + s * (3.0 * k1 + s * (5.0 * k2 + s * 7.0 * k3));
  };
  // The last point of [lo, hi] where `inside` holds (it holds at lo, not at hi).
  const auto bisect = [](double lo, double hi, const auto& inside) {
    for (int it = 0; it < 60; ++it) {
      const double mid = 0.5 * (lo + hi);
      (inside(mid) ? lo : hi) = mid;
    }
    return lo;
  };
  const std::string corner_text = "inside the image corner r_d = " + fixed3(corner);
  // Walk out from the centre until r_d reaches the corner (then bisect for
  // the radius r_max that maps onto it) or the slope stops being positive
  // (then bisect for the turning point).
  const double h = corner / kRadialSteps;
  double r = 0.0, r_max = -1.0;
  for (int i = 1; i <= kRadialSteps * kMaxRadiusRatio && r_max < 0.0; ++i) {
    const double next = h * i;
    if (radial(next) >= corner) {
      r_max = bisect(r, next, [&](double x) { return radial(x) < corner; });
    } else if (!(slope(next) > 0.0)) {
      const double turn = bisect(r, next, [&](double x) { return slope(x) > 0.0; });
      return "the radial map r_d = r (1 + k1 r^2 + k2 r^4 + k3 r^6) turns back at r = " +
             fixed3(turn) + " (r_d = " + fixed3(radial(turn)) + "), " + corner_text;
    } else {
      r = next;
    }
  }
  if (r_max < 0.0) {
    return "the radial map r_d = r (1 + k1 r^2 + k2 r^4 + k3 r^6) reaches only r_d = " +
           fixed3(radial(r)) + " by r = " + fixed3(r) +
           ", short of the image corner r_d = " + fixed3(corner);
  }
  // The whole map, tangential terms included: its Jacobian determinant
  // (the formulas of CameraModel::normalise's Newton step) must stay > 0.
  for (int i = 1; i <= kDiscRadii; ++i) {
    for (int j = 0; j < kDiscAngles; ++j) {
      const double rr = r_max * i / kDiscRadii;
      const double a = 2.0 * std::numbers::pi * j / kDiscAngles;
      const double x = rr * std::cos(a), y = rr * std::sin(a), s = rr * rr;
      const double g = 1.0 + s * (k1 + s * (k2 + s * k3));
      const double gp = k1 + s * (2.0 * k2 + 3.0 * s * k3);
      const double j11 = g + 2.0 * x * x * gp + 2.0 * p1 * y + 6.0 * p2 * x;
      const double j12 = 2.0 * x * y * gp + 2.0 * p1 * x + 2.0 * p2 * y;
      const double j22 = g + 2.0 * y * y * gp + 6.0 * p1 * y + 2.0 * p2 * x;
      const double det = j11 * j22 - j12 * j12;
      if (!(det > 0.0)) {
        return "the distortion map folds (Jacobian determinant " + fixed3(det) + ") at (x, y) = (" +
               fixed3(x) + ", " + fixed3(y) + "), " + corner_text +
               " (the tangential terms p1, p2 are too large for this lens)";
      }
    }
  }
  return std::nullopt;
}

void validate_camera_config(const CameraConfig& cfg, const std::string& source) {
  if (cfg.image_width < 1 || cfg.image_width > kMaxImageSide) {
    fail(source, "image_width", "must be in 1..2048, got " + std::to_string(cfg.image_width));
  }
  if (cfg.image_height < 1 || cfg.image_height > kMaxImageSide) {
    fail(source, "image_height", "must be in 1..2048, got " + std::to_string(cfg.image_height));
  }
  for (double v : cfg.camera_matrix) {
    if (!std::isfinite(v)) fail(source, "camera_matrix", "has a non-finite element");
  }
  const auto& k = cfg.camera_matrix;
  if (k[1] != 0.0 || k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
    fail(source, "camera_matrix", "must be [fx 0 cx; 0 fy cy; 0 0 1] (zero skew)");
  }
  if (!(cfg.fx() > 0.0) || !(cfg.fy() > 0.0))
    fail(source, "camera_matrix", "fx and fy must be > 0");
  // The principal point must lie on the sensor: [-0.5, W - 0.5] x [-0.5, H - 0.5].
  if (cfg.cx() < -0.5 || cfg.cx() > cfg.image_width - 0.5 || cfg.cy() < -0.5 ||
      cfg.cy() > cfg.image_height - 0.5) {
    fail(source, "camera_matrix", "principal point (cx, cy) outside the image");
  }
  for (double v : cfg.distortion_coefficients) {
    if (!std::isfinite(v)) fail(source, "distortion_coefficients", "has a non-finite element");
  }
  if (const auto why = distortion_fold(cfg)) {
    fail(source, "distortion_coefficients", "not invertible over the image: " + *why);
  }
  if (!std::isfinite(cfg.camera_pitch_deg) || !(cfg.camera_pitch_deg > 0.0) ||
      cfg.camera_pitch_deg > 90.0) {
    fail(source, "camera_pitch_deg", "must be in (0, 90]");
  }
  if (!std::isfinite(cfg.camera_height_m)) fail(source, "camera_height_m", "must be finite");
  if (!std::isfinite(cfg.ceiling_height_m) || !(cfg.ceiling_height_m > cfg.camera_height_m)) {
    fail(source, "ceiling_height_m", "must be greater than camera_height_m");
  }
  if (!std::isfinite(cfg.tape_width_m) || !(cfg.tape_width_m > 0.0)) {
    fail(source, "tape_width_m", "must be > 0");
  }
}

namespace {

// Parses and checks the file's text.
CameraConfig parse_camera_config(const std::string& path, const std::string& text,
                                 ConfigKeys keys) {
  const size_t first = text.find_first_not_of(" \t\r\n");
  const Document doc = (first != std::string::npos && text[first] == '<') ? read_xml(path, text)
                                                                          : read_yaml(path, text);
  CameraConfig cfg;
  cfg.image_width = read_int(doc, path, "image_width");
  cfg.image_height = read_int(doc, path, "image_height");

  const Matrix& k = read_matrix(doc, path, "camera_matrix");
  if (k.rows != 3 || k.cols != 3) fail(path, "camera_matrix", "must be 3x3");
  std::copy(k.data.begin(), k.data.end(), cfg.camera_matrix.begin());

  const Matrix& d = read_matrix(doc, path, "distortion_coefficients");
  const int n = d.rows * d.cols;
  if ((d.rows != 1 && d.cols != 1) || (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)) {
    fail(path, "distortion_coefficients",
         "must be 1x5, 5x1, 1x4 or 4x1 (k1 k2 p1 p2 [k3]); 8, 12 or 14 only with the extra "
         "terms zero");
  }
  // cv::calibrateCamera with the rational, thin-prism or tilted model writes
  // 8, 12 or 14 coefficients; only the 5-term model is supported, so the
  // extra terms must be zero.
  for (int i = 5; i < n; ++i) {
    if (d.data[static_cast<size_t>(i)] != 0.0) {
      fail(path, "distortion_coefficients",
           "has non-zero terms beyond k3 (rational/thin-prism/tilted models are not supported)");
    }
  }
  cfg.distortion_coefficients = {};
  for (int i = 0; i < std::min(n, 5); ++i) {
    cfg.distortion_coefficients[static_cast<size_t>(i)] = d.data[static_cast<size_t>(i)];
  }

  // The scene keys; with ConfigKeys::camera_only an absent one keeps its default.
  const auto scene_key = [&](const char* key, double& field) {
    if (keys == ConfigKeys::scene || doc.count(key) != 0) field = read_real(doc, path, key);
  };
  scene_key("camera_pitch_deg", cfg.camera_pitch_deg);
  scene_key("camera_height_m", cfg.camera_height_m);
  scene_key("ceiling_height_m", cfg.ceiling_height_m);
  scene_key("tape_width_m", cfg.tape_width_m);
  validate_camera_config(cfg, path);
  return cfg;
}

}  // namespace

CameraConfig load_camera_config(const std::string& path, ConfigKeys keys) {
  {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail(path, "", "no such file");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) fail(path, "", "cannot be opened for reading");
    if (probe.peek() == std::ifstream::traits_type::eof()) fail(path, "", "file is empty");
    screen_text(probe, path);
  }
  std::ifstream in(path, std::ios::binary);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (!in.good() && !in.eof()) fail(path, "", "cannot be read");
  return parse_camera_config(path, text, keys);
}

void save_camera_config(const CameraConfig& cfg, const std::string& path) {
  validate_camera_config(cfg, path);
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
    if (!fs.isOpened()) fail(path, "", "cannot be opened for writing");
    const cv::Mat k(3, 3, CV_64F, const_cast<double*>(cfg.camera_matrix.data()));
    const cv::Mat d(1, 5, CV_64F, const_cast<double*>(cfg.distortion_coefficients.data()));
    fs << "image_width" << cfg.image_width << "image_height" << cfg.image_height;
    fs << "camera_matrix" << k << "distortion_coefficients" << d;
    fs << "camera_pitch_deg" << cfg.camera_pitch_deg << "camera_height_m" << cfg.camera_height_m;
    fs << "ceiling_height_m" << cfg.ceiling_height_m << "tape_width_m" << cfg.tape_width_m;
    fs.release();
  } catch (const cv::Exception& e) {
    fail(path, "", std::string("cannot be written: ") + e.what());
  }
}

}  // namespace ceilnav::host
