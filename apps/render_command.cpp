// `ceilnav render`: frames of known pose, their truth and scene.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "apps/atomic_file.hpp"
#include "apps/command_support.hpp"
#include "apps/commands.hpp"
#include "apps/progress.hpp"
#include "apps/results_csv.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/camera_config_io.hpp"
#include "host/navigator.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

int run_render(const RenderOptions& o) {
  if (o.frames < 1) throw std::runtime_error("--frames must be at least 1");
  const fs::path out = o.out_dir;
  host::CameraConfig camera = scaled_camera(o.width, o.height, o.distortion);
  camera.camera_pitch_deg = o.pitch_deg;
  host::validate_camera_config(camera, "--width/--height/--pitch-deg");
  // Everything goes into a staging folder, renamed into place at the end.
  OutputFolder folder(out);
  const golden::CeilingScene scene = o.random_poses ? golden::single_tape_scene(camera.tape_width_m)
                                                    : golden::default_corridor(camera);
  golden::RenderParams params = golden::default_render_params();
  if (o.noise_sigma >= 0) params.noise_sigma_grey = o.noise_sigma;
  if (o.blur_sigma >= 0) params.blur_sigma_px = o.blur_sigma;

  std::mt19937_64 rng(o.seed);
  const std::vector<golden::DrivePose> drive = golden::default_drive(o.frames);
  std::vector<std::pair<std::string, golden::FrameTruth>> truth_rows;
  Progress progress("render", static_cast<size_t>(o.frames));
  for (int i = 0; i < o.frames; ++i) {
    golden::CameraPose pose = drive[static_cast<size_t>(i)].pose;
    if (o.random_poses) {
      pose = sample_pose(rng, o.pitch_deg, o.pitch_deg, 15.0, 0.5, 0.0, 0.0).pose;
    }
    params.noise_seed = o.seed * 7919u + static_cast<uint64_t>(i);
    const cv::Mat frame = golden::render_frame(camera, scene, pose, params);
    const std::string name = frame_name(i);
    write_png(folder, name, frame);
    truth_rows.emplace_back(name, golden::truth_for(camera, scene, pose));
    progress.update(static_cast<size_t>(i + 1));
  }
  progress.finish();
  golden::write_truth_csv(folder.path("truth.csv").string(), truth_rows);
  write_scene(folder, camera);
  folder.commit();
  std::printf("wrote %d frames, truth.csv and scene.yaml to %s\n", o.frames, out.string().c_str());
  return 0;
}

}  // namespace ceilnav::app
