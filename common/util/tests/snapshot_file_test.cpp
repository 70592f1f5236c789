#include "common/util/snapshot_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

namespace tb {
namespace {

namespace fs = std::filesystem;

std::string slurp(std::ifstream& in) {
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string read_whole(const fs::path& p) {
  std::ifstream in(p);
  return slurp(in);
}

class SnapshotFileTest : public ::testing::TestWithParam<fs::path> {
 protected:
  void SetUp() override {
    dir_ = GetParam() / ("snapshot_file_test-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// Each write leaves exactly its content at the path, longer or shorter than the one before.
TEST_P(SnapshotFileTest, EveryWriteLeavesExactlyItsContent) {
  const fs::path p = dir_ / "status.json";
  SnapshotFile f(p.string());
  const std::string contents[] = {
      "{\"a\":1}\n",      std::string(20000, 'x') + "\n", "{}\n", std::string(5000, 'y'), "",
      "{\"last\":true}\n"};
  for (const auto& c : contents) {
    f.write(c);
    EXPECT_EQ(read_whole(p), c);
    EXPECT_EQ(fs::file_size(p), c.size());
  }
}

// A reader that opened the file before a write still reads the whole snapshot it opened,
// not a mix with the next one.
TEST_P(SnapshotFileTest, AReaderOpenBeforeAWriteKeepsItsWholeSnapshot) {
  const fs::path p = dir_ / "status.json";
  SnapshotFile f(p.string());
  f.write(std::string(8000, 'a'));
  f.write(std::string(3000, 'b'));
  std::ifstream reader(p);  // opens the 'b' snapshot
  f.write(std::string(12000, 'c'));
  EXPECT_EQ(slurp(reader), std::string(3000, 'b'));
  EXPECT_EQ(read_whole(p), std::string(12000, 'c'));
}

// A file left by an earlier run, and a stale .tmp of a killed one, are replaced.
TEST_P(SnapshotFileTest, ReplacesLeftoversOfEarlierRuns) {
  const fs::path p = dir_ / "status.json";
  std::ofstream(p) << "old file, longer than what comes next";
  std::ofstream(p.string() + ".tmp") << "stale tmp of a killed writer, long as well";
  SnapshotFile f(p.string());
  f.write("new\n");
  EXPECT_EQ(read_whole(p), "new\n");
  f.write("newer\n");
  EXPECT_EQ(read_whole(p), "newer\n");
}

// The writer removes its spare name when it ends; the last snapshot stays.
TEST_P(SnapshotFileTest, LeavesOnlyThePathBehind) {
  const fs::path p = dir_ / "status.json";
  {
    SnapshotFile f(p.string());
    f.write("1");
    f.write("2");
    f.write("3");
  }
  EXPECT_EQ(read_whole(p), "3");
  EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
}

// A file that cannot be written is an error naming it; the writer recovers once it can.
TEST_P(SnapshotFileTest, AnUnwritablePathIsAnErrorNamingTheFile) {
  const fs::path p = dir_ / "missing-dir" / "status.json";
  SnapshotFile f(p.string());
  try {
    f.write("x");
    FAIL() << "no error";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find(p.string() + ".tmp"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), std::errc::no_such_file_or_directory);
  }
  fs::create_directories(p.parent_path());
  f.write("y");
  EXPECT_EQ(read_whole(p), "y");
}

// Somebody removing the files between writes: that write fails naming the file, the next one
// starts afresh.
TEST_P(SnapshotFileTest, FilesRemovedUnderneathAreRecreated) {
  const fs::path p = dir_ / "status.json";
  SnapshotFile f(p.string());
  f.write("1");
  f.write("2");
  fs::remove(p);
  fs::remove(p.string() + ".tmp");
  EXPECT_THROW(f.write("3"), std::system_error);
  f.write("4");
  EXPECT_EQ(read_whole(p), "4");
}

// The temporary directory's file system (ext4 on this VM, as the run directories) and tmpfs.
INSTANTIATE_TEST_SUITE_P(FileSystems, SnapshotFileTest,
                         ::testing::Values(fs::temp_directory_path(), fs::path("/dev/shm")));

}  // namespace
}  // namespace tb
