// ausbau-collision-bench: the collision check of --validity collision
// (FclCollisionChecker::InCollision: FCL's trees walked by
// collision/fcl_tree_walk.h) against FCL's own collide on the same trees,
// on the poses a planner actually checks, side by side in one run.
// Markdown on stdout and in <output-dir>/collision-summary.md.
//
// Per scene:
//   1. plan with FCL's collide as the validity (CR-RRTC, the given seed and
//      time limit), recording every pose checked and FCL's answer;
//   2. replay those poses (evenly thinned to --max-samples) through both
//      checks, in interleaved chunks of 2,000, --repetitions times, and count
//      the poses on which the two answers differ (must be 0);
//   3. plan again with each as the validity, same seed: the whole planning
//      time, and whether the two paths are equal (they must be: the same
//      answers on every pose).
//
//   ausbau-collision-bench [--scenes a,b,...] [--seed 1] [--time-limit 30]
//                          [--max-samples 200000] [--repetitions 3]
//                          [--output-dir out/bench-collision]
//
// Scene names: OMPL.app scenes by name (../shared/benchmarks/ompl/<name>.yaml),
// parasol-flange-1.0, flange-<scale> (generated; bench/bench_scenes.h).

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_scenes.h"
#include "collision/fcl_checker.h"
#include "core/format.h"
#include "core/log.h"
#include "fcl_collide_validity.h"
#include "machine.h"
#include "parse_args.h"
#include "planning/planner.h"
#include "scene/scene.h"
#include "split_list.h"

namespace {

using namespace ausbau;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

double Seconds(Clock::time_point from) { return std::chrono::duration<double>(Clock::now() - from).count(); }

// The walk alone as the validity: no proofs of whole motions (which
// FclCollisionChecker also makes), which would hide the per-pose cost.
// FclCollideValidity (fcl_collide_validity.h) is the same for fcl::collide.
class WalkOnly : public PoseValidity {
 public:
  explicit WalkOnly(const FclCollisionChecker& checker) : checker_(checker) {}

 protected:
  bool CheckValid(const Pose& pose) const override { return !checker_.InCollision(pose); }

