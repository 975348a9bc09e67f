// Renders one 640x480 frame of a taped ceiling with a known pose, streams it
// beat by beat through the C++ cycle-level model of the device (registers
// programmed by the host driver over AXI4-Lite), and prints the pose the host
// computes from the device's runs next to the truth.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "common/camera_config.hpp"
#include "drivers/device.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/navigator.hpp"
#include "host/status.hpp"

int main() {
  using namespace ceilnav;
  host::CameraConfig camera;
  camera.image_width = 640;
  camera.image_height = 480;
  camera.camera_matrix = {500.0, 0.0, 319.5, 0.0, 500.0, 239.5, 0.0, 0.0, 1.0};
  camera.camera_pitch_deg = 45.0;
  camera.camera_height_m = 0.3;
  camera.ceiling_height_m = 2.8;
  camera.tape_width_m = 0.05;

  constexpr double kDeg = std::numbers::pi / 180.0;
  const golden::CameraPose truth{0.0, 0.12, 5.0 * kDeg};  // 12 cm left of the tape, yaw 5 deg
  const cv::Mat frame =
      golden::render_frame(camera, golden::single_tape_scene(camera.tape_width_m), truth, {});

  drivers::DeviceOptions device;
  device.backend = drivers::Backend::model;  // the C++ cycle model behind its registers
  host::Navigator navigator(camera, drivers::make_device(device));
  const host::FrameOutcome out = navigator.process(frame);

  std::printf("device: %llu cycles, %zu runs, %d pass(es)\n",
              static_cast<unsigned long long>(out.cycles), out.runs.size(), out.passes);
  std::printf("status %s\n", std::string(host::to_string(out.pose.status)).c_str());
  std::printf("yaw    %+.3f deg (truth %+.3f)\n", out.pose.yaw_rad / kDeg, truth.yaw_rad / kDeg);
  std::printf("offset %+.4f m   (truth %+.4f)\n", out.pose.offset_m, truth.y_m);
  return out.pose.status == host::Status::ok ? 0 : 1;
}
