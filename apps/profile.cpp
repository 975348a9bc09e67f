// `ceilnav profile`: the command. Checks its arguments, runs the scenario and
// the back-pressure sweep (profile_run.cpp) and reports them (profile_report.cpp).
#include "apps/profile.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "apps/atomic_file.hpp"
#include "apps/profile_report.hpp"
#include "common/csv.hpp"
#include "common/limits.hpp"
#include "host/camera_config_io.hpp"
#include "host/frame_io.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

namespace {

// The output folder exists and is writable, or can be created: its nearest
// existing ancestor is a writable folder. Creates nothing.
void check_out_dir(const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) {
    if (!fs::is_directory(out, ec)) {
      throw std::runtime_error("cannot write to '" + out.string() + "': not a folder");
    }
    check_writable(out / "profile.csv");
    return;
  }
  fs::path ancestor = fs::absolute(out).parent_path();
  while (!ancestor.empty() && !fs::exists(ancestor, ec)) ancestor = ancestor.parent_path();
  if (!fs::is_directory(ancestor, ec) || ::access(ancestor.c_str(), W_OK) != 0) {
    throw std::runtime_error("cannot create output folder '" + out.string() + "': '" +
                             ancestor.string() + "' is not a writable folder");
  }
}

// The scenario of the options; std::runtime_error on a bad argument. The frame
// size is set by frame_source().
ProfileScenario scenario_of(const ProfileOptions& o) {
  if (o.backend != "model" && o.backend != "rtl") {
    throw std::runtime_error("--backend must be model or rtl (the fast path has no cycles)");
  }
  ProfileScenario s;
  const regs::Config* config = nullptr;
  for (const regs::Config& c : regs::kConfigs) {
    if (o.config == c.name) config = &c;
  }
  if (config == nullptr) {
    throw std::runtime_error(
        "--config must name a device configuration (tape, corridor, full or homing), not '" +
        o.config + "'");
  }
  s.device_config = *config;
  s.blanking = parse_blanking(o.blanking);
  s.gap_probability = o.gap_probability;
  s.backpressure = o.backpressure;
  s.tapes = o.tapes;
  s.seed = o.seed;
  if (!(o.backpressure >= 0.0 && o.backpressure < 1.0)) {
    throw std::runtime_error("--backpressure must be in [0, 1)");
  }
  if (!(o.gap_probability >= 0.0 && o.gap_probability < 1.0)) {
    throw std::runtime_error("--gap-probability must be in [0, 1)");
  }
  for (double d : o.sweep_duties) {
    if (!(d >= 0.0 && d < 1.0)) throw std::runtime_error("--sweep duties must be in [0, 1)");
  }
  if (o.tapes < 1 || o.tapes > 8) throw std::runtime_error("--tapes must be 1 .. 8");
  if (o.count < 0) throw std::runtime_error("--count must be positive");
  if (o.sweep_frames < 0) throw std::runtime_error("--sweep-frames must be >= 0");
  return s;
}

// Where the frames come from: PNGs of frames_dir with their scene, or rendered.
struct FrameSource {
  host::CameraConfig camera;
  std::vector<fs::path> files;  // empty: rendered
  size_t count = 0;
};

FrameSource frame_source(const ProfileOptions& o, ProfileScenario& s) {
  FrameSource src;
  host::CameraConfig& camera = src.camera;
  std::vector<fs::path>& files = src.files;
  size_t& count = src.count;
  if (!o.frames_dir.empty()) {
    files = host::list_png_frames(o.frames_dir);
    const fs::path scene =
        o.scene_file.empty() ? fs::path(o.frames_dir) / "scene.yaml" : fs::path(o.scene_file);
    if (o.scene_file.empty() && !fs::exists(scene)) {
      throw host::InputError("no scene for the frames: give --scene or put scene.yaml in '" +
                             o.frames_dir + "'");
    }
    camera = host::load_camera_config(scene.string());
    s.width = camera.image_width;
    s.height = camera.image_height;
    count =
        o.count > 0 ? std::min<size_t>(files.size(), static_cast<size_t>(o.count)) : files.size();
  } else {
    if (o.width < 1 || o.height < 1 || o.width > 1920 || o.height > 1080) {
      throw std::runtime_error("--width/--height must be 1..1920 x 1..1080 (got " +
                               std::to_string(o.width) + "x" + std::to_string(o.height) + ")");
    }
    s.width = o.width;
    s.height = o.height;
    camera = profile_camera(s);
    count = o.count > 0 ? static_cast<size_t>(o.count) : 10;
  }
  if (static_cast<uint32_t>(s.width) > stream::kMaxWidth ||
      static_cast<uint32_t>(s.height) > stream::kMaxHeight) {
    throw std::runtime_error("frames larger than the device's limit");
  }
  return src;
}

