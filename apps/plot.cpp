#include "apps/plot.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include <fmt/format.h>

#include "apps/atomic_file.hpp"

namespace ceilnav::app {

namespace fs = std::filesystem;

namespace {

// A gnuplot string literal: single quotes, a quote doubled.
std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += '\'';
    q += c;
  }
  return q + "'";
}

std::string rgb(const cv::Scalar& bgr) {
  const auto c = [](double v) { return static_cast<int>(std::lround(std::clamp(v, 0.0, 255.0))); };
  return fmt::format("#{:02x}{:02x}{:02x}", c(bgr[2]), c(bgr[1]), c(bgr[0]));
}

// The shell word of a path (single-quoted).
std::string shell_word(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

bool program_found(const std::string& program) {
  const std::string cmd = "command -v " + shell_word(program) + " >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

void write_text(const fs::path& path, const std::string& text) {
  AtomicFile file(path);
  file.stream() << text;
  file.commit();
}

void write_data(const fs::path& dat, const std::vector<PlotPanel>& panels) {
  AtomicFile file(dat);
  std::ostream& out = file.stream();
  bool first = true;
  for (size_t p = 0; p < panels.size(); ++p) {
    for (const PlotSeries& s : panels[p].series) {
      if (s.x.size() != s.y.size()) {
        throw std::runtime_error("plot series '" + s.label + "': x and y differ in length");
      }
      if (!first) out << "\n\n";
      first = false;
      out << "# panel " << p + 1 << " (" << panels[p].title << "): " << s.label << "\n";
      for (size_t i = 0; i < s.x.size(); ++i) {
        if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
        out << fmt::format("{:.10g} {:.10g}\n", s.x[i], s.y[i]);
      }
    }
  }
  file.commit();
}

// Autoscaled ("[0:*]" from zero), unless the data span nothing (one point, a
// constant), where gnuplot would warn and pick a range itself.
std::string axis_range(const char* axis, const std::vector<PlotSeries>& series, bool x_axis,
                       bool from_zero) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const PlotSeries& s : series) {
    for (double v : x_axis ? s.x : s.y) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(hi >= lo)) return fmt::format("set {}range [-1:1]\n", axis);  // no data
  if (from_zero) lo = 0.0;
  if (hi > lo) return fmt::format("set {}range [{}:*]\n", axis, from_zero ? "0" : "*");
  const double pad = lo == 0.0 ? 1.0 : std::abs(lo) * 0.5;
  return fmt::format("set {}range [{:.10g}:{:.10g}]\n", axis, from_zero ? 0.0 : lo - pad, hi + pad);
}

// A PNG written to the end: its last chunk is IEND. gnuplot does not report a
// failed write (full disk, file size limit) in its exit status.
bool complete_png(const fs::path& path) {
  static constexpr std::string_view kHead("\x89PNG\r\n\x1a\n", 8);
  static constexpr std::string_view kEnd("\0\0\0\0IEND\xae\x42\x60\x82", 12);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return false;
  const std::streamoff size = in.tellg();
  if (size < 20) return false;
  char head[8], tail[12];
  in.seekg(0);
  in.read(head, 8);
  in.seekg(size - 12);
  in.read(tail, 12);
  return in && std::string_view(head, 8) == kHead && std::string_view(tail, 12) == kEnd;
}

std::string script(const fs::path& png, const fs::path& dat, const std::vector<PlotPanel>& panels,
                   int width, int panel_height) {
  std::string gp;
  gp += fmt::format("set terminal pngcairo noenhanced size {},{} font 'sans,10'\n", width,
                    panel_height * static_cast<int>(panels.size()));
  gp += "set output " + quoted(png.string()) + "\n";
  gp += fmt::format("set multiplot layout {},1\n", panels.size());
  gp += "set grid lc rgb '#e1e1e1'\nset key top right opaque box spacing 1.4\n";
  int index = 0;
  for (const PlotPanel& panel : panels) {
    bool non_negative = true;
    for (const PlotSeries& s : panel.series) {
      for (double v : s.y) non_negative = non_negative && (!std::isfinite(v) || v >= 0);
    }
    const bool from_zero = panel.y_from_zero && non_negative;
    gp += "set title " + quoted(panel.title) + "\n";
    gp += "set xlabel " + quoted(panel.x_label) + "\n";
    gp += "set ylabel " + quoted(panel.y_label) + "\n";
    gp += axis_range("x", panel.series, true, false);
    gp += axis_range("y", panel.series, false, from_zero);
    // Head room above the data for the key; none below a zero floor.
    gp +=
        fmt::format("set offsets 0, 0, graph {:.2f}, graph {:.2f}\n",
                    0.1 + 0.08 * static_cast<double>(panel.series.size()), from_zero ? 0.0 : 0.05);
    gp += "plot ";
    for (size_t k = 0; k < panel.series.size(); ++k) {
      const PlotSeries& s = panel.series[k];
      if (k > 0) gp += ", \\\n     ";
      gp += fmt::format(
          "{} index {} using 1:2 with linespoints lw 2 dt {} pt 7 ps 0.6 lc rgb '{}' title {}",
          quoted(dat.filename().string()), index++, k + 1, rgb(s.colour), quoted(s.label));
    }
    gp += "\n";
  }
  gp += "unset multiplot\n";
  return gp;
}

}  // namespace

void write_plots(const fs::path& png, const std::vector<PlotPanel>& panels, int width,
                 int panel_height, const std::string& gnuplot) {
  if (panels.empty()) throw std::runtime_error("write_plots: no panels");
  if (!program_found(gnuplot)) {
    throw std::runtime_error("cannot draw '" + png.string() + "': the program '" + gnuplot +
                             "' was not found (install the Debian package gnuplot-nox)");
  }
  fs::path dat = png, gp_path = png, tmp = png;
  dat.replace_extension(".dat");
  gp_path.replace_extension(".gp");
  tmp += ".tmp";
  write_data(dat, panels);
  // The script names the data file relative to its own folder, and gnuplot
  // runs there, so the three files can be moved together.
  write_text(gp_path, script(png.filename().string() + ".tmp", dat, panels, width, panel_height));
  const fs::path dir = png.has_parent_path() ? png.parent_path() : fs::path(".");
  const std::string cmd = "cd " + shell_word(dir.string()) + " && " + shell_word(gnuplot) + " " +
                          shell_word(gp_path.filename().string());
  const int status = std::system(cmd.c_str());
  std::error_code ec;
  if (status != 0) {
    fs::remove(tmp, ec);
    throw std::runtime_error("gnuplot failed to draw '" + png.string() + "' from '" +
                             gp_path.string() + "' (exit status " +
                             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")");
  }
  if (!complete_png(tmp)) {
    fs::remove(tmp, ec);
    throw std::runtime_error("error while writing '" + png.string() +
                             "': gnuplot left an incomplete PNG");
  }
  fs::rename(tmp, png);
  // The script as kept names the PNG itself, so running it by hand redraws it.
  write_text(gp_path, script(png.filename(), dat, panels, width, panel_height));
}

}  // namespace ceilnav::app
