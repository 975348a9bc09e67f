// A scratch folder for one gtest test: created empty, named after the test
// (and the random seed, so parallel runs of one executable do not collide),
// removed with everything in it at the end of the scope.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace ceilnav::test {

class TempDir {
 public:
  explicit TempDir(const std::string& prefix) {
    const auto* unit = ::testing::UnitTest::GetInstance();
    path_ = std::filesystem::temp_directory_path() /
            (prefix + "_" + std::to_string(unit->random_seed()) + "_" +
             unit->current_test_info()->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace ceilnav::test
