// The tape path on the real-image corpus (testdata/real/README.md): frames of
// ceiling lights and ordinary photos, none showing tape. Every frame through
// the Navigator, as `ceilnav run` does (one navigator per sequence), on the
// default camera at pitch 45 and 90 deg and on the cycloid car's camera at
// pitch 45, its own 68 and 90 deg: no centre-line and no zenith result may be
// `ok`. Statuses per configuration are printed (docs/results.md, real corpus).
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "drivers/device.hpp"
#include "host/camera_config_io.hpp"
#include "host/navigator.hpp"
#include "real_corpus.hpp"

namespace ceilnav::host {
namespace {

namespace ts = ceilnav::test_support;

struct CameraSetup {
  std::string name;
  CameraConfig camera;
};

std::vector<CameraSetup> setups() {
  std::vector<CameraSetup> out;
  for (double pitch : {45.0, 90.0}) {
    CameraConfig c;  // the default camera: 640x480, f = 500 px
    c.camera_pitch_deg = pitch;
    out.push_back({"default camera, pitch " + std::to_string(static_cast<int>(pitch)), c});
  }
  const CameraConfig cycloid =
      load_camera_config((ts::real_corpus_dir() / "cycloid_ceiltrack" / "camera.yaml").string());
  for (double pitch : {45.0, cycloid.camera_pitch_deg, 90.0}) {
    CameraConfig c = cycloid;
    c.camera_pitch_deg = pitch;
    out.push_back(
        {"cycloid camera (f = 189 px), pitch " + std::to_string(static_cast<int>(pitch)), c});
  }
  return out;
}

TEST(TapeRealCorpus, NoFrameIsOk) {
  const std::vector<ts::RealFrame> frames = ts::load_real_corpus();
  ASSERT_GE(frames.size(), 280u);
  for (const CameraSetup& s : setups()) {
    std::map<std::string, int> statuses, zenith_statuses;
    std::map<std::string, std::unique_ptr<Navigator>> navs;  // one per set: a sequence each
    for (const ts::RealFrame& f : frames) {
      const std::string set = f.name.substr(0, f.name.find('/'));
      auto& nav = navs[set];
      if (!nav) nav = std::make_unique<Navigator>(s.camera, drivers::make_device());
      const FrameOutcome r = nav->process(f.grey);
      ++statuses[std::string(to_string(r.pose.status))];
      EXPECT_NE(r.pose.status, Status::ok)
          << s.name << ": " << f.name << " yaw " << r.pose.yaw_rad << " offset " << r.pose.offset_m;
      if (s.camera.camera_pitch_deg < 89.999) {
        EXPECT_FALSE(r.zenith.has_value()) << s.name;
      }
      if (r.zenith) {
        ++zenith_statuses[std::string(to_string(r.zenith->status))];
        EXPECT_NE(r.zenith->status, Status::ok) << s.name << ": zenith, " << f.name;
      }
    }
    std::printf("%-40s centre line:", s.name.c_str());
    for (const auto& [st, n] : statuses) std::printf(" %s %d", st.c_str(), n);
    if (!zenith_statuses.empty()) {
      std::printf("; zenith:");
      for (const auto& [st, n] : zenith_statuses) std::printf(" %s %d", st.c_str(), n);
    }
    std::printf("\n");
  }
}

}  // namespace
}  // namespace ceilnav::host
