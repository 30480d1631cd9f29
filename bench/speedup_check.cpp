#include "speedup_check.h"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/format.h"
#include "core/input_file.h"
#include "split_list.h"

namespace ausbau::bench {

namespace {
constexpr char kOmplDefault[] = "OMPL default";

std::string Secs(double s) { return Fmt(s < 1 ? "%.3f" : "%.2f", s); }
}  // namespace

std::vector<SpeedupRow> Speedups(const std::vector<SceneResult>& scenes, double time_limit_s) {
  std::vector<SpeedupRow> rows;
  for (const SceneResult& scene : scenes) {
    if (!scene.loaded) continue;
    const Stats ompl = Summarize(scene.runs, kOmplDefault, time_limit_s);
    if (ompl.runs == 0) continue;
    for (const ConfigInfo& c : scene.configs) {
      if (c.ompl || !c.skipped.empty()) continue;
      const Stats s = Summarize(scene.runs, c.label, time_limit_s);
      if (s.runs == 0) continue;
      SpeedupRow row;
      row.scene = scene.name;
      row.planner = c.label;
      row.solved = s.successes;
      row.runs = s.runs;
      row.median_s = s.median_s;
      row.ompl_solved = ompl.successes;
      row.ompl_runs = ompl.runs;
      row.ompl_median_s = ompl.median_s;
      row.speedup = s.median_s > 0 ? ompl.median_s / s.median_s : 0;
      row.bad_paths = s.bad_paths;
      rows.push_back(row);
    }
  }
  return rows;
}

void WriteSpeedupsCsv(const std::filesystem::path& file, const std::vector<SpeedupRow>& rows) {
  std::ostringstream csv;
  csv << "scene,planner,solved,runs,median_s,ompl_solved,ompl_runs,ompl_median_s,speedup,bad_paths\n";
  for (const SpeedupRow& r : rows) {
    csv << r.scene << "," << r.planner << "," << r.solved << "," << r.runs << "," << Fmt("%.6g", r.median_s) << ","
        << r.ompl_solved << "," << r.ompl_runs << "," << Fmt("%.6g", r.ompl_median_s) << "," << Fmt("%.4g", r.speedup)
        << "," << r.bad_paths << "\n";
  }
  WriteTextFileAtomically(file, csv.str());
}

std::string SpeedupSection(const std::vector<SpeedupRow>& rows, double time_limit_s) {
  std::ostringstream md;
  md << "\n## Speed-up against OMPL's RRT-Connect (default range)\n\n";
  if (rows.empty()) {
    md << "OMPL default did not run on any scene: no speed-up.\n\n";
    return md.str();
  }
  md << "| scene | planner | solved | median (s) | OMPL default solved | OMPL median (s) | speed-up (OMPL / ours)"
        " | bad paths |\n|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const SpeedupRow& r : rows) {
    md << "| " << r.scene << " | " << r.planner << " | " << r.solved << "/" << r.runs << " | " << Secs(r.median_s)
       << " | " << r.ompl_solved << "/" << r.ompl_runs << " | " << Secs(r.ompl_median_s) << " | "
       << Fmt("%.2fx", r.speedup) << " | " << r.bad_paths << " |\n";
  }
  md << "\nMedians of wall time; a failed run counts as the time limit (" << Secs(time_limit_s)
     << " s), so a speed-up where either side failed is a bound. `ausbau-plan` is the whole process with "
        "its default flags (loading, planning, certification, dense re-check, writing); the other rows and OMPL "
        "are timed around the planner call in this process.\n\n";
  return md.str();
}

