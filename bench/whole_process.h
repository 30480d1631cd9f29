// Ausbau's planner as a user runs it: the ausbau-plan executable with its
// default flags, one process per run, timed from spawn to exit. This is
// what issue 29's ratios mean by "whole process": loading and preparing the
// meshes, planning, certification and the dense re-check, and writing the
// artifact all count against Ausbau, while OMPL is timed around its solve()
// only (so the ratio is a lower bound of Ausbau's advantage).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "planning/planner.h"

namespace ausbau::bench {

struct WholeProcessRun {
  bool solved = false;     // exit 0 and a path artifact that says so
  double time_s = 0;       // wall clock, spawn to exit
  int exit_code = -1;      // the process's exit status (-1: killed or not started)
  std::string failure;     // why not solved (exit code, signal, missing file), empty when solved
  std::vector<Pose> path;  // scene convention (as written), empty unless solved
  PlanStats stats;         // from the artifact
};

// Runs `ausbau_plan --scene scene --seed seed --time-limit limit -o artifact
// --csv csv --force`, with stdout and stderr going to `log`. No shell is involved:
// names are passed as argv. A process still running after `kill_after_s`
// is killed (a hang must not stop the benchmark; such a run is a failure).
WholeProcessRun RunAusbauPlan(const std::filesystem::path& ausbau_plan, const std::filesystem::path& scene,
                              std::uint64_t seed, double time_limit_s, const std::filesystem::path& artifact,
                              const std::filesystem::path& csv, const std::filesystem::path& log, double kill_after_s);

// The folder of the running executable (/proc/self/exe), where the other
// stages of the same build lie.
std::filesystem::path OwnBinDir();

}  // namespace ausbau::bench
