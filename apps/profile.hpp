// `ceilnav profile`: frames streamed cycle by cycle through the device (the C++
// cycle-level model or the Verilated RTL) with a chosen video timing and
// run-stream back-pressure, measured at the device ports and through its
// registers, frame by frame. See docs/profile.md. The command's options and
// entry point; the scenario, the port probe and the run have their headers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "apps/port_probe.hpp"
#include "apps/profile_run.hpp"
#include "apps/profile_scenario.hpp"

namespace ceilnav::app {

struct ProfileOptions {
  std::string backend = "model";  // model | rtl
  std::string config = "full";    // device configuration (regs::kConfigs): tape | corridor | full
  std::string frames_dir;         // empty: render
  std::string scene_file;         // with frames_dir; default <frames_dir>/scene.yaml
  std::string out_dir;            // empty: summary on stdout only
  int width = 640, height = 480;
  std::string blanking = "none";
  double gap_probability = 0.25;
  double backpressure = 0.0;
  int tapes = 1;
  int count = 0;  // 0: 10 rendered frames, or every frame of frames_dir
  uint64_t seed = 1;
  std::vector<double> sweep_duties{0.0, 0.25, 0.5, 0.75, 0.9};
  int sweep_frames = 2;  // frames per sweep point; 0: no sweep
};
int run_profile(const ProfileOptions& o);

}  // namespace ceilnav::app
