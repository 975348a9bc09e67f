#include "bench/hough_model.hpp"

#include "stream/hough.hpp"

namespace ceilnav::bench {

HoughModel::HoughModel(const stream::HoughShape& shape)
    : hough_(std::make_unique<stream::Hough>(shape)) {}
HoughModel::~HoughModel() = default;

void HoughModel::process_frame(const std::vector<uint64_t>& edges, uint64_t trailer,
                               const stream::HoughConfig& cfg) {
  hough_->process_frame(edges, trailer, cfg);
}
uint32_t HoughModel::votes() const {
  return hough_->counters().votes;
}
uint32_t HoughModel::dropped() const {
  return hough_->counters().dropped;
}
std::vector<uint32_t> HoughModel::results() const {
  return hough_->results();
}

}  // namespace ceilnav::bench
