// `ceilnav drive --corridor`: a robot guided down a corridor without tape by
// seed 002 (sim/corridor_drive.hpp): the learning drive's model, then the
// closed loop from an offset start over --length metres. Writes
// corridor_drive.csv (a row per frame), model.json, summary.json (with the
// goal: lateral RMS <= 5 cm over the drive) and drive.png.
// docs/corridor.md, "Closed loop".
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "apps/plot.hpp"
#include "apps/progress.hpp"
#include "golden/corridor/corridor_file.hpp"
#include "sim/corridor_drive.hpp"

namespace ceilnav::app {
namespace {

namespace gc = golden::corridor;
namespace hc = host::corridor;

// The tape course's options that mean nothing in a corridor drive: refused
// rather than ignored.
void refuse_tape_options(const DriveOptions& o) {
  const auto refuse = [](bool set, const char* name) {
    if (set)
      throw std::runtime_error(
          fmt::format("drive: {} applies to the tape course, not --corridor", name));
  };
  refuse(o.backend != "fast", "--backend");
  refuse(o.monte_carlo != 1, "--monte-carlo");
  refuse(o.steering != "feedback", "--steering");
  refuse(!o.vision, "--no-vision");
  refuse(o.map_height_scale != 1.0, "--map-height-scale");
  refuse(o.max_time_s != 0.0, "--max-time");
}

}  // namespace

int run_corridor_drive(const DriveOptions& o) {
  refuse_tape_options(o);
  gc::Corridor corridor = gc::default_corridor();
  gc::Pose start = gc::default_pose();
  if (o.corridor != "default") {
    const gc::CorridorFile f = gc::load_corridor(o.corridor);
    corridor = f.corridor;
    if (f.camera) start = *f.camera;
  }
  const host::CameraConfig camera;  // 640 x 480, f = 500 px
  sim::CorridorDriveParams p;
  p.length_m = o.length_m;
  p.seed = o.seed;
  p.robot.seed = o.seed;
  p.render.supersample = 4;
  sim::validate(p);
  if (start.x_m + p.length_m >= corridor.x_end_m()) {
    throw std::runtime_error(
        fmt::format("drive: a {} m drive from x = {} m passes the corridor's far end at {} m",
                    p.length_m, start.x_m, corridor.x_end_m()));
  }

  OutputFolder out(o.out_dir);
  AtomicFile csv(out.path("corridor_drive.csv"));
  csv.stream() << "frame,t_s,x_m,y_m,heading_deg,true_offset_m,status,lines,axis_lines,pan_deg,"
                  "delta_phi_deg,delta_x_m,delta_x_sigma_m,delta_x_error_m,turn_deg,"
                  "yaw_rate_cmd_rad_s,edges\n";
  const int expected_frames =
      static_cast<int>(std::ceil(p.length_m / p.speed_m_s * p.frame_rate_hz)) + 5;
  Progress bar("corridor drive", static_cast<std::size_t>(expected_frames), !o.quiet);
  int ok = 0, pan_only = 0;
  double shift_sum2 = 0.0, shift_max = 0.0;
  std::vector<double> xs, offsets, shifts_x, shifts;
  const sim::CorridorDriveResult r = sim::run_corridor_drive(
      corridor, camera, start, p, [&](const sim::CorridorDriveFrame& f, const cv::Mat&) {
        const double offset = f.camera.y_m - f.path_y_m;
        const bool has_pan = f.status != hc::GuideStatus::not_found;
        const bool has_shift = f.status == hc::GuideStatus::ok;
        ok += has_shift;
        pan_only += f.status == hc::GuideStatus::pan_only;
        std::string shift_cols = ",,";
        if (has_shift) {
          const double e = f.shift_m - offset;
          shift_sum2 += e * e;
          shift_max = std::max(shift_max, std::abs(e));
          shift_cols = fmt::format("{:.4f},{:.4f},{:.4f}", f.shift_m, f.shift_sigma_m, e);
          shifts_x.push_back(f.camera.x_m);
          shifts.push_back(f.shift_m);
        }
        xs.push_back(f.camera.x_m);
        offsets.push_back(offset);
        csv.stream() << fmt::format(
            "{},{:.3f},{:.4f},{:.4f},{:.4f},{:.4f},{},{},{},{},{},{},{:.3f},{:.5f},{}\n", f.index,
            f.t_s, f.camera.x_m, f.camera.y_m, (f.camera.pan_rad - start.pan_rad) / kDeg, offset,
            hc::to_string(f.status), f.lines, f.axis_lines,
            has_pan ? fmt::format("{:.4f}", f.pan_rad / kDeg) : "",
            has_pan ? fmt::format("{:.4f}", f.delta_phi_rad / kDeg) : "", shift_cols,
            f.turn_rad / kDeg, f.yaw_rate_cmd_rad_s, f.edges);
        bar.update(static_cast<std::size_t>(std::min(f.index + 1, expected_frames)));
      });
  csv.commit();
  hc::write_model_file(out.path("model.json").string(), r.model);

  const int frames = static_cast<int>(r.frames.size());
  nlohmann::json j;
  j["corridor"] = o.corridor;
  j["length_m"] = p.length_m;
  j["distance_m"] = r.distance_m;
  j["time_s"] = r.time_s;
  j["completed"] = r.completed;
  if (!r.completed) j["stop_reason"] = r.stop_reason;
  j["speed_m_s"] = p.speed_m_s;
  j["frame_rate_hz"] = p.frame_rate_hz;
  j["start_offset_m"] = p.start_offset_m;
  j["start_heading_deg"] = p.start_heading_rad / kDeg;
  j["convergence_length_m"] = p.convergence_length_m;
  j["seed"] = o.seed;
  j["learning_frames"] = r.learning_frames;
  j["learning_frames_with_pan"] = r.learning_frames_with_pan;
  j["model_lines"] = r.model.lines.size();
  j["frames"] = frames;
  j["frames_ok"] = ok;
  j["frames_pan_only"] = pan_only;
  j["frames_not_found"] = frames - ok - pan_only;
  j["lateral_rms_m"] = r.lateral_rms_m;
  j["lateral_max_m"] = r.lateral_max_m;
  j["final_lateral_m"] = r.final_lateral_m;
  j["held_rms_m"] = r.held_rms_m;  // from 5 m on (captured)
  j["held_max_m"] = r.held_max_m;
  if (ok > 0) {
    j["delta_x_rms_m"] = std::sqrt(shift_sum2 / ok);
    j["delta_x_max_m"] = shift_max;
  }
  nlohmann::json goal;
  goal["completed"] = r.completed;
  goal["lateral_rms_le_5cm"] = r.completed && r.lateral_rms_m <= 0.05;
  j["goals"] = goal;
  const bool goals = r.completed && r.lateral_rms_m <= 0.05;
  j["goals_met"] = goals;
  {
    AtomicFile f(out.path("summary.json"));
    f.stream() << j.dump(2) << "\n";
    f.commit();
  }
  if (o.plot) {
    PlotPanel panel{"Corridor drive: the camera's offset from the learnt path",
                    "x along the corridor (m)",
                    "offset (m, left +)",
                    {{"true offset", xs, offsets, cv::Scalar(200, 80, 0)},
                     {"measured lateral shift", shifts_x, shifts, cv::Scalar(0, 120, 255)}},
                    false};
    write_plots(out.path("drive.png"), {panel});
  }
  out.commit();
  if (!o.quiet) {
    fmt::print(
        "drive --corridor: {:.1f} m in {:.1f} s, {} frames ({} ok, {} pan only); lateral RMS "
        "{:.1f} mm, max {:.1f} mm (from 5 m on: {:.1f} / {:.1f} mm){}\n",
        r.distance_m, r.time_s, frames, ok, pan_only, 1e3 * r.lateral_rms_m, 1e3 * r.lateral_max_m,
        1e3 * r.held_rms_m, 1e3 * r.held_max_m,
        r.completed ? "" : fmt::format(" ({})", r.stop_reason));
  }
  return o.require && !goals ? 1 : 0;
}

}  // namespace ceilnav::app
