// `ceilnav profile`'s report: CSV rows, the text summary and the charts.
#include "apps/profile_report.hpp"

#include <cstdio>

#include <fmt/format.h>
#include "apps/plot.hpp"
#include "ceilnav/regs.hpp"
#include "host/status.hpp"

namespace ceilnav::app {

namespace {

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

}  // namespace

void write_frame_header(CsvWriter& w) {
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

void write_frame_row(CsvWriter& w, size_t i, const FrameProfile& f) {
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

void write_summary_header(CsvWriter& w) {
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

void write_summary_row(CsvWriter& w, const ProfileSummary& m, const std::string& backend) {
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
  w.integer(m.problems.size()).text(m.s.device_config.name).end_row();
}

void print_summary(const ProfileSummary& m, const std::string& backend) {
  const auto& v = m.frames;
  fmt::print("{} ({} backend, {} device): {}x{}, blanking {}", m.name.c_str(), backend.c_str(),
             m.s.device_config.name, m.s.width, m.s.height,
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

size_t print_sweep(const std::vector<ProfileSummary>& sweep, int frames_per_point) {
  size_t violations = 0;
  if (sweep.empty()) return violations;
  fmt::print(
      "back-pressure sweep ({} frames each): duty -> II min, bubbles, FIFO high-water"
      " max, drops, stall cycles/frame\n",
      frames_per_point);
  for (const ProfileSummary& m : sweep) {
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
  return violations;
}

void write_profile_plots(const std::filesystem::path& dir, const ProfileSummary& main_run,
                         const std::vector<ProfileSummary>& sweep) {
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
  for (const ProfileSummary& m : sweep) {
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
  write_plots(dir / "latency.png", latency);
  write_plots(dir / "fifo.png", fifo);
  if (!sweep.empty()) write_plots(dir / "throughput.png", throughput);
}

}  // namespace ceilnav::app
