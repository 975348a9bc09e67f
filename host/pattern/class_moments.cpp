#include "host/pattern/class_moments.hpp"

#include <algorithm>

namespace ceilnav::host::pattern {

FrameMoments device_moments(const stream::ClassMomentResults& r) {
  FrameMoments out{};
  for (int c = 1; c < kClasses; ++c) {
    const auto& m = r.of(c);
    auto as_int = [](uint64_t v) { return static_cast<int64_t>(v); };
    out[static_cast<std::size_t>(c)] = {as_int(m[stream::kM00]), as_int(m[stream::kM10]),
                                        as_int(m[stream::kM01]), as_int(m[stream::kM20]),
                                        as_int(m[stream::kM11]), as_int(m[stream::kM02])};
  }
  return out;
}

Extents disc_extents_from_runs(std::span<const stream::RunRecord> disc_runs) {
  Extents e;
  bool any = false;
  for (const auto& r : disc_runs) {
    if (!any) {
      e = {r.x_start, r.x_end, r.row, r.row};
      any = true;
      continue;
    }
    e.u_min = std::min<int>(e.u_min, r.x_start);
    e.u_max = std::max<int>(e.u_max, r.x_end);
    e.v_min = std::min<int>(e.v_min, r.row);
    e.v_max = std::max<int>(e.v_max, r.row);
  }
  return e;
}

FrameMoments class_moments(const uint8_t* classes, int width, int height, std::size_t stride) {
  FrameMoments m{};
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = classes + static_cast<std::size_t>(y) * stride;
    std::array<int64_t, kClasses> n{}, sx{}, sxx{};
    for (int x = 0; x < width; ++x) {
      const unsigned c = row[x];
      if (c >= kClasses) continue;
      ++n[c];
      sx[c] += x;
      sxx[c] += static_cast<int64_t>(x) * x;
    }
    for (std::size_t c = 0; c < kClasses; ++c) {
      m[c].m00 += n[c];
      m[c].m10 += sx[c];
      m[c].m01 += n[c] * y;
      m[c].m20 += sxx[c];
      m[c].m11 += sx[c] * y;
      m[c].m02 += n[c] * static_cast<int64_t>(y) * y;
    }
  }
  return m;
}

Extents class_extents(const uint8_t* classes, int width, int height, std::size_t stride, int cls) {
  Extents e{width, -1, height, -1};
  for (int y = 0; y < height; ++y) {
    const uint8_t* row = classes + static_cast<std::size_t>(y) * stride;
    for (int x = 0; x < width; ++x) {
      if (row[x] != cls) continue;
      e.u_min = std::min(e.u_min, x);
      e.u_max = std::max(e.u_max, x);
      e.v_min = std::min(e.v_min, y);
      e.v_max = std::max(e.v_max, y);
    }
  }
  if (e.u_max < 0) return Extents{};
  return e;
}

}  // namespace ceilnav::host::pattern
