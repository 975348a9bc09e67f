#include "host/camera_config_io.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/core.hpp>

namespace ceilnav::host {
namespace {

constexpr int kMaxImageSide = 2048;
constexpr int kMaxMatrixSide = 16;  // camera_matrix 3x3, distortion_coefficients up to 1x14
constexpr std::uintmax_t kMaxFileBytes = 1u << 20;
constexpr int kParseTimeoutMs = 5000;  // a scene file parses in about a millisecond
constexpr int kChildRefused = 3;       // exit status of the parse probe on a ConfigError

[[noreturn]] void fail(const std::string& source, const std::string& key, const std::string& what) {
  std::ostringstream msg;
  msg << "camera config '" << source << "'";
  if (!key.empty()) msg << ": key '" << key << "'";
  msg << ": " << what;
  throw ConfigError(msg.str());
}

cv::FileNode require(const cv::FileStorage& fs, const std::string& source, const std::string& key) {
  cv::FileNode node = fs[key];
  if (node.empty() || node.isNone()) fail(source, key, "missing");
  return node;
}

int read_int(const cv::FileStorage& fs, const std::string& source, const std::string& key) {
  const cv::FileNode node = require(fs, source, key);
  if (!node.isInt()) fail(source, key, "must be an integer");
  return static_cast<int>(node);
}

double read_real(const cv::FileStorage& fs, const std::string& source, const std::string& key) {
  const cv::FileNode node = require(fs, source, key);
  if (!node.isInt() && !node.isReal()) fail(source, key, "must be a number");
  const double value = static_cast<double>(node);
  if (!std::isfinite(value)) fail(source, key, "must be finite");
  return value;
}

cv::Mat read_matrix(const cv::FileStorage& fs, const std::string& source, const std::string& key) {
  const cv::FileNode node = require(fs, source, key);
  if (!node.isMap() || node["rows"].empty() || node["cols"].empty() || node["data"].empty()) {
    fail(source, key, "must be an opencv-matrix (rows, cols, dt, data)");
  }
  // OpenCV allocates rows x cols before it compares them with the data: check
  // the header first, so that a corrupt size cannot ask for gigabytes.
  const cv::FileNode rows_node = node["rows"], cols_node = node["cols"], data = node["data"];
  if (!rows_node.isInt() || !cols_node.isInt() || !data.isSeq()) {
    fail(source, key, "rows and cols must be integers and data a sequence");
  }
  const int rows = static_cast<int>(rows_node), cols = static_cast<int>(cols_node);
  if (rows < 1 || rows > kMaxMatrixSide || cols < 1 || cols > kMaxMatrixSide) {
    fail(source, key, "rows and cols must be in 1.." + std::to_string(kMaxMatrixSide));
  }
  if (data.size() != static_cast<size_t>(rows) * static_cast<size_t>(cols)) {
    fail(source, key,
         "data has " + std::to_string(data.size()) +
             " elements, rows x cols = " + std::to_string(rows * cols));
  }
  cv::Mat m;
  try {
    node >> m;
  } catch (const std::exception& e) {
    fail(source, key, std::string("unreadable matrix: ") + e.what());
  }
  if (m.empty() || m.channels() != 1) fail(source, key, "must be a non-empty 1-channel matrix");
  cv::Mat m64;
  m.convertTo(m64, CV_64F);
  for (int r = 0; r < m64.rows; ++r) {
    for (int c = 0; c < m64.cols; ++c) {
      if (!std::isfinite(m64.at<double>(r, c))) fail(source, key, "has a non-finite element");
    }
  }
  return m64;
}

// Screens the file before OpenCV's parser sees it. OpenCV 4.6's FileStorage
// YAML parser loops for ever on a document whose '---' marker line carries
// content and is followed by certain lines ("%YAML:1.0", "--- a: 1", "i-",
// "-"; found by fuzz_scene_yaml, docs/fuzzing.md). cv::FileStorage and
// cv::calibrateCamera always write the marker alone on its line, so such a
// file is refused. A scene file is a few hundred bytes: larger than 1 MB is
// refused too (the parsers also recurse once per nesting level, unbounded).
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

}  // namespace

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

// Parses and checks the file (load_camera_config without the guards).
CameraConfig parse_camera_config(const std::string& path) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_AUTO);
  } catch (const std::exception& e) {
    // cv::Exception, and std::length_error from OpenCV 4.6's YAML parser on
    // some malformed keys (found by fuzz_scene_yaml, docs/fuzzing.md).
    fail(path, "", std::string("not a FileStorage YAML file: ") + e.what());
  }
  if (!fs.isOpened()) fail(path, "", "cannot be parsed as FileStorage YAML");
  if (!fs.root().isMap()) fail(path, "", "top level is not a map of keys");

  CameraConfig cfg;
  cfg.image_width = read_int(fs, path, "image_width");
  cfg.image_height = read_int(fs, path, "image_height");

  const cv::Mat k = read_matrix(fs, path, "camera_matrix");
  if (k.rows != 3 || k.cols != 3) fail(path, "camera_matrix", "must be 3x3");
  for (int i = 0; i < 9; ++i)
    cfg.camera_matrix[static_cast<size_t>(i)] = k.at<double>(i / 3, i % 3);

  const cv::Mat d = read_matrix(fs, path, "distortion_coefficients");
  const int n = static_cast<int>(d.total());
  if ((d.rows != 1 && d.cols != 1) || (n != 4 && n != 5 && n != 8 && n != 12 && n != 14)) {
    fail(path, "distortion_coefficients",
         "must be 1x5, 5x1, 1x4 or 4x1 (k1 k2 p1 p2 [k3]); 8, 12 or 14 only with the extra "
         "terms zero");
  }
  // cv::calibrateCamera with the rational, thin-prism or tilted model writes
  // 8, 12 or 14 coefficients; only the 5-term model is supported, so the
  // extra terms must be zero.
  for (int i = 5; i < n; ++i) {
    if (d.at<double>(d.rows == 1 ? 0 : i, d.rows == 1 ? i : 0) != 0.0) {
      fail(path, "distortion_coefficients",
           "has non-zero terms beyond k3 (rational/thin-prism/tilted models are not supported)");
    }
  }
  cfg.distortion_coefficients = {};
  for (int i = 0; i < std::min(n, 5); ++i) {
    cfg.distortion_coefficients[static_cast<size_t>(i)] =
        d.at<double>(d.rows == 1 ? 0 : i, d.rows == 1 ? i : 0);
  }

  cfg.camera_pitch_deg = read_real(fs, path, "camera_pitch_deg");
  cfg.camera_height_m = read_real(fs, path, "camera_height_m");
  cfg.ceiling_height_m = read_real(fs, path, "ceiling_height_m");
  cfg.tape_width_m = read_real(fs, path, "tape_width_m");
  validate_camera_config(cfg, path);
  return cfg;
}

