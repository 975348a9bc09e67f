// Output files appear whole or not at all: content goes to a temporary file in
// the destination folder, which is renamed over the destination on commit().
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace ceilnav::app {

class AtomicFile {
 public:
  // Throws std::runtime_error naming the path if the folder is not writable.
  explicit AtomicFile(std::filesystem::path destination);
  ~AtomicFile();  // removes the temporary file unless committed
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks the stream and renames into place. Throws on failure.
  void commit();

 private:
  std::filesystem::path destination_;
  std::filesystem::path temporary_;
  std::ofstream out_;
  bool committed_ = false;
};

// Throws std::runtime_error unless a file can be created at `destination`
// (its folder exists and is writable). Leaves nothing behind.
void check_writable(const std::filesystem::path& destination);

}  // namespace ceilnav::app
