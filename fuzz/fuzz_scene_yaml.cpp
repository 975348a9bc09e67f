// Fuzz target: the scene YAML reader (host::load_camera_config) on arbitrary
// file contents. The reader picks pugixml for XML and yaml-cpp for YAML and
// JSON from the contents, so all three are reached.
//
// Invariants (docs/fuzzing.md):
//  * the reader returns a config or throws host::ConfigError; any other
//    exception escaping it is a bug;
//  * a returned config passes validate_camera_config and has only finite
//    fields;
//  * it survives the round trip save_camera_config -> load_camera_config
//    exactly (the writer's documented contract);
//  * the camera model can be built from it (the inverse-distortion table is
//    computed over the whole image); without distortion it maps the
//    principal point to (0, 0) exactly.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

#include "fuzz/check.hpp"
#include "fuzz/temp_file.hpp"
#include "host/camera_config_io.hpp"
#include "host/camera_model.hpp"

namespace {

bool same_config(const ceilnav::host::CameraConfig& a, const ceilnav::host::CameraConfig& b) {
  return a.image_width == b.image_width && a.image_height == b.image_height &&
         a.camera_matrix == b.camera_matrix &&
         a.distortion_coefficients == b.distortion_coefficients &&
         a.camera_pitch_deg == b.camera_pitch_deg && a.camera_height_m == b.camera_height_m &&
         a.ceiling_height_m == b.ceiling_height_m && a.tape_width_m == b.tape_width_m;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace ceilnav;
  static fuzz::TempFile input(".yaml");
  static fuzz::TempFile copy(".yaml");
  host::CameraConfig cfg;
  try {
    cfg = host::load_camera_config(input.write(data, size));
  } catch (const host::ConfigError& e) {
    if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) std::printf("refused: %s\n", e.what());
    return 0;  // refused with a message: fine
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "load_camera_config let a non-ConfigError escape: %s", e.what());
  }
  if (std::getenv("CEILNAV_FUZZ_VERBOSE") != nullptr) {
    std::printf("loaded %dx%d, fx %g\n", cfg.image_width, cfg.image_height, cfg.fx());
  }
  for (double v : cfg.camera_matrix) FUZZ_CHECK(std::isfinite(v), "non-finite camera_matrix");
  for (double v : cfg.distortion_coefficients) {
    FUZZ_CHECK(std::isfinite(v), "non-finite distortion coefficient");
  }
  try {
    host::validate_camera_config(cfg, "fuzz");
  } catch (const host::ConfigError& e) {
    FUZZ_CHECK(false, "a loaded config fails validation: %s", e.what());
  }
  try {
    host::save_camera_config(cfg, copy.path());
    const host::CameraConfig again = host::load_camera_config(copy.path());
    FUZZ_CHECK(same_config(cfg, again), "save -> load round trip changed the config");
  } catch (const std::exception& e) {
    FUZZ_CHECK(false, "save -> load of a loaded config failed: %s", e.what());
  }
  const host::CameraModel cam(cfg);
  const auto centre = cam.normalise(cfg.cx(), cfg.cy());
  FUZZ_CHECK(cam.has_distortion() || (centre.x() == 0.0 && centre.y() == 0.0),
             "the principal point does not normalise to (0, 0): (%g, %g)", centre.x(), centre.y());
  return 0;
}
