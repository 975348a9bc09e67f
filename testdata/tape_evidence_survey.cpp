// The false-accept table of docs/results.md ("Evidence: no pose that is not
// there"): for each evidence check, the `ok` results (centre line + zenith)
// with every check on but that one, on the real corpus (5 cameras, one
// navigator per set as `ceilnav run`) and on distractor renders without tape.
// Usage: ceilnav_tape_evidence_survey (no arguments; prints one line per variant).
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/camera_config_io.hpp"
#include "host/navigator.hpp"
#include "real_corpus.hpp"

using namespace ceilnav;
namespace ts = ceilnav::test_support;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct Variant {
  std::string name;
  std::function<void(host::NavigatorOptions&)> f;
};

int main() {
  std::vector<Variant> variants = {
      {"all checks", [](host::NavigatorOptions&) {}},
      {"no width check",
       [](host::NavigatorOptions& o) {
         o.pose.width_tolerance = 1e9;
         o.zenith.width_tolerance = 1e9;
       }},
      {"no coverage", [](host::NavigatorOptions& o) { o.pose.min_coverage = 0; }},
      {"no border end", [](host::NavigatorOptions& o) { o.pose.require_border_end = false; }},
      {"no min length", [](host::NavigatorOptions& o) { o.pose.min_visible_length_m = 0; }},
      {"no gap limit", [](host::NavigatorOptions& o) { o.pose.max_gap_m = 0; }},
      {"zenith: no crossing", [](host::NavigatorOptions& o) { o.zenith.min_chord_fraction = 0; }},
      {"zenith: no fill", [](host::NavigatorOptions& o) { o.zenith.fill_tolerance = 1e9; }},
      {"none (as before)",
       [](host::NavigatorOptions& o) {
         o.pose.width_tolerance = 1e9;
         o.pose.min_coverage = 0;
         o.pose.require_border_end = false;
         o.pose.min_visible_length_m = 0;
         o.pose.max_gap_m = 0;
         o.zenith.width_tolerance = 1e9;
         o.zenith.min_chord_fraction = 0;
         o.zenith.fill_tolerance = 1e9;
       }},
  };
  // Real corpus, 5 cameras.
  const auto frames = ts::load_real_corpus();
  std::vector<host::CameraConfig> cams;
  for (double p : {45.0, 90.0}) {
    host::CameraConfig c;
    c.camera_pitch_deg = p;
    cams.push_back(c);
  }
  const auto cyc = host::load_camera_config(
      (ts::real_corpus_dir() / "cycloid_ceiltrack" / "camera.yaml").string());
  for (double p : {45.0, 68.0, 90.0}) {
    auto c = cyc;
    c.camera_pitch_deg = p;
    cams.push_back(c);
  }
  const auto scenes = golden::distractor_scenes();
  std::vector<golden::CameraPose> poses;
  for (int i = 0; i < 8; ++i)
    poses.push_back({0.37 * i, -0.6 + 0.17 * i, (-30.0 + 8.0 * i) * kDeg});
  for (const auto& v : variants) {
    host::NavigatorOptions opt;
    v.f(opt);
    int ok = 0, zok = 0, n = 0;
    for (const auto& cam : cams) {
      std::map<std::string, std::unique_ptr<host::Navigator>> navs;
      for (const auto& f : frames) {
        auto& nav = navs[f.name.substr(0, f.name.find('/'))];
        if (!nav) nav = std::make_unique<host::Navigator>(cam, drivers::make_device(), opt);
        const auto r = nav->process(f.grey);
        ++n;
        ok += r.pose.status == host::Status::ok;
        zok += r.zenith && r.zenith->status == host::Status::ok;
      }
    }
    std::printf("%-20s corpus: %d frames, ok %d, zenith ok %d |", v.name.c_str(), n, ok, zok);
    for (const auto& [name, scene] : scenes) {
      int sok = 0, szok = 0, sn = 0;
      for (double pitch : {30.0, 45.0, 68.0, 90.0}) {
        host::CameraConfig cam = golden::default_camera();
        cam.camera_pitch_deg = pitch;
        for (const auto& pose : poses) {
          golden::RenderParams p = golden::default_render_params();
          p.noise_seed = static_cast<uint64_t>(sn + 1);
          host::Navigator nav(cam, drivers::make_device(), opt);
          const auto r = nav.process(golden::render_frame(cam, scene, pose, p));
          ++sn;
          sok += r.pose.status == host::Status::ok;
          szok += r.zenith && r.zenith->status == host::Status::ok;
        }
      }
      std::printf(" %s %d+%d/%d", name.c_str(), sok, szok, sn);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
}
