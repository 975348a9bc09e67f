// Helpers shared by the tape commands, and the backend and camera choices
// declared in commands.hpp.
#include "apps/command_support.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "apps/commands.hpp"
#include "drivers/rtl_backend.hpp"
#include "golden/default_scene.hpp"
#include "host/camera_config_io.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

double wrap_angle(double a) {
  return std::remainder(a, 2.0 * std::numbers::pi);
}

void write_png(const OutputFolder& folder, const fs::path& relative, const cv::Mat& img) {
  const fs::path shown = folder.folder() / relative;
  std::vector<unsigned char> bytes;
  if (!cv::imencode(".png", img, bytes)) {
    throw std::runtime_error("cannot encode image '" + shown.string() + "'");
  }
  std::ofstream out(folder.path(relative), std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error("error while writing '" + shown.string() + "'");
}

// scene.yaml, read back: cv::FileStorage does not report every write error.
void write_scene(const OutputFolder& folder, const host::CameraConfig& camera) {
  const std::string path = folder.path("scene.yaml").string();
  host::save_camera_config(camera, path);
  host::load_camera_config(path);
}

std::string frame_name(int i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%04d.png", i);
  return buf;
}

void check_overlay_every(int every) {
  if (every < 0) {
    throw std::runtime_error("--overlay-every must be 0 (off) or a positive frame count, not " +
                             std::to_string(every));
  }
}

bool overlay_due(int every, size_t index) {
  check_overlay_every(every);
  return every > 0 && index % static_cast<size_t>(every) == 0;
}

fs::path overlay_file_name(const std::string& frame_file) {
  return fs::path(frame_file).filename().stem().string() + ".png";
}

SampledPose sample_pose(std::mt19937_64& rng, double pitch_min, double pitch_max, double yaw_max,
                        double offset_max, double noise_max, double blur_max) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  SampledPose s;
  s.pitch_deg = pitch_min + (pitch_max - pitch_min) * u01(rng);
  s.pose.yaw_rad = (2.0 * u01(rng) - 1.0) * yaw_max * kDeg;
  s.pose.y_m = (2.0 * u01(rng) - 1.0) * offset_max;
  s.pose.x_m = 10.0 * u01(rng);
  s.noise = noise_max * u01(rng);
  s.blur = blur_max * u01(rng);
  return s;
}

drivers::DeviceOptions device_options(const std::string& backend) {
  drivers::DeviceOptions opt;
  if (backend == "fast") {
    opt.backend = drivers::Backend::fast;
  } else if (backend == "model") {
    opt.backend = drivers::Backend::model;
  } else if (backend == "rtl") {
    opt.backend = drivers::Backend::rtl;
    opt.bus_factory = drivers::rtl_bus_factory();
    if (!opt.bus_factory) {
      throw std::runtime_error("this ceilnav was built without the Verilated RTL backend");
    }
  } else {
    throw std::runtime_error("unknown backend '" + backend + "' (fast, model or rtl)");
  }
  if (opt.backend != drivers::Backend::fast) {  // exercise the stream handshakes, as demo does
    opt.gap_probability = 0.1;
    opt.backpressure_probability = 0.3;
  }
  return opt;
}

host::CameraConfig scaled_camera(int width, int height, bool distortion) {
  host::CameraConfig c = golden::default_camera();
  const double sx = width / 640.0, sy = height / 480.0;
  c.image_width = width;
  c.image_height = height;
  c.camera_matrix = {520.0 * sx, 0.0,        (321.7 + 0.5) * sx - 0.5,
                     0.0,        518.5 * sy, (238.2 + 0.5) * sy - 0.5,
                     0.0,        0.0,        1.0};
  if (!distortion) c.distortion_coefficients = {};
  return c;
}

}  // namespace ceilnav::app
