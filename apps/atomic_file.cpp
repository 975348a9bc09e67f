#include "apps/atomic_file.hpp"

#include <unistd.h>

#include <random>
#include <stdexcept>
#include <system_error>

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

}  // namespace ceilnav::app
