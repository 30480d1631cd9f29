// ausbau-inistate-bench --end-to-end: the whole pipeline (pipelines/
// inistate.mk, as `make run` runs it) on every scene family, old and new,
// and on an external set, each path judged by a checker that is not the
// pipeline's own:
//   - panel-* families (generated turned and metres out, coarse, fine and
//     their moulded twin: D one welded solid) and the external scenes (box
//     soup and moulded): the external exact checker oracle.py on path.csv
//     (it reads the scene's boxes.json);
//   - clips-ds1 .. clips-ds5: ausbau-check-path against the generator's
//     ground truth (the rigid parts never penetrate S beyond the installed
//     pose, the path ends disassembled).
// Per scene: correct (removable, and the checker accepts the path), WRONG
// (removable, and the checker rejects it: the worst result a planner can
// give), not removable; the deepest rigid penetration the verdict's exact
// check measured on path.csv; the wall time of the whole pipeline.
// Output in OUT: end-to-end-results.csv (one row per scene, rewritten after
// each), end-to-end-summary.md (a table per family, the machine, the
// command) and runs/<scene>/ with each run's artifacts and log.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace ausbau::bench {

struct EndToEndOptions {
  std::filesystem::path out = "out/inistate-end-to-end";
  std::vector<std::string> families;  // empty: every clips-ds* and panel-* family
  std::vector<int> seeds = {1, 2, 3};
  std::filesystem::path external;  // folder with scenes/<name>/ and oracle.py; empty: none
  bool external_scenes = true;     // also run external/scenes and external/scenes-molded (else only its oracle)
  std::string validity;            // pipeline VALIDITY; empty: the pipeline's default
  std::filesystem::path bin;       // the stages
  std::filesystem::path pipeline = "pipelines/inistate.mk";
  std::string python = "/usr/bin/python3";
  std::string command;  // for the summary
};

// Returns 0 when no scene was wrongly removable, 1 otherwise. Throws
// InputError for bad options (unknown family, missing pipeline, oracle or
// numpy where they are needed).
int RunEndToEnd(const EndToEndOptions& options);

}  // namespace ausbau::bench