void write_outputs(const fs::path& out, const ProfileSummary& main_run,
                   const std::vector<ProfileSummary>& sweep, const std::string& backend) {
  // Every file is staged and renamed into place together (OutputFolder).
  OutputFolder folder(out);
  AtomicFile csv(folder.path("profile.csv"));
  CsvWriter frames_csv(csv.stream());
  write_frame_header(frames_csv);
  for (size_t i = 0; i < main_run.frames.size(); ++i) {
    write_frame_row(frames_csv, i, main_run.frames[i]);
  }
  AtomicFile summary(folder.path("profile_summary.csv"));
  CsvWriter summary_csv(summary.stream());
  write_summary_header(summary_csv);
  write_summary_row(summary_csv, main_run, backend);
  for (const ProfileSummary& m : sweep) write_summary_row(summary_csv, m, backend);
  // gnuplot draws into the staged folder (PNG, .dat, .gp each); nothing is
  // renamed into place unless every chart was drawn.
  write_profile_plots(folder.path("latency.png").parent_path(), main_run, sweep);
  csv.commit();
  summary.commit();
  folder.commit();
  std::printf("wrote %s/profile.csv, profile_summary.csv, latency.png, fifo.png%s\n",
              out.string().c_str(), sweep.empty() ? "" : ", throughput.png");
}

}  // namespace

int run_profile(const ProfileOptions& o) {
  // Arguments first: nothing is written before they are all good.
  ProfileScenario s = scenario_of(o);
  const FrameSource src = frame_source(o, s);
  const size_t count = src.count;
  const fs::path out = o.out_dir;
  if (!o.out_dir.empty()) check_out_dir(out);

  std::vector<cv::Mat> cache;  // rendered or read once, shared by the sweep
  const auto frame_at = [&](size_t i) -> cv::Mat {
    if (i < cache.size() && !cache[i].empty()) return cache[i];
    cv::Mat m = src.files.empty() ? render_profile_frame(s, src.camera, i, count)
                                  : host::read_grey_frame(src.files[i], s.width, s.height);
    const size_t keep = std::max<size_t>(static_cast<size_t>(o.sweep_frames), 1);
    if (i < keep) {
      if (cache.size() <= i) cache.resize(i + 1);
      cache[i] = m;
    }
    return m;
  };

  const auto run_scenario = [&](const std::string& name, const ProfileScenario& sc, size_t n) {
    drivers::SimBusOptions bus_opt;
    bus_opt.seed = sc.seed;
    bus_opt.run_tready_low_probability = sc.backpressure;
    bus_opt.device_config = sc.device_config;
    std::unique_ptr<drivers::SimBus> bus = make_profile_bus(o.backend, bus_opt);
    ProfileSummary m{name, sc, profile_frames(*bus, frame_at, n, sc, src.camera), {}};
    m.problems = check_profile(m.frames, sc);
    return m;
  };

  const ProfileSummary main_run = run_scenario("scenario", s, count);
  std::vector<ProfileSummary> sweep;
  if (o.sweep_frames > 0) {
    for (double duty : o.sweep_duties) {
      ProfileScenario sc = s;
      sc.backpressure = duty;
      char name[32];
      std::snprintf(name, sizeof name, "sweep_bp%.2f", duty);
      sweep.push_back(run_scenario(name, sc, std::min(count, static_cast<size_t>(o.sweep_frames))));
    }
  }

  print_summary(main_run, o.backend);
  const size_t violations = main_run.problems.size() + print_sweep(sweep, o.sweep_frames);
  if (!o.out_dir.empty()) write_outputs(out, main_run, sweep, o.backend);
  if (violations > 0) {
    std::fprintf(stderr, "ceilnav profile: %zu violation(s) of II = 1 / 0 bubbles / counts\n",
                 violations);
    return 1;
  }
  return 0;
}

}  // namespace ceilnav::app
