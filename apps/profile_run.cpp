// `ceilnav profile`'s device runs: the backend, the rendered frames, the
// frame-by-frame measurement through the driver and the rules checked on it.
#include "apps/profile_run.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "apps/commands.hpp"
#include "apps/port_probe.hpp"
#include "apps/progress.hpp"
#include "ceilnav/regs.hpp"
#include "drivers/model_bus.hpp"
#include "drivers/rtl_backend.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/auto_threshold.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/driver.hpp"
#include "host/navigator.hpp"
#include "host/tape_pose.hpp"
#include "stream/ceilnav_top.hpp"

namespace ceilnav::app {

std::unique_ptr<drivers::SimBus> make_profile_bus(const std::string& backend,
                                                  const drivers::SimBusOptions& options) {
  if (backend == "model") return std::make_unique<drivers::ModelBus>(options);
  if (backend == "rtl") {
    const auto factory = drivers::rtl_bus_factory();
    if (!factory) {
      throw std::runtime_error("this ceilnav was built without the Verilated RTL backend");
    }
    std::unique_ptr<host::Bus> bus = factory(options);
    auto* sim = dynamic_cast<drivers::SimBus*>(bus.get());
    if (sim == nullptr) throw std::logic_error("the RTL backend is not a SimBus");
    bus.release();
    return std::unique_ptr<drivers::SimBus>(sim);
  }
  throw std::runtime_error("unknown profile backend '" + backend + "' (model or rtl)");
}

host::CameraConfig profile_camera(const ProfileScenario& s) {
  host::CameraConfig camera = scaled_camera(s.width, s.height, true);
  host::validate_camera_config(camera, "--width/--height");
  return camera;
}

cv::Mat render_profile_frame(const ProfileScenario& s, const host::CameraConfig& camera,
                             size_t index, size_t count) {
  golden::CorridorOptions corridor;
  golden::CeilingScene scene = golden::corridor_scene(camera.tape_width_m, corridor);
  // Extra tapes parallel to the reference, alternately left and right.
  constexpr double kTapeSpacingM = 0.5;
  for (int k = 1; k < s.tapes; ++k) {
    const double y = kTapeSpacingM * ((k + 1) / 2) * (k % 2 == 1 ? 1.0 : -1.0);
    scene.tapes.push_back({corridor.x_start_m, y, corridor.x_end_m, y, camera.tape_width_m, 1.0});
  }
  const std::vector<golden::DrivePose> drive =
      golden::default_drive(static_cast<int>(std::max<size_t>(count, 1)));
  golden::RenderParams params = golden::default_render_params();
  params.noise_seed = s.seed * 7919u + index;
  return golden::render_frame(camera, scene, drive[index].pose, params);
}

namespace {

struct HostTimer {
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double us() const {
    return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
  }
};

stream::PipelineConfig frame_config(const ProfileScenario& s, const host::ThresholdSettings& t) {
  const host::NavigatorOptions nav;  // the navigator's run settings
  stream::PipelineConfig cfg;
  cfg.width = static_cast<uint16_t>(s.width);
  cfg.height = static_cast<uint16_t>(s.height);
  cfg.min_run_length = nav.min_run_length;
  cfg.max_runs_per_row = nav.max_runs_per_row;
  cfg.hist_source_remap = false;  // the histogram counts every pixel accepted
  return host::apply_threshold(cfg, t);
}

uint64_t histogram_total(const stream::HistogramResults& h) {
  uint64_t n = 0;
  for (uint32_t b : h.bins) n += b;
  return n;
}

}  // namespace

std::vector<FrameProfile> profile_frames(drivers::SimBus& bus,
                                         const std::function<cv::Mat(size_t)>& frame_at,
                                         size_t count, const ProfileScenario& s,
                                         const host::CameraConfig& camera) {
  const host::NavigatorOptions nav;
  const host::CameraModel model(camera);
  host::Driver driver(bus);
  driver.identify();
  PortProbe probe(s.height);
  bus.set_observer(&probe);
  const drivers::FrameFeed feed = frame_feed(s);

  uint64_t configure_cycles = 0;
  const auto stream_one = [&](const cv::Mat& grey, const host::ThresholdSettings& t) {
    if (grey.type() != CV_8UC1 || grey.cols != s.width || grey.rows != s.height) {
      throw std::runtime_error("profile: a frame is not 8-bit grey " + std::to_string(s.width) +
                               "x" + std::to_string(s.height));
    }
    const uint64_t c0 = bus.cycles();
    driver.configure(frame_config(s, t));
    configure_cycles = bus.cycles() - c0;
    bus.queue_frame(grey.ptr<uint8_t>(0), grey.cols, grey.rows, grey.step[0], feed);
    return driver.read_frame();
  };

  std::vector<FrameProfile> out;
  out.reserve(count);
  host::ThresholdSettings settings;
  cv::Mat grey = count > 0 ? frame_at(0) : cv::Mat();
  if (count > 0) {
    const host::FrameReadout warm = stream_one(grey, settings);
    settings = host::choose_threshold(warm.results.histogram, nav.threshold);
  }
  Progress progress("profile", count);
  for (size_t i = 0; i < count; ++i) {
    if (i > 0) grey = frame_at(i);
    probe.take();
    const HostTimer driver_time;
    const host::FrameReadout r = stream_one(grey, settings);
    FrameProfile f;
    f.host_driver_us = driver_time.us();
    const PortProbe::Counts c = probe.take();

    const HostTimer pose_time;
    settings = host::choose_threshold(r.results.histogram, nav.threshold);
    const host::TapePose pose = host::estimate_tape_pose(r.runs, model, camera, nav.pose);
    f.host_pose_us = pose_time.us();
    f.pose_status = r.results.valid ? pose.status : host::Status::frame_invalid;

    f.cycles = c.eof_seen ? c.frame_cycles : 0;
    f.tvalid_cycles = c.tvalid_cycles;
    f.accepted = c.accepted_beats;
    f.bubbles = c.bubbles;
    f.pixels_counted = histogram_total(r.results.histogram);
    f.device_cycles = r.results.cycles_in_frame;
    f.eof_to_irq_cycles =
        c.eof_seen && c.irq_rise_seen ? static_cast<int64_t>(c.irq_rise_edge - c.eof_edge) : -1;
    f.eof_to_irq_register = r.eof_to_irq_cycles;
    f.fifo_high_water = r.results.run_stats.fifo_high_water;
    f.runs_dropped_overflow = r.results.run_stats.runs_dropped_overflow;
    f.runs_dropped_row_limit = r.results.run_stats.runs_dropped_row_limit;
    f.runs_emitted = r.results.run_stats.runs_emitted;
    f.runs = r.runs.size();
    f.run_beats = c.run_beats;
    f.run_stall_cycles = c.run_stall_cycles;
    f.words_read = c.axil_reads;
    f.words_written = c.axil_writes;
    f.host_cycles = c.edges;
    f.configure_cycles = configure_cycles;
    f.readout_cycles = c.irq_rise_seen ? c.first_edge + c.edges - 1 - c.irq_rise_edge : 0;
    f.frame_ok = c.frames_started == 1 && r.results.valid && r.trailer_seen && r.consistent &&
                 (r.intr_state & regs::intr_state::kFrameError.mask()) == 0;
    out.push_back(f);
    progress.update(i + 1);
  }
  progress.finish();
  bus.set_observer(nullptr);
  return out;
}

std::vector<std::string> check_profile(const std::vector<FrameProfile>& frames,
                                       const ProfileScenario& s) {
  std::vector<std::string> problems;
  const uint64_t pixels = static_cast<uint64_t>(s.width) * static_cast<uint64_t>(s.height);
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameProfile& f = frames[i];
    const std::string at = "frame " + std::to_string(i) + ": ";
    if (f.accepted != f.tvalid_cycles) {
      problems.push_back(at + std::to_string(f.accepted) + " pixels accepted in " +
                         std::to_string(f.tvalid_cycles) + " cycles with tvalid (II != 1)");
    }
    if (f.bubbles != 0) problems.push_back(at + std::to_string(f.bubbles) + " bubbles");
    if (f.accepted != pixels || f.pixels_counted != pixels) {
      problems.push_back(at + std::to_string(f.accepted) + " pixels accepted, " +
                         std::to_string(f.pixels_counted) + " counted by the device, expected " +
                         std::to_string(pixels));
    }
    if (f.device_cycles != f.cycles) {
      problems.push_back(at + "CYCLES_PER_FRAME " + std::to_string(f.device_cycles) +
                         " != cycles at the ports " + std::to_string(f.cycles));
    }
    if (f.eof_to_irq_cycles < 0) {
      problems.push_back(at + "no interrupt after the frame's end");
    } else if (static_cast<uint64_t>(f.eof_to_irq_cycles) != f.eof_to_irq_register) {
      problems.push_back(at + "EOF_TO_IRQ_CYCLES " + std::to_string(f.eof_to_irq_register) +
                         " != " + std::to_string(f.eof_to_irq_cycles) + " at the ports");
    }
    if (!f.frame_ok) problems.push_back(at + "the device did not report the frame as good");
  }
  return problems;
}

}  // namespace ceilnav::app
