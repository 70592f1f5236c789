#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "common/trace/tracer.hpp"

namespace tb::trace {
namespace {

std::vector<nlohmann::json> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);)
    out.push_back(nlohmann::json::parse(line));
  return out;
}

class TracerTest : public ::testing::Test {
 protected:
  std::string path_ = (std::filesystem::temp_directory_path() /
                       ("tracer_test_" + std::to_string(::getpid()) + ".jsonl"))
                          .string();
  void TearDown() override { std::filesystem::remove(path_); }
};

TEST_F(TracerTest, WritesOneParseableJsonObjectPerRecord) {
  {
    Tracer t(path_, "its-station");
    t.record_at(1'732'233'600'123'456'789, "cam.tx",
                {{"station", 1001u},
                 {"gdt", 4242},
                 {"lat", 41.5},
                 {"why", "heading \"4\"\n"},
                 {"lf", true},
                 {"neg", -7LL}});
    t.record("nan", {{"v", 0.0 / 0.0}});
  }
  const auto lines = read_lines(path_);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["ts"], 1'732'233'600'123'456'789LL);
  EXPECT_EQ(lines[0]["proc"], "its-station");
  EXPECT_EQ(lines[0]["ev"], "cam.tx");
  EXPECT_EQ(lines[0]["station"], 1001);
  EXPECT_EQ(lines[0]["gdt"], 4242);
  EXPECT_EQ(lines[0]["lat"], 41.5);
  EXPECT_EQ(lines[0]["why"], "heading \"4\"\n");
  EXPECT_EQ(lines[0]["lf"], true);
  EXPECT_EQ(lines[0]["neg"], -7);
  EXPECT_TRUE(lines[1]["v"].is_null());
}

TEST_F(TracerTest, TimestampsAreRealtimeNanoseconds) {
  const std::int64_t before = Tracer::now_ns();
  {
    Tracer t(path_, "p");
    t.record("x", {});
  }
  const std::int64_t after = Tracer::now_ns();
  const auto lines = read_lines(path_);
  ASSERT_EQ(lines.size(), 1u);
  const std::int64_t ts = lines[0]["ts"];
  EXPECT_GE(ts, before);
  EXPECT_LE(ts, after);
  EXPECT_GT(ts, 1'600'000'000'000'000'000LL);  // CLOCK_REALTIME, not CLOCK_MONOTONIC
}

TEST_F(TracerTest, ManyRecordsSurviveBufferFlushes) {
  {
    Tracer t(path_, "p");
    for (int i = 0; i < 20000; ++i)
      t.record("n", {{"i", i}});
  }
  const auto lines = read_lines(path_);
  ASSERT_EQ(lines.size(), 20000u);
  EXPECT_EQ(lines.back()["i"], 19999);
}

TEST_F(TracerTest, RecordsReachTheFileWithinASecondWithoutFlush) {
  Tracer t(path_, "p");
  // The first record is always written (nothing was flushed yet); a record one second after
  // the last write goes out with everything before it, without waiting for a full buffer.
  t.record_at(5'000'000'000, "a", {});
  t.record_at(5'100'000'000, "b", {});
  EXPECT_EQ(read_lines(path_).size(), 1u);
  t.record_at(6'100'000'000, "c", {});
  EXPECT_EQ(read_lines(path_).size(), 3u);
}

TEST(Tracer, DisabledTracerWritesNothing) {
  // Records go nowhere: not to the console, not to a file in the working directory, and the
  // global tracer stays off while TESTBED_TRACE_DIR is empty.
  const auto dir =
      std::filesystem::temp_directory_path() / ("tracer_off_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  ::setenv("TESTBED_TRACE_DIR", "", 1);
  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(configure_from_env("p"), "");
  EXPECT_FALSE(global().enabled());
  Tracer t;
  EXPECT_FALSE(t.enabled());
  t.record("x", {{"i", 1}});
  t.record_at(1, "y", {{"s", "text"}});
  t.flush();
  global().record("z", {{"i", 2}});
  global().flush();
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  std::filesystem::current_path(cwd);
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST(Tracer, UnwritablePathIsAnErrorNamingIt) {
  try {
    Tracer t("/nonexistent-dir/trace.jsonl", "p");
    FAIL() << "expected an error";
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/trace.jsonl"), std::string::npos);
  }
}

}  // namespace
}  // namespace tb::trace
