// A progress bar on standard error for long runs, shown only on a terminal.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <string>

namespace ceilnav::app {

class Progress {
 public:
  Progress(std::string label, size_t total, bool enabled = ::isatty(STDERR_FILENO) != 0)
      : label_(std::move(label)), total_(total), enabled_(enabled && total > 1) {}
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void update(size_t done) {
    if (!enabled_) return;
    const int width = 40;
    const int filled = total_ == 0 ? width : static_cast<int>(width * done / total_);
    std::fprintf(stderr, "\r%s [%s%s] %zu/%zu", label_.c_str(),
                 std::string(static_cast<size_t>(filled), '#').c_str(),
                 std::string(static_cast<size_t>(width - filled), '.').c_str(), done, total_);
    std::fflush(stderr);
    drawn_ = true;
  }
  void finish() {
    if (drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }

 private:
  std::string label_;
  size_t total_;
  bool enabled_;
  bool drawn_ = false;
};

}  // namespace ceilnav::app
