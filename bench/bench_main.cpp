// ausbau-bench: Ausbau's planners side by side with OMPL's RRT-Connect on
// the OMPL.app scenes, in one process, on the same collision checker; and
// (--study) the RRTC parameter study of thesis 3.3.1. See docs/benchmarks.md,
// section "Benchmarks".
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>

#include "bench_report.h"
#include "cli/stage_main.h"
#include "collision/fcl_checker.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/random.h"
#include "fcl_collide_validity.h"
#include "ompl_rrtc.h"
#include "planning/dense_check.h"
#include "planning/planner.h"
#include "planning/state_space.h"
#include "scene/scene.h"
#include "speedup_check.h"
#include "split_list.h"
#include "whole_process.h"

#ifndef AUSBAU_SOURCE_DIR
#define AUSBAU_SOURCE_DIR "."
#endif

namespace ausbau::bench {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* kDefaultScenes = "alpha-1.5,alpha-1.2,Apartment,Home,Easy,Twistycool";
constexpr double kDenseStep = 0.01;  // dense re-check step: 1% of D's diagonal

struct Options {
  std::string scenes = kDefaultScenes;
  std::string benchmarks_dir = std::string(AUSBAU_SOURCE_DIR) + "/../shared/benchmarks/ompl";
  std::string planners = "rrtc,cr-rrtc,est";
  int runs = 10;
  double time_limit_s = 60;
  std::uint64_t seed = 1;
  std::string output_dir = "out/bench";
  bool study = false;
  bool no_ompl = false;
  std::string ompl_ranges = "default,1%,5%,cfg";
  std::string ompl_resolution = "matched";
  double resolution = PlannerOptions{}.resolution;
  std::string bin_dir;   // where ausbau-plan lies (--planners ausbau-plan); empty: this executable's folder
  std::string recorded;  // speedups.csv to check against (--recorded); empty: no check
  std::string command_line;
};

// The regression gate: a speed-up below this share of the recorded one fails.
constexpr double kRecordedShare = 0.5;
// The planner name that runs the ausbau-plan executable (whole process).
constexpr char kWholeProcess[] = "ausbau-plan";

struct SceneSpec {
  std::string name;  // a label; the scene's name is used once loaded
  fs::path file;
};

// A name without '/' and without ".yaml" is <benchmarks-dir>/<name>.yaml.
std::vector<SceneSpec> ResolveScenes(const Options& options) {
  std::vector<SceneSpec> specs;
  for (const std::string& item : SplitList(options.scenes)) {
    SceneSpec spec;
    const bool is_path = item.find('/') != std::string::npos || fs::path(item).extension() == ".yaml";
    spec.file = is_path ? fs::path(item) : fs::path(options.benchmarks_dir) / (item + ".yaml");
    spec.name = fs::path(item).stem().string();
    if (!fs::is_regular_file(spec.file)) {
      throw InputErrorAt(spec.file.string(), "scene file not found (--scenes, --benchmarks-dir)");
    }
    specs.push_back(spec);
  }
  if (specs.empty()) throw InputError("--scenes: no scene given");
  return specs;
}

// "rrtc" (Def-RRTC defaults), "rrtc:U:R" (fixed u and range_max), or any
// planner name the library may know ("cr-rrtc", "est", ...).
struct PlannerSpec {
  std::string label;
  PlannerOptions options;
};

std::string Upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

std::vector<PlannerSpec> ParsePlanners(const Options& options) {
  std::vector<PlannerSpec> specs;
  for (const std::string& item : SplitList(options.planners)) {
    PlannerSpec spec;
    std::vector<std::string> parts;
    std::stringstream stream(item);
    std::string part;
    while (std::getline(stream, part, ':')) parts.push_back(part);
    spec.options.planner = parts[0];
    spec.options.resolution = options.resolution;
    // As ausbau-plan's collision validity (workflow/plan_scene.cpp, ResolvedPlanner).
    spec.options.coarse_iterations = CoarseFirstIterationsFor(parts[0]);
    if (parts[0] == "rrtc" && parts.size() == 3) {
      try {
        spec.options.u = std::stod(parts[1]);
        spec.options.range_max = std::stod(parts[2]);
      } catch (const std::exception&) {
        throw InputError("--planners: '" + item + "' is not rrtc:U:RANGE_MAX");
      }
      spec.label = Fmt("Opt-RRTC u%g r%g", spec.options.u, spec.options.range_max);
    } else if (parts.size() != 1) {
      throw InputError("--planners: '" + item + "' (expected a planner name, or rrtc:U:RANGE_MAX)");
    } else if (parts[0] == "rrtc") {
      spec.label = "Def-RRTC";
    } else if (parts[0] == "cr-rrtc") {
      spec.label = "CR-RRTC";
    } else if (parts[0] == kWholeProcess) {
      spec.label = kWholeProcess;
    } else {
      spec.label = Upper(parts[0]);
    }
    specs.push_back(spec);
  }
  if (specs.empty()) throw InputError("--planners: no planner given");
  return specs;
}

// OMPL ranges: "default" (no setRange), "N%" of the maximum extent, "cfg"
// (rrt.range of the scene's OMPL.app .cfg next to the yaml, when it has
// one), or an absolute number.
struct OmplRangeSpec {
  std::string label;
  double range = 0;  // 0 = default
};

std::optional<double> CfgRange(const fs::path& scene_file) {
  fs::path cfg = scene_file;
  cfg.replace_extension(".cfg");
  std::ifstream in(cfg);
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string key = line.substr(0, eq);
    key.erase(key.find_last_not_of(" \t") + 1);
    key.erase(0, key.find_first_not_of(" \t"));
    if (key != "rrt.range") continue;
    try {
      return std::stod(line.substr(eq + 1));
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return std::nullopt;
}

std::vector<OmplRangeSpec> OmplRanges(const Options& options, double extent, const fs::path& scene_file) {
  std::vector<OmplRangeSpec> specs;
  for (const std::string& item : SplitList(options.ompl_ranges)) {
    OmplRangeSpec spec;
    if (item == "default") {
      spec.label = "OMPL default";
    } else if (item == "cfg") {
      const std::optional<double> range = CfgRange(scene_file);
      if (!range) continue;
      spec.label = Fmt("OMPL cfg range %g", *range);
      spec.range = *range;
    } else {
      try {
        if (item.back() == '%') {
          const double pct = std::stod(item.substr(0, item.size() - 1));
          spec.label = Fmt("OMPL %g%%", pct);
          spec.range = pct / 100.0 * extent;
        } else {
          spec.range = std::stod(item);
          spec.label = Fmt("OMPL range %g", spec.range);
        }
      } catch (const std::exception&) {
        throw InputError("--ompl-ranges: '" + item + "' (expected default, N%, cfg or a number)");
      }
      if (!(spec.range > 0)) throw InputError("--ompl-ranges: '" + item + "' must be positive");
    }
    specs.push_back(spec);
  }
  return specs;
}

// A loaded scene with its problem and the collision checks: ours
// (FclCollisionChecker, FCL's trees walked by collision/fcl_tree_walk.h) and
// OMPL's (FCL's own collide on the same trees, as OMPL.app checks poses).
// The same answers on every pose; the time each side's check takes is part
// of what the ratios measure.
struct LoadedScene {
  Scene scene;
  PlanningProblem problem;
  std::unique_ptr<FclCollisionChecker> checker;
  std::unique_ptr<FclCollideValidity> ompl_validity;
};

std::unique_ptr<LoadedScene> Load(const SceneSpec& spec) {
  auto loaded = std::make_unique<LoadedScene>();
  loaded->scene = LoadScene(spec.file);
  loaded->problem = MakePlanningProblem(loaded->scene);
  loaded->checker = std::make_unique<FclCollisionChecker>(loaded->problem.robot, loaded->problem.environment);
  loaded->ompl_validity = std::make_unique<FclCollideValidity>(*loaded->checker);
  CheckEndpoints(loaded->problem, *loaded->checker, spec.file.string());
  return loaded;
}

std::string SceneName(const SceneSpec& spec, const LoadedScene* loaded) {
  return (loaded && !loaded->scene.name.empty()) ? loaded->scene.name : spec.name;
}

// Dense re-check of a path in the scene convention: 1 ok, 0 bad.
int DenseCheckScene(const LoadedScene& s, const std::vector<Pose>& waypoints, std::string* reason) {
  const DenseCheckReport report = DenseCheckPath(s.scene, s.problem.reference_point, waypoints, kDenseStep);
  if (!report.valid) *reason = "segment " + std::to_string(report.first_bad_segment) + ": " + report.reason;
  return report.valid ? 1 : 0;
}

// Dense re-check of a path in the planning convention: 1 ok, 0 bad.
int DenseCheck(const LoadedScene& s, const std::vector<Pose>& path, std::string* reason) {
  std::vector<Pose> waypoints;
  waypoints.reserve(path.size());
  for (const Pose& p : path) waypoints.push_back(s.problem.PlanningToScene(p));
  return DenseCheckScene(s, waypoints, reason);
}

void PrintProgress(const RunRecord& r, int index, int total, const std::string& extra) {
  std::fprintf(stderr, "[%s %d/%d] %-18s seed %3llu  %-7s %9.3f s %11lld checks %9lld nodes%s\n", r.scene.c_str(),
               index, total, r.label.c_str(), static_cast<unsigned long long>(r.seed), r.success ? "solved" : "failed",
               r.time_s, static_cast<long long>(r.collision_checks), static_cast<long long>(r.nodes), extra.c_str());
}

std::string ReferenceFacts(const LoadedScene& s) {
  const PlanningProblem& p = s.problem;
  return Fmt(
      "S: %zu triangles, D: %zu triangles; D's AABB diagonal %.4g, radius about the reference point %.4g; "
      "translation bounds diagonal %.4g; goal: %s.",
      p.environment.triangles.size(), p.robot.triangles.size(), p.robot_diagonal, p.robot_radius, p.bounds.Diagonal(),
      p.goal ? "a pose" : "disassembly region");
}

// How the two edge checks compare on random edges (uniform pairs shortened to
// a uniform fraction): checked poses per edge, OMPL / Ausbau, and the largest
// displacement bound of a vertex of D per OMPL segment, in Ausbau steps.
std::string EdgeCheckFacts(const PlanningProblem& problem, const PoseValidity& validity, const OmplRrtConnect& ompl,
                           double step) {
  const MotionChecker motion(problem, validity, step);
  Random random(12345);
  double ours = 0, theirs = 0, worst = 0;
  const int pairs = 2000;
  for (int i = 0; i < pairs; ++i) {
    const Pose a = problem.SampleUniform(random);
    const Pose b = Interpolate(a, problem.SampleUniform(random), random.UniformOpen01());
    const int n_ours = motion.Steps(a, b);
    const unsigned int n_ompl = std::max(1u, ompl.SegmentCount(a, b));
    ours += n_ours;
    theirs += n_ompl;
    worst = std::max(worst, MaxDisplacement(a, b, problem.robot_radius) / n_ompl / step);
  }
  return Fmt(
      "Edge checks on %d random edges: OMPL checks %.2f x as many poses as Ausbau; a vertex of D moves at "
      "most %.2f Ausbau steps between OMPL's checked poses.",
      pairs, theirs / std::max(1.0, ours), worst);
}

// ---- the side-by-side benchmark ----

int RunBenchmark(const Options& options) {
  const std::vector<SceneSpec> scene_specs = ResolveScenes(options);
  const std::vector<PlannerSpec> planner_specs = ParsePlanners(options);
  const OmplResolution ompl_resolution = ParseOmplResolution(options.ompl_resolution);
  const fs::path bin_dir = options.bin_dir.empty() ? OwnBinDir() : fs::path(options.bin_dir);
  for (const PlannerSpec& p : planner_specs) {
    if (p.options.planner == kWholeProcess && !fs::is_regular_file(bin_dir / kWholeProcess)) {
      throw InputErrorAt((bin_dir / kWholeProcess).string(), "not found (build it, or give --bin)");
    }
  }
  // Read before any run, so that a bad file fails in a second, not after an hour.
  const std::vector<RecordedSpeedup> recorded =
      options.recorded.empty() ? std::vector<RecordedSpeedup>{} : ReadRecordedSpeedups(options.recorded);
  fs::create_directories(options.output_dir);
  const fs::path out_dir(options.output_dir);

  MachineInfo machine = DescribeMachine();
  machine.ompl = OmplVersion();
  BenchSettings settings;
  settings.runs = options.runs;
  settings.time_limit_s = options.time_limit_s;
  settings.first_seed = options.seed;
  settings.ompl_seed = static_cast<std::uint32_t>(options.seed);
  settings.resolution = options.resolution;
  settings.ompl_resolution = options.no_ompl ? "not run (--no-ompl)" : options.ompl_resolution;
  settings.command_line = options.command_line;
  const std::string status_enum = OmplStatusEnumLine();

  ResultsCsv csv(out_dir / "results.csv");
  std::vector<SceneResult> results;
  results.reserve(scene_specs.size());
  for (std::size_t si = 0; si < scene_specs.size(); ++si) {
    const SceneSpec& spec = scene_specs[si];
    results.emplace_back();
    SceneResult& result = results.back();
    result.file = spec.file.string();
    result.started_iso = NowIsoUtc();
    const auto scene_begin = Clock::now();
    std::unique_ptr<LoadedScene> loaded;
    try {
      loaded = Load(spec);
    } catch (const InputError& e) {
      result.name = spec.name;
      result.notes.push_back(std::string("scene not run: ") + e.what());
      std::fprintf(stderr, "ausbau-bench: scene %s not run: %s\n", spec.name.c_str(), e.what());
      continue;
    }
    result.loaded = true;
    result.name = SceneName(spec, loaded.get());
    const PlanningProblem& problem = loaded->problem;
    const double step = options.resolution * problem.robot_diagonal;
    result.facts.push_back("Scene file `" + spec.file.string() + "`. " + ReferenceFacts(*loaded));

    // Our planners.
    for (const PlannerSpec& p : planner_specs) {
      ConfigInfo c;
      c.label = p.label;
      c.log_name = "ausbau_" + SafeName(p.label);
      c.settings = {{"planner", p.options.planner}};
      if (p.options.planner == kWholeProcess) {
        c.settings = {{"planner", "ausbau-plan executable, default flags (whole process)"}};
        result.configs.push_back(c);
        continue;
      }
      if (p.options.planner == "rrtc") {
        c.settings.emplace_back("u", Fmt("%g", p.options.u));
        c.settings.emplace_back("range_max", Fmt("%g", p.options.range_max));
      } else if (p.options.planner == "cr-rrtc") {
        c.settings.emplace_back("u", "U(0,1) per extension");
        c.settings.emplace_back("range_max", "U(0,1) per extension");
      }
      c.settings.emplace_back("resolution", Fmt("%g", p.options.resolution));
      result.configs.push_back(c);
    }
    // OMPL.
    std::unique_ptr<OmplRrtConnect> ompl;
    std::vector<OmplRangeSpec> ranges;
    if (options.no_ompl) {
      result.notes.push_back("OMPL not run (--no-ompl).");
    } else if (!problem.goal) {
      result.notes.push_back("OMPL not run: the scene has no goal pose (disassembly region).");
    } else {
      ompl = std::make_unique<OmplRrtConnect>(problem, *loaded->ompl_validity, step, ompl_resolution);
      ranges = OmplRanges(options, ompl->MaximumExtent(), spec.file);
      for (const OmplRangeSpec& r : ranges) {
        ConfigInfo c;
        c.label = r.label;
        c.ompl = true;
        c.log_name = "geometric_RRTConnect_" + SafeName(r.label.substr(5));
        const double range = r.range > 0 ? r.range : ompl->DefaultRange();
        c.settings = {{"range", Fmt("%.6g", range)}};
        if (ompl_resolution == OmplResolution::kExact) {
          c.settings.emplace_back("motion_validator", Fmt("ausbau-exact step %.6g", step));
        } else {
          c.settings.emplace_back("longest_valid_segment_fraction", Fmt("%.6g", ompl->SegmentFraction()));
        }
        result.configs.push_back(c);
      }
      const std::string edge_mode = ompl_resolution == OmplResolution::kExact
                                        ? std::string("motion validator stepping like Ausbau's (mode exact)")
                                        : Fmt("longest valid segment fraction %.4g (mode %s)", ompl->SegmentFraction(),
                                              options.ompl_resolution.c_str());
      result.facts.push_back(
          Fmt("OMPL: maximum extent %.4g, default range (0.2 x extent) %.4g; %s; Ausbau's step "
              "%.4g = %g%% of D's diagonal.",
              ompl->MaximumExtent(), ompl->DefaultRange(), edge_mode.c_str(), step, options.resolution * 100));
      result.facts.push_back(EdgeCheckFacts(problem, *loaded->checker, *ompl, step));
      if (problem.bounded_point.norm() > 1e-9) {
        result.notes.push_back(
            "The scene's bounds apply to a point other than the reference point; OMPL samples "
            "the reference point in the box, validity uses the scene's bounds.");
      }
    }

    // Runs: seed by seed, every configuration once per seed (interleaved, so
    // a change of background load hits all configurations alike).
    const int per_seed = static_cast<int>(result.configs.size());
    const int total = per_seed * options.runs;
    int index = 0;
    for (int i = 0; i < options.runs; ++i) {
      const std::uint64_t seed = options.seed + static_cast<std::uint64_t>(i);
      for (std::size_t k = 0; k < result.configs.size(); ++k) {
        ConfigInfo& config = result.configs[k];
        ++index;
        if (!config.skipped.empty()) continue;
        RunRecord r;
        r.scene = result.name;
        r.label = config.label;
        r.seed = seed;
        std::vector<Pose> path;        // planning convention (this process's planners, OMPL)
        std::vector<Pose> scene_path;  // scene convention (ausbau-plan's artifact)
        std::string extra;
        if (!config.ompl && planner_specs[k].options.planner == kWholeProcess) {
          const fs::path runs_dir = out_dir / "ausbau-plan";
          fs::create_directories(runs_dir);
          const std::string stem = SafeName(result.name) + "-seed" + std::to_string(seed);
          // A hang guard only: ausbau-plan stops itself at its time limit.
          const double kill_after_s = 3 * options.time_limit_s + 60;
          const WholeProcessRun run =
              RunAusbauPlan(bin_dir / kWholeProcess, spec.file, seed, options.time_limit_s, runs_dir / (stem + ".h5"),
                            runs_dir / (stem + ".csv"), runs_dir / (stem + ".log"), kill_after_s);
          r.time_s = run.time_s;
          r.success = run.solved;
          r.status = r.success ? OmplStatusExactSolution() : OmplStatusTimeout();
          r.collision_checks = run.stats.collision_checks;
          r.iterations = run.stats.iterations;
          r.nodes = run.stats.nodes;
          if (!run.solved) extra = "  " + run.failure;
          scene_path = run.path;
        } else if (!config.ompl) {
          PlannerOptions o = planner_specs[k].options;
          o.seed = seed;
          o.time_limit_s = options.time_limit_s;
          try {
            const auto begin = Clock::now();
            const PlanResult plan = Plan(problem, *loaded->checker, o);
            r.time_s = std::chrono::duration<double>(Clock::now() - begin).count();
            r.success = plan.solved();
            r.status = r.success ? OmplStatusExactSolution() : OmplStatusTimeout();
            r.collision_checks = plan.stats.collision_checks;
            r.iterations = plan.stats.iterations;
            r.nodes = plan.stats.nodes;
            path = plan.path;
          } catch (const InputError& e) {
            config.skipped = e.what();
            std::fprintf(stderr, "[%s] %s skipped: %s\n", result.name.c_str(), config.label.c_str(), e.what());
            continue;
          } catch (const std::exception& e) {
            if (config.error.empty()) config.error = e.what();
            r.success = false;
            r.status = OmplStatusTimeout();
            r.time_s = options.time_limit_s;
            extra = std::string("  error: ") + e.what();
          }
        } else {
          const OmplRangeSpec& range = ranges[k - planner_specs.size()];
          const OmplRun run = ompl->Solve(range.range, options.time_limit_s);
          r.time_s = run.time_s;
          r.success = run.solved;
          r.status = run.status;
          r.collision_checks = run.collision_checks;
          r.nodes = run.nodes;
          path = run.path;
        }
        if (r.success) {
          std::string reason;
          r.dense_check =
              scene_path.empty() ? DenseCheck(*loaded, path, &reason) : DenseCheckScene(*loaded, scene_path, &reason);
          if (!r.dense_check) extra += "  BAD PATH (dense re-check: " + reason + ")";
        }
        result.runs.push_back(r);
        csv.Add(r);
        PrintProgress(r, index, total, extra);
      }
    }
    result.wall_s = std::chrono::duration<double>(Clock::now() - scene_begin).count();

    // This scene's OMPL benchmark log.
    std::vector<LogPlanner> log_planners;
    for (const ConfigInfo& c : result.configs) {
      if (!c.skipped.empty()) continue;
      LogPlanner lp{c.log_name, &c, {}};
      for (const RunRecord& r : result.runs) {
        if (r.label == c.label) lp.runs.push_back(&r);
      }
      log_planners.push_back(lp);
    }
    std::string setup = "ausbau-bench, scene " + result.name + " (" + result.file + ")\n";
    for (const std::string& f : result.facts) setup += f + "\n";
    if (!log_planners.empty()) {  // like OMPL, no log without data
      WriteOmplLog(out_dir / ("ompl-benchmark-" + SafeName(result.name) + ".log"), result.name, machine, settings,
                   setup, result.started_iso, result.wall_s, status_enum, log_planners);
    }
  }

  // All scenes in one log: one experiment, planners named <scene>_<planner>.
  {
    std::vector<LogPlanner> planners;
    std::string setup = "ausbau-bench, all scenes; planner names are <scene>_<planner>\n";
    double total = 0;
    for (const SceneResult& result : results) {
      total += result.wall_s;
      if (!result.loaded) continue;
      for (const std::string& f : result.facts) setup += result.name + ": " + f + "\n";
      for (const ConfigInfo& c : result.configs) {
        if (!c.skipped.empty()) continue;
        LogPlanner lp{SafeName(result.name) + "_" + c.log_name, &c, {}};
        for (const RunRecord& r : result.runs) {
          if (r.label == c.label) lp.runs.push_back(&r);
        }
        planners.push_back(lp);
      }
    }
    if (!planners.empty()) {
      WriteOmplLog(out_dir / "ompl-benchmark.log", "ausbau-bench", machine, settings, setup,
                   results.empty() ? NowIsoUtc() : results.front().started_iso, total, status_enum, planners);
    }
  }
  std::string summary = WriteSummary(out_dir / "summary.md", machine, settings, results);
  const std::vector<SpeedupRow> speedups = Speedups(results, options.time_limit_s);
  WriteSpeedupsCsv(out_dir / "speedups.csv", speedups);
  summary += SpeedupSection(speedups, options.time_limit_s);
  bool check_failed = false;
  if (!options.recorded.empty()) {
    const SpeedupCheck check = CheckSpeedups(speedups, recorded, kRecordedShare, options.recorded);
    summary += check.markdown;
    check_failed = !check.passed;
  }
  WriteTextFileAtomically(out_dir / "summary.md", summary);
  std::fputs(summary.c_str(), stdout);
  std::fflush(stdout);
  std::fprintf(stderr,
               "ausbau-bench: wrote %s/{results.csv,summary.md,speedups.csv,ompl-benchmark.log,"
               "ompl-benchmark-<scene>.log}\n",
               options.output_dir.c_str());
  for (const SceneResult& r : results) {
    if (!r.loaded) return kExitBadInput;
  }
  if (check_failed) {
    std::fprintf(stderr, "ausbau-bench: the check against %s FAILED (summary.md, last section)\n",
                 options.recorded.c_str());
    return kExitInternal;
  }
  return kExitOk;
}

// ---- the parameter study ----

int RunStudy(const Options& options) {
  const std::vector<SceneSpec> scene_specs = ResolveScenes(options);
  fs::create_directories(options.output_dir);
  const fs::path out_dir(options.output_dir);
  MachineInfo machine = DescribeMachine();
  BenchSettings settings;
  settings.runs = options.runs;
  settings.time_limit_s = options.time_limit_s;
  settings.first_seed = options.seed;
  settings.resolution = options.resolution;
  settings.command_line = options.command_line;

  std::vector<StudyResult> studies;
  bool all_loaded = true;
  for (const SceneSpec& spec : scene_specs) {
    std::unique_ptr<LoadedScene> loaded;
    try {
      loaded = Load(spec);
    } catch (const InputError& e) {
      std::fprintf(stderr, "ausbau-bench: scene %s not run: %s\n", spec.name.c_str(), e.what());
      all_loaded = false;
      continue;
    }
    StudyResult study;
    study.scene = SceneName(spec, loaded.get());
    study.runs = options.runs;
    study.time_limit_s = options.time_limit_s;
    for (int i = 1; i <= 9; ++i) study.us.push_back(i / 10.0);
    for (int j = 1; j <= 10; ++j) study.ranges.push_back(j / 10.0);
    const auto begin = Clock::now();
    const int cells = static_cast<int>(study.us.size() * study.ranges.size());
    for (double u : study.us) {
      for (double range_max : study.ranges) {
        StudyCell cell;
        cell.u = u;
        cell.range_max = range_max;
        double time_sum = 0, checks_sum = 0;
        for (int i = 0; i < options.runs; ++i) {
          PlannerOptions o;
          o.planner = "rrtc";
          o.u = u;
          o.range_max = range_max;
          o.seed = options.seed + static_cast<std::uint64_t>(i);
          o.time_limit_s = options.time_limit_s;
          o.resolution = options.resolution;
          const auto run_begin = Clock::now();
          const PlanResult plan = Plan(loaded->problem, *loaded->checker, o);
          const double t = std::chrono::duration<double>(Clock::now() - run_begin).count();
          ++cell.runs;
          if (plan.solved()) ++cell.successes;
          time_sum += plan.solved() ? std::min(t, options.time_limit_s) : options.time_limit_s;
          checks_sum += static_cast<double>(plan.stats.collision_checks);
        }
        cell.mean_time_s = time_sum / cell.runs;
        cell.mean_pct = 100.0 * cell.mean_time_s / options.time_limit_s;
        cell.mean_checks = checks_sum / cell.runs;
        study.cells.push_back(cell);
        std::fprintf(stderr, "[%s cell %zu/%d] u %.1f range_max %.1f: %6.2f%% of T_max (mean %.3f s), %d/%d solved\n",
                     study.scene.c_str(), study.cells.size(), cells, u, range_max, cell.mean_pct, cell.mean_time_s,
                     cell.successes, cell.runs);
      }
    }
    study.wall_s = std::chrono::duration<double>(Clock::now() - begin).count();
    WriteStudyCsv(out_dir / ("study-" + SafeName(study.scene) + ".csv"), study);
    WriteStudySvg(out_dir / ("study-" + SafeName(study.scene) + ".svg"), study);
    studies.push_back(study);
    WriteStudySummary(out_dir / "study-summary.md", machine, settings, studies);  // partial results survive
  }
  const std::string summary = WriteStudySummary(out_dir / "study-summary.md", machine, settings, studies);
  std::fputs(summary.c_str(), stdout);
  std::fflush(stdout);
  std::fprintf(stderr, "ausbau-bench: wrote %s/{study-summary.md,study-<scene>.csv,study-<scene>.svg}\n",
               options.output_dir.c_str());
  return all_loaded ? kExitOk : kExitBadInput;
}

}  // namespace
}  // namespace ausbau::bench

