// The ceiling's height above the camera, per zone of the map, fused from the
// map's height and the vision's two measurements of it (seed 000): the tape's
// image width (host::ceiling_height_from_tape_width, no odometry) and the
// optic flow of a tape end against the odometry (host::FlowTrack, eq. 44 and
// 57). docs/navigation.md, "Ceiling height".
//
// Each source has an error shared by all its measurements, relative to the
// height: the width method scales with the configured tape width (and a blur
// or plateau bias), the flow with the odometry's distance scale. Averaging
// frames cannot remove it, so each is a state. The state is
//   (beta_width, beta_flow, h_1 .. h_Z)
// with one h per zone seen (zone keys are the caller's, e.g. the map zone's
// index, -1 for the default ceiling), and the measurements are
//   z_width = h_k (1 + beta_width) + e,   z_flow = h_k (1 + beta_flow) + e,
// linearised at the estimate (an EKF; the betas are a few per mille, so the
// second-order term h beta is far below the noise). A zone's h starts at
// the map's height with a relative sigma; heights do not change with time
// (no process noise). Without any measurement the estimate is the map's.
#pragma once

#include <map>

#include <Eigen/Core>

namespace ceilnav::nav {

struct CeilingHeightOptions {
  double map_sigma_fraction = 0.02;    // the map's height: relative sigma of its survey
  double width_bias_fraction = 0.003;  // the width method's shared error (tape width, blur)
  double flow_bias_fraction = 0.01;    // the flow's: the odometry's distance scale
  double gate_probability = 0.999;     // chi-square(1) innovation gate
};

class CeilingHeightFilter {
 public:
  enum class Source { width, flow };
  struct Estimate {
    double height_m = 0.0;  // ceiling above the camera
    double sigma_m = 0.0;
    int updates = 0;  // measurements of this zone accepted
  };
  struct Counters {
    int width_accepted = 0, width_rejected = 0;
    int flow_accepted = 0, flow_rejected = 0;
  };

  explicit CeilingHeightFilter(const CeilingHeightOptions& options = {});

  // The estimate for `zone`; `map_height_m` (ceiling above the camera from
  // the map) starts it on first use.
  Estimate estimate(int zone, double map_height_m);
  // A measurement of zone `zone` (height above the camera, its white sigma);
  // false when the gate rejects it (the filter is unchanged).
  bool update(int zone, double map_height_m, Source source, double z_m, double sigma_m);

  double width_bias() const { return x_(0); }
  double flow_bias() const { return x_(1); }
  const Counters& counters() const { return counters_; }

 private:
  int index_of(int zone, double map_height_m);
  CeilingHeightOptions opt_;
  Eigen::VectorXd x_;
  Eigen::MatrixXd p_;
  std::map<int, int> zone_index_;  // zone key -> state index
  std::map<int, int> updates_;
  Counters counters_;
  double gate_ = 0.0;
};

}  // namespace ceilnav::nav