// OpenCV 4.6's FileStorage parsers crash (SIGSEGV) or loop for ever on some
// malformed files (found by fuzz_scene_yaml, docs/fuzzing.md). The file is
// therefore parsed once in a child process first; only when the child ends
// normally (the file was read, or refused with an exception) is it parsed
// again in this process. The parsers are deterministic: the second parse
// takes the same path. Throws ConfigError when the child is killed by a
// signal, exits with another status (a sanitizer's report) or has not
// finished after kParseTimeoutMs.
void probe_parse_in_child(const std::string& path) {
  int fds[2];
  if (pipe(fds) != 0) fail(path, "", "cannot start the parser process (pipe)");
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    fail(path, "", "cannot start the parser process (fork)");
  }
  if (pid == 0) {
    // The child: no output (a crash report would only confuse), no exit
    // handlers. Exit 0: the file was read; kChildRefused: it was refused.
    close(fds[0]);
    const int null_fd = open("/dev/null", O_WRONLY);
    if (null_fd >= 0) dup2(null_fd, STDERR_FILENO);
    int code = 0;
    try {
      (void)parse_camera_config(path);
    } catch (...) {
      code = kChildRefused;
    }
    _exit(code);
  }
  // The parent: the pipe's write end closes when the child ends.
  close(fds[1]);
  pollfd pfd{fds[0], POLLIN, 0};
  int ready = 0;
  do {
    ready = poll(&pfd, 1, kParseTimeoutMs);
  } while (ready < 0 && errno == EINTR);
  close(fds[0]);
  if (ready == 0) kill(pid, SIGKILL);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (ready == 0) {
    fail(path, "",
         "OpenCV's FileStorage parser did not finish within " +
             std::to_string(kParseTimeoutMs / 1000) + " s on this file");
  }
  if (WIFSIGNALED(status)) {
    fail(path, "",
         "OpenCV's FileStorage parser crashed on this file (signal " +
             std::to_string(WTERMSIG(status)) + ")");
  }
  // Any other exit status: a sanitizer reported the crash and exited.
  if (!WIFEXITED(status) || (WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != kChildRefused)) {
    fail(path, "",
         "OpenCV's FileStorage parser failed on this file (exit status " +
             std::to_string(WEXITSTATUS(status)) + ")");
  }
}

}  // namespace

CameraConfig load_camera_config(const std::string& path) {
  {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) fail(path, "", "no such file");
    std::ifstream probe(path, std::ios::binary);
    if (!probe) fail(path, "", "cannot be opened for reading");
    if (probe.peek() == std::ifstream::traits_type::eof()) fail(path, "", "file is empty");
    screen_text(probe, path);
  }
  probe_parse_in_child(path);
  return parse_camera_config(path);
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
