#include "apps/overlay.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

#include <opencv2/imgproc.hpp>

namespace ceilnav::app {

namespace {

// Distance (normalised units) of the run centre from the fitted line.
double line_distance(const Eigen::Vector3d& l, const Eigen::Vector2d& xy) {
  const double n = std::hypot(l.x(), l.y());
  return n > 0 ? std::abs(l.x() * xy.x() + l.y() * xy.y() + l.z()) / n : 0.0;
}

}  // namespace

cv::Mat draw_overlay(const cv::Mat& grey, const host::FrameOutcome& o,
                     const host::CameraModel& cam) {
  cv::Mat bgr;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  const host::TapePose& p = o.pose;
  const bool have_line = p.status == host::Status::ok;
  const double gate_norm =
      p.residual_rms_px > 0 ? 4.0 * p.residual_rms_px / cam.fx() + 1e-3 : 1.5 / cam.fx();

  for (const auto& r : o.runs) {
    const double xc =
        r.sum_w > 0 ? static_cast<double>(r.sum_xw) / r.sum_w : 0.5 * (r.x_start + r.x_end);
    const Eigen::Vector2d xy = cam.normalise(xc, r.row);
    const bool used = have_line && line_distance(p.line_norm, xy) < gate_norm;
    const cv::Scalar colour = used ? cv::Scalar(0, 200, 0) : cv::Scalar(0, 0, 230);
    cv::line(bgr, {r.x_start, r.row}, {r.x_end, r.row}, colour, 1);
    cv::circle(bgr, {static_cast<int>(std::lround(xc)), r.row}, 1, cv::Scalar(255, 0, 255),
               cv::FILLED);
  }

  if (have_line) {
    // The line is straight in normalised coordinates; through the lens it may
    // bend, so draw it as a polyline of distorted points, one per 4 rows.
    std::vector<cv::Point> pts;
    const Eigen::Vector3d& l = p.line_norm;
    for (int v = 0; v < grey.rows; v += 4) {
      const Eigen::Vector2d xy0 = cam.normalise(cam.cx(), v);
      if (std::abs(l.x()) < 1e-12) break;
      const double y = xy0.y();
      const double x = -(l.y() * y + l.z()) / l.x();
      const Eigen::Vector2d px = cam.distort_to_pixel({x, y});
      if (std::isfinite(px.x()) && std::abs(px.x()) < 1e5) {
        pts.emplace_back(static_cast<int>(std::lround(px.x())),
                         static_cast<int>(std::lround(px.y())));
      }
    }
    if (pts.size() >= 2) cv::polylines(bgr, pts, false, cv::Scalar(0, 220, 255), 1, cv::LINE_AA);

    if (p.vp_finite) {
      const cv::Point2d vp(p.vp_u_px, p.vp_v_px);
      const cv::Rect frame(0, 0, grey.cols, grey.rows);
      if (vp.x >= 0 && vp.y >= 0 && vp.x < grey.cols && vp.y < grey.rows) {
        cv::drawMarker(bgr, cv::Point(static_cast<int>(vp.x), static_cast<int>(vp.y)),
                       cv::Scalar(255, 255, 0), cv::MARKER_CROSS, 15, 2);
      } else {
        // Arrow from the image centre towards the vanishing point, ending at the border.
        const cv::Point2d c(grey.cols / 2.0, grey.rows / 2.0);
        cv::Point2d d = vp - c;
        const double s = std::min(std::abs((grey.cols / 2.0 - 4) / (d.x == 0 ? 1e-9 : d.x)),
                                  std::abs((grey.rows / 2.0 - 4) / (d.y == 0 ? 1e-9 : d.y)));
        const cv::Point2d end = c + d * std::min(1.0, s);
        cv::arrowedLine(bgr, c, end, cv::Scalar(255, 255, 0), 2, cv::LINE_AA, 0, 0.05);
      }
      if (p.vp_v_px >= 0 && p.vp_v_px < grey.rows) {
        const int hv = static_cast<int>(std::lround(p.vp_v_px));
        cv::line(bgr, {0, hv}, {grey.cols - 1, hv}, cv::Scalar(255, 80, 0), 1);
      }
    }
  }

  char text[160];
  if (have_line) {
    std::snprintf(text, sizeof text, "yaw %.3f deg  offset %.1f mm  VP (%.1f, %.1f)  pts %d",
                  p.yaw_rad * 180.0 / std::numbers::pi, p.offset_m * 1000.0, p.vp_u_px, p.vp_v_px,
                  p.points_used);
  } else {
    std::snprintf(text, sizeof text, "status %s", std::string(host::to_string(p.status)).c_str());
  }
  cv::putText(bgr, text, {6, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 3,
              cv::LINE_AA);
  cv::putText(bgr, text, {6, 16}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return bgr;
}

}  // namespace ceilnav::app
