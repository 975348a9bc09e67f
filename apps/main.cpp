// ceilnav: the command-line program. `ceilnav --help` lists the commands.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "apps/commands.hpp"
#include "apps/pattern_commands.hpp"
#include "apps/profile.hpp"
#include "common/version.hpp"
#include "host/camera_config_io.hpp"
#include "host/frame_io.hpp"
#include "nav/odometry.hpp"

namespace {

// A finite number in [lo, hi]. (CLI::Range lets NaN through: every
// comparison with NaN is false.)
CLI::Validator finite_in(double lo, double hi) {
  std::ostringstream range;
  range << "[" << lo << ", " << hi << "]";
  return CLI::Validator(
      [lo, hi, r = range.str()](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(begin, &end);
        if (end == begin || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < lo ||
            v > hi) {
          return "'" + text + "' is not a finite number in " + r;
        }
        return {};
      },
      "NUMBER in " + range.str());
}

// A seed: digits only, fitting 64 bits. (CLI11 would take "-1" as 2^64 - 1.)
CLI::Validator unsigned_integer() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits =
            !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        errno = 0;
        if (digits) std::strtoull(text.c_str(), nullptr, 10);
        if (!digits || errno == ERANGE) return "'" + text + "' is not an integer in [0, 2^64)";
        return {};
      },
      "UINT64");
}

}  // namespace

