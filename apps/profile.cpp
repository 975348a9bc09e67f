#include "apps/profile.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"

#include "apps/plot.hpp"
#include "apps/progress.hpp"
#include "apps/rtl_backend.hpp"
#include "ceilnav/regs.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/auto_threshold.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"
#include "host/csv.hpp"
#include "host/driver.hpp"
#include "host/frame_io.hpp"
#include "host/model_bus.hpp"
#include "host/navigator.hpp"
#include "host/tape_pose.hpp"
#include "stream/ceilnav_top.hpp"
#include "stream/limits.hpp"

namespace ceilnav::app {
namespace fs = std::filesystem;

std::string_view to_string(Blanking b) {
  switch (b) {
    case Blanking::none:
      return "none";
    case Blanking::vga:
      return "vga";
    case Blanking::random:
      return "random";
  }
  return "?";
}

Blanking parse_blanking(const std::string& name) {
  if (name == "none") return Blanking::none;
  if (name == "vga") return Blanking::vga;
  if (name == "random") return Blanking::random;
  throw std::runtime_error("unknown blanking '" + name + "' (none, vga or random)");
}

VideoTiming vga_like_timing(int width, int height) {
  // VESA 640x480@60: 640 + 160 clocks per line, 480 + 45 lines per frame.
  constexpr double kLineBlankPerPixel = 160.0 / 640.0;
  constexpr double kFrameBlankLinesPerLine = 45.0 / 480.0;
  VideoTiming t;
  t.line_blanking_cycles = static_cast<uint32_t>(std::lround(kLineBlankPerPixel * width));
  const auto lines = static_cast<uint32_t>(std::lround(kFrameBlankLinesPerLine * height));
  t.frame_blanking_cycles = lines * (static_cast<uint32_t>(width) + t.line_blanking_cycles);
  return t;
}

host::FrameFeed frame_feed(const ProfileScenario& s) {
  host::FrameFeed f;
  f.blanking_cycles = kMinFrameBlankingCycles;
  if (s.blanking == Blanking::vga) {
    const VideoTiming t = vga_like_timing(s.width, s.height);
    f.line_blanking_cycles = t.line_blanking_cycles;
    f.blanking_cycles = std::max(t.frame_blanking_cycles, kMinFrameBlankingCycles);
  } else if (s.blanking == Blanking::random) {
    f.gap_probability = s.gap_probability;
  }
  return f;
}

// ---------------------------------------------------------------- PortProbe

void PortProbe::on_edge(uint64_t edge, const host::SimInputs& in, const host::SimOutputs& out) {
  if (!started_) {
    started_ = true;
    irq_prev_ = out.irq;
    c_.first_edge = edge;
  }
  ++c_.edges;
  const stream::VideoBeat& v = in.s_axis_video;
  const bool accept = v.tvalid && out.s_axis_video_tready;
  if (v.tvalid && !out.s_axis_video_tready) ++c_.bubbles;
  if (accept && v.tuser) {
    ++c_.frames_started;
    c_.sof_seen = true;
    c_.eof_seen = false;
    c_.irq_rise_seen = false;
    c_.sof_edge = edge;
    c_.frame_cycles = c_.tvalid_cycles = c_.accepted_beats = 0;
    in_frame_ = true;
    lines_ = 0;
  }
  if (in_frame_) {
    ++c_.frame_cycles;
    if (v.tvalid) ++c_.tvalid_cycles;
    if (accept) ++c_.accepted_beats;
    if (accept && v.tlast && ++lines_ == lines_per_frame_) {
      in_frame_ = false;
      c_.eof_seen = true;
      c_.eof_edge = edge;
    }
  }
  // out.irq is the level after edge - 1: a rise seen here happened on edge - 1.
  if (out.irq && !irq_prev_ && c_.eof_seen && !c_.irq_rise_seen && edge - 1 >= c_.eof_edge) {
    c_.irq_rise_seen = true;
    c_.irq_rise_edge = edge - 1;
  }
  irq_prev_ = out.irq;

  if (out.m_axis_runs.tvalid) {
    if (in.m_axis_runs_tready) {
      ++c_.run_beats;
    } else {
      ++c_.run_stall_cycles;
    }
  }
  if (!in.m_axis_runs_tready) ++c_.run_tready_low_cycles;
  if (in.s_axil.arvalid && out.s_axil.arready) ++c_.axil_reads;
  if (in.s_axil.awvalid && in.s_axil.wvalid && out.s_axil.awready) ++c_.axil_writes;
}

PortProbe::Counts PortProbe::take() {
  Counts done = c_;
  c_ = Counts{};
  started_ = false;
  // A frame still open keeps its counts into the next window (it should not happen).
  if (in_frame_) {
    c_.sof_seen = true;
    c_.sof_edge = done.sof_edge;
    c_.frame_cycles = done.frame_cycles;
    c_.tvalid_cycles = done.tvalid_cycles;
    c_.accepted_beats = done.accepted_beats;
  }
  return done;
}

// ---------------------------------------------------------------- device runs

std::unique_ptr<host::SimBus> make_profile_bus(const std::string& backend,
                                               const host::SimBusOptions& options) {
  if (backend == "model") return std::make_unique<host::ModelBus>(options);
  if (backend == "rtl") {
    const auto factory = rtl_bus_factory();
    if (!factory) {
      throw std::runtime_error("this ceilnav was built without the Verilated RTL backend");
    }
    std::unique_ptr<host::Bus> bus = factory(options);
    auto* sim = dynamic_cast<host::SimBus*>(bus.get());
    if (sim == nullptr) throw std::logic_error("the RTL backend is not a SimBus");
    bus.release();
    return std::unique_ptr<host::SimBus>(sim);
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

std::vector<FrameProfile> profile_frames(host::SimBus& bus,
                                         const std::function<cv::Mat(size_t)>& frame_at,
                                         size_t count, const ProfileScenario& s,
                                         const host::CameraConfig& camera) {
  const host::NavigatorOptions nav;
  const host::CameraModel model(camera);
  host::Driver driver(bus);
  driver.identify();
  PortProbe probe(s.height);
  bus.set_observer(&probe);
  const host::FrameFeed feed = frame_feed(s);

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

// ---------------------------------------------------------------- the command

namespace {

struct Summary {
  std::string name;
  ProfileScenario s;
  std::vector<FrameProfile> frames;
  std::vector<std::string> problems;
};

template <typename F>
double mean_of(const std::vector<FrameProfile>& v, F get) {
  double sum = 0.0;
  for (const auto& f : v) sum += static_cast<double>(get(f));
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}
template <typename F>
double max_of(const std::vector<FrameProfile>& v, F get) {
  double m = v.empty() ? 0.0 : -std::numeric_limits<double>::infinity();
  for (const auto& f : v) m = std::max(m, static_cast<double>(get(f)));
  return m;
}
template <typename F>
double min_of(const std::vector<FrameProfile>& v, F get) {
  double m = v.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (const auto& f : v) m = std::min(m, static_cast<double>(get(f)));
  return m;
}
template <typename F>
double median_of(const std::vector<FrameProfile>& v, F get) {
  std::vector<double> x;
  for (const auto& f : v) x.push_back(static_cast<double>(get(f)));
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  const size_t n = x.size();
  return n % 2 == 1 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}
template <typename F>
double sum_of(const std::vector<FrameProfile>& v, F get) {
  double sum = 0.0;
  for (const auto& f : v) sum += static_cast<double>(get(f));
  return sum;
}

void write_frame_header(host::CsvWriter& w) {
  w.row({"frame",
         "cycles",
         "tvalid_cycles",
         "accepted",
         "pixels_per_valid_cycle",
         "bubbles",
         "pixels_counted",
         "device_cycles",
         "eof_to_irq_cycles",
         "eof_to_irq_register",
         "fifo_high_water",
         "runs_dropped_overflow",
         "runs_dropped_row_limit",
         "runs_emitted",
         "runs",
         "run_beats",
         "run_stall_cycles",
         "words_read",
         "words_written",
         "configure_cycles",
         "readout_cycles",
         "host_cycles",
         "frame_ok",
         "host_driver_us",
         "host_pose_us",
         "pose_status"});
}

void write_frame_row(host::CsvWriter& w, size_t i, const FrameProfile& f) {
  w.integer(i).integer(f.cycles).integer(f.tvalid_cycles).integer(f.accepted);
  w.fixed(f.pixels_per_valid_cycle(), 6).integer(f.bubbles).integer(f.pixels_counted);
  w.integer(f.device_cycles).integer(f.eof_to_irq_cycles).integer(f.eof_to_irq_register);
  w.integer(f.fifo_high_water).integer(f.runs_dropped_overflow).integer(f.runs_dropped_row_limit);
  w.integer(f.runs_emitted).integer(f.runs).integer(f.run_beats).integer(f.run_stall_cycles);
  w.integer(f.words_read).integer(f.words_written).integer(f.configure_cycles);
  w.integer(f.readout_cycles).integer(f.host_cycles).integer(f.frame_ok);
  w.fixed(f.host_driver_us, 1).fixed(f.host_pose_us, 1).text(host::to_string(f.pose_status));
  w.end_row();
}

void write_summary_header(host::CsvWriter& w) {
  w.row({"scenario",
         "backend",
         "width",
         "height",
         "blanking",
         "gap_probability",
         "backpressure",
         "tapes",
         "frames",
         "cycles_min",
         "cycles_max",
         "pixels_per_valid_cycle_min",
         "bubbles_total",
         "eof_to_irq_min",
         "eof_to_irq_max",
         "fifo_high_water_max",
         "runs_dropped_overflow_total",
         "runs_mean",
         "run_stall_cycles_mean",
         "words_read_mean",
         "words_written_mean",
         "configure_cycles_mean",
         "readout_cycles_mean",
         "vertical_blanking_cycles",
         "host_driver_us_median",
         "host_pose_us_median",
         "violations",
         "config"});
}

void write_summary_row(host::CsvWriter& w, const Summary& m, const std::string& backend,
                       const std::string& config) {
  const auto& v = m.frames;
  w.text(m.name).text(backend).integer(m.s.width).integer(m.s.height);
  w.text(to_string(m.s.blanking));
  w.fixed(m.s.blanking == Blanking::random ? m.s.gap_probability : 0.0, 3);
  w.fixed(m.s.backpressure, 3).integer(m.s.tapes).integer(v.size());
  w.fixed(min_of(v, [](const auto& f) { return f.cycles; }), 0);
  w.fixed(max_of(v, [](const auto& f) { return f.cycles; }), 0);
  w.fixed(min_of(v, [](const auto& f) { return f.pixels_per_valid_cycle(); }), 6);
  w.fixed(sum_of(v, [](const auto& f) { return f.bubbles; }), 0);
  w.fixed(min_of(v, [](const auto& f) { return f.eof_to_irq_cycles; }), 0);
  w.fixed(max_of(v, [](const auto& f) { return f.eof_to_irq_cycles; }), 0);
  w.fixed(max_of(v, [](const auto& f) { return f.fifo_high_water; }), 0);
  w.fixed(sum_of(v, [](const auto& f) { return f.runs_dropped_overflow; }), 0);
  w.fixed(mean_of(v, [](const auto& f) { return f.runs; }), 1);
  w.fixed(mean_of(v, [](const auto& f) { return f.run_stall_cycles; }), 1);
  w.fixed(mean_of(v, [](const auto& f) { return f.words_read; }), 1);
  w.fixed(mean_of(v, [](const auto& f) { return f.words_written; }), 1);
  w.fixed(mean_of(v, [](const auto& f) { return f.configure_cycles; }), 1);
  w.fixed(mean_of(v, [](const auto& f) { return f.readout_cycles; }), 1);
  w.integer(frame_feed(m.s).blanking_cycles);
  w.fixed(median_of(v, [](const auto& f) { return f.host_driver_us; }), 1);
  w.fixed(median_of(v, [](const auto& f) { return f.host_pose_us; }), 1);
  w.integer(m.problems.size()).text(config).end_row();
}

void print_summary(const Summary& m, const std::string& backend) {
  const auto& v = m.frames;
  fmt::print("{} ({}): {}x{}, blanking {}", m.name.c_str(), backend.c_str(), m.s.width, m.s.height,
             std::string(to_string(m.s.blanking)).c_str());
  if (m.s.blanking == Blanking::random) fmt::print(" (gap P {:.2f})", m.s.gap_probability);
  fmt::print(", back-pressure {:.2f}, {} tape{}, {} frames\n", m.s.backpressure, m.s.tapes,
             m.s.tapes == 1 ? "" : "s", v.size());
  const auto u = [](double x) { return static_cast<unsigned long long>(x); };
  fmt::print("  cycles per frame (SOF..EOF)   {} .. {} (pixels {})\n",
             u(min_of(v, [](const auto& f) { return f.cycles; })),
             u(max_of(v, [](const auto& f) { return f.cycles; })),
             u(static_cast<double>(m.s.width) * m.s.height));
  fmt::print("  pixels per tvalid cycle (II)  min {:.6f}   bubbles {}\n",
             min_of(v, [](const auto& f) { return f.pixels_per_valid_cycle(); }),
             u(sum_of(v, [](const auto& f) { return f.bubbles; })));
  fmt::print("  EOF -> irq latency, cycles    {} .. {} (register {} .. {})\n",
             static_cast<long long>(min_of(v, [](const auto& f) { return f.eof_to_irq_cycles; })),
             static_cast<long long>(max_of(v, [](const auto& f) { return f.eof_to_irq_cycles; })),
             u(min_of(v, [](const auto& f) { return f.eof_to_irq_register; })),
             u(max_of(v, [](const auto& f) { return f.eof_to_irq_register; })));
  fmt::print("  run FIFO high-water / drops   max {} / {} total (row limit {})\n",
             u(max_of(v, [](const auto& f) { return f.fifo_high_water; })),
             u(sum_of(v, [](const auto& f) { return f.runs_dropped_overflow; })),
             u(sum_of(v, [](const auto& f) { return f.runs_dropped_row_limit; })));
  fmt::print(
      "  runs per frame                mean {:.1f} (run stream stalls {:.1f} cycles/frame)\n",
      mean_of(v, [](const auto& f) { return f.runs; }),
      mean_of(v, [](const auto& f) { return f.run_stall_cycles; }));
  fmt::print("  host AXI4-Lite words / frame  read {:.1f}, written {:.1f}\n",
             mean_of(v, [](const auto& f) { return f.words_read; }),
             mean_of(v, [](const auto& f) { return f.words_written; }));
  fmt::print(
      "  host bus cycles / frame       configure {:.1f} + readout (irq .. done) {:.1f}; vertical "
      "blanking {}\n",
      mean_of(v, [](const auto& f) { return f.configure_cycles; }),
      mean_of(v, [](const auto& f) { return f.readout_cycles; }), frame_feed(m.s).blanking_cycles);
  fmt::print(
      "  host time per frame (median)  driver {:.1f} us (simulation included), pose maths {:.1f} "
      "us\n",
      median_of(v, [](const auto& f) { return f.host_driver_us; }),
      median_of(v, [](const auto& f) { return f.host_pose_us; }));
  if (m.problems.empty()) {
    fmt::print("  II = 1 and 0 bubbles on every frame: MET\n");
  } else {
    fmt::print("  VIOLATED ({}):\n", m.problems.size());
    for (size_t i = 0; i < std::min<size_t>(m.problems.size(), 10); ++i) {
      fmt::print("    {}\n", m.problems[i].c_str());
    }
  }
}

std::vector<double> frame_axis(size_t n) {
  std::vector<double> x(n);
  for (size_t i = 0; i < n; ++i) x[i] = static_cast<double>(i);
  return x;
}

template <typename F>
std::vector<double> column(const std::vector<FrameProfile>& v, F get) {
  std::vector<double> y;
  y.reserve(v.size());
  for (const auto& f : v) y.push_back(static_cast<double>(get(f)));
  return y;
}

const cv::Scalar kBlue{200, 90, 20}, kRed{40, 40, 210}, kGreen{40, 150, 40};

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

}  // namespace

int run_profile(const ProfileOptions& o) {
  // Arguments first: nothing is written before they are all good.
  if (o.backend != "model" && o.backend != "rtl") {
    throw std::runtime_error("--backend must be model or rtl (the fast path has no cycles)");
  }
  const regs::Config* found = nullptr;
  for (const regs::Config& c : regs::kConfigs) {
    if (o.config == c.name) found = &c;
  }
  if (found == nullptr) {
    throw std::runtime_error("--config must name a device configuration (tape or full), not '" +
                             o.config + "'");
  }
  const regs::Config device_config = *found;
  ProfileScenario s;
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

  host::CameraConfig camera;
  std::vector<fs::path> files;
  size_t count = 0;
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
  const fs::path out = o.out_dir;
  if (!o.out_dir.empty()) check_out_dir(out);

  std::vector<cv::Mat> cache;  // rendered or read once, shared by the sweep
  const auto frame_at = [&](size_t i) -> cv::Mat {
    if (i < cache.size() && !cache[i].empty()) return cache[i];
    cv::Mat m = files.empty() ? render_profile_frame(s, camera, i, count)
                              : host::read_grey_frame(files[i], s.width, s.height);
    const size_t keep = std::max<size_t>(static_cast<size_t>(o.sweep_frames), 1);
    if (i < keep) {
      if (cache.size() <= i) cache.resize(i + 1);
      cache[i] = m;
    }
    return m;
  };

  const auto run_scenario = [&](const std::string& name, const ProfileScenario& sc, size_t n) {
    host::SimBusOptions bus_opt;
    bus_opt.seed = sc.seed;
    bus_opt.device_config = device_config;
    bus_opt.run_tready_low_probability = sc.backpressure;
    std::unique_ptr<host::SimBus> bus = make_profile_bus(o.backend, bus_opt);
    Summary m{name, sc, profile_frames(*bus, frame_at, n, sc, camera), {}};
    m.problems = check_profile(m.frames, sc);
    return m;
  };

  const Summary main_run = run_scenario("scenario", s, count);
  std::vector<Summary> sweep;
  if (o.sweep_frames > 0) {
    for (double duty : o.sweep_duties) {
      ProfileScenario sc = s;
      sc.backpressure = duty;
      char name[32];
      std::snprintf(name, sizeof name, "sweep_bp%.2f", duty);
      sweep.push_back(run_scenario(name, sc, std::min(count, static_cast<size_t>(o.sweep_frames))));
    }
  }

  print_summary(main_run, o.backend + " backend, " + o.config + " device");
  size_t violations = main_run.problems.size();
  if (!sweep.empty()) {
    fmt::print(
        "back-pressure sweep ({} frames each): duty -> II min, bubbles, FIFO high-water"
        " max, drops, stall cycles/frame\n",
        o.sweep_frames);
    for (const Summary& m : sweep) {
      fmt::print("  {:.2f} -> {:.6f}, {:.0f}, {:.0f}, {:.0f}, {:.1f}{}\n", m.s.backpressure,
                 min_of(m.frames, [](const auto& f) { return f.pixels_per_valid_cycle(); }),
                 sum_of(m.frames, [](const auto& f) { return f.bubbles; }),
                 max_of(m.frames, [](const auto& f) { return f.fifo_high_water; }),
                 sum_of(m.frames, [](const auto& f) { return f.runs_dropped_overflow; }),
                 mean_of(m.frames, [](const auto& f) { return f.run_stall_cycles; }),
                 m.problems.empty() ? "" : "  VIOLATED");
      for (const std::string& p : m.problems) std::fprintf(stderr, "  %s\n", p.c_str());
      violations += m.problems.size();
    }
  }

  if (!o.out_dir.empty()) {
    // Every file is staged and renamed into place together (OutputFolder).
    OutputFolder folder(out);
    AtomicFile csv(folder.path("profile.csv"));
    host::CsvWriter frames_csv(csv.stream());
    write_frame_header(frames_csv);
    for (size_t i = 0; i < main_run.frames.size(); ++i) {
      write_frame_row(frames_csv, i, main_run.frames[i]);
    }
    AtomicFile summary(folder.path("profile_summary.csv"));
    host::CsvWriter summary_csv(summary.stream());
    write_summary_header(summary_csv);
    write_summary_row(summary_csv, main_run, o.backend, o.config);
    for (const Summary& m : sweep) write_summary_row(summary_csv, m, o.backend, o.config);

    const auto& v = main_run.frames;
    const std::vector<double> x = frame_axis(v.size());
    const std::vector<PlotPanel> latency{
        {"Frame end (EOF pixel accepted) to irq rise",
         "frame",
         "cycles",
         {{"at the ports", x, column(v, [](const auto& f) { return f.eof_to_irq_cycles; }), kBlue},
          {"EOF_TO_IRQ_CYCLES", x, column(v, [](const auto& f) { return f.eof_to_irq_register; }),
           kRed}}},
        {"Host readout: irq rise to the driver's last transaction",
         "frame",
         "cycles",
         {{"readout", x, column(v, [](const auto& f) { return f.readout_cycles; }), kGreen}}}};
    const std::vector<PlotPanel> fifo{
        {"Run FIFO per frame (depth " + std::to_string(regs::kRunFifoDepth) + ")",
         "frame",
         "entries / runs",
         {{"high-water", x, column(v, [](const auto& f) { return f.fifo_high_water; }), kBlue},
          {"drops (overflow)", x, column(v, [](const auto& f) { return f.runs_dropped_overflow; }),
           kRed}}}};
    std::vector<double> duty, ii, hw, drops, stalls;
    for (const Summary& m : sweep) {
      duty.push_back(m.s.backpressure);
      ii.push_back(min_of(m.frames, [](const auto& f) { return f.pixels_per_valid_cycle(); }));
      hw.push_back(max_of(m.frames, [](const auto& f) { return f.fifo_high_water; }));
      drops.push_back(sum_of(m.frames, [](const auto& f) { return f.runs_dropped_overflow; }));
      stalls.push_back(mean_of(m.frames, [](const auto& f) { return f.run_stall_cycles; }));
    }
    const std::vector<PlotPanel> throughput{
        {"Video throughput vs run-stream back-pressure",
         "m_axis_runs tready-low duty",
         "pixels / tvalid cycle",
         {{"min over frames", duty, ii, kBlue}}},
        {"Run FIFO vs back-pressure",
         "m_axis_runs tready-low duty",
         "entries",
         {{"high-water (max)", duty, hw, kBlue}, {"drops (total)", duty, drops, kRed}}},
        {"Run stream stalls vs back-pressure",
         "m_axis_runs tready-low duty",
         "cycles / frame",
         {{"tvalid && !tready", duty, stalls, kGreen}}}};
    // gnuplot draws into the staged folder (PNG, .dat, .gp each); nothing is
    // renamed into place unless every chart was drawn.
    write_plots(folder.path("latency.png"), latency);
    write_plots(folder.path("fifo.png"), fifo);
    if (!sweep.empty()) write_plots(folder.path("throughput.png"), throughput);
    csv.commit();
    summary.commit();
    folder.commit();
    std::printf("wrote %s/profile.csv, profile_summary.csv, latency.png, fifo.png%s\n",
                out.string().c_str(), sweep.empty() ? "" : ", throughput.png");
  }
  if (violations > 0) {
    std::fprintf(stderr, "ceilnav profile: %zu violation(s) of II = 1 / 0 bubbles / counts\n",
                 violations);
    return 1;
  }
  return 0;
}

}  // namespace ceilnav::app
