// A per-process scratch file for the targets whose code under test reads a
// path (the scene YAML reader, the frame reader): the input bytes are written
// to it before each call. Removed at exit.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace ceilnav::fuzz {

class TempFile {
 public:
  // `suffix` is the file name extension, e.g. ".yaml" (the readers look at it).
  explicit TempFile(const std::string& suffix) {
    const char* dir = std::getenv("TMPDIR");
    std::string templ = std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") +
                        "/ceilnav-fuzz-XXXXXX" + suffix;
    const int fd = mkstemps(templ.data(), static_cast<int>(suffix.size()));
    if (fd < 0) {
      std::perror("ceilnav fuzz: mkstemps");
      std::abort();
    }
    close(fd);
    path_ = templ;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  // Replaces the file's contents with data[0 .. size).
  const std::string& write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (f == nullptr || (size > 0 && std::fwrite(data, 1, size, f) != size) ||
        std::fclose(f) != 0) {
      std::perror("ceilnav fuzz: writing the scratch file");
      std::abort();
    }
    return path_;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace ceilnav::fuzz
