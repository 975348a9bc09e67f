#include "apps/atomic_file.hpp"

#include <unistd.h>

#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace ceilnav::app {
namespace fs = std::filesystem;

namespace {

fs::path temporary_name(const fs::path& destination) {
  std::random_device rd;
  // Built with append(): g++ 12 reports a false -Wrestrict on chained operator+.
  std::string name(".");
  name.append(destination.filename().string());
  name.append(".").append(std::to_string(::getpid()));
  name.append(".").append(std::to_string(rd() & 0xFFFFFFu)).append(".tmp");
  return destination.parent_path() / name;
}

// Absolute, without "." / ".." components or a trailing separator.
fs::path normalised(const fs::path& p) {
  fs::path a = fs::absolute(p).lexically_normal();
  if (!a.has_filename() && a.has_parent_path()) a = a.parent_path();
  return a;
}

fs::path folder_of(const fs::path& p) {
  const fs::path parent = p.parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

}  // namespace

void check_writable(const fs::path& destination) {
  const fs::path folder = folder_of(destination);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw std::runtime_error("cannot write '" + destination.string() + "': folder '" +
                             folder.string() + "' does not exist");
  }
  if (fs::is_directory(destination, ec)) {
    throw std::runtime_error("cannot write '" + destination.string() + "': it is a folder");
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw std::runtime_error("cannot write '" + destination.string() + "': folder '" +
                             folder.string() + "' is not writable");
  }
}

AtomicFile::AtomicFile(fs::path destination) : destination_(std::move(destination)) {
  check_writable(destination_);
  temporary_ = temporary_name(fs::absolute(destination_));
  out_.open(temporary_, std::ios::out | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error("cannot write '" + destination_.string() +
                             "': cannot create a temporary file beside it");
  }
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    out_.close();
    std::error_code ec;
    fs::remove(temporary_, ec);
  }
}

void AtomicFile::commit() {
  out_.flush();
  const bool good = static_cast<bool>(out_);
  out_.close();
  if (!good) {
    throw std::runtime_error("error while writing '" + destination_.string() + "'");
  }
  std::error_code ec;
  fs::rename(temporary_, destination_, ec);
  if (ec) {
    throw std::runtime_error("cannot write '" + destination_.string() + "': " + ec.message());
  }
  committed_ = true;
}

OutputFolder::OutputFolder(fs::path folder)
    : folder_(std::move(folder)), dir_(normalised(folder_)) {
  std::error_code ec;
  if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec)) {
    throw std::runtime_error("cannot create output folder '" + folder_.string() +
                             "': a file of that name exists");
  }
  if (!fs::exists(dir_, ec)) {
    // The outermost folder this creates: removed again on failure.
    created_root_ = dir_;
    while (created_root_.has_parent_path() && created_root_.parent_path() != created_root_ &&
           !fs::exists(created_root_.parent_path(), ec)) {
      created_root_ = created_root_.parent_path();
    }
    created_ = true;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_)) {
      discard();
      throw std::runtime_error("cannot create output folder '" + folder_.string() + "'" +
                               (ec ? ": " + ec.message() : ""));
    }
  }
  if (::access(dir_.c_str(), W_OK) != 0) {
    discard();
    throw std::runtime_error("cannot write to output folder '" + folder_.string() +
                             "': not writable");
  }
  std::random_device rd;
  std::string name(".staging.");
  name.append(std::to_string(::getpid())).append(".").append(std::to_string(rd() & 0xFFFFFFu));
  staging_ = dir_ / name;
  if (!fs::create_directory(staging_, ec) || ec) {
    const std::string why = ec ? ec.message() : "exists";
    staging_.clear();
    discard();
    throw std::runtime_error("cannot write to output folder '" + folder_.string() + "': " + why);
  }
}

OutputFolder::~OutputFolder() {
  if (!committed_) discard();
}

void OutputFolder::discard() {
  std::error_code ec;
  if (!staging_.empty()) fs::remove_all(staging_, ec);
  if (!created_) return;
  // Up from the output folder to the outermost one created, while empty.
  for (fs::path p = dir_;; p = p.parent_path()) {
    if (!fs::is_empty(p, ec) || ec || !fs::remove(p, ec)) break;
    if (p == created_root_ || !p.has_parent_path()) break;
  }
}

fs::path OutputFolder::path(const fs::path& relative) const {
  const fs::path p = staging_ / relative;
  std::error_code ec;
  fs::create_directories(p.parent_path(), ec);
  if (ec) {
    throw std::runtime_error("cannot write '" + (folder_ / relative).string() +
                             "': " + ec.message());
  }
  return p;
}

void OutputFolder::commit() {
  // Staged files (and folders, parents first), listed before any is moved.
  std::vector<fs::path> entries;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(staging_, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    entries.push_back(fs::relative(it->path(), staging_));
  }
  if (ec) throw std::runtime_error("cannot list '" + staging_.string() + "': " + ec.message());
  for (const fs::path& rel : entries) {
    const fs::path from = staging_ / rel, dest = dir_ / rel;
    if (fs::is_directory(from, ec)) {
      fs::create_directories(dest, ec);
    } else {
      fs::rename(from, dest, ec);
    }
    if (ec) throw std::runtime_error("cannot write '" + dest.string() + "': " + ec.message());
  }
  fs::remove_all(staging_, ec);
  committed_ = true;
}

}  // namespace ceilnav::app
