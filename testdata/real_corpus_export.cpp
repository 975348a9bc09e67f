// ceilnav_real_corpus_export DIR: the real-image corpus (testdata/real/README.md)
// as PNG folders, DIR/<set>/<item>.png, one folder per set, for
// `ceilnav run --frames DIR/<set>` and `ceilnav pattern --frames DIR/<set>`.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>

#include "real_corpus.hpp"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc != 2) {
    fmt::print(stderr, "usage: {} DIR\n", argc > 0 ? argv[0] : "ceilnav_real_corpus_export");
    return 2;
  }
  try {
    const fs::path out = argv[1];
    if (fs::exists(out) && !fs::is_empty(out)) {
      fmt::print(stderr, "error: {} exists and is not empty\n", out.string());
      return 1;
    }
    int n = 0;
    for (const auto& f : ceilnav::test_support::load_real_corpus()) {
      const auto slash = f.name.find('/');
      const fs::path file = out / f.name.substr(0, slash) / (f.name.substr(slash + 1) + ".png");
      fs::create_directories(file.parent_path());
      if (!cv::imwrite(file.string(), f.grey)) {
        fmt::print(stderr, "error: cannot write {}\n", file.string());
        return 1;
      }
      ++n;
    }
    fmt::print("{} frames written under {}\n", n, out.string());
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
  return 0;
}
