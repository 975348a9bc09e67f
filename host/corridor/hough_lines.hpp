// Lines from the hough block's accumulator (seed 002, learning stage steps
// 4-9 = matching steps 3-8, eq. 19-20), their sub-bin refinement, and their
// conversion from the distorted (raw) image the hardware votes on to the
// undistorted image of corridor_types.hpp. docs/corridor.md, "Lines,
// vanishing points and pan".
//
// The accumulator is the host's readout of one frame (docs/blocks/hough.md,
// "Readout"): cell (j, r) at index j * rho_bins + r, j the cell of the
// configured theta range (theta = (theta_first + j) * theta_step degrees),
// r the rho bin centred on r * 2^rho_shift - width pixels. golden::hough_ref
// returns exactly this vector (its rows past the range are 0).
#pragma once

#include <cstdint>
#include <vector>

#include "common/hough_params.hpp"
#include "host/camera_model.hpp"
#include "host/corridor/corridor_types.hpp"

namespace ceilnav::host::corridor {

struct Accumulator {
  stream::HoughShape shape;
  stream::HoughConfig config;
  std::vector<uint64_t> cells;  // shape.n_theta() x rho_bins, j-major

  int rows() const { return stream::theta_range(shape, config).count; }
  int bins() const { return static_cast<int>(shape.rho_bins()); }
  uint64_t at(int j, int r) const {
    return cells[static_cast<size_t>(j) * shape.rho_bins() + static_cast<size_t>(r)];
  }
  double theta_deg(double j) const {
    return (stream::theta_range(shape, config).first + j) * shape.theta_step;
  }
  double rho_px(double r) const {
    return r * static_cast<double>(1u << config.rho_shift) - config.width;
  }
  // True when the range covers all of [0, 180): the theta string wraps.
  bool full_circle() const { return rows() == shape.n_theta(); }
};

// The per-theta plateau marks of step 5 (eq. 19): mark[j] = some cell of row
// j holds k > max * c.
std::vector<bool> plateau_marks(const Accumulator& acc, uint64_t max, double c);

// Step 6: every run of one to three 0s with a 1 on both sides ("101",
// "1001", "10001") becomes 1s. With `wrap` the string is circular: the
// neighbour of the last theta is the first (theta 180 - step and 0 are
// neighbours: a line near vertical in the image has cells near theta 0 at
// rho and near theta 180 at -rho, one plateau across the end of the range).
void fill_holes(std::vector<bool>& marks, bool wrap);

// Step 7 (eq. 20): the rows [first, last] (circular when wrap: first > last
// means first..end, 0..last) to reset for the peak row j_max: the 1s run of
// `marks` containing j_max when it spans more than theta_range_deg, else
// j_max +- theta_range_deg / 2.
struct RowRange {
  int first = 0, last = 0;
};
RowRange plateau_rows(const Accumulator& acc, const std::vector<bool>& marks, int j_max,
                      double theta_range_deg, bool wrap);
// Resets every cell of the rows of `range` (circular when first > last).
void remove_rows(Accumulator& acc, const RowRange& range);

struct LineExtractionParams {
  double plateau_c = 0.8;            // c of eq. 19
  double theta_range_deg = 12.0;     // theta_range of eq. 20
  int max_lines = 8;                 // i of step 8 (the seed: 2)
  double min_strength_ratio = 0.25;  // stop when the max < this x the first max
  // Step 6 on a circular string when the range covers [0, 180) (see
  // fill_holes); false treats the ends as the string's ends, as the seed.
  bool wrap = true;
};

// One line of step 4: its peak cell and the sub-bin estimate.
struct HoughLine {
  int row = 0, bin = 0;  // the peak cell
  uint64_t votes = 0;    // its value (the "max" of step 4 in its round)
  ImageLine line;        // sub-bin theta and rho on the voted (raw) image; strength = votes
};

// Steps 4-8 on a copy of `acc`, then step 9 (ordered by theta). Each line
// is refined on the untouched accumulator (refine_peak).
std::vector<HoughLine> extract_lines(const Accumulator& acc, const LineExtractionParams& params);

// The sub-bin estimate of the line at peak cell (j, r), from the rows j - 1,
// j, j + 1: in each, the votes within two bins of the local maximum near
// the line's rho (their mass, mean and spread). theta from the spreads of
// the two neighbour rows (a segment's votes spread over a rho interval that
// grows as |t - theta|: theta = t_j + step (W- - W+) / (W- + W+), within
// half a row); rho from the sinusoid x cos t + y sin t of the segment's
// centroid fitted to the three rows' means, at that theta. Rows past the
// range's ends wrap (theta -+ 180, -rho) when it is a full circle, else the
// estimate is the peak row's theta and mean.
ImageLine refine_peak(const Accumulator& acc, int j, int r);

// A line of the distorted (raw) image to the undistorted one: its chord
// inside the frame [-0.5, W - 0.5) x [-0.5, H - 0.5) sampled at `samples`
// points, each undistorted (CameraModel::normalise, ideal_pixel), and the
// total-least-squares line through them. Exact without distortion. Returns
// false when the line misses the frame.
bool undistort_line(const ImageLine& raw, const CameraModel& camera, int width, int height,
                    ImageLine& out, int samples = 33);

}  // namespace ceilnav::host::corridor
