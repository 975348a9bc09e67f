#include "stream/edge_hough_fast.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "fixedpoint/datapath.hpp"
#include "fixedpoint/hough_trig.hpp"

namespace ceilnav::stream {

namespace {

// The compaction reads eight 0/1 bytes as one word, the first pixel in the
// low byte.
static_assert(std::endian::native == std::endian::little);

constexpr uint32_t kMaxSide = fp::datapath::kMaxWidth;  // 2048
constexpr int kFrac = fp::hough::kTrigFrac;
// Interleaved copies of the rho row a theta votes into (edge i -> copy i % 4).
constexpr size_t kCopies = 4;
// Edges per block of the voter: 1024 x (8 + 8 + 4) bytes of coordinates,
// weights and indices, within L1.
constexpr size_t kBlock = 1024;

size_t padded(uint32_t width) {
  return (size_t{width} + 7u) / 8u * 8u;
}

// d = cur[i] - prev[i] for i < n: |d|, d > 0 and |d| > t, no branch.
void difference_row(const uint8_t* cur, const uint8_t* prev, int n, int16_t t, int16_t* mag,
                    uint8_t* rises, uint8_t* hit) {
  for (int i = 0; i < n; ++i) {
    const auto d = static_cast<int16_t>(cur[i] - prev[i]);
    const auto m = static_cast<int16_t>(d < 0 ? -d : d);
    mag[i] = m;
    rises[i] = d > 0;
    hit[i] = m > t;
  }
}

}  // namespace

EdgeHoughFast::EdgeHoughFast(const HoughShape& shape) : shape_(shape) {
  if (shape_.theta_step < 1 || 180 % shape_.theta_step != 0 || shape_.rho_bits < 1 ||
      shape_.rho_bits > 12) {
    throw std::invalid_argument("EdgeHoughFast: bad shape");
  }
  acc_.assign(static_cast<size_t>(shape_.n_theta()) * shape_.rho_bins(), 0u);
  rows_.assign(static_cast<size_t>(shape_.n_theta()) * kCopies * (shape_.rho_bins() + 1u), 0u);
  idx_.resize(kBlock);
  w_.resize(kBlock);
}

void EdgeHoughFast::reserve(uint32_t width, uint32_t height) {
  const size_t pixels = size_t{width} * height;
  if (records_.size() < pixels) {
    records_.resize(pixels);
    xs_.resize(pixels);
    ys_.resize(pixels);
  }
  const size_t row = padded(width);
  if (hit_.size() < row) {
    mag_.resize(row);
    rises_.resize(row);
    hit_.resize(row);
    tmp_.resize(row);
    tmp2_.resize(row);
  }
}

std::span<const EdgeRecord> EdgeHoughFast::find_edges(const EdgeConfig& cfg, const uint8_t* remap,
                                                      uint32_t width, uint32_t height,
                                                      size_t stride) {
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide || stride < width) {
    throw std::invalid_argument("EdgeHoughFast::find_edges: bad frame size");
  }
  reserve(width, height);
  n_edges_ = 0;
  // Every magnitude is <= 2040, so a threshold past 4095 finds what 4095 does
  // and the compare fits 16 bits.
  const auto t = static_cast<int16_t>(std::min<int>(cfg.threshold, 4095));
  const auto w = static_cast<int>(width);
  int16_t* mag = mag_.data();
  uint8_t* rises = rises_.data();
  uint8_t* hit = hit_.data();
  std::fill(hit_.begin() + w, hit_.begin() + static_cast<std::ptrdiff_t>(padded(width)), 0);

  EdgeKind kind = EdgeKind::kHorizontal;
  uint32_t y_first = 0;  // rows (centre rows for Sobel) that can hold edge points
  uint32_t y_end = height;
  switch (cfg.mode) {
    case EdgeMode::kHorizontal:
      if (width < 2) return edges();
      break;
    case EdgeMode::kVertical:
      kind = EdgeKind::kVertical;
      y_first = 1;
      break;
    case EdgeMode::kSobel:
      if (width < 3 || height < 3) return edges();
      kind = EdgeKind::kSobel;
      y_first = 1;
      y_end = height - 1;
      break;
    case EdgeMode::kReserved:
      return edges();
  }

