// `ceilnav homing`: seed 004's home-on-ceiling in the loop (sim/homing.hpp).
// The sites of a ceiling file (default: the built-in office ceiling) are
// recorded (map/: map.json and the patches, or --map: a recorded map), then
// the triangle race: --loops times round the sites on odometric paths with
// the navigation layer's drift, homing at every site. Writes
// homing_race.csv (a row per homing: the seed's Table 1 with the arrival
// error and the heading), homing_frames.csv (a row per frame), the same
// race on odometry alone (odometry_race.csv), ceiling.yaml (the world
// of the run), summary.json (with the goals), race.png; with --capture the capture zone of one site
// (capture_zone.csv, capture.png). docs/homing.md.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "apps/atomic_file.hpp"
#include "apps/commands.hpp"
#include "apps/plot.hpp"
#include "apps/progress.hpp"
#include "golden/ceiling/ceiling_file.hpp"
#include "golden/orientation_ref.hpp"
#include "host/camera_config_io.hpp"
#include "host/frame_io.hpp"
#include "sim/homing.hpp"

namespace ceilnav::app {
namespace {

namespace gc = golden::ceiling;
namespace hh = host::homing;

std::string leg_row(const sim::RaceLeg& l) {
  const bool homed = l.homing.outcome == sim::HomingOutcome::homed;
  return fmt::format("{},{},{:.2f},{:.3f},{},{},{},{},{:.2f}\n", l.loop, l.site + 1,
                     1e3 * l.arrival_distance_m, l.arrival_heading_error_rad / kDeg,
                     sim::to_string(l.homing.outcome),
                     homed ? fmt::format("{:.3f}", 1e3 * l.homing.position_error_m) : "",
                     homed ? fmt::format("{:.4f}", l.homing.heading_error_rad / kDeg) : "",
                     l.homing.frames, l.homing.time_s);
}

// --frames: every site of the map searched in every recorded frame, over
// 360 deg and in the fast mode about each quarter turn (what a homing's
// acquisition does); each `ok` is a claim that the frame shows the site.
int replay_frames(const HomingOptions& o) {
  if (o.map_file.empty()) throw std::runtime_error("homing: --frames needs --map");
  hh::SiteMap map;
  try {
    map = hh::load_site_map(o.map_file);
  } catch (const hh::SiteMapError& e) {
    throw std::runtime_error(std::string("homing: ") + e.what());
  }
  const std::vector<std::filesystem::path> files = host::list_png_frames(o.frames_dir);
  std::vector<hh::SiteTracker> trackers;
  for (const hh::MapSite& s : map.sites) trackers.emplace_back(s.site);
  OutputFolder out(o.out_dir);
  AtomicFile csv(out.path("frames.csv"));
  csv.stream() << "frame,site,search,status,score,x_px,y_px,gamma_deg\n";
  Progress bar("homing frames", files.size(), !o.quiet);
  std::map<std::string, int> counts;
  int frames_with_ok = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const cv::Mat grey = host::read_grey_frame(files[i]);
    const std::vector<uint32_t> bins = golden::orientation_histogram_fixed(grey);  // the device's
    const hh::OrientationHistogram h(bins.begin(), bins.end());
    bool any = false;
    for (std::size_t k = 0; k < trackers.size(); ++k) {
      for (int q = -1; q < 4; ++q) {
        const hh::TrackResult r =
            q < 0 ? trackers[k].track(grey, h) : trackers[k].track(grey, h, std::nullopt, 90.0 * q);
        ++counts[hh::to_string(r.status)];
        any = any || r.status == hh::TrackStatus::ok;
        csv.stream() << fmt::format("{},{},{},{},{:.4f},{:.2f},{:.2f},{:.3f}\n",
                                    files[i].filename().string(), k + 1,
                                    q < 0 ? std::string("360") : fmt::format("fast {}", 90 * q),
                                    hh::to_string(r.status), r.score, r.x_px, r.y_px, r.gamma_deg);
      }
    }
    frames_with_ok += any;
    bar.update(i + 1);
  }
  csv.commit();
  nlohmann::json j;
  j["map"] = o.map_file;
  j["frames_dir"] = o.frames_dir;
  j["frames"] = files.size();
  j["sites"] = map.sites.size();
  j["searches"] = {
      {"ok", counts["ok"]}, {"ambiguous", counts["ambiguous"]}, {"not_found", counts["not_found"]}};
  j["frames_with_a_site"] = frames_with_ok;
  {
    AtomicFile f(out.path("summary.json"));
    f.stream() << j.dump(2) << "\n";
    f.commit();
  }
  out.commit();
  if (!o.quiet) {
    fmt::print("homing --frames: {} frames x {} sites: {} ok, {} ambiguous, {} not found\n",
               files.size(), map.sites.size(), counts["ok"], counts["ambiguous"],
               counts["not_found"]);
  }
  return 0;
}

}  // namespace

