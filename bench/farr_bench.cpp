// ausbau-farr-bench: FARR (thesis 4.3) against plain FCL on the
// configurations a planner actually checks, all measured side by side in one
// run; markdown on stdout and in <output-dir>/farr-summary.md, one CSV row per
// scene in <output-dir>/farr-results.csv.
//
// Per scene:
//   1. plan with FCL (CR-RRTC by default), recording every pose the planner
//      checks and FCL's answer: the sample set (thesis table 10);
//   2. build both distance fields (fresh, no cache): the pre-processing;
//   3. plan again with FARR (adaptive, the default of --collision farr) and
//      with FARR as in the thesis (30 rays on every query), same seed (and,
//      when FCL hit the time limit, the same number of iterations): the
//      whole-planning comparison (table 12), and whether the paths are equal;
//   4. on the sample set: the invalid portion, the detection rate of the rays
//      alone for k = 1, 2, 5, 10, 20, 30, 50 on the invalid samples (fig. 25),
//      the overhead of 30 rays on the valid samples (the worst case, where
//      the rays cannot help), and the collision time of FCL, FARR-30 and
//      adaptive FARR over all samples, replayed in the planner's order in
//      interleaved chunks (table 11).
//
//   ausbau-farr-bench [--scenes a,b,...] [--field-cells 256] [--planner cr-rrtc]
//                     [--seed 1] [--time-limit 60] [--max-samples 200000]
//                     [--repetitions 2] [--threads 0] [--output-dir out/bench-farr]
//
// Scene names: OMPL.app scenes by name (../shared/benchmarks/ompl/<name>.yaml),
// flange-1.00 / flange-0.95 / flange-0.90 (generated, common/fixtures/flange.h),
// parasol-flange-1.0 (../shared/benchmarks/parasol/flange-1.0/, if present).

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "cli/stage_main.h"
#include "collision/distance_field.h"
#include "collision/farr_checker.h"
#include "collision/fcl_checker.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "machine.h"
#include "parse_args.h"
#include "planning/planner.h"
#include "scene/scene.h"

