// Records, statistics and output files of ausbau-bench: results.csv,
// summary.md, OMPL benchmark logs, and the parameter study's CSV, SVG heat
// map and summary. No OMPL headers here.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/format.h"
#include "machine.h"

namespace ausbau::bench {

// One run of one planner configuration.
struct RunRecord {
  std::string scene;
  std::string label;  // "CR-RRTC", "OMPL default", ...
  std::uint64_t seed = 0;
  bool success = false;
  int status = 0;  // OMPL PlannerStatus value (exact solution / timeout)
  double time_s = 0;
  std::int64_t collision_checks = 0;
  std::int64_t iterations = 0;  // 0 = unknown (OMPL)
  std::int64_t nodes = 0;
  int dense_check = -1;  // -1: no path; 1: passed; 0: failed (a bad path)
};

// A planner configuration on one scene.
struct ConfigInfo {
  std::string label;     // table label
  std::string log_name;  // name in the OMPL benchmark log (no spaces)
  bool ompl = false;
  std::vector<std::pair<std::string, std::string>> settings;  // "common properties"
  std::string skipped;                                        // why it did not run (empty: it ran)
  std::string error;                                          // first unexpected error during a run, if any
};

struct SceneResult {
  std::string name;
  std::string file;
  std::vector<std::string> facts;  // one line each, under the scene's heading
  std::vector<std::string> notes;  // remarks (skipped OMPL, bounds, ...)
  std::vector<ConfigInfo> configs;
  std::vector<RunRecord> runs;
  std::string started_iso;
  double wall_s = 0;
  bool loaded = false;  // false: the scene could not be set up (notes say why)
};

struct Stats {
  int runs = 0;
  int successes = 0;
  double median_s = 0;  // failures count as the time limit
  double mean_s = 0;    // failures count as the time limit
  double mean_checks = 0;
  int bad_paths = 0;
  double success_rate() const { return runs > 0 ? static_cast<double>(successes) / runs : 0.0; }
};
Stats Summarize(const std::vector<RunRecord>& runs, const std::string& label, double time_limit_s);

struct BenchSettings {
  int runs = 10;
  double time_limit_s = 60;
  std::uint64_t first_seed = 1;
  std::uint32_t ompl_seed = 1;
  double resolution = 0.005;
  std::string ompl_resolution;  // matched | extent | ompl
  std::string command_line;
};

// results.csv, written as runs finish (a long benchmark that is stopped
// keeps what it has).
class ResultsCsv {
 public:
  explicit ResultsCsv(const std::filesystem::path& path);
  void Add(const RunRecord& run);

 private:
  std::ofstream out_;
};

// summary.md (also returned, for stdout).
std::string WriteSummary(const std::filesystem::path& path, const MachineInfo& machine, const BenchSettings& settings,
                         const std::vector<SceneResult>& scenes);

// OMPL's benchmark log format (the one ompl_benchmark_statistics.py reads):
// one experiment; each planner entry is (log name, config, runs).
struct LogPlanner {
  std::string name;
  const ConfigInfo* config = nullptr;
  std::vector<const RunRecord*> runs;
};
void WriteOmplLog(const std::filesystem::path& path, const std::string& experiment, const MachineInfo& machine,
                  const BenchSettings& settings, const std::string& setup_text, const std::string& started_iso,
                  double total_s, const std::string& status_enum_line, const std::vector<LogPlanner>& planners);

// Parameter study (thesis 3.3.1): one cell per (u, range_max).
struct StudyCell {
  double u = 0;
  double range_max = 0;
  int runs = 0;
  int successes = 0;
  double mean_time_s = 0;  // failures count as T_max
  double mean_pct = 0;     // mean_time_s / T_max * 100
  double mean_checks = 0;
};
struct StudyResult {
  std::string scene;
  std::vector<double> us;        // rows
  std::vector<double> ranges;    // columns
  std::vector<StudyCell> cells;  // row-major: cells[i * ranges.size() + j]
  int runs = 0;
  double time_limit_s = 0;
  double wall_s = 0;
  const StudyCell* Best() const;  // lowest mean_pct, then most successes
};
void WriteStudyCsv(const std::filesystem::path& path, const StudyResult& study);
void WriteStudySvg(const std::filesystem::path& path, const StudyResult& study);
std::string WriteStudySummary(const std::filesystem::path& path, const MachineInfo& machine,
                              const BenchSettings& settings, const std::vector<StudyResult>& studies);

// Formatting helpers (Fmt: core/format.h).
std::string SafeName(const std::string& text);  // letters, digits, '-', '.', '_' only

}  // namespace ausbau::bench