int run_homing(const HomingOptions& o) {
  if (!o.frames_dir.empty()) return replay_frames(o);
  gc::CeilingFile world =
      o.ceiling_file.empty() ? gc::default_homing_world() : gc::load_ceiling(o.ceiling_file);
  if (world.sites.size() < 2) {
    throw std::runtime_error("homing: the ceiling file needs two or more sites for the race");
  }
  host::CameraConfig intrinsics;
  if (!o.camera_file.empty())
    intrinsics = host::load_camera_config(o.camera_file, host::ConfigKeys::camera_only);
  const host::CameraConfig camera = sim::homing_camera(intrinsics, world);
  sim::HomingSimParams p;
  p.seed = o.seed;
  p.robot.seed = o.seed;
  p.render.noise_sigma_grey = o.noise_grey;
  p.device = device_options(o.backend);
  sim::validate(p);
  if (o.capture_radii_m.empty() ||
      !std::is_sorted(o.capture_radii_m.begin(), o.capture_radii_m.end(), std::less_equal<>()) ||
      !(o.capture_radii_m.front() > 0.0) || !std::isfinite(o.capture_radii_m.back())) {
    throw std::runtime_error("homing: --capture-radii must be positive and strictly ascending");
  }
  if (o.capture_site < 1 || o.capture_site > static_cast<int>(world.sites.size())) {
    throw std::runtime_error(
        fmt::format("homing: --capture-site must be 1 .. {}", world.sites.size()));
  }

  OutputFolder out(o.out_dir);
  gc::save_ceiling(world, out.path("ceiling.yaml").string());  // the world of this run
  hh::SiteMap map;
  if (o.map_file.empty()) {
    map = sim::record_sites(world, camera, p);
    std::filesystem::create_directories(out.path("map"));
    hh::save_site_map(map, out.path("map").string());
  } else {
    try {
      map = hh::load_site_map(o.map_file);
    } catch (const hh::SiteMapError& e) {
      throw std::runtime_error(std::string("homing: ") + e.what());
    }
    if (map.sites.size() != world.sites.size()) {
      throw std::runtime_error(fmt::format("homing: the map has {} sites, the ceiling file {}",
                                           map.sites.size(), world.sites.size()));
    }
  }

  // The race on odometry alone: the drift the homing takes out.
  const sim::RaceResult odo = sim::run_race(world, camera, map, p, o.loops, false);
  {
    AtomicFile csv(out.path("odometry_race.csv"));
    csv.stream() << "loop,site,arrival_error_mm,arrival_heading_deg\n";
    for (const sim::RaceLeg& l : odo.legs) {
      csv.stream() << fmt::format("{},{},{:.2f},{:.3f}\n", l.loop, l.site + 1,
                                  1e3 * l.arrival_distance_m, l.arrival_heading_error_rad / kDeg);
    }
    csv.commit();
  }

  AtomicFile race_csv(out.path("homing_race.csv"));
  race_csv.stream() << "loop,site,arrival_error_mm,arrival_heading_deg,outcome,error_mm,"
                       "heading_error_deg,frames,time_s\n";
  AtomicFile frames_csv(out.path("homing_frames.csv"));
  frames_csv.stream() << "loop,site,t_s,x_m,y_m,yaw_deg,track,score,forward_m,left_m,turn_deg,"
                         "true_forward_m,true_left_m,true_turn_deg,phase,v_cmd_m_s,"
                         "omega_cmd_rad_s,consistent\n";
  const std::size_t homings = static_cast<std::size_t>(o.loops) * world.sites.size();
  Progress bar("homing race", homings, !o.quiet);
  int loop = 1, site = 0;
  std::size_t done = 0;
  const sim::RaceResult race = sim::run_race(
      world, camera, map, p, o.loops, true,
      [&](const sim::RaceLeg& l) {
        race_csv.stream() << leg_row(l);
        bar.update(++done);
        if (l.site + 1 == static_cast<int>(world.sites.size())) ++loop;
        site = (l.site + 1) % static_cast<int>(world.sites.size());
      },
      [&](const sim::HomingFrame& f) {
        const bool ok = f.track == hh::TrackStatus::ok;  // the tracker's, checked or not
        frames_csv.stream() << fmt::format(
            "{},{},{:.2f},{:.5f},{:.5f},{:.4f},{},{:.4f},{},{},{},{:.5f},{:.5f},{:.4f},{},{:.4f},"
            "{:.4f},{}\n",
            loop, site + 1, f.t_s, f.robot.x_m, f.robot.y_m, f.robot.yaw_rad / kDeg,
            hh::to_string(f.track), f.score,
            ok ? fmt::format("{:.5f}", f.measurement.forward_m) : "",
            ok ? fmt::format("{:.5f}", f.measurement.left_m) : "",
            ok ? fmt::format("{:.4f}", f.measurement.turn_rad / kDeg) : "", f.true_error.forward_m,
            f.true_error.left_m, f.true_error.turn_rad / kDeg, nav::to_string(f.command.phase),
            f.command.v_m_s, f.command.omega_rad_s, f.consistent ? 1 : 0);
      });
  race_csv.commit();
  frames_csv.commit();

  nlohmann::json j;
  j["ceiling"] = o.ceiling_file.empty() ? std::string("built-in office") : o.ceiling_file;
  j["map"] = o.map_file.empty() ? std::string("recorded: map/map.json") : o.map_file;
  j["seed"] = o.seed;
  j["loops"] = o.loops;
  j["sites"] = world.sites.size();
  j["ceiling_height_m"] = world.ceiling.height_m;
  j["camera_height_m"] = world.camera.height_m;
  j["noise_grey"] = o.noise_grey;
  j["backend"] = o.backend;
  j["frame_rate_hz"] = p.frame_rate_hz;
  j["homings"] = race.legs.size();
  j["homed"] = race.homed;
  j["failed"] = race.failed;
  j["false_homings"] = race.false_homings;
  j["position_rms_mm"] = 1e3 * race.position_rms_m;
  j["position_max_mm"] = 1e3 * race.position_max_m;
  j["heading_rms_deg"] = race.heading_rms_rad / kDeg;
  j["heading_max_deg"] = race.heading_max_rad / kDeg;
  j["arrival_rms_mm"] = 1e3 * race.arrival_rms_m;
  int inconsistent = 0;
  for (const sim::RaceLeg& l : race.legs) inconsistent += l.homing.inconsistent_frames;
  j["inconsistent_frames"] = inconsistent;
  j["distance_m"] = race.distance_m;
  j["time_s"] = race.time_s;
  j["odometry_only"] = {{"arrival_rms_mm", 1e3 * odo.arrival_rms_m},
                        {"final_arrival_mm", 1e3 * odo.legs.back().arrival_distance_m},
                        {"distance_m", odo.distance_m}};
  nlohmann::json sites = nlohmann::json::array();
  for (const hh::MapSite& s : map.sites) {
    sites.push_back({{"name", s.name},
                     {"self_similarity", s.site.self_similarity},
                     {"rotational_similarity", s.site.rotational_similarity},
                     {"look_forward_m", s.look_forward_m},
                     {"look_left_m", s.look_left_m},
                     {"usable", s.unusable.empty()}});
    if (!s.unusable.empty()) sites.back()["unusable"] = s.unusable;
  }
  j["site_list"] = sites;
  nlohmann::json goals;
  goals["all_homed"] = race.failed == 0;
  goals["position_rms_le_3mm"] = race.homed > 0 && race.position_rms_m <= 0.003;
  goals["heading_rms_le_0p2deg"] = race.homed > 0 && race.heading_rms_rad <= 0.2 * kDeg;
  goals["no_false_homing"] = race.false_homings == 0;

  std::vector<double> cap_r, cap_frac;
  if (o.capture) {
    sim::CaptureParams cp;
    cp.radii_m = o.capture_radii_m;
    const int site_index = o.capture_site - 1;
    Progress cbar(
        "capture zone",
        cp.radii_m.size() * static_cast<std::size_t>(cp.bearings) * cp.heading_offsets_rad.size(),
        !o.quiet);
    std::size_t n = 0;
    AtomicFile cap_csv(out.path("capture_zone.csv"));
    cap_csv.stream() << "radius_m,bearing_deg,heading_offset_deg,outcome,error_mm,"
                        "heading_error_deg,frames,success\n";
    const sim::CaptureZone zone =
        sim::capture_zone(world, camera, map, site_index, p, cp, [&](const sim::CaptureStart& s) {
          cap_csv.stream() << fmt::format(
              "{:.3f},{:.1f},{:.1f},{},{:.3f},{:.4f},{},{}\n", s.radius_m, s.bearing_rad / kDeg,
              s.heading_offset_rad / kDeg, sim::to_string(s.run.outcome),
              1e3 * s.run.position_error_m, s.run.heading_error_rad / kDeg, s.run.frames,
              s.success ? 1 : 0);
          cbar.update(++n);
        });
    cap_csv.commit();
    std::map<double, std::pair<int, int>> by_radius;
    for (const sim::CaptureStart& s : zone.starts) {
      auto& [ok, all] = by_radius[s.radius_m];
      ok += s.success;
      ++all;
    }
    nlohmann::json fractions = nlohmann::json::object();
    for (const auto& [r, c] : by_radius) {
      cap_r.push_back(r);
      cap_frac.push_back(static_cast<double>(c.first) / c.second);
      fractions[fmt::format("{:.2f}", r)] = cap_frac.back();
    }
    j["capture"] = {{"site", o.capture_site},
                    {"radius_m", zone.radius_m},
                    {"paper_radius_m", 1.15},
                    {"starts", zone.starts.size()},
                    {"false_homings", zone.false_homings},
                    {"success_by_radius", fractions}};
    goals["capture_radius_ge_1m"] = zone.radius_m >= 1.0;
    goals["capture_no_false_homing"] = zone.false_homings == 0;
  }
  bool all = true;
  for (const auto& [k, v] : goals.items()) all = all && v.get<bool>();
  j["goals"] = goals;
  j["goals_met"] = all;
  {
    AtomicFile f(out.path("summary.json"));
    f.stream() << j.dump(2) << "\n";
    f.commit();
  }
  if (o.plot) {
    std::vector<double> leg, err, arr, odo_arr;
    for (std::size_t k = 0; k < race.legs.size(); ++k) {
      leg.push_back(static_cast<double>(k + 1));
      const sim::RaceLeg& l = race.legs[k];
      err.push_back(l.homing.outcome == sim::HomingOutcome::homed ? 1e3 * l.homing.position_error_m
                                                                  : std::nan(""));
      arr.push_back(1e3 * l.arrival_distance_m);
      odo_arr.push_back(1e3 * odo.legs[k].arrival_distance_m);
    }
    std::vector<PlotPanel> panels{
        {"Triangle race: the error after each homing",
         "homing (sites 1, 2, 3, 1, ...)",
         "position error (mm)",
         {{"after homing", leg, err, cv::Scalar(200, 80, 0)}},
         true},
        {"Arrival at each site: odometric path with homing vs odometry alone",
         "homing (sites 1, 2, 3, 1, ...)",
         "distance from the site (mm)",
         {{"with homing (arrival)", leg, arr, cv::Scalar(0, 120, 255)},
          {"odometry alone", leg, odo_arr, cv::Scalar(40, 40, 200)}},
         true}};
    if (o.capture) {
      panels.push_back({"Capture zone: homed starts by distance from the site",
                        "start distance (m)",
                        "fraction homed",
                        {{"homed within 5 mm and 0.5 deg", cap_r, cap_frac, cv::Scalar(0, 160, 0)}},
                        true});
    }
    write_plots(out.path("race.png"), panels);
  }
  out.commit();
  if (!o.quiet) {
    fmt::print(
        "homing: {} homings ({} homed, {} failed, {} false): error RMS {:.2f} mm / {:.3f} deg, "
        "max {:.2f} mm / {:.3f} deg; arrival RMS {:.0f} mm (odometry alone {:.0f} mm){}\n",
        race.legs.size(), race.homed, race.failed, race.false_homings, 1e3 * race.position_rms_m,
        race.heading_rms_rad / kDeg, 1e3 * race.position_max_m, race.heading_max_rad / kDeg,
        1e3 * race.arrival_rms_m, 1e3 * odo.arrival_rms_m,
        o.capture ? fmt::format("; capture radius {:.2f} m", j["capture"]["radius_m"].get<double>())
                  : "");
  }
  return o.require && !all ? 1 : 0;
}

}  // namespace ceilnav::app