namespace ceilnav::app {
namespace {

// --overlay-every N (run, pattern): N >= 0, checked by CLI11 before any output;
// `where` ends the help text (where the folder goes, what 0 means).
void add_overlay_every(CLI::App& cmd, int& every, const std::string& where) {
  cmd.add_option("--overlay-every", every,
                 "N >= 1: an overlay PNG of every N-th frame (frame 0 included) as "
                 "overlays/<frame name>.png " +
                     where)
      ->check(CLI::Range(0, std::numeric_limits<int>::max()))
      ->capture_default_str();
}

// `ceilnav demo` and its options, parsed into `demo`.
CLI::App* add_demo_command(CLI::App& app, DemoOptions& demo) {
  auto* demo_cmd = app.add_subcommand(
      "demo",
      "Render a drive down a taped corridor, run every frame through the device model "
      "and the host, print the errors against truth, write CSV and an overlay PNG");
  demo_cmd->add_option("--out", demo.out_dir, "Output folder (created)")->capture_default_str();
  demo_cmd->add_option("--frames", demo.frames, "Frames in the drive")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  demo_cmd
      ->add_option("--backend", demo.backend,
                   "fast (frame at a time), model (C++ cycle-level device through its "
                   "registers) or rtl (Verilated RTL through its registers)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  return demo_cmd;
}

// `ceilnav run` and its options, parsed into `run`.
CLI::App* add_run_command(CLI::App& app, RunOptions& run) {
  auto* run_cmd = app.add_subcommand(
      "run", "Process every PNG of a folder (name order) and write one CSV row per frame");
  run_cmd->add_option("--frames", run.frames_dir, "Folder of PNG frames")->required();
  run_cmd->add_option("--scene", run.scene_file, "Scene/camera YAML (OpenCV FileStorage)")
      ->required();
  run_cmd->add_option("--out", run.out_csv, "Results CSV (written whole or not at all)")
      ->required();
  run_cmd
      ->add_option("--backend", run.backend,
                   "fast (frame at a time), model (C++ cycle-level device through its "
                   "registers) or rtl (Verilated RTL through its registers)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  run_cmd
      ->add_option("--gap-probability", run.gap_probability,
                   "model/rtl: probability of a tvalid gap before a pixel")
      ->check(finite_in(0.0, 0.99));
  run_cmd
      ->add_option("--backpressure-probability", run.backpressure_probability,
                   "model/rtl: probability of tready low on the run stream per cycle")
      ->check(finite_in(0.0, 0.99));
  run_cmd->add_option("--seed", run.seed, "model/rtl: seed of the gap/back-pressure pattern")
      ->check(unsigned_integer());
  add_overlay_every(*run_cmd, run.overlay_every, "in the CSV's folder; 0: none");
  run_cmd->add_flag("--track", run.track,
                    "The frames are one sequence in name order: a pose farther from the previous "
                    "ok frame's than the robot can move between frames is 'jump'");
  auto* odo = run_cmd->add_option(
      "--odometry", run.odometry_file,
      "Measured odometry CSV (t_s,left_ticks,right_ticks or t_s,v_mps,omega_radps): adds the "
      "flow and tape-width ceiling heights and the odometry scale to the CSV");
  run_cmd
      ->add_option("--robot", run.robot_file,
                   "Robot YAML (wheel_base_m, left_m_per_count, right_m_per_count) for "
                   "encoder counts")
      ->needs(odo);
  auto* times = run_cmd
                    ->add_option("--frame-times", run.frame_times_file,
                                 "CSV frame,t_s: each PNG's file name and mid-exposure time")
                    ->needs(odo);
  run_cmd->add_option("--fps", run.fps, "Frame i (name order) exposed at i / F s")
      ->check(finite_in(1e-6, 1e6))
      ->needs(odo)
      ->excludes(times);
  return run_cmd;
}

// `ceilnav render-drive` and its options, parsed into `drive`.
CLI::App* add_render_drive_command(CLI::App& app, RenderDriveOptions& drive) {
  auto* cmd = app.add_subcommand(
      "render-drive",
      "Render a drive over the corridor with the wheel odometry it logs (frames/, scene.yaml, "
      "odometry.csv, robot.yaml, frame_times.csv, truth.csv) for run --odometry");
  cmd->add_option("--out", drive.out_dir, "Output folder (written whole or not at all)")
      ->required();
  cmd->add_option("--path", drive.path, "straight or curve (gentle S-curves)")
      ->check(CLI::IsMember({"straight", "curve"}))
      ->capture_default_str();
  cmd->add_option("--length", drive.length_m, "Distance along the corridor, m")
      ->check(finite_in(0.5, 50.0))
      ->capture_default_str();
  cmd->add_option("--speed", drive.speed_mps, "m/s")
      ->check(finite_in(0.05, 5.0))
      ->capture_default_str();
  cmd->add_option("--fps", drive.fps, "Frames per second")
      ->check(finite_in(0.1, 100.0))
      ->capture_default_str();
  cmd->add_option("--tick-hz", drive.tick_hz, "Odometry ticks per second")
      ->check(finite_in(1.0, 10000.0))
      ->capture_default_str();
  cmd->add_option("--scale-error", drive.scale_error,
                  "The odometry reports (1 + E) times the wheels' travel")
      ->check(finite_in(-0.5, 0.5))
      ->capture_default_str();
  cmd->add_option("--m-per-count", drive.m_per_count, "Wheel travel per encoder count, m")
      ->check(finite_in(1e-7, 0.1))
      ->capture_default_str();
  cmd->add_option("--seed", drive.seed, "Noise seed")->check(unsigned_integer());
  return cmd;
}

// `ceilnav render` and its options, parsed into `render`.
CLI::App* add_render_command(CLI::App& app, RenderOptions& render) {
  auto* render_cmd = app.add_subcommand(
      "render", "Render frames with known pose: PNGs, truth.csv and scene.yaml into a folder");
  render_cmd->add_option("--out", render.out_dir, "Output folder (created)")->required();
  render_cmd->add_option("--frames", render.frames, "Number of frames")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  render_cmd->add_flag("--random-poses", render.random_poses,
                       "Random yaw (+-15 deg) and offset (+-0.5 m) over one tape, instead of the "
                       "demo drive");
  render_cmd->add_option("--seed", render.seed, "Random seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  render_cmd->add_option("--noise", render.noise_sigma, "Noise sigma, grey levels")
      ->check(finite_in(0.0, 255.0));
  render_cmd->add_option("--blur", render.blur_sigma, "Blur sigma, pixels")
      ->check(finite_in(0.0, 20.0));
  render_cmd->add_option("--pitch-deg", render.pitch_deg, "Camera pitch")
      ->check(finite_in(1.0, 90.0))
      ->capture_default_str();
  render_cmd->add_option("--width", render.width, "Image width")->check(CLI::Range(16, 2048));
  render_cmd->add_option("--height", render.height, "Image height")->check(CLI::Range(16, 2048));
  render_cmd->add_flag("!--no-distortion", render.distortion, "Render without lens distortion");
  return render_cmd;
}

// `ceilnav accuracy` and its options, parsed into `acc`.
CLI::App* add_accuracy_command(CLI::App& app, AccuracyOptions& acc) {
  auto* acc_cmd = app.add_subcommand(
      "accuracy", "Accuracy benchmark: random poses rendered and estimated, RMS errors vs truth");
  acc_cmd->add_option("--frames", acc.frames, "Number of random frames")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  acc_cmd->add_option("--seed", acc.seed, "Random seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  acc_cmd->add_option("--pitch-min", acc.pitch_min_deg, "Degrees")
      ->check(finite_in(0.0, 90.0))
      ->capture_default_str();
  acc_cmd->add_option("--pitch-max", acc.pitch_max_deg, "Degrees")
      ->check(finite_in(0.0, 90.0))
      ->capture_default_str();
  acc_cmd->add_option("--yaw-max", acc.yaw_max_deg, "Degrees")
      ->check(finite_in(0.0, 89.0))
      ->capture_default_str();
  acc_cmd->add_option("--offset-max", acc.offset_max_m, "Metres")
      ->check(finite_in(0.0, 10.0))
      ->capture_default_str();
  acc_cmd->add_option("--noise-max", acc.noise_max, "Noise sigma, grey levels")
      ->check(finite_in(0.0, 255.0))
      ->capture_default_str();
  acc_cmd->add_option("--blur-max", acc.blur_max, "Blur sigma, pixels")
      ->check(finite_in(0.0, 20.0))
      ->capture_default_str();
  acc_cmd->add_option("--width", acc.width, "Image width")->check(CLI::Range(16, 2048));
  acc_cmd->add_option("--height", acc.height, "Image height")->check(CLI::Range(16, 2048));
  acc_cmd->add_flag("!--no-distortion", acc.distortion, "Render without lens distortion");
  acc_cmd->add_option("--tape-gain", acc.tape_gain, "Tape return: grey above background at 1 m")
      ->check(finite_in(0.0, 1e7));
  acc_cmd->add_option("--background", acc.background_grey, "Ceiling grey level")
      ->check(finite_in(0.0, 255.0));
  acc_cmd->add_option("--ceiling-m", acc.ceiling_height_m, "Ceiling height above the floor")
      ->check(finite_in(0.0, 100.0));
  acc_cmd->add_option("--tape-width-m", acc.tape_width_m, "Tape width")
      ->check(finite_in(0.001, 1.0));
  acc_cmd->add_option("--csv", acc.csv, "Per-frame errors to this CSV");
  acc_cmd->add_flag("--require", acc.require,
                    "Exit 1 unless yaw RMS <= 0.02 deg, offset RMS <= 1 mm and every frame ok");
  return acc_cmd;
}

// `ceilnav exposure` and its options, parsed into `expo`.
CLI::App* add_exposure_command(CLI::App& app, ExposureOptions& expo) {
  auto* cmd = app.add_subcommand(
      "exposure",
      "Histogram correction table (seed 000) on an exposure sweep: a drive along one tape with "
      "exposure steps of x0.5-x2 between frames, under each threshold policy; errors vs truth");
  cmd->add_option("--frames", expo.frames, "Number of frames")
      ->check(CLI::Range(2, 100000))
      ->capture_default_str();
  cmd->add_option("--pitch", expo.pitch_deg, "Camera pitch, degrees")
      ->check(finite_in(1.0, 90.0))
      ->capture_default_str();
  cmd->add_option("--step", expo.step_m, "Travel between frames, metres")
      ->check(finite_in(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--tape-gain", expo.tape_gain, "Tape return at nominal exposure: grey at 1 m")
      ->check(finite_in(0.0, 1e7));
  cmd->add_option("--background", expo.background_grey, "Ceiling grey at nominal exposure")
      ->check(finite_in(0.0, 255.0));
  cmd->add_option("--noise", expo.noise_sigma, "Read noise sigma, grey levels")
      ->check(finite_in(0.0, 255.0));
  cmd->add_option("--seed", expo.seed, "Noise seed")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--backend", expo.backend, "fast, model or rtl")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  cmd->add_option("--csv", expo.csv, "Per-frame, per-policy rows to this CSV");
  return cmd;
}

// `ceilnav profile` and its options, parsed into `prof`.
// `ceilnav drive` and its options, parsed into `drive`.
CLI::App* add_drive_command(CLI::App& app, DriveOptions& drive) {
  auto* cmd = app.add_subcommand(
      "drive",
      "Drive a course closed loop on ceilnav: a simulated robot, its camera frames through the "
      "device and the host, the fusion filter and the path follower; writes trajectory.csv, "
      "summary.json and drive.png");
  cmd->add_option("--course", drive.course_file,
                  "Course file (YAML or JSON, docs/navigation.md); default: the built-in course")
      ->check(CLI::ExistingFile);
  auto* random_opt =
      cmd->add_option("--random-course", drive.random_course,
                      "Instead of the built-in course, a random one (sim::random_course) of this "
                      "seed; course.yaml in the output folder keeps it")
          ->check(CLI::NonNegativeNumber)
          ->excludes("--course");
  cmd->add_option("--random-length", drive.random_length_m, "Length of the random course, m")
      ->check(CLI::Range(60.0, 10000.0))
      ->needs(random_opt)
      ->capture_default_str();
  auto* corridor_opt =
      cmd->add_option("--corridor", drive.corridor,
                      "Drive down a corridor without tape on seed 002's guidance instead: "
                      "'default' (the built-in corridor) or a corridor file "
                      "(docs/navigation_io.md); writes corridor_drive.csv, model.json, "
                      "summary.json and drive.png")
          ->check(CLI::ExistingFile | CLI::IsMember({"default"}))
          ->excludes("--course")
          ->excludes(random_opt);
  cmd->add_option("--length", drive.length_m, "Length of the corridor drive, m")
      ->check(CLI::Range(2.0, 10000.0))
      ->needs(corridor_opt)
      ->capture_default_str();
  cmd->add_option("--out", drive.out_dir, "Output folder (created)")->capture_default_str();
  cmd->add_option("--backend", drive.backend,
                  "fast, model (C++ cycle-level device) or rtl (Verilated RTL; slow: use a short "
                  "course)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  cmd->add_option("--seed", drive.seed, "Seed of slip, wheel scale errors and frame noise")
      ->capture_default_str();
  cmd->add_option("--monte-carlo", drive.monte_carlo,
                  "Runs with seeds seed .. seed + N - 1; summary.json gets their distributions")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--steering", drive.steering, "Steering law: feedback, linear or pure-pursuit")
      ->check(CLI::IsMember({"feedback", "linear", "pure-pursuit"}))
      ->capture_default_str();
  cmd->add_option("--pitch", drive.pitch_deg, "Camera pitch above the horizontal, degrees")
      ->check(CLI::Range(20.0, 90.0))
      ->capture_default_str();
  cmd->add_option("--width", drive.width, "Camera image width (the demo camera scaled)")
      ->check(CLI::Range(64, 2048))
      ->capture_default_str();
  cmd->add_option("--height", drive.height, "Camera image height")
      ->check(CLI::Range(48, 2048))
      ->capture_default_str();
  cmd->add_option("--max-time", drive.max_time_s, "Stop after this many simulated seconds")
      ->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--map-height-scale", drive.map_height_scale,
                  "The map's ceiling heights are the course's times this (a wrong survey)")
      ->check(CLI::Range(0.5, 2.0));
  cmd->add_flag("!--no-vision", drive.vision, "Dead reckoning only: no frames reach the filter");
  cmd->add_flag("!--no-plot", drive.plot, "No drive.png");
  cmd->add_flag("--quiet", drive.quiet, "No progress bar");
  cmd->add_flag("--require", drive.require, "Exit 1 unless summary.json's goals are met");
  return cmd;
}

// `ceilnav calibrate-mount` and its options, parsed into `cal`.
CLI::App* add_calibrate_mount_command(CLI::App& app, CalibrateMountOptions& cal) {
  auto* cmd = app.add_subcommand(
      "calibrate-mount",
      "The camera mount calibration drive: a simulated robot drives along a tape at +-4 deg, "
      "turns in place and drives back; its frames through the device and the host give the "
      "camera's mounting yaw, roll and pitch errors; writes calibration.json and frames.csv");
  cmd->add_option("--out", cal.out_dir, "Output folder (written whole or not at all)")
      ->capture_default_str();
  cmd->add_option("--yaw", cal.yaw_deg, "True mount yaw error, degrees")
      ->check(finite_in(-5.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--roll", cal.roll_deg, "True camera roll error, degrees")
      ->check(finite_in(-5.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--pitch-error", cal.pitch_error_deg, "True camera pitch error, degrees")
      ->check(finite_in(-5.0, 5.0))
      ->capture_default_str();
  cmd->add_option("--forward", cal.forward_m,
                  "Camera ahead of the wheel axis, m (drawings = truth)")
      ->check(finite_in(-0.5, 0.5))
      ->capture_default_str();
  cmd->add_option("--left", cal.left_m, "Camera left of the robot's centre line, m (truth)")
      ->check(finite_in(-0.5, 0.5))
      ->capture_default_str();
  cmd->add_option("--left-error", cal.left_error_mm,
                  "The drawings' lateral minus the true one, mm (moves the roll and the yaw)")
      ->check(finite_in(-50.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--left-sigma", cal.left_sigma_mm, "The drawings' lateral sigma, mm")
      ->check(finite_in(0.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--backend", cal.backend, "fast, model or rtl")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  cmd->add_option("--seed", cal.seed, "Seed of slip, wheel scale errors, start pose and noise")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--monte-carlo", cal.monte_carlo,
                  "Runs with seeds seed .. seed + N - 1; calibration.json gets the error "
                  "distributions")
      ->check(CLI::Range(1, 10000))
      ->capture_default_str();
  cmd->add_option("--run-length", cal.run_length_m, "Length of each run, m")
      ->check(finite_in(1.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--speed", cal.speed_mps, "Driving speed, m/s")
      ->check(finite_in(0.05, 1.0))
      ->capture_default_str();
  cmd->add_option("--heading", cal.heading_deg, "Heading relative to the tape in each half, deg")
      ->check(finite_in(1.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--pitch", cal.pitch_deg, "Configured camera pitch above the horizontal, deg")
      ->check(finite_in(30.0, 80.0))
      ->capture_default_str();
  cmd->add_option("--width", cal.width, "Camera image width (the demo camera scaled)")
      ->check(CLI::Range(64, 2048))
      ->capture_default_str();
  cmd->add_option("--height", cal.height, "Camera image height")
      ->check(CLI::Range(48, 2048))
      ->capture_default_str();
  cmd->add_flag("!--no-pitch", cal.fit_pitch,
                "Do not fit the pitch error (its yaw bias then stays in the yaw)");
  cmd->add_flag("--quiet", cal.quiet, "No progress bar");
  cmd->add_flag("--require", cal.require,
                "Exit 1 unless every run's mounting yaw is within 0.05 deg of the truth");
  return cmd;
}

CLI::App* add_profile_command(CLI::App& app, ProfileOptions& prof) {
  auto* prof_cmd = app.add_subcommand(
      "profile",
      "Stream frames cycle by cycle through the device model or RTL and report, per frame and "
      "in summary: cycles, pixels per tvalid cycle (II), bubbles, EOF-to-irq latency, run FIFO "
      "high-water and drops, host bus words and time; CSV and PNG plots with --out");
  prof_cmd
      ->add_option("--backend", prof.backend,
                   "model (C++ cycle-level device) or rtl (Verilated RTL)")
      ->check(CLI::IsMember({"model", "rtl"}))
      ->capture_default_str();
  prof_cmd
      ->add_option("--config", prof.config,
                   "Device configuration: full (every block) or tape (no class_moments; the "
                   "device that fits the iCE40 HX8K)")
      ->check(CLI::IsMember({"full", "tape"}))
      ->capture_default_str();
  prof_cmd->add_option("--frames", prof.frames_dir,
                       "Folder of PNG frames (default: render the demo corridor)");
  prof_cmd->add_option("--scene", prof.scene_file,
                       "Scene/camera YAML for --frames (default: <frames>/scene.yaml)");
  prof_cmd->add_option(
      "--out", prof.out_dir,
      "Folder for profile.csv, profile_summary.csv and the PNG plots drawn by gnuplot, "
      "each with its .dat and .gp (created); "
      "without it only the summary is printed");
  prof_cmd->add_option("--width", prof.width, "Rendered frame width, 1..1920")
      ->capture_default_str();
  prof_cmd->add_option("--height", prof.height, "Rendered frame height, 1..1080")
      ->capture_default_str();
  prof_cmd
      ->add_option("--blanking", prof.blanking,
                   "none (back to back), vga (640x480@60-like line and frame blanking, scaled) "
                   "or random (random tvalid gaps)")
      ->capture_default_str();
  prof_cmd
      ->add_option("--gap-probability", prof.gap_probability,
                   "random blanking: probability of an idle cycle before a pixel (repeated)")
      ->capture_default_str();
  prof_cmd
      ->add_option("--backpressure", prof.backpressure,
                   "Fraction of cycles with m_axis_runs tready low (random), in [0, 1)")
      ->capture_default_str();
  prof_cmd->add_option("--tapes", prof.tapes, "Parallel tapes in the rendered scene, 1..8")
      ->capture_default_str();
  prof_cmd->add_option("--count", prof.count,
                       "Frames (default 10 rendered, or every frame of --frames)");
  prof_cmd->add_option("--seed", prof.seed, "Seed of gaps, back-pressure and render noise")
      ->capture_default_str();
  prof_cmd->add_option("--sweep", prof.sweep_duties, "Back-pressure duties of the throughput sweep")
      ->delimiter(',')
      ->capture_default_str();
  prof_cmd->add_option("--sweep-frames", prof.sweep_frames, "Frames per sweep point (0: no sweep)")
      ->capture_default_str();
  return prof_cmd;
}

// `ceilnav pattern` and its options, parsed into `pat`.
CLI::App* add_pattern_command(CLI::App& app, PatternOptions& pat) {
  auto* pat_cmd = app.add_subcommand(
      "pattern",
      "Seed 003's standard pattern: a robot arrives near a station, pans its camera until it "
      "finds the pattern's bar code, centres the disc and verifies its position (built-in "
      "scene), or processes recorded frames (--frames, --scene, --database); CSV of D, theta, "
      "beta, identity, status, x, y, heading and an overlay PNG with the fitted ellipse");
  pat_cmd->add_option("--out", pat.out_dir, "Output folder (created)")->required();
  pat_cmd->add_option("--frames", pat.frames_dir, "Folder of PNG frames instead of the scene");
  pat_cmd->add_option("--scene", pat.scene_file, "Camera YAML (OpenCV FileStorage), with --frames");
  pat_cmd->add_option("--database", pat.database,
                      "Pattern database YAML (identity -> position, facing), with --frames");
  pat_cmd->add_option("--noise", pat.noise_sigma, "Built-in scene: noise sigma (grey levels)")
      ->check(CLI::Range(0.0, 50.0))
      ->capture_default_str();
  pat_cmd->add_option("--seed", pat.seed, "Built-in scene: noise seed")->capture_default_str();
  pat_cmd
      ->add_option("--backend", pat.backend,
                   "fast (frame at a time), model (C++ cycle-level device through its "
                   "registers) or rtl (Verilated RTL through its registers)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  pat_cmd->add_flag("--quiet", pat.quiet, "No per-frame lines");
  add_overlay_every(*pat_cmd, pat.overlay_every,
                    "in --out, besides overlay.png of the last frame; 0: only overlay.png");
  return pat_cmd;
}

// `ceilnav pattern-accuracy` and its options, parsed into `pacc`.
CLI::App* add_pattern_accuracy_command(CLI::App& app, PatternAccuracyOptions& pacc) {
  auto* pacc_cmd = app.add_subcommand(
      "pattern-accuracy",
      "Error study of the pattern pose on rendered frames (seed 003 Tables I and II): theta "
      "error vs theta and D error vs D for the projection, moment and exact conic methods, "
      "bar-code reads; checks the bars with --require");
  pacc_cmd->add_option("--width", pacc.width, "Frame width")
      ->check(CLI::Range(64, 1920))
      ->capture_default_str();
  pacc_cmd->add_option("--height", pacc.height, "Frame height")
      ->check(CLI::Range(48, 1080))
      ->capture_default_str();
  pacc_cmd->add_option("--noise", pacc.noise_sigma, "Noise sigma (grey levels)")
      ->check(CLI::Range(0.0, 50.0))
      ->capture_default_str();
  pacc_cmd->add_option("--blur", pacc.blur_sigma, "Blur sigma (pixels)")
      ->check(CLI::Range(0.0, 5.0))
      ->capture_default_str();
  pacc_cmd
      ->add_option("--calib-blur", pacc.calib_blur_sigma,
                   "Blur sigma the host assumes (pixels; default: the rendered --blur)")
      ->check(CLI::Range(0.0, 5.0));
  pacc_cmd
      ->add_option("--calib-noise", pacc.calib_noise_sigma,
                   "Noise sigma the host assumes (grey levels; default: the rendered --noise)")
      ->check(CLI::Range(0.0, 50.0));
  pacc_cmd
      ->add_option("--supersample", pacc.supersample,
                   "Renderer: N x N samples per edge pixel (the frames' own sampling error)")
      ->check(CLI::Range(1, 16))
      ->capture_default_str();
  pacc_cmd->add_flag("!--no-distortion", pacc.distortion, "Camera without lens distortion");
  pacc_cmd->add_option("--betas", pacc.betas, "Random co-azimuths per (D, theta) besides +-90 deg")
      ->check(CLI::Range(0, 20))
      ->capture_default_str();
  pacc_cmd->add_option("--seed", pacc.seed, "Seed of identities, co-azimuths and noise")
      ->capture_default_str();
  pacc_cmd->add_option("--backend", pacc.backend, "fast, model or rtl (as for pattern)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  auto* csv_opt = pacc_cmd->add_option("--csv", pacc.csv, "Per-frame errors to this CSV");
  auto* plot_opt = pacc_cmd->add_option(
      "--plot", pacc.plot,
      "PNG of the error curves beside the seed's tables, drawn by gnuplot (its .dat and .gp "
      "beside it)");
  auto* gain_opt =
      pacc_cmd
          ->add_option("--gain", pacc.gain,
                       "Camera gain rendered, not told to the host (it self-calibrates)")
          ->check(CLI::Range(0.05, 4.0))
          ->capture_default_str();
  auto* offset_opt = pacc_cmd
                         ->add_option("--offset", pacc.offset_grey,
                                      "Camera offset rendered (grey levels), not told to the host")
                         ->check(CLI::Range(-100.0, 100.0))
                         ->capture_default_str();
  auto* vignetting_opt =
      pacc_cmd
          ->add_option("--vignetting", pacc.vignetting,
                       "Camera vignetting rendered: fraction lost at the image corner, quadratic "
                       "in the radius")
          ->check(CLI::Range(0.0, 0.9))
          ->capture_default_str();
  pacc_cmd->add_flag("!--no-photometric-calibration", pacc.self_calibrate,
                     "The host takes the nominal grey levels instead of calibrating each frame");
  pacc_cmd
      ->add_flag("--photometric-sweep", pacc.photometric_sweep,
                 "The table of gain 0.8-1.2 x offset -15, 0, +15 x vignetting 0, 20 % and "
                 "settings beyond the calibrated range (--require: exit 1 if any frame is "
                 "reported ok with a pose off the bars)")
      ->excludes(csv_opt)
      ->excludes(plot_opt)
      ->excludes(gain_opt)
      ->excludes(offset_opt)
      ->excludes(vignetting_opt);
  pacc_cmd->add_flag("--require", pacc.require,
                     "Exit 1 unless D error <= 0.3 %, theta error <= 0.3 deg (theta >= 15) "
                     "for the conic method and every visible code is read, none wrongly");
  pacc_cmd->add_flag("--swing-height", pacc.swing_height,
                     "Instead: the seed's swing (eq. 57-66, 70) and sensor height (eq. 69) error "
                     "analysis on rendered frames (pinhole camera), Markdown tables on stdout");
  return pacc_cmd;
}

CLI::App* add_corridor_command(CLI::App& app, CorridorOptions& c) {
  auto* cmd = app.add_subcommand(
      "corridor",
      "Seed 002's corridor guidance: learn a model of the ceiling lines from a driven path, "
      "then guide (pan, delta-phi, lateral shift, wheel turn per frame); frames through the "
      "device's edge and hough blocks; writes corridor.csv, model.json, summary.json and "
      "overlay PNGs");
  cmd->add_option("--out", c.out_dir, "Output folder (written whole or not at all)")
      ->capture_default_str();
  cmd->add_option("--scene", c.scene_file,
                  "Corridor file (docs/navigation_io.md, \"Corridor files\"); default: the "
                  "built-in corridor")
      ->check(CLI::ExistingFile);
  cmd->add_option("--camera", c.camera_file, "OpenCV camera YAML; default 640 x 480, f = 500")
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames", c.frames_dir,
                  "Recorded frames (PNG, in name order) instead of rendered ones; the first "
                  "--learn-frames are the learning drive")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--learn-frames", c.learn_frames, "Frames of the learning drive (--frames)")
      ->check(CLI::Range(3, 100000))
      ->capture_default_str();
  cmd->add_option("--tilt", c.tilt_deg, "Camera tilt, degrees (default: the scene's camera)")
      ->check(finite_in(-89.0, 89.0));
  cmd->add_option("--swing", c.swing_deg, "Camera swing, degrees (default: the scene's camera)")
      ->check(finite_in(-45.0, 45.0));
  cmd->add_option("--noise", c.noise_grey, "Rendered frames: noise sigma, grey levels")
      ->check(finite_in(0.0, 50.0))
      ->capture_default_str();
  cmd->add_option("--camera-height", c.camera_height_m, "Camera height above the floor, m")
      ->check(finite_in(0.05, 100.0));
  cmd->add_option("--overlays", c.overlays, "Overlay PNGs of the first guided frames")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
  cmd->add_flag("--quiet", c.quiet, "No progress bar, no summary line");
  cmd->add_flag(
      "--require", c.require,
      "Exit 1 unless pan RMS <= 0.3 deg, delta-x RMS <= 2 cm and 95 % of the guided frames "
      "are ok (rendered frames)");
  return cmd;
}

CLI::App* add_homing_command(CLI::App& app, HomingOptions& h) {
  auto* cmd = app.add_subcommand(
      "homing",
      "Seed 004's homing on ceiling structures: record the homing sites of a ceiling, then the "
      "triangle race (odometric paths with drift, homing at every site); writes map/, "
      "homing_race.csv, homing_frames.csv, odometry_race.csv, summary.json and race.png");
  cmd->add_option("--out", h.out_dir, "Output folder (written whole or not at all)")
      ->capture_default_str();
  cmd->add_option("--ceiling", h.ceiling_file,
                  "Ceiling file with sites (docs/navigation_io.md, \"Ceiling files\"); default: "
                  "the built-in office ceiling")
      ->check(CLI::ExistingFile);
  cmd->add_option("--camera", h.camera_file, "OpenCV camera YAML; default 640 x 480, f = 500")
      ->check(CLI::ExistingFile);
  cmd->add_option("--map", h.map_file,
                  "A recorded site map (map.json of an earlier run) instead of recording the "
                  "sites")
      ->check(CLI::ExistingFile);
  cmd->add_option("--frames", h.frames_dir,
                  "Recorded frames (PNG, name order): search every site of --map in each (the "
                  "360 deg search and the fast mode about each quarter turn); writes frames.csv "
                  "and summary.json instead of the race")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--loops", h.loops, "Loops of the race")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--noise", h.noise_grey, "Rendered frames: noise sigma, grey levels")
      ->check(finite_in(0.0, 50.0))
      ->capture_default_str();
  cmd->add_flag("--capture", h.capture,
                "Also measure the capture zone of --capture-site (homings from 144 starts 0.5 to "
                "1.5 m away, 8 bearings, 3 headings; capture_zone.csv)");
  cmd->add_option("--capture-site", h.capture_site, "Site of the capture study (1 = first)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--capture-radii", h.capture_radii_m,
                  "Start distances of the capture study, metres, strictly ascending")
      ->delimiter(',')
      ->check(finite_in(0.01, 20.0))
      ->capture_default_str();
  cmd->add_option("--seed", h.seed, "Seed of the frame noise and the wheel slip")
      ->check(unsigned_integer())
      ->capture_default_str();
  cmd->add_option("--backend", h.backend,
                  "The homing device each frame streams through for its orientation histogram: "
                  "fast (frame at a time), model (C++ cycle-level device through its registers) "
                  "or rtl (Verilated RTL through its registers)")
      ->check(CLI::IsMember({"fast", "model", "rtl"}))
      ->capture_default_str();
  cmd->add_flag("!--no-plot", h.plot, "No race.png");
  cmd->add_flag("--quiet", h.quiet, "No progress bar, no summary line");
  cmd->add_flag("--require", h.require,
                "Exit 1 unless every homing homed, the error RMS is <= 3 mm and 0.2 deg, no "
                "homing was false (and with --capture: radius >= 1 m, no false homing)");
  return cmd;
}

}  // namespace
}  // namespace ceilnav::app

int main(int argc, char** argv) {
  using namespace ceilnav::app;
  CLI::App app{"ceilnav: a ceiling-vision navigation device, modelled bit for bit"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ceilnav::version_string());

  DemoOptions demo;
  RunOptions run;
  RenderOptions render;
  AccuracyOptions acc;
  ProfileOptions prof;
  PatternOptions pat;
  PatternAccuracyOptions pacc;
  ExposureOptions expo;
  DriveOptions drive;
  RenderDriveOptions render_drive;
  CalibrateMountOptions calibrate;
  CorridorOptions corridor;
  HomingOptions homing;
  CLI::App* demo_cmd = add_demo_command(app, demo);
  CLI::App* run_cmd = add_run_command(app, run);
  CLI::App* render_cmd = add_render_command(app, render);
  CLI::App* acc_cmd = add_accuracy_command(app, acc);
  CLI::App* prof_cmd = add_profile_command(app, prof);
  CLI::App* pat_cmd = add_pattern_command(app, pat);
  CLI::App* pacc_cmd = add_pattern_accuracy_command(app, pacc);
  CLI::App* expo_cmd = add_exposure_command(app, expo);
  CLI::App* drive_cmd = add_drive_command(app, drive);
  CLI::App* render_drive_cmd = add_render_drive_command(app, render_drive);
  CLI::App* calibrate_cmd = add_calibrate_mount_command(app, calibrate);
  CLI::App* corridor_cmd = add_corridor_command(app, corridor);
  CLI::App* homing_cmd = add_homing_command(app, homing);

  CLI11_PARSE(app, argc, argv);
  try {
    if (*demo_cmd) return run_demo(demo);
    if (*run_cmd) return run_frames(run);
    if (*render_cmd) return run_render(render);
    if (*acc_cmd) return run_accuracy(acc);
    if (*prof_cmd) return run_profile(prof);
    if (*pat_cmd) return run_pattern(pat);
    if (*pacc_cmd) return run_pattern_accuracy(pacc);
    if (*expo_cmd) return run_exposure(expo);
    if (*drive_cmd) return run_drive(drive);
    if (*render_drive_cmd) return run_render_drive(render_drive);
    if (*calibrate_cmd) return run_calibrate_mount(calibrate);
    if (*corridor_cmd) return run_corridor(corridor);
    if (*homing_cmd) return run_homing(homing);
  } catch (const ceilnav::host::ConfigError& e) {
    std::cerr << "ceilnav: scene error: " << e.what() << '\n';
    return 1;
  } catch (const ceilnav::nav::OdometryFileError& e) {
    std::cerr << "ceilnav: odometry error: " << e.what() << '\n';
    return 1;
  } catch (const ceilnav::host::InputError& e) {
    std::cerr << "ceilnav: input error: " << e.what() << '\n';
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "ceilnav: error: " << e.what() << '\n';
    return 1;
  }
  return 2;
}