 private:
  const FclCollisionChecker& checker_;
};

struct BenchOptions {
  std::vector<std::string> scenes = {"cubicles", "alpha-1.5", "Apartment", "Easy", "Home", "Twistycool", "Abstract"};
  std::uint64_t seed = 1;
  double time_limit_s = 30;
  std::int64_t max_samples = 200000;
  int reps = 3;
  std::string output_dir = "out/bench-collision";
};

struct SceneResult {
  std::string name, skipped;
  std::size_t robot_triangles = 0, environment_triangles = 0;
  std::int64_t samples = 0, invalid = 0, disagreements = 0;
  double fcl_s = 0, walk_s = 0;            // replay, per repetition
  double fcl_plan_s = 0, walk_plan_s = 0;  // whole planning, same seed
  bool fcl_solved = false, walk_solved = false, same_path = false;
};

SceneResult RunScene(const std::string& name, const BenchOptions& options) {
  SceneResult r;
  r.name = name;
  const fs::path yaml = bench::BenchSceneFile(name, options.output_dir, &r.skipped);
  if (yaml.empty()) return r;
  const PlanningProblem problem = MakePlanningProblem(LoadScene(yaml));
  r.robot_triangles = problem.robot.triangles.size();
  r.environment_triangles = problem.environment.triangles.size();
  std::fprintf(stderr, "== %s: D %zu, S %zu triangles\n", name.c_str(), r.robot_triangles, r.environment_triangles);

  const FclCollisionChecker checker(problem.robot, problem.environment);

  PlannerOptions planner;
  planner.seed = options.seed;
  planner.time_limit_s = options.time_limit_s;
  planner.coarse_iterations = CoarseFirstIterationsFor(planner.planner);
  const bench::FclCollideValidity fcl_collide(checker);
  bench::RecordingValidity fcl_validity(fcl_collide);
  auto start = Clock::now();
  const PlanResult fcl_result = Plan(problem, fcl_validity, planner);
  r.fcl_plan_s = Seconds(start);
  r.fcl_solved = fcl_result.solved();
  // The same work for the second plan (FCL's iterations where it ran out of time).
  PlannerOptions same = planner;
  if (!r.fcl_solved) {
    same.max_iterations = fcl_result.stats.iterations;
    same.time_limit_s = 1e6;
  }
  const WalkOnly walk_validity(checker);
  start = Clock::now();
  const PlanResult walk_result = Plan(problem, walk_validity, same);
  r.walk_plan_s = Seconds(start);
  r.walk_solved = walk_result.solved();
  r.same_path = bench::SamePath(fcl_result, walk_result);
  std::fprintf(stderr, "   plan: FCL %.2f s, tree walk %.2f s, %s path; %zu poses checked\n", r.fcl_plan_s,
               r.walk_plan_s, r.same_path ? "same" : "DIFFERENT", fcl_validity.poses.size());

  std::vector<Pose> poses;
  std::vector<char> collides;
  const double stride = std::max(1.0, static_cast<double>(fcl_validity.poses.size()) / options.max_samples);
  for (double x = 0; x < fcl_validity.poses.size(); x += stride) {
    poses.push_back(fcl_validity.poses[static_cast<std::size_t>(x)]);
    collides.push_back(fcl_validity.invalid[static_cast<std::size_t>(x)]);
  }
  r.samples = static_cast<std::int64_t>(poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    r.invalid += collides[i];
    r.disagreements += checker.InCollision(poses[i]) != static_cast<bool>(collides[i]);
  }
  std::vector<std::size_t> order(poses.size());  // the planner's order
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto fcl_check = [&](const Pose& p) { return static_cast<int>(checker.InCollisionByFclCollide(p)); };
  auto walk_check = [&](const Pose& p) { return static_cast<int>(checker.InCollision(p)); };
  constexpr std::size_t kChunk = 2000;
  for (int rep = 0; rep < options.reps; ++rep) {
    for (std::size_t b = 0; b < poses.size(); b += kChunk) {
      const std::size_t e = std::min(poses.size(), b + kChunk);
      r.fcl_s += bench::TimeChunk(poses, order, b, e, fcl_check);
      r.walk_s += bench::TimeChunk(poses, order, b, e, walk_check);
    }
  }
  r.fcl_s /= options.reps;
  r.walk_s /= options.reps;
  return r;
}

std::string Us(double seconds, std::int64_t count) { return count > 0 ? Fmt("%.2f", 1e6 * seconds / count) : "–"; }
std::string Ratio(double a, double b) { return b > 0 && a > 0 ? Fmt("%.2f", a / b) : "–"; }

std::string Summary(const std::vector<SceneResult>& results, const BenchOptions& options, const std::string& machine,
                    const std::string& load_start) {
  std::ostringstream md;
  md << "# The collision check (tree walk) against FCL's collide\n\n";
  md << "- Machine: " << machine << "\n";
  md << "- Load average at start " << load_start << ", at end " << bench::LoadAverage()
     << " (timings interleaved in chunks of 2,000 poses, averaged over " << options.reps << " repetitions)\n";
  md << "- Poses: those CR-RRTC checks planning with FCL's collide (seed " << options.seed << ", time limit "
     << options.time_limit_s << " s), thinned to at most " << options.max_samples << "\n\n";
  md << "| scene | triangles D / S | poses | in collision | differing answers | FCL us/pose | tree walk us/pose "
        "| speedup | plan FCL / walk s | plan speedup | same path |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    if (!r.skipped.empty()) {
      md << "| " << r.name << " | skipped: " << r.skipped << " ||||||||||\n";
      continue;
    }
    md << "| " << r.name << " | " << r.robot_triangles << " / " << r.environment_triangles << " | " << r.samples
       << " | " << Fmt("%.1f%%", r.samples ? 100.0 * r.invalid / r.samples : 0.0) << " | " << r.disagreements << " | "
       << Us(r.fcl_s, r.samples) << " | " << Us(r.walk_s, r.samples) << " | " << Ratio(r.fcl_s, r.walk_s) << " | "
       << Fmt("%.2f / %.2f", r.fcl_plan_s, r.walk_plan_s) << " | " << Ratio(r.fcl_plan_s, r.walk_plan_s) << " | "
       << (r.same_path ? "yes" : "NO") << " |\n";
  }
  return md.str();
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions options;
  std::string scenes;
  CLI::App app("The collision check (tree walk) against FCL's collide on the poses a planner checks",
               "ausbau-collision-bench");
  app.set_version_flag("--version", std::string(AUSBAU_VERSION));
  app.add_option("--scenes", scenes, "comma-separated scene names (see the top of bench/collision_bench.cpp)");
  app.add_option("--seed", options.seed, "planner seed")->capture_default_str();
  app.add_option("--time-limit", options.time_limit_s, "planning time limit, seconds")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-samples", options.max_samples, "poses replayed per scene (evenly thinned)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--repetitions", options.reps, "timing repetitions")->capture_default_str()->check(CLI::Range(1, 100));
  app.add_option("--output-dir", options.output_dir, "where collision-summary.md goes")->capture_default_str();
  if (const int code = ausbau::bench::ParseArguments(app, argc, argv); code >= 0) return code;
  if (!scenes.empty()) options.scenes = bench::SplitList(scenes);
  SetLogProgramName("ausbau-collision-bench");
  SetLogLevel(LogLevel::kWarn);
  const std::string machine = bench::MachineLine(bench::DescribeMachine());
  const std::string load_start = bench::LoadAverage();
  std::vector<SceneResult> results;
  try {
    fs::create_directories(options.output_dir);
    for (const std::string& name : options.scenes) results.push_back(RunScene(name, options));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ausbau-collision-bench: error: %s\n", e.what());
    return 1;
  }
  const std::string summary = Summary(results, options, machine, load_start);
  std::ofstream(fs::path(options.output_dir) / "collision-summary.md") << summary;
  std::fputs(summary.c_str(), stdout);
  for (const auto& r : results) {
    if (r.skipped.empty() && (r.disagreements > 0 || !r.same_path)) {
      std::fprintf(stderr, "ausbau-collision-bench: error: the tree walk and FCL disagree on %s\n", r.name.c_str());
      return 1;
    }
  }
  return 0;
}