int main(int argc, char** argv) {
  using namespace ausbau;
  using namespace ausbau::bench;
  Options options;
  for (int i = 0; i < argc; ++i) options.command_line += (i ? " " : "") + std::string(argv[i]);
  CLI::Option* runs_option = nullptr;
  CLI::Option* time_option = nullptr;
  return RunStage(
      {"ausbau-bench",
       "Benchmarks Ausbau's planners side by side with OMPL's RRT-Connect on the OMPL.app scenes, or (--study) "
       "runs the RRTC parameter study of thesis 3.3.1."},
      argc, argv,
      [&](CLI::App& app) {
        app.add_option("--scenes", options.scenes, "comma list of scene names (in --benchmarks-dir) or yaml paths")
            ->capture_default_str();
        app.add_option("--benchmarks-dir", options.benchmarks_dir, "folder of the OMPL.app scenes (<name>.yaml)")
            ->capture_default_str();
        app.add_option("--planners", options.planners,
                       "comma list of Ausbau planners: rrtc (Def-RRTC), rrtc:U:RANGE_MAX (Opt-RRTC), cr-rrtc, est, "
                       "...; unknown ones are reported as skipped; ausbau-plan runs the ausbau-plan executable "
                       "with its default flags (whole process, timed from spawn to exit)")
            ->capture_default_str();
        runs_option = app.add_option("--runs", options.runs,
                                     "runs (seeds) per planner and scene; default 10, "
                                     "with --study 5 per cell");
        time_option =
            app.add_option("--time-limit", options.time_limit_s, "seconds per run; default 60, with --study 10");
        app.add_option("--seed", options.seed,
                       "first Ausbau seed (runs use seed, seed+1, ...) and OMPL's global RNG seed")
            ->capture_default_str();
        app.add_option("--output-dir", options.output_dir, "where the results go")->capture_default_str();
        app.add_flag("--study", options.study, "run the parameter study (rrtc, u 0.1..0.9 x range_max 0.1..1.0)");
        app.add_flag("--no-ompl", options.no_ompl, "run only Ausbau's planners");
        app.add_option("--ompl-ranges", options.ompl_ranges,
                       "OMPL RRT-Connect ranges: default (0.2 x maximum extent), N% of the maximum extent, cfg "
                       "(rrt.range of the scene's .cfg, if any), or a number")
            ->capture_default_str();
        app.add_option("--ompl-resolution", options.ompl_resolution,
                       "OMPL edge resolution: matched (stock validator, fraction giving Ausbau's displacement "
                       "bound), exact (a validator stepping exactly like Ausbau), extent (step / (max(1, 2r) x "
                       "maximum extent)) or ompl (0.01)")
            ->capture_default_str();
        app.add_option("--bin", options.bin_dir,
                       "folder of the ausbau-plan executable that --planners ausbau-plan runs; default: this "
                       "executable's folder");
        app.add_option("--recorded", options.recorded,
                       "speedups.csv of an earlier run: fail (exit 1) when a speed-up against OMPL default falls "
                       "below half of the recorded one, or a path fails the dense re-check");
        app.add_option("--resolution", options.resolution,
                       "Ausbau's edge check step as a fraction of D's AABB diagonal")
            ->capture_default_str();
      },
      [&] {
        if (options.study) {
          if (runs_option->count() == 0) options.runs = 5;
          if (time_option->count() == 0) options.time_limit_s = 10;
        }
        if (options.runs < 1) throw InputError("--runs: must be >= 1");
        if (!(options.time_limit_s > 0) || !std::isfinite(options.time_limit_s)) {
          throw InputError("--time-limit: must be a positive number of seconds");
        }
        InitOmpl(static_cast<std::uint32_t>(options.seed));  // before any OMPL object
        return options.study ? RunStudy(options) : RunBenchmark(options);
      });
}
