// Rendered junction scenes with truth for the junction tests
// (junction_render_test.cpp, junction_sweep_test.cpp): the golden corridor
// (T-branch on the right at x = 10 m, gaps from 6, 15 and 27 m) and built
// scenes (T-branch left, crossing, L-turns left and right, tape end at x = 8
// m), the demo camera (k1 = -0.08) and render parameters.
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "drivers/device.hpp"
#include "golden/default_scene.hpp"
#include "golden/renderer.hpp"
#include "golden/scene.hpp"
#include "host/junction.hpp"
#include "host/navigator.hpp"

namespace ceilnav::host::junction_test {

inline constexpr double kDeg = std::numbers::pi / 180.0;
inline constexpr double kMatchM = 0.3;  // a reported distance farther than this from truth is wrong
inline constexpr double kW = 0.05;      // the demo tape
inline constexpr double kJx = 8.0;      // junction x of the built scenes

inline CameraConfig camera(double pitch_deg) {
  CameraConfig c = golden::default_camera();
  c.camera_pitch_deg = pitch_deg;
  return c;
}

inline golden::RenderParams render_params(uint64_t seed) {
  golden::RenderParams p = golden::default_render_params();
  p.noise_seed = seed;
  return p;
}

// A junction of a scene: kind, side and x of its centre on the reference tape.
struct TruthJunction {
  JunctionKind kind;
  JunctionSide side;
  double x_m;
};

struct TruthScene {
  std::string name;
  golden::CeilingScene scene;
  std::vector<TruthJunction> junctions;  // [0]: the one a sweep approaches
};

inline golden::TapeSegment strip(double x0, double y0, double x1, double y1) {
  return {x0, y0, x1, y1, kW};
}

// The corridor's junctions with `first` moved to the front.
inline TruthScene corridor(const std::string& name, size_t first) {
  TruthScene t{name, golden::corridor_scene(kW), {}};
  t.junctions = {{JunctionKind::t_branch, JunctionSide::right, 10.0},
                 {JunctionKind::tape_end, JunctionSide::none, 6.0},
                 {JunctionKind::tape_end, JunctionSide::none, 15.0},
                 {JunctionKind::tape_end, JunctionSide::none, 27.0}};
  std::swap(t.junctions[0], t.junctions[first]);
  return t;
}

inline TruthScene built(const std::string& name, std::vector<golden::TapeSegment> tapes,
                        TruthJunction j) {
  TruthScene t;
  t.name = name;
  t.scene.tapes = std::move(tapes);
  t.junctions = {j};
  return t;
}

inline std::vector<TruthScene> scenes() {
  return {corridor("corridor T right", 0),
          corridor("corridor gap", 1),
          built("T left", {strip(-10, 0, 100, 0), strip(kJx, 0, kJx, 3)},
                {JunctionKind::t_branch, JunctionSide::left, kJx}),
          built("crossing", {strip(-10, 0, 100, 0), strip(kJx, -3, kJx, 3)},
                {JunctionKind::t_branch, JunctionSide::both, kJx}),
          built("L left", {strip(-10, 0, kJx, 0), strip(kJx, 0, kJx, 3)},
                {JunctionKind::l_turn, JunctionSide::left, kJx}),
          built("L right", {strip(-10, 0, kJx, 0), strip(kJx, 0, kJx, -3)},
                {JunctionKind::l_turn, JunctionSide::right, kJx}),
          built("tape end", {strip(-10, 0, kJx, 0)},
                {JunctionKind::tape_end, JunctionSide::none, kJx})};
}

struct Frame {
  FrameOutcome outcome;
  std::vector<Junction> junctions;
};

// One frame through a fresh Navigator (as `ceilnav run` on one frame) and the detector.
inline Frame run(const CameraConfig& cam, const golden::CeilingScene& scene,
                 const golden::CameraPose& pose, uint64_t seed) {
  Navigator nav(cam, drivers::make_device());
  Frame f;
  f.outcome = nav.process(golden::render_frame(cam, scene, pose, render_params(seed)));
  f.junctions = detect_junctions(f.outcome, nav.camera_model(), cam);
  return f;
}

inline bool matches(const Junction& j, const TruthJunction& t, double camera_x) {
  return j.kind == t.kind && j.side == t.side &&
         std::abs(j.distance_m - (t.x_m - camera_x)) <= kMatchM;
}

// The junction of `f` that is one of the scene's, or nullptr; `unknown` counts
// the reported junctions that are none of the scene's.
inline const Junction* find_match(const Frame& f, const TruthScene& ts, const TruthJunction& t,
                                  double camera_x, int& unknown) {
  const Junction* hit = nullptr;
  for (const Junction& j : f.junctions) {
    bool known = false;
    for (const TruthJunction& any : ts.junctions) known = known || matches(j, any, camera_x);
    if (!known) ++unknown;
    if (matches(j, t, camera_x)) hit = &j;
  }
  return hit;
}

}  // namespace ceilnav::host::junction_test
