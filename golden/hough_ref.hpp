// Golden reference of hough (seed 002 step 3, eq. 18): the weighted Hough
// accumulator computed directly, theta by theta, from the edge list, with the
// block's quantised cos/sin table (fixedpoint/hough_trig.hpp), so that its
// cells equal the block's exactly (docs/blocks/hough.md). Also the same
// transform with unquantised double trigonometry, and cv::HoughLines, to show
// that the quantisation moves no peak by more than one bin.
#pragma once

#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "common/edge_record.hpp"
#include "common/hough_params.hpp"

namespace ceilnav::golden {

struct EdgePoint {
  uint16_t x = 0;
  uint16_t y = 0;
};

// Unsaturated cell sums, j-major (n_theta x rho_bins); cells of thetas outside
// the configured range are 0. A disabled config gives all zeros.
std::vector<uint64_t> hough_ref(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                                const std::vector<EdgePoint>& edges);

// The cells as the hough block holds them for the edge points of an edge
// detector (golden::find_edges_ref, stream::EdgeDetector): hough_ref on their
// (x, y), each saturated at shape.acc_max().
std::vector<uint32_t> hough_cells_ref(const stream::HoughShape& shape,
                                      const stream::HoughConfig& cfg,
                                      const std::vector<stream::EdgeRecord>& edges);
// The same with cos and sin in double precision and the rho index
// floor((x cos + y sin + W) / 2^rho_shift + 1/2).
std::vector<uint64_t> hough_ref_double(const stream::HoughShape& shape,
                                       const stream::HoughConfig& cfg,
                                       const std::vector<EdgePoint>& edges);

// The pixels of the line x cos(theta) + y sin(theta) = rho inside w x h: one
// per column (or per row, for a steep line), rounded to the nearest pixel.
std::vector<EdgePoint> line_points(double rho, double theta_deg, int w, int h);

struct HoughPeak {
  double rho = 0.0;    // pixels (the centre of the bin: index * 2^rho_shift - W)
  double theta = 0.0;  // radians
  uint64_t votes = 0;
};

// The largest cell of an accumulator of hough_ref (ties: the lowest index).
HoughPeak hough_peak(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                     const std::vector<uint64_t>& acc);

// cv::HoughLines on a CV_8UC1 image with the edge points set, rho step
// 2^rho_shift, theta step of the shape over [0, 180): the strongest line.
HoughPeak opencv_strongest_line(const stream::HoughShape& shape, const stream::HoughConfig& cfg,
                                const std::vector<EdgePoint>& edges, int width, int height);

}  // namespace ceilnav::golden
