// Atomic output: files appear whole on commit, or not at all.
#include "apps/atomic_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "host/tests/temp_dir.hpp"

namespace fs = std::filesystem;
using ceilnav::app::AtomicFile;
using ceilnav::app::OutputFolder;

namespace {

// One scratch folder per test.
class TempDir : public ceilnav::test::TempDir {
 public:
  TempDir() : ceilnav::test::TempDir("ceilnav_atomic_file") {}
};

}  // namespace

TEST(AtomicFile, NothingAppearsUntilCommit) {
  TempDir d;
  const fs::path dest = d.path() / "out.csv";
  {
    AtomicFile f(dest);
    f.stream() << "partial";
    EXPECT_FALSE(fs::exists(dest));
  }  // destroyed without commit
  EXPECT_FALSE(fs::exists(dest));
  EXPECT_TRUE(fs::is_empty(d.path()));  // no temporary left behind
  {
    AtomicFile f(dest);
    f.stream() << "whole\n";
    f.commit();
  }
  std::ifstream in(dest);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "whole");
}

TEST(AtomicFile, UnwritableDestinations) {
  TempDir d;
  EXPECT_THROW(AtomicFile(d.path() / "missing" / "x.csv"), std::runtime_error);
  EXPECT_THROW(AtomicFile(d.path()), std::runtime_error);  // a folder
  std::ofstream(d.path() / "file") << "x";
  EXPECT_THROW(AtomicFile(d.path() / "file" / "x.csv"), std::runtime_error);
}

TEST(OutputFolder, FilesAppearOnlyOnCommit) {
  TempDir d;
  const fs::path out = d.path() / "a" / "b";
  {
    OutputFolder f(out);
    std::ofstream(f.path("x.csv")) << "x";
    std::ofstream(f.path(fs::path("frames") / "y.png")) << "y";
    EXPECT_FALSE(fs::exists(out / "x.csv"));
  }  // destroyed without commit: the folders it created are gone too
  EXPECT_FALSE(fs::exists(d.path() / "a"));
  {
    OutputFolder f(out);
    std::ofstream(f.path("x.csv")) << "x";
    std::ofstream(f.path(fs::path("frames") / "y.png")) << "y";
    f.commit();
  }
  EXPECT_TRUE(fs::is_regular_file(out / "x.csv"));
  EXPECT_TRUE(fs::is_regular_file(out / "frames" / "y.png"));
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(out)) entries += e.path().filename() != "" ? 1u : 0u;
  EXPECT_EQ(entries, 2u);  // x.csv and frames/, no staging folder
  {
    OutputFolder f(out);  // exists: kept as it was without commit
    std::ofstream(f.path("z.csv")) << "z";
  }
  EXPECT_TRUE(fs::exists(out / "x.csv"));
  EXPECT_FALSE(fs::exists(out / "z.csv"));
  {
    // "..", "." and a trailing separator: only "c" is created, and removed.
    OutputFolder f(d.path() / "x" / ".." / "c" / "." / "");
    std::ofstream(f.path("x.csv")) << "x";
  }
  EXPECT_FALSE(fs::exists(d.path() / "x"));
  EXPECT_FALSE(fs::exists(d.path() / "c"));
  std::ofstream(d.path() / "file") << "f";
  EXPECT_THROW(OutputFolder(d.path() / "file"), std::runtime_error);
  EXPECT_THROW(OutputFolder(d.path() / "file" / "sub"), std::runtime_error);
}
