// The speed-up table and the regression gate of `make bench-planners`
// (bench/speedup_check.h), on hand-made run records.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "speedup_check.h"
#include "test_scenes.h"

namespace ausbau::bench {
namespace {

namespace fs = std::filesystem;

RunRecord Run(const std::string& label, double seconds, bool solved = true, int dense = 1) {
  RunRecord r;
  r.scene = "alpha";
  r.label = label;
  r.time_s = seconds;
  r.success = solved;
  r.dense_check = solved ? dense : -1;
  return r;
}

// alpha: ours 1, 2, 3 s (median 2); OMPL 10, 20, a failure at 60 s (median 20).
SceneResult Alpha(int ours_dense = 1) {
  SceneResult s;
  s.name = "alpha";
  s.loaded = true;
  ConfigInfo ours;
  ours.label = "ausbau-plan";
  ConfigInfo ompl;
  ompl.label = "OMPL default";
  ompl.ompl = true;
  s.configs = {ours, ompl};
  s.runs = {Run("ausbau-plan", 1),   Run("OMPL default", 10), Run("ausbau-plan", 3, true, ours_dense),
            Run("OMPL default", 20), Run("ausbau-plan", 2),   Run("OMPL default", 60, false)};
  return s;
}

// The test process's folder for its files, removed when it ends.
const testing::ScopedTempDir& Dir() {
  static const testing::ScopedTempDir dir("bench-speedups");
  return dir;
}

fs::path WriteFile(const std::string& name, const std::string& text) {
  const fs::path file = Dir() / (name + ".csv");
  std::ofstream(file) << text;
  return file;
}

TEST(BenchSpeedups, RatioOfMediansWithFailuresAtTheLimit) {
  const std::vector<SpeedupRow> rows = Speedups({Alpha()}, 60);
  ASSERT_EQ(rows.size(), 1u);  // OMPL is the reference, not a row
  EXPECT_EQ(rows[0].planner, "ausbau-plan");
  EXPECT_DOUBLE_EQ(rows[0].median_s, 2);
  EXPECT_DOUBLE_EQ(rows[0].ompl_median_s, 20);
  EXPECT_EQ(rows[0].ompl_solved, 2);
  EXPECT_DOUBLE_EQ(rows[0].speedup, 10);
}

TEST(BenchSpeedups, NoOmplRunNoRow) {
  SceneResult s = Alpha();
  s.configs.pop_back();
  s.runs.erase(
      std::remove_if(s.runs.begin(), s.runs.end(), [](const RunRecord& r) { return r.label != "ausbau-plan"; }),
      s.runs.end());
  EXPECT_TRUE(Speedups({s}, 60).empty());
}

TEST(BenchSpeedups, CsvRoundTripsAndTheGateHalvesTheRecordedRatio) {
  const std::vector<SpeedupRow> rows = Speedups({Alpha()}, 60);
  const fs::path file = Dir() / "speedups.csv";
  WriteSpeedupsCsv(file, rows);
  const std::vector<RecordedSpeedup> back = ReadRecordedSpeedups(file);
  fs::remove(file);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].scene, "alpha");
  EXPECT_DOUBLE_EQ(back[0].speedup, 10);

  // Measured 10x: passes against a recorded 20x (least 10x), fails against 20.5x.
  EXPECT_TRUE(CheckSpeedups(rows, {{"alpha", "ausbau-plan", 20}}, 0.5, "r").passed);
  const SpeedupCheck slower = CheckSpeedups(rows, {{"alpha", "ausbau-plan", 20.5}}, 0.5, "r");
  EXPECT_FALSE(slower.passed);
  EXPECT_NE(slower.markdown.find("FAILED"), std::string::npos);
}

TEST(BenchSpeedups, ABadPathFailsTheGateWhateverTheRatio) {
  const std::vector<SpeedupRow> rows = Speedups({Alpha(/*ours_dense=*/0)}, 60);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].bad_paths, 1);
  EXPECT_FALSE(CheckSpeedups(rows, {{"alpha", "ausbau-plan", 1}}, 0.5, "r").passed);
  // Also when no recorded row names it: the row is listed as failed.
  const SpeedupCheck unlisted = CheckSpeedups(rows, {{"alpha", "CR-RRTC", 1}}, 0.5, "r");
  EXPECT_FALSE(unlisted.passed);
  EXPECT_NE(unlisted.markdown.find("alpha, ausbau-plan: 1 bad path(s): **FAILED**"), std::string::npos)
      << unlisted.markdown;
}

TEST(BenchSpeedups, AGateThatComparesNothingFails) {
  const std::vector<SpeedupRow> rows = Speedups({Alpha()}, 60);
  const SpeedupCheck check = CheckSpeedups(rows, {{"Home", "ausbau-plan", 3}}, 0.5, "r");
  EXPECT_EQ(check.compared, 0);
  EXPECT_FALSE(check.passed);
  EXPECT_NE(check.markdown.find("Home, ausbau-plan: not run"), std::string::npos);
}

TEST(BenchSpeedups, RecordedFileErrorsNameFileAndLine) {
  const fs::path no_header = WriteFile("no-header", "# only a comment\n");
  EXPECT_THROW(ReadRecordedSpeedups(no_header), InputError);
  const fs::path bad_number = WriteFile("bad-number", "scene,planner,speedup\nalpha,ausbau-plan,fast\n");
  try {
    ReadRecordedSpeedups(bad_number);
    ADD_FAILURE() << "a speed-up 'fast' was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":2"), std::string::npos) << e.what();
  }
  const fs::path negative = WriteFile("negative", "scene,planner,speedup\nalpha,ausbau-plan,-3\n");
  EXPECT_THROW(ReadRecordedSpeedups(negative), InputError);
  const fs::path short_row = WriteFile("short-row", "scene,planner,speedup\nalpha,3\n");
  EXPECT_THROW(ReadRecordedSpeedups(short_row), InputError);
  EXPECT_THROW(ReadRecordedSpeedups("/nonexistent/speedups.csv"), InputError);
  for (const fs::path& f : {no_header, bad_number, negative, short_row}) fs::remove(f);
}

}  // namespace
}  // namespace ausbau::bench
