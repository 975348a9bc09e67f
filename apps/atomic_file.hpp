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

// A command's output folder whose files appear together or not at all: they
// are written into a hidden staging folder inside it (path()), and commit()
// renames each into place. Without commit() the staging folder is removed, and
// so is the output folder if this object created it. Throws std::runtime_error
// naming the folder if it cannot be created or written.
class OutputFolder {
 public:
  explicit OutputFolder(std::filesystem::path folder);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // Where to write `relative` (its parent folders are created).
  std::filesystem::path path(const std::filesystem::path& relative) const;
  const std::filesystem::path& folder() const { return folder_; }
  // Renames every staged file into the output folder. Throws on failure.
  void commit();

 private:
  void discard();  // removes the staging folder, and the output folder if created here and empty

  std::filesystem::path folder_;  // as given (messages)
  std::filesystem::path dir_;     // absolute, normalised
  std::filesystem::path staging_;
  std::filesystem::path created_root_;  // outermost folder created by the constructor
  bool created_ = false;
  bool committed_ = false;
};

// Throws std::runtime_error unless a file can be created at `destination`
// (its folder exists and is writable). Leaves nothing behind.
void check_writable(const std::filesystem::path& destination);

}  // namespace ceilnav::app