namespace {

using namespace ausbau;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double Seconds(Clock::time_point from) { return std::chrono::duration<double>(Clock::now() - from).count(); }

struct BenchOptions {
  std::vector<std::string> scenes = {"alpha-1.2",   "alpha-1.5",   "Twistycool",        "flange-1.00",
                                     "flange-0.95", "flange-0.90", "parasol-flange-1.0"};
  int resolution = 256;
  std::string planner = "cr-rrtc";
  std::uint64_t seed = 1;
  double time_limit_s = 60;
  std::int64_t max_samples = 200000;
  int reps = 2;
  int threads = 0;
  std::string output_dir = "out/bench-farr";
};

const std::vector<int> kRays = {1, 2, 5, 10, 20, 30, 50};

struct SceneResult {
  std::string name;
  std::string skipped;
  std::size_t robot_triangles = 0, environment_triangles = 0;
  // Planning (table 12).
  bool fcl_solved = false, farr_solved = false, farr30_solved = false, same_path = false, same_path30 = false;
  std::int64_t iterations = 0;
  double fcl_prep_s = 0, fcl_plan_s = 0;
  double build_static_s = 0, build_dynamic_s = 0;
  std::array<int, 3> dims_static{}, dims_dynamic{};
  double farr_plan_s = 0, farr30_plan_s = 0;
  int adaptive_rays_end = 0;
  // Samples (table 10, fig. 25, table 11).
  std::int64_t samples = 0, recorded = 0, invalid = 0;
  std::vector<double> detection;  // per kRays
  double fcl_valid_s = 0, fcl_invalid_s = 0, rays_valid_s = 0, farr30_valid_s = 0, farr30_invalid_s = 0;
  double fcl_all_s = 0, adaptive_all_s = 0;
  std::int64_t valid_count = 0;
};

SceneResult RunScene(const std::string& name, const BenchOptions& options) {
  SceneResult r;
  r.name = name;
  const fs::path yaml = bench::BenchSceneFile(name, options.output_dir, &r.skipped);
  if (yaml.empty()) return r;
  const Scene scene = LoadScene(yaml);
  const PlanningProblem problem = MakePlanningProblem(scene);
  r.robot_triangles = problem.robot.triangles.size();
  r.environment_triangles = problem.environment.triangles.size();
  std::fprintf(stderr, "== %s: D %zu, S %zu triangles\n", name.c_str(), r.robot_triangles, r.environment_triangles);

  // 1. FCL: pre-processing (the BVHs) and planning, recording the samples.
  auto start = Clock::now();
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  r.fcl_prep_s = Seconds(start);
  PlannerOptions planner;
  planner.planner = options.planner;
  planner.seed = options.seed;
  planner.time_limit_s = options.time_limit_s;
  bench::RecordingValidity recorder(fcl);
  start = Clock::now();
  const PlanResult fcl_result = Plan(problem, recorder, planner);
  r.fcl_plan_s = Seconds(start);
  r.fcl_solved = fcl_result.solved();
  r.iterations = fcl_result.stats.iterations;
  std::fprintf(stderr, "   FCL plan: %s in %.2f s, %lld iterations, %zu checks\n", r.fcl_solved ? "solved" : "unsolved",
               r.fcl_plan_s, static_cast<long long>(r.iterations), recorder.poses.size());

  // 2. The distance fields.
  DistanceFieldOptions field_options;
  field_options.resolution = options.resolution;
  field_options.threads = options.threads;
  start = Clock::now();
  const auto static_field = BuildDistanceField(problem.environment, field_options);
  r.build_static_s = Seconds(start);
  start = Clock::now();
  const auto dynamic_field = BuildDistanceField(problem.robot, field_options);
  r.build_dynamic_s = Seconds(start);
  r.dims_static = static_field->dims();
  r.dims_dynamic = dynamic_field->dims();
  std::fprintf(stderr, "   fields: S %.2f s, D %.2f s\n", r.build_static_s, r.build_dynamic_s);

  // 3. Planning with FARR: the same work (same seed; FCL's iteration count
  // when it ran out of time).
  PlannerOptions same = planner;
  if (!r.fcl_solved) {
    same.max_iterations = fcl_result.stats.iterations;
    same.time_limit_s = 1e6;
  }
  FarrOptions thesis;
  thesis.adaptive = false;
  {
    start = Clock::now();
    const FarrCollisionChecker farr(problem.robot, problem.environment, dynamic_field, static_field, options.seed);
    const PlanResult result = Plan(problem, farr, same);
    r.farr_plan_s = Seconds(start);
    r.farr_solved = result.solved();
    r.same_path = bench::SamePath(fcl_result, result);
    r.adaptive_rays_end = farr.stats().rays_now;
  }
  {
    start = Clock::now();
    const FarrCollisionChecker farr(problem.robot, problem.environment, dynamic_field, static_field, options.seed,
                                    thesis);
    const PlanResult result = Plan(problem, farr, same);
    r.farr30_plan_s = Seconds(start);
    r.farr30_solved = result.solved();
    r.same_path30 = bench::SamePath(fcl_result, result);
  }
  std::fprintf(stderr, "   FARR plan: %.2f s (adaptive, %s path), %.2f s (30 rays, %s path)\n", r.farr_plan_s,
               r.same_path ? "same" : "DIFFERENT", r.farr30_plan_s, r.same_path30 ? "same" : "DIFFERENT");

  // 4. The sample set, in the planner's order (evenly thinned to max_samples).
  std::vector<Pose> poses;
  std::vector<char> invalid;
  r.recorded = static_cast<std::int64_t>(recorder.poses.size());
  const double stride = std::max(1.0, static_cast<double>(recorder.poses.size()) / options.max_samples);
  for (double x = 0; x < recorder.poses.size(); x += stride) {
    poses.push_back(recorder.poses[static_cast<std::size_t>(x)]);
    invalid.push_back(recorder.invalid[static_cast<std::size_t>(x)]);
  }
  r.samples = static_cast<std::int64_t>(poses.size());
  std::vector<std::size_t> valid_idx, invalid_idx, all_idx(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    all_idx[i] = i;
    (invalid[i] ? invalid_idx : valid_idx).push_back(i);
  }
  r.invalid = static_cast<std::int64_t>(invalid_idx.size());
  r.valid_count = static_cast<std::int64_t>(valid_idx.size());

  // Detection rate of the rays alone (fig. 25): one complete probe with 50
  // rays gives the lowest ray that finds a witness, hence every k at once.
  {
    FarrOptions fifty = thesis;
    fifty.rays = 50;
    const FarrCollisionChecker farr(problem.robot, problem.environment, dynamic_field, static_field, options.seed,
                                    fifty);
    std::vector<std::int64_t> by_ray(51, 0);
    for (std::size_t i : invalid_idx) {
      const auto probe = farr.Probe(poses[i], 50, true);
      if (probe.witness) ++by_ray[probe.witness_ray];
    }
    std::int64_t cumulative = 0;
    int next = 0;
    for (int k : kRays) {
      for (; next < k; ++next) cumulative += by_ray[next];
      r.detection.push_back(invalid_idx.empty() ? 0.0 : static_cast<double>(cumulative) / invalid_idx.size());
    }
  }

  // Collision time (table 11), interleaved chunks, `reps` times.
  const FarrCollisionChecker farr30(problem.robot, problem.environment, dynamic_field, static_field, options.seed,
                                    thesis);
  auto fcl_check = [&](const Pose& p) { return static_cast<int>(fcl.InCollision(p)); };
  auto farr_check = [&](const Pose& p) { return static_cast<int>(farr30.InCollision(p)); };
  auto rays_check = [&](const Pose& p) { return static_cast<int>(farr30.Probe(p, 30).witness); };
  constexpr std::size_t kChunk = 2000;
  for (int rep = 0; rep < options.reps; ++rep) {
    for (std::size_t b = 0; b < valid_idx.size(); b += kChunk) {
      const std::size_t e = std::min(valid_idx.size(), b + kChunk);
      r.fcl_valid_s += bench::TimeChunk(poses, valid_idx, b, e, fcl_check);
      r.farr30_valid_s += bench::TimeChunk(poses, valid_idx, b, e, farr_check);
      r.rays_valid_s += bench::TimeChunk(poses, valid_idx, b, e, rays_check);
    }
    for (std::size_t b = 0; b < invalid_idx.size(); b += kChunk) {
      const std::size_t e = std::min(invalid_idx.size(), b + kChunk);
      r.fcl_invalid_s += bench::TimeChunk(poses, invalid_idx, b, e, fcl_check);
      r.farr30_invalid_s += bench::TimeChunk(poses, invalid_idx, b, e, farr_check);
    }
    // Adaptive FARR learns along the way: a fresh checker per repetition,
    // the samples in the planner's order, interleaved with FCL.
    const FarrCollisionChecker adaptive(problem.robot, problem.environment, dynamic_field, static_field, options.seed);
    auto adaptive_check = [&](const Pose& p) { return static_cast<int>(adaptive.InCollision(p)); };
    for (std::size_t b = 0; b < all_idx.size(); b += kChunk) {
      const std::size_t e = std::min(all_idx.size(), b + kChunk);
      r.fcl_all_s += bench::TimeChunk(poses, all_idx, b, e, fcl_check);
      r.adaptive_all_s += bench::TimeChunk(poses, all_idx, b, e, adaptive_check);
    }
  }
  for (double* t : {&r.fcl_valid_s, &r.fcl_invalid_s, &r.rays_valid_s, &r.farr30_valid_s, &r.farr30_invalid_s,
                    &r.fcl_all_s, &r.adaptive_all_s}) {
    *t /= options.reps;
  }
  return r;
}

std::string Us(double seconds, std::int64_t count) { return count > 0 ? Fmt("%.2f", 1e6 * seconds / count) : "–"; }
std::string Ratio(double a, double b) { return b > 0 && a > 0 ? Fmt("%.2f", a / b) : "–"; }

std::string Summary(const std::vector<SceneResult>& results, const BenchOptions& options, const std::string& machine,
                    const std::string& date, const std::string& load_start) {
  std::ostringstream md;
  md << "# FARR collision detection against FCL\n\n";
  md << "- Machine: " << machine << "\n";
  md << "- Date: " << date << " (UTC); load average at start " << load_start << ", at end " << bench::LoadAverage()
     << " (the machine may be shared: timings are interleaved in chunks of 2,000 samples and averaged over "
     << options.reps << " repetitions)\n";
  md << "- Planner " << options.planner << ", seed " << options.seed << ", time limit " << options.time_limit_s
     << " s; distance fields at resolution " << options.resolution << "; FARR: k = 30 rays, at most 19 alternations,"
     << " epsilon 6e-6 x D's diagonal (thesis); \"adaptive\" is the default of `--collision farr`\n\n";

  md << "## Sample sets (thesis table 10)\n\n";
  md << "| scene | triangles D / S | samples checked | used | invalid portion |\n|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) {
      md << "| " << r.name << " | skipped: " << r.skipped << " | | | |\n";
      continue;
    }
    md << "| " << r.name << " | " << r.robot_triangles << " / " << r.environment_triangles << " | " << r.recorded
       << " | " << r.samples << " | " << Fmt("%.1f%%", r.samples ? 100.0 * r.invalid / r.samples : 0.0) << " |\n";
  }

  md << "\n## Detection rate of the rays alone on the invalid samples (thesis fig. 25)\n\n| scene |";
  for (int k : kRays) md << " k = " << k << " |";
  md << "\n|---|";
  for (std::size_t i = 0; i < kRays.size(); ++i) md << "---|";
  md << "\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) continue;
    md << "| " << r.name << " |";
    for (double d : r.detection) md << Fmt(" %.1f%%", 100 * d) << " |";
    md << "\n";
  }

  md << "\n## Collision time over the sample set (thesis table 11)\n\n";
  md << "Per sample, microseconds. Overhead: 30 rays on a valid sample (the worst case: they cannot help) "
        "relative to FCL on it. Speedup: FCL's total time over FARR's on all samples.\n\n";
  md << "| scene | FCL valid | FCL invalid | rays on valid (overhead) | FARR-30 valid | FARR-30 invalid | "
        "speedup FARR-30 | speedup on invalid | speedup adaptive |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) continue;
    const double fcl_total = r.fcl_valid_s + r.fcl_invalid_s, farr_total = r.farr30_valid_s + r.farr30_invalid_s;
    md << "| " << r.name << " | " << Us(r.fcl_valid_s, r.valid_count) << " | " << Us(r.fcl_invalid_s, r.invalid)
       << " | " << Us(r.rays_valid_s, r.valid_count)
       << (r.fcl_valid_s > 0 ? Fmt(" (%+.0f%%)", 100 * r.rays_valid_s / r.fcl_valid_s) : std::string()) << " | "
       << Us(r.farr30_valid_s, r.valid_count) << " | " << Us(r.farr30_invalid_s, r.invalid) << " | "
       << Ratio(fcl_total, farr_total) << " | " << Ratio(r.fcl_invalid_s, r.farr30_invalid_s) << " | "
       << Ratio(r.fcl_all_s, r.adaptive_all_s) << " |\n";
  }

  md << "\n## Whole planning (thesis table 12)\n\n";
  md << "Pre-processing: FCL's BVHs; for FARR also both distance fields (fresh, all cores; cells of S / of D). "
        "Planning: the planner's wall time with each checker, same seed (and FCL's iteration count when FCL ran "
        "out of time), so the work is the same: the paths must be equal.\n\n";
  md << "| scene | FCL pre | FCL planning | FCL sum | fields (S + D) | FARR planning | FARR sum | speedup | "
        "FARR-30 planning | speedup FARR-30 | same path |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) continue;
    const double fcl_sum = r.fcl_prep_s + r.fcl_plan_s;
    const double build = r.build_static_s + r.build_dynamic_s;
    const double farr_sum = r.fcl_prep_s + build + r.farr_plan_s;
    const double farr30_sum = r.fcl_prep_s + build + r.farr30_plan_s;
    md << "| " << r.name << (r.fcl_solved ? "" : " (unsolved)") << " | " << Fmt("%.3f s", r.fcl_prep_s) << " | "
       << Fmt("%.2f s", r.fcl_plan_s) << " | " << Fmt("%.2f s", fcl_sum) << " | "
       << Fmt("%.2f + %.2f s (%dx%dx%d / %dx%dx%d)", r.build_static_s, r.build_dynamic_s, r.dims_static[0],
              r.dims_static[1], r.dims_static[2], r.dims_dynamic[0], r.dims_dynamic[1], r.dims_dynamic[2])
       << " | " << Fmt("%.2f s", r.farr_plan_s) << " | " << Fmt("%.2f s", farr_sum) << " | " << Ratio(fcl_sum, farr_sum)
       << " | " << Fmt("%.2f s", r.farr30_plan_s) << " | " << Ratio(fcl_sum, farr30_sum) << " | "
       << (r.same_path && r.same_path30 ? "yes" : "NO") << " |\n";
  }
  md << "\nWithout the pre-processing (fields reused from the cache), the planning speedups are:";
  for (const auto& r : results) {
    if (!r.skipped.empty()) continue;
    md << " " << r.name << " " << Ratio(r.fcl_plan_s, r.farr_plan_s) << " (FARR-30 "
       << Ratio(r.fcl_plan_s, r.farr30_plan_s) << ");";
  }
  md << "\n";
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions options;
  std::string scenes;
  CLI::App app("FARR against FCL on the configurations a planner checks (thesis 4.3)", "ausbau-farr-bench");
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  app.add_option("--scenes", scenes, "comma-separated scene names (see the top of bench/farr_bench.cpp)");
  app.add_option("--field-cells", options.resolution, "distance field: cells along the longest axis")
      ->capture_default_str();
  app.add_option("--planner", options.planner, "planner that generates the samples")->capture_default_str();
  app.add_option("--seed", options.seed, "planner seed")->capture_default_str();
  app.add_option("--time-limit", options.time_limit_s, "planning time limit, seconds")->capture_default_str();
  app.add_option("--max-samples", options.max_samples, "samples replayed per scene (evenly thinned)")
      ->capture_default_str();
  app.add_option("--repetitions", options.reps, "timing repetitions")->capture_default_str();
  AddRenamedFlag(app, "--reps", "--repetitions");
  AddRenamedFlag(app, "--resolution", "--field-cells");
  app.add_option("--threads", options.threads, "field construction threads; 0 = all cores")
      ->capture_default_str()
      ->check(ThreadCount());
  app.add_option("--output-dir", options.output_dir, "where farr-summary.md and farr-results.csv go")
      ->capture_default_str();
  if (const int code = ausbau::bench::ParseArguments(app, argc, argv); code >= 0) return code;
  if (!scenes.empty()) {
    options.scenes.clear();
    std::stringstream list(scenes);
    for (std::string name; std::getline(list, name, ',');) {
      if (!name.empty()) options.scenes.push_back(name);
    }
  }
  if (options.reps < 1 || options.max_samples < 1) {
    std::fprintf(stderr, "ausbau-farr-bench: error: --repetitions and --max-samples must be positive\n");
    return 2;
  }
  SetLogProgramName("ausbau-farr-bench");
  SetLogLevel(LogLevel::kWarn);
  const std::string machine = bench::MachineLine(bench::DescribeMachine());
  const std::string date = bench::NowIsoUtc(), load_start = bench::LoadAverage();
  std::vector<SceneResult> results;
  try {
    fs::create_directories(options.output_dir);
    for (const std::string& name : options.scenes) results.push_back(RunScene(name, options));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ausbau-farr-bench: error: %s\n", e.what());
    return 1;
  }
  const std::string summary = Summary(results, options, machine, date, load_start);
  std::ofstream(fs::path(options.output_dir) / "farr-summary.md") << summary;
  std::ofstream csv(fs::path(options.output_dir) / "farr-results.csv");
  csv << "scene,robot_triangles,environment_triangles,samples,invalid,";
  for (int k : kRays) csv << "detection_k" << k << ",";
  csv << "fcl_valid_s,fcl_invalid_s,rays_valid_s,farr30_valid_s,farr30_invalid_s,fcl_all_s,adaptive_all_s,"
         "fcl_prep_s,fcl_plan_s,build_static_s,build_dynamic_s,farr_plan_s,farr30_plan_s,fcl_solved,same_path\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) continue;
    csv << r.name << "," << r.robot_triangles << "," << r.environment_triangles << "," << r.samples << "," << r.invalid
        << ",";
    for (double d : r.detection) csv << d << ",";
    csv << r.fcl_valid_s << "," << r.fcl_invalid_s << "," << r.rays_valid_s << "," << r.farr30_valid_s << ","
        << r.farr30_invalid_s << "," << r.fcl_all_s << "," << r.adaptive_all_s << "," << r.fcl_prep_s << ","
        << r.fcl_plan_s << "," << r.build_static_s << "," << r.build_dynamic_s << "," << r.farr_plan_s << ","
        << r.farr30_plan_s << "," << r.fcl_solved << "," << (r.same_path && r.same_path30) << "\n";
  }
  std::fputs(summary.c_str(), stdout);
  return 0;
}