std::vector<RecordedSpeedup> ReadRecordedSpeedups(const std::filesystem::path& file) {
  // A FIFO would block, a device never end.
  CheckInputFile(file, kMaxTextInputBytes, "recorded speed-ups (--recorded)");
  std::ifstream in(file);
  if (!in) throw InputErrorAt(file.string(), "cannot read the recorded speed-ups (--recorded)");
  std::vector<RecordedSpeedup> recorded;
  std::string line;
  int number = 0;
  int scene_col = -1, planner_col = -1, speedup_col = -1;
  std::size_t columns = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    const std::string where = file.string() + ":" + std::to_string(number);
    if (scene_col < 0) {
      for (std::size_t i = 0; i < cells.size(); ++i) {
        if (cells[i] == "scene") scene_col = static_cast<int>(i);
        if (cells[i] == "planner") planner_col = static_cast<int>(i);
        if (cells[i] == "speedup") speedup_col = static_cast<int>(i);
      }
      if (scene_col < 0 || planner_col < 0 || speedup_col < 0) {
        throw InputErrorAt(where, "the header must name the columns scene, planner and speedup");
      }
      columns = cells.size();
      continue;
    }
    if (cells.size() != columns) {
      throw InputErrorAt(where, Fmt("%zu fields, the header has %zu", cells.size(), columns));
    }
    RecordedSpeedup r;
    r.scene = cells[scene_col];
    r.planner = cells[planner_col];
    std::size_t used = 0;
    try {
      r.speedup = std::stod(cells[speedup_col], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != cells[speedup_col].size() || !(r.speedup > 0) || !std::isfinite(r.speedup)) {
      throw InputErrorAt(where, "speedup '" + cells[speedup_col] + "' is not a positive number");
    }
    recorded.push_back(r);
  }
  if (scene_col < 0) throw InputErrorAt(file.string(), "no header line (scene,planner,speedup)");
  return recorded;
}

SpeedupCheck CheckSpeedups(const std::vector<SpeedupRow>& measured, const std::vector<RecordedSpeedup>& recorded,
                           double share, const std::string& recorded_name) {
  SpeedupCheck check;
  std::ostringstream md;
  md << "## Check against the recorded speed-ups (" << recorded_name << ")\n\n";
  md << "Fails when a speed-up is below " << Fmt("%g", share)
     << " x the recorded one, or when any path failed the dense re-check.\n\n";
  std::map<std::pair<std::string, std::string>, const SpeedupRow*> by_key;
  for (const SpeedupRow& r : measured) by_key[{r.scene, r.planner}] = &r;
  for (const RecordedSpeedup& rec : recorded) {
    const auto it = by_key.find({rec.scene, rec.planner});
    if (it == by_key.end()) {
      md << "- " << rec.scene << ", " << rec.planner << ": not run (recorded " << Fmt("%.2fx", rec.speedup) << ")\n";
      continue;
    }
    const SpeedupRow& r = *it->second;
    ++check.compared;
    const bool ok = r.speedup >= share * rec.speedup && r.bad_paths == 0;
    check.passed = check.passed && ok;
    md << "- " << rec.scene << ", " << rec.planner << ": " << Fmt("%.2fx", r.speedup) << " against recorded "
       << Fmt("%.2fx", rec.speedup) << " (least allowed " << Fmt("%.2fx", share * rec.speedup) << ")"
       << (r.bad_paths ? Fmt(", %d bad path(s)", r.bad_paths) : std::string()) << ": " << (ok ? "ok" : "**FAILED**")
       << "\n";
  }
  for (const SpeedupRow& r : measured) {
    if (r.bad_paths > 0) {
      bool listed = false;
      for (const RecordedSpeedup& rec : recorded) listed = listed || (rec.scene == r.scene && rec.planner == r.planner);
      if (!listed) {
        check.passed = false;
        md << "- " << r.scene << ", " << r.planner << ": " << r.bad_paths << " bad path(s): **FAILED**\n";
      }
    }
  }
  if (check.compared == 0) {
    check.passed = false;
    md << "- no recorded row matches a scene and planner of this run: **FAILED** (nothing was checked)\n";
  }
  md << "\nCheck: " << (check.passed ? "passed" : "**FAILED**") << "\n\n";
  check.markdown = md.str();
  return check;
}

}  // namespace ausbau::bench
