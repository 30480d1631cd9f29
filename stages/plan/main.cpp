// ausbau-plan: rigid-body planning for one scene, from the start pose to the
// goal pose or, without a goal, out of S (disassembly). See README.md.
#include <filesystem>
#include <memory>

#include "cli/stage_main.h"
#include "collision/farr_checker.h"
#include "collision/fcl_checker.h"
#include "core/hash.h"
#include "core/log.h"
#include "planning/dense_check.h"
#include "planning/path_io.h"
#include "planning/planner.h"
#include "planning/smoother.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct PlanStageOptions {
  std::string scene;
  std::string output = "path.h5";
  std::string csv;
  std::string ompl_path;
  bool verify = true;
  bool force = false;
  PlannerOptions planner;
  std::string collision = "fcl";  // fcl | farr
  std::string distfield;          // "S.h5,D.h5" (farr); empty: build or reuse through the cache
};

// The two files of --distfield, or none.
std::vector<std::string> DistfieldPaths(const PlanStageOptions& options) {
  if (options.collision != "farr" || options.distfield.empty()) return {};
  const auto comma = options.distfield.find(',');
  if (comma == std::string::npos || comma == 0 || comma + 1 == options.distfield.size() ||
      options.distfield.find(',', comma + 1) != std::string::npos) {
    throw InputError("--distfield: expected two files, S.h5,D.h5 (got '" + options.distfield + "')");
  }
  return {options.distfield.substr(0, comma), options.distfield.substr(comma + 1)};
}

// FCL, or FARR in front of FCL with the distance fields of S and D (given,
// or built / reused through the cache beside the scene).
std::unique_ptr<PoseValidity> MakeChecker(const PlanStageOptions& options, const Scene& scene,
                                          const PlanningProblem& problem) {
  if (options.collision != "farr") {
    if (!options.distfield.empty()) LogWarn("--distfield is ignored with --collision fcl");
    return std::make_unique<FclCollisionChecker>(problem.robot, problem.environment);
  }
  std::shared_ptr<const DistanceField> static_field, dynamic_field;
  const std::vector<std::string> paths = DistfieldPaths(options);
  if (!paths.empty()) {
    static_field = ReadDistanceField(paths[0]);
    dynamic_field = ReadDistanceField(paths[1]);
    if (static_field->mesh_hash() != MeshContentHash(problem.environment)) {
      throw InputErrorAt(paths[0], "distance field built for another mesh than this scene's S (ausbau-distfield-build)");
    }
    if (dynamic_field->mesh_hash() != MeshContentHash(problem.robot)) {
      throw InputErrorAt(paths[1], "distance field built for another mesh than this scene's D (ausbau-distfield-build)");
    }
  } else {
    DistanceFieldOptions field_options;
    field_options.threads = options.planner.threads;
    const std::filesystem::path cache = DefaultDistanceFieldCacheDir(scene.file);
    static_field = LoadOrBuildDistanceField(problem.environment, field_options, cache, "distance field of S",
                                            scene.units, "world");
    dynamic_field = LoadOrBuildDistanceField(problem.robot, field_options, cache, "distance field of D", scene.units,
                                             "D relative to its reference point");
  }
  return std::make_unique<FarrCollisionChecker>(problem.robot, problem.environment, dynamic_field, static_field,
                                                options.planner.seed);
}

Provenance MakeProvenance(const Scene& scene, const std::string& parameters, const PlanStageOptions& options) {
  Provenance provenance{"ausbau-plan", AUSBAU_VERSION, parameters, {}};
  AddSceneInputs(scene, &provenance);
  const std::vector<std::string> distfield = DistfieldPaths(options);
  if (!distfield.empty()) {
    provenance.inputs.emplace_back("distfield-static", HashFile(distfield[0]));
    provenance.inputs.emplace_back("distfield-dynamic", HashFile(distfield[1]));
  }
  return provenance;
}

