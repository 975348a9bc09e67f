// The real-image corpus (testdata/real/README.md: ceiling lights and photos,
// no tape) through the Navigator and host::detect_junctions, as `ceilnav run`
// does (one navigator per sequence): no centre line is ok and no junction is
// claimed, on the default camera at pitch 45 and 90 deg and on the cycloid
// car's camera at its own pitch.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "drivers/device.hpp"
#include "host/camera_config_io.hpp"
#include "host/junction.hpp"
#include "host/navigator.hpp"
#include "real_corpus.hpp"

namespace ceilnav::host {
namespace {

namespace ts = ceilnav::test_support;

TEST(JunctionRealCorpus, NoJunction) {
  const std::vector<ts::RealFrame> frames = ts::load_real_corpus();
  ASSERT_GE(frames.size(), 280u);
  std::vector<std::pair<std::string, CameraConfig>> setups;
  for (double pitch : {45.0, 90.0}) {
    CameraConfig c;
    c.camera_pitch_deg = pitch;
    setups.emplace_back("default camera, pitch " + std::to_string(static_cast<int>(pitch)), c);
  }
  setups.emplace_back(
      "cycloid camera, own pitch",
      load_camera_config((ts::real_corpus_dir() / "cycloid_ceiltrack" / "camera.yaml").string()));
  for (const auto& [name, cam] : setups) {
    std::map<std::string, std::unique_ptr<Navigator>> navs;  // one per set: a sequence each
    int checked = 0;
    for (const ts::RealFrame& f : frames) {
      const std::string set = f.name.substr(0, f.name.find('/'));
      auto& nav = navs[set];
      if (!nav) nav = std::make_unique<Navigator>(cam, drivers::make_device());
      const FrameOutcome r = nav->process(f.grey);
      EXPECT_NE(r.pose.status, Status::ok) << name << ": " << f.name;
      const std::vector<Junction> js = detect_junctions(r, nav->camera_model(), cam);
      EXPECT_TRUE(js.empty()) << name << ": " << f.name << ": " << to_string(js.front().kind);
      ++checked;
    }
    std::printf("%-32s %d frames, no junction\n", name.c_str(), checked);
  }
}

}  // namespace
}  // namespace ceilnav::host
