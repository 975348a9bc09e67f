#include "host/frame_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/limits.hpp"

namespace ceilnav::host {
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

namespace {

std::string size_mismatch(const fs::path& file, uint32_t width, uint32_t height, int expected_width,
                          int expected_height) {
  return "frame '" + file.string() + "' is " + std::to_string(width) + "x" +
         std::to_string(height) + " but the scene says " + std::to_string(expected_width) + "x" +
         std::to_string(expected_height);
}

// Checks the PNG signature and the image size in the header chunk (IHDR, the
// first chunk) before anything is decoded: OpenCV allocates the whole image
// from the header, so a few bytes claiming 30000 x 30000 RGBA would cost
// gigabytes before the decoder finds that the data is missing.
void check_png_header(std::ifstream& probe, const fs::path& file) {
  std::array<unsigned char, 24> h{};
  probe.read(reinterpret_cast<char*>(h.data()), static_cast<std::streamsize>(h.size()));
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P',  'N',  'G',
                                                              '\r', '\n', 0x1A, '\n'};
  if (probe.gcount() != static_cast<std::streamsize>(h.size()) ||
      !std::equal(kSignature.begin(), kSignature.end(), h.begin())) {
    throw InputError("cannot decode frame '" + file.string() + "' (not a PNG file)");
  }
  const auto be32 = [&](size_t at) {
    return uint32_t{h[at]} << 24 | uint32_t{h[at + 1]} << 16 | uint32_t{h[at + 2]} << 8 |
           uint32_t{h[at + 3]};
  };
  if (std::memcmp(h.data() + 12, "IHDR", 4) != 0) {
    throw InputError("cannot decode frame '" + file.string() + "' (corrupt PNG header)");
  }
  const uint32_t width = be32(16), height = be32(20);
  if (width == 0 || height == 0) {
    throw InputError("cannot decode frame '" + file.string() + "' (corrupt PNG header: " +
                     std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  if (width > stream::kMaxWidth || height > stream::kMaxHeight) {
    throw InputError("frame '" + file.string() + "' is " + std::to_string(width) + "x" +
                     std::to_string(height) + "; the device takes at most " +
                     std::to_string(stream::kMaxWidth) + "x" + std::to_string(stream::kMaxHeight));
  }
}

}  // namespace

cv::Mat read_grey_frame(const fs::path& file, int expected_width, int expected_height) {
  std::ifstream probe(file, std::ios::binary);
  if (!probe) {
    throw InputError("cannot open frame '" + file.string() + "'");
  }
  check_png_header(probe, file);
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
    throw InputError(size_mismatch(file, static_cast<uint32_t>(grey.cols),
                                   static_cast<uint32_t>(grey.rows), expected_width,
                                   expected_height));
  }
  return grey;
}

}  // namespace ceilnav::host