  for (uint32_t y = y_first; y < y_end; ++y) {
    const uint8_t* r = remap + size_t{y} * stride;
    // The row's magnitudes, rises and hits, with no branch per pixel.
    switch (cfg.mode) {
      case EdgeMode::kHorizontal:
        // |p(x,y) - p(x-1,y)|, x >= 1
        hit[0] = 0;
        difference_row(r + 1, r, w - 1, t, mag + 1, rises + 1, hit + 1);
        break;
      case EdgeMode::kVertical:
        // |p(x,y) - p(x,y-1)|, y >= 1
        difference_row(r, r - stride, w, t, mag, rises, hit);
        break;
      case EdgeMode::kSobel: {
        // Centre row y: rows a = y-1, b = y, c = y+1. Per column the 1 2 1
        // sum v = a + 2b + c (for gx) and the difference e = c - a (for gy);
        // gx = v(x+1) - v(x-1), gy = e(x-1) + 2 e(x) + e(x+1).
        const uint8_t* a = r - stride;
        const uint8_t* c = r + stride;
        int16_t* v = tmp_.data();
        int16_t* e = tmp2_.data();
        for (int x = 0; x < w; ++x) {
          v[x] = static_cast<int16_t>(a[x] + 2 * r[x] + c[x]);
          e[x] = static_cast<int16_t>(c[x] - a[x]);
        }
        hit[0] = 0;
        hit[w - 1] = 0;
        for (int x = 1; x < w - 1; ++x) {
          const auto gx = static_cast<int16_t>(v[x + 1] - v[x - 1]);
          const auto gy = static_cast<int16_t>(e[x - 1] + 2 * e[x] + e[x + 1]);
          // |gx| + |gy| <= 2040: the 4095 clip of the 12-bit field never acts.
          const auto m = static_cast<int16_t>((gx < 0 ? -gx : gx) + (gy < 0 ? -gy : gy));
          mag[x] = m;
          rises[x] = gx > 0;
          hit[x] = m > t;
        }
        break;
      }
      case EdgeMode::kReserved:
        break;
    }
    // Compaction: eight hit bytes per word; only words with a hit loop.
    EdgeRecord* out = records_.data() + n_edges_;
    int32_t* ox = xs_.data() + n_edges_;
    int32_t* oy = ys_.data() + n_edges_;
    size_t n = 0;
    const auto yy = static_cast<uint16_t>(y);
    for (int x0 = 0; x0 < w; x0 += 8) {
      uint64_t m = 0;
      std::memcpy(&m, hit + x0, sizeof m);
      while (m != 0) {
        const int x = x0 + (std::countr_zero(m) >> 3);
        m &= m - 1;
        out[n] = {static_cast<uint16_t>(x), yy, static_cast<uint16_t>(mag[x]), rises[x] != 0, kind};
        ox[n] = x;
        oy[n] = static_cast<int32_t>(y);
        ++n;
      }
    }
    n_edges_ += n;
  }
  return edges();
}

std::span<const uint64_t> EdgeHoughFast::vote(const HoughConfig& cfg) {
  std::fill(acc_.begin(), acc_.end(), 0u);
  votes_ = 0;
  dropped_ = 0;
  if (!cfg.enable) return accumulator();
  if (cfg.weight_shift > 15 || cfg.rho_shift > 7 || cfg.width > 4095) {
    throw std::invalid_argument("EdgeHoughFast::vote: configuration outside the register ranges");
  }
  const size_t n = n_edges_;
  const uint32_t bins = shape_.rho_bins();
  const ThetaRange range = theta_range(shape_, cfg);
  const auto& table = fp::hough::trig_table();

  // rho index = (x C + y S + (W << 14) + 2^(13 + rho_shift)) >> (14 + rho_shift),
  // floor (arithmetic shift); |sum| < 2^28 fits int32. A negative index or
  // one >= bins goes to the spare cell `bins` of the row copies.
  const int32_t bias = (int32_t{cfg.width} << kFrac) + (int32_t{1} << (kFrac - 1 + cfg.rho_shift));
  const int shift = kFrac + cfg.rho_shift;
  const size_t row_len = bins + 1u;
  const size_t theta_len = kCopies * row_len;  // the copies of one theta's row
  std::fill_n(rows_.begin(), static_cast<size_t>(range.count) * theta_len, 0u);
  uint64_t* w = w_.data();
  uint32_t* idx = idx_.data();
  uint64_t landed = 0;
  // Blocks of kBlock edges: their coordinates, weights and indices stay in
  // L1 while every theta of the range votes them.
  for (size_t b0 = 0; b0 < n; b0 += kBlock) {
    const size_t nb = std::min(kBlock, n - b0);
    const int32_t* xs = xs_.data() + b0;
    const int32_t* ys = ys_.data() + b0;
    // eq. 18 weights: w = (y + 1) >> weight_shift, or 1.
    for (size_t i = 0; i < nb; ++i) {
      w[i] = cfg.unit_weight ? 1u : static_cast<uint64_t>((ys[i] + 1) >> cfg.weight_shift);
    }
    for (int j = 0; j < range.count; ++j) {
      const auto k = static_cast<size_t>((range.first + j) * shape_.theta_step);
      const int32_t c = table.cos[k];
      const int32_t s = table.sin[k];
      uint32_t in_block = 0;
      for (size_t i = 0; i < nb; ++i) {
        const int32_t sum = xs[i] * c + ys[i] * s + bias;
        const auto r = static_cast<uint32_t>(sum >> shift);  // negative -> >= 2^31
        const uint32_t in = r < bins ? 1u : 0u;
        in_block += in;
        idx[i] = in != 0 ? r : bins;
      }
      landed += in_block;
      uint64_t* r0 = rows_.data() + static_cast<size_t>(j) * theta_len;
      uint64_t* r1 = r0 + row_len;
      uint64_t* r2 = r1 + row_len;
      uint64_t* r3 = r2 + row_len;
      size_t i = 0;
      for (; i + kCopies <= nb; i += kCopies) {
        r0[idx[i]] += w[i];
        r1[idx[i + 1]] += w[i + 1];
        r2[idx[i + 2]] += w[i + 2];
        r3[idx[i + 3]] += w[i + 3];
      }
      for (; i < nb; ++i) r0[idx[i]] += w[i];
    }
  }
  for (int j = 0; j < range.count; ++j) {
    const uint64_t* r0 = rows_.data() + static_cast<size_t>(j) * theta_len;
    const uint64_t* r1 = r0 + row_len;
    const uint64_t* r2 = r1 + row_len;
    const uint64_t* r3 = r2 + row_len;
    uint64_t* out = acc_.data() + static_cast<size_t>(j) * bins;
    for (uint32_t b = 0; b < bins; ++b) out[b] = r0[b] + r1[b] + r2[b] + r3[b];
  }
  votes_ = landed;
  dropped_ = n * static_cast<uint64_t>(range.count) - landed;
  return accumulator();
}

}  // namespace ceilnav::stream
