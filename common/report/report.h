// The HTML report of a run (ausbau-report): one self-contained file that
// shows S and D in 3D, animates D along the path, plots per-pose values
// (clearance) along it and lists the stats and the verdict; and the
// benchmark page (ausbau-report --bench-dir).
//
// The HTML needs no network and no other file at view time: meshes are
// base64 binary buffers (Float32 positions, Uint32 indices), three.js and the
// viewer's module code are inlined (an import map of data: URLs). The
// JavaScript is not part of this library: the caller passes it in
// (`ReportAssets`; ausbau-report compiles it into its executable).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace ausbau {

struct ReportOptions {
  std::filesystem::path scene;     // required
  std::filesystem::path path;      // the planned path (ausbau-path); optional
  std::filesystem::path smoothed;  // the smoothed path (ausbau-path); optional
  // A run's output folder: path.h5, path-smooth.h5, labels.h5, spheres.h5,
  // verdict.json, profile.csv, path.csv are used when present and regular
  // files (a symbolic link is not followed; explicit options win).
  std::filesystem::path run_dir;
  // Clearance is computed at every waypoint and at this many poses evenly
  // spread over the path's animation time (0: waypoints only).
  int clearance_samples = 200;
};

struct ReportAssets {
  std::string_view three_module;    // three.module.min.js (npm package three)
  std::string_view orbit_controls;  // three/examples/jsm/controls/OrbitControls.js
  std::string_view viewer;          // the report's viewer module (stages/report/viewer.js)
  std::string three_version;
};

// What went into a report, for the stage's log.
struct ReportSummary {
  std::vector<std::string> used;   // "planned path: out/path.h5", ...
  std::vector<std::string> notes;  // absent or ignored inputs, with the reason
};

// Reads the scene and the artifacts, computes the clearance along each path
// and returns the HTML. Throws InputError (one line, naming the file) for a
// missing or bad scene, a path file that is missing or not an ausbau-path
// artifact, or a path that belongs to another scene. Optional run-folder
// extras (labels, verdict, profile) that are unreadable are reported in
// `summary->notes` and in the page instead.
std::string BuildReportHtml(const ReportOptions& options, const ReportAssets& assets, ReportSummary* summary);

// The benchmark page: summary.md and study-summary.md rendered, study-*.svg
// heat maps inlined, and a bar chart per scene of the median times in
// results.csv. Throws InputError when the folder is missing or holds none of
// these files.
std::string BuildBenchPageHtml(const std::filesystem::path& bench_dir, ReportSummary* summary);

// Helpers, exposed for tests.
std::string Base64Encode(const void* data, std::size_t size);
std::string HtmlEscape(std::string_view text);
// The subset of Markdown that ausbau-bench writes: # headings, pipe tables
// with an alignment row, - and 1. lists (one level of nesting), paragraphs,
// **bold** and `code`.
std::string MarkdownToHtml(const std::string& markdown);

}  // namespace ausbau
