// ausbau-report: one self-contained HTML file with the verdict first, S and D in 3D, D animated
// along the path, the clearance along it, the stats and the verdict; or, with
// --bench-dir, a page of ausbau-bench's tables and pictures. See README.md.
#include <cstdio>
#include <string_view>

#include "artifact/run_files.h"
#include "cli/stage.h"
#include "core/log.h"
#include "planning/path_io.h"
#include "report/report.h"

// Compiled in from the build's copy of three.js and viewer.js (embed.cmake).
namespace ausbau::report_assets {
extern const char kThreeVersion[];
extern const unsigned char kThreeModule[], kOrbitControls[], kViewer[];
extern const std::size_t kThreeModule_size, kOrbitControls_size, kViewer_size;
}  // namespace ausbau::report_assets

namespace ausbau {
namespace {

std::string_view View(const unsigned char* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// No artifact: the page is written anew each time. --scene is its own
// option (SceneHash::kNoScene): a benchmark page (--bench-dir) reads none.
constexpr StageSpec kReportStage{"ausbau-report",
                                 "Writes a self-contained HTML report: the verdict in one sentence, S and D in 3D, D "
                                 "animated along the path, clearance and penetration along it, a table per waypoint, "
                                 "stats and verdict (or a benchmark page with --bench-dir).",
                                 SceneHash::kNoScene,
                                 {},
                                 {},
                                 "accepted for a pipeline's sake: the page is always written anew"};

struct ReportStageOptions {
  std::string scene, path, smoothed, run_dir;  // as text: into `report` by WriteReport
  ReportOptions report;
  std::string bench_dir;
  std::string output = kRunFileReport;
};

// The inputs are read by the report itself (no cache): not hashed, only
// kept from being overwritten by -o.
void DeclareReport(StageDefinition& stage, ReportStageOptions* options) {
  stage.InputFile("--scene", &options->scene, "", "scene.yaml");
  stage.InputFile("--path", &options->path, "", "planned path artifact (ausbau-path)");
  stage.InputFile("--smoothed", &options->smoothed, "", "smoothed path artifact (ausbau-path)");
  stage.Option("--run-dir", &options->run_dir,
               "a run's output folder: uses path.h5, path-smooth.h5, labels.h5, verdict.json "
               "when present (explicit --path/--smoothed win)",
               CacheKey::kNo);
  stage
      .Option("--clearance-samples", &options->report.clearance_samples,
              "poses along the path at which clearance and penetration are measured, besides the waypoints",
              CacheKey::kYes)
      ->check(CLI::Range(0, 100000));
  stage.Option("--bench-dir", &options->bench_dir,
               "instead: a page of ausbau-bench's outputs in this folder (summary.md, results.csv, "
               "study-*.svg)",
               CacheKey::kNo);
  stage.ExtraOutput("-o,--output", &options->output, "the HTML file");
  stage.CheckOptions([options] {
    if (!options->bench_dir.empty()) {
      if (!options->scene.empty() || !options->path.empty() || !options->smoothed.empty() ||
          !options->run_dir.empty()) {
        throw InputError("--bench-dir makes a benchmark page and takes no --scene, --path, --smoothed or --run-dir");
      }
    } else if (options->scene.empty()) {
      throw InputError("--scene is required (or --bench-dir for a benchmark page)");
    }
  });
}

int WriteReport(const StageRun&, const ReportStageOptions& stage_options) {
  ReportStageOptions options = stage_options;
  options.report.scene = options.scene;
  options.report.path = options.path;
  options.report.smoothed = options.smoothed;
  options.report.run_dir = options.run_dir;
  ReportSummary summary;
  std::string html;
  if (!options.bench_dir.empty()) {
    html = BuildBenchPageHtml(options.bench_dir, &summary);
  } else {
    namespace a = report_assets;
    const ReportAssets assets{View(a::kThreeModule, a::kThreeModule_size),
                              View(a::kOrbitControls, a::kOrbitControls_size), View(a::kViewer, a::kViewer_size),
                              a::kThreeVersion};
    html = BuildReportHtml(options.report, assets, &summary);
  }
  for (const std::string& line : summary.used) LogInfo("%s", line.c_str());
  for (const std::string& line : summary.notes) LogInfo("%s", line.c_str());
  WriteTextFileAtomically(options.output, html);
  LogInfo("wrote %s (%.2f MiB)", options.output.c_str(), html.size() / (1024.0 * 1024.0));
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kReportStage, DeclareReport, WriteReport)