int Run(const PlanStageOptions& options, const std::string& parameters) {
  options.planner.Check();
  const Scene scene = LoadScene(options.scene);
  const Provenance provenance = MakeProvenance(scene, parameters, options);

  // Cache: an existing output with the same provenance is the same answer.
  if (!options.force && ExistingProvenanceHash(options.output, kPathSchema, kPathSchemaVersion) == provenance.Hash()) {
    const PathArtifact cached = ReadPathArtifact(options.output);
    LogInfo("%s is up to date (same inputs and options); use --force to plan again", options.output.c_str());
    if (!options.csv.empty() && cached.success) WritePathCsv(options.csv, cached.waypoints);
    if (!options.ompl_path.empty() && cached.success) WriteOmplPath(options.ompl_path, cached.waypoints);
    return cached.success ? kExitOk : kExitNoPath;
  }

  const PlanningProblem problem = MakePlanningProblem(scene);
  LogInfo("scene %s: S %zu triangles, D %zu triangles, planner %s, seed %llu, time limit %.1f s",
          scene.name.c_str(), problem.environment.triangles.size(), problem.robot.triangles.size(),
          options.planner.planner.c_str(), static_cast<unsigned long long>(options.planner.seed),
          options.planner.time_limit_s);
  const std::unique_ptr<PoseValidity> checker_owner = MakeChecker(options, scene, problem);
  const PoseValidity& checker = *checker_owner;
  CheckEndpoints(problem, checker, scene.file.string());

  const PlanResult result = Plan(problem, checker, options.planner);
  if (const auto* farr = dynamic_cast<const FarrCollisionChecker*>(&checker)) {
    const FarrStats stats = farr->stats();
    LogInfo("FARR: %lld queries, %lld collisions proven by rays, %lld answered by FCL (%lld of them collisions), "
            "%d rays per query at the end",
            static_cast<long long>(stats.queries), static_cast<long long>(stats.witnesses),
            static_cast<long long>(stats.fcl_calls), static_cast<long long>(stats.fcl_collisions), stats.rays_now);
  }
  PathArtifact artifact;
  artifact.reference_point = problem.reference_point;
  artifact.dynamic_origin = problem.dynamic_origin;
  artifact.planner = options.planner.planner;
  artifact.scene = scene.name;
  artifact.success = result.solved();
  artifact.stats = result.stats;
  for (const Pose& pose : result.path) artifact.waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&artifact.waypoints);
  const PathLength length = MeasurePath(problem, result.path);
  artifact.length_normalized = length.normalized;
  artifact.length_translation = length.translation;
  artifact.length_rotation = length.rotation;

  LogInfo("%s after %.3f s: %lld iterations, %lld nodes, %lld collision checks (%.1f%% invalid)",
          result.solved() ? "solved" : "no path", result.stats.time_s,
          static_cast<long long>(result.stats.iterations), static_cast<long long>(result.stats.nodes),
          static_cast<long long>(result.stats.collision_checks),
          result.stats.collision_checks > 0
              ? 100.0 * result.stats.invalid_checks / result.stats.collision_checks
              : 0.0);
  if (result.solved() && options.verify) {
    const DenseCheckReport report = DenseCheckPath(scene, problem.reference_point, artifact.waypoints, 0.01);
    if (!report.valid) {
      throw std::runtime_error("planned path fails the dense re-check: segment " +
                               std::to_string(report.first_bad_segment) + " " + report.reason);
    }
    LogInfo("dense re-check passed (%lld poses, step 1%% of D's diagonal)",
            static_cast<long long>(report.poses_checked));
  }
  WritePathArtifact(options.output, artifact, provenance);
  if (result.solved() && !options.csv.empty()) WritePathCsv(options.csv, artifact.waypoints);
  if (result.solved() && !options.ompl_path.empty()) WriteOmplPath(options.ompl_path, artifact.waypoints);
  if (!result.solved()) {
    LogError("no path within the budget (%s)",
             result.status == PlanStatus::kTimeLimit ? "time limit" : "iteration limit");
    return kExitNoPath;
  }
  LogInfo("path: %zu waypoints, length %.4f (normalized), written to %s%s%s", artifact.waypoints.size(),
          length.normalized, options.output.c_str(), options.csv.empty() ? "" : " and ", options.csv.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  PlanStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-plan", "Plans a collision-free motion of the part D out of (or through) its surroundings S."}, argc,
      argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--planner", options.planner.planner, "rrt | rrtc | cr-rrtc | est | prm")
            ->capture_default_str();
        app.add_option("--sampler", options.planner.sampler, "uniform | gaussian | bridge | mixed")
            ->capture_default_str();
        app.add_option("--sigma", options.planner.sampler_sigma,
                       "gaussian/bridge deviation as a fraction of D's diagonal; 0 = automatic (0.25)")
            ->capture_default_str();
        app.add_option("--threads", options.planner.threads, "prm edge verification (and farr distance-field) threads; 0 = all cores")
            ->capture_default_str();
        app.add_option("--seed", options.planner.seed, "random seed")->capture_default_str();
        app.add_option("--time-limit", options.planner.time_limit_s, "seconds")->capture_default_str();
        app.add_option("--max-iterations", options.planner.max_iterations, "0 = unlimited")->capture_default_str();
        app.add_option("--u", options.planner.u, "rrtc: metric weight of translation, (0, 1)")
            ->capture_default_str();
        app.add_option("--range-max", options.planner.range_max, "rrtc: maximal edge range, (0, 1]")
            ->capture_default_str();
        app.add_option("--resolution", options.planner.resolution,
                       "edge check step as a fraction of D's AABB diagonal")
            ->capture_default_str();
        app.add_option("-o,--output", options.output, "path artifact (HDF5)")->capture_default_str();
        app.add_option("--csv", options.csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)");
        app.add_option("--ompl-path", options.ompl_path, "also write the path in OMPL's format (x y z qx qy qz qw)");
        app.add_flag("!--no-verify", options.verify, "skip the dense re-check of the result");
        app.add_flag("--force", options.force, "plan even when the output is up to date");
        app.add_option("--collision", options.collision,
                       "fcl | farr (FARR rays in front of FCL, same answers; README \"FARR collision detection\")")
            ->check(CLI::IsMember({"fcl", "farr"}))
            ->capture_default_str();
        app.add_option("--distfield", options.distfield,
                       "farr: distance fields S.h5,D.h5 (ausbau-distfield-build); default: built or reused "
                       "through the cache (<scene dir>/.ausbau-cache or $AUSBAU_CACHE_DIR)");
      },
      [&] {
        return Run(options, OptionsYaml(*app_ptr, {"scene", "output", "csv", "ompl-path", "force", "no-verify", "threads", "distfield"}));
      });
}
