// stream::Hough behind a header of its own: stream/hough.hpp and
// stream/edge.hpp each define a stream::EdgeBeat (the block's input and the
// edge detector's output), so no translation unit includes both.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "common/hough_params.hpp"

namespace ceilnav::stream {
class Hough;
}

namespace ceilnav::bench {

class HoughModel {
 public:
  explicit HoughModel(const stream::HoughShape& shape = stream::HoughShape{});
  ~HoughModel();
  HoughModel(const HoughModel&) = delete;
  HoughModel& operator=(const HoughModel&) = delete;

  // stream::Hough::process_frame.
  void process_frame(const std::vector<uint64_t>& edges, uint64_t trailer,
                     const stream::HoughConfig& cfg);
  uint32_t votes() const;  // the published frame's counters
  uint32_t dropped() const;
  std::vector<uint32_t> results() const;

 private:
  std::unique_ptr<stream::Hough> hough_;
};

}  // namespace ceilnav::bench
