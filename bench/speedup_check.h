// Speed-ups against OMPL's RRT-Connect (default range), side by side in one
// run, and the regression gate of `make bench-planners-check`: a speed-up
// that falls below a share (one half) of the recorded one fails.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "bench_report.h"

namespace ausbau::bench {

// One Ausbau configuration on one scene against "OMPL default".
struct SpeedupRow {
  std::string scene;
  std::string planner;
  int solved = 0, runs = 0;
  double median_s = 0;  // failures count as the time limit
  int ompl_solved = 0, ompl_runs = 0;
  double ompl_median_s = 0;
  double speedup = 0;  // ompl_median_s / median_s: > 1 means Ausbau is faster
  int bad_paths = 0;   // solved runs whose path failed the dense re-check
};

// Every Ausbau configuration of every loaded scene where "OMPL default" ran.
std::vector<SpeedupRow> Speedups(const std::vector<SceneResult>& scenes, double time_limit_s);

// speedups.csv: scene,planner,solved,runs,median_s,ompl_solved,ompl_runs,
// ompl_median_s,speedup,bad_paths (the format --recorded reads back).
void WriteSpeedupsCsv(const std::filesystem::path& file, const std::vector<SpeedupRow>& rows);

// A markdown section: the table of speed-ups.
std::string SpeedupSection(const std::vector<SpeedupRow>& rows, double time_limit_s);

struct RecordedSpeedup {
  std::string scene;
  std::string planner;
  double speedup = 0;
};
// Reads a speedups.csv (columns named in its header; scene, planner and
// speedup are needed, others ignored; '#' lines are comments). InputError
// naming the file and line on anything else.
std::vector<RecordedSpeedup> ReadRecordedSpeedups(const std::filesystem::path& file);

struct SpeedupCheck {
  bool passed = true;
  int compared = 0;      // recorded rows that ran
  std::string markdown;  // a section with one line per compared row and the verdict
};
// Fails when a measured speed-up is below share x the recorded one, or when
// any Ausbau path failed the dense re-check. Recorded rows whose scene or
// planner did not run are listed, not failed; no row compared fails (a gate
// that checks nothing must not pass).
SpeedupCheck CheckSpeedups(const std::vector<SpeedupRow>& measured, const std::vector<RecordedSpeedup>& recorded,
                           double share, const std::string& recorded_name);

}  // namespace ausbau::bench
