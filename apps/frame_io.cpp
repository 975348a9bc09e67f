#include "apps/frame_io.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace ceilnav::app {
namespace fs = std::filesystem;

std::vector<fs::path> list_png_frames(const fs::path& folder) {
  std::error_code ec;
  if (!fs::exists(folder, ec)) {
    throw InputError("frames folder '" + folder.string() + "' does not exist");
  }
  if (!fs::is_directory(folder, ec)) {
    throw InputError("'" + folder.string() + "' is not a folder");
  }
  std::vector<fs::path> frames;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (!entry.is_regular_file()) continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png") frames.push_back(entry.path());
  }
  if (ec) {
    throw InputError("cannot list folder '" + folder.string() + "': " + ec.message());
  }
  if (frames.empty()) {
    throw InputError("no PNG frames in folder '" + folder.string() + "'");
  }
  std::sort(frames.begin(), frames.end(), [](const fs::path& a, const fs::path& b) {
    return a.filename().string() < b.filename().string();
  });
  return frames;
}

cv::Mat read_grey_frame(const fs::path& file, int expected_width, int expected_height) {
  std::ifstream probe(file, std::ios::binary);
  if (!probe) {
    throw InputError("cannot open frame '" + file.string() + "'");
  }
  probe.close();
  cv::Mat img;
  try {
    img = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError("cannot decode frame '" + file.string() + "': " + e.what());
  }
  if (img.empty()) {
    throw InputError("cannot decode frame '" + file.string() + "' (corrupt or not an image)");
  }
  if (img.depth() != CV_8U) {
    throw InputError("frame '" + file.string() + "' has " + std::to_string(8 * img.elemSize1()) +
                     "-bit samples; only 8-bit images are accepted");
  }
  cv::Mat grey;
  switch (img.channels()) {
    case 1:
      grey = img;
      break;
    case 3:
      cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
      break;
    case 4:
      cv::cvtColor(img, grey, cv::COLOR_BGRA2GRAY);
      break;
    default:
      throw InputError("frame '" + file.string() + "' has " + std::to_string(img.channels()) +
                       " channels; expected grey, BGR or BGRA");
  }
  if ((expected_width > 0 && grey.cols != expected_width) ||
      (expected_height > 0 && grey.rows != expected_height)) {
    throw InputError("frame '" + file.string() + "' is " + std::to_string(grey.cols) + "x" +
                     std::to_string(grey.rows) + " but the scene says " +
                     std::to_string(expected_width) + "x" + std::to_string(expected_height));
  }
  return grey;
}

}  // namespace ceilnav::app
