// ausbau-smooth: shortcut smoothing of a planned path under the same
// validity check; never returns a path that fails the dense re-check.
#include "cli/stage_main.h"
#include "collision/fcl_checker.h"
#include "core/hash.h"
#include "core/log.h"
#include "planning/dense_check.h"
#include "planning/path_io.h"
#include "planning/smoother.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct SmoothStageOptions {
  std::string scene;
  std::string path;
  std::string output = "path-smooth.h5";
  std::string csv;
  bool force = false;
  SmoothOptions smooth;
};

int Run(const SmoothStageOptions& options, const std::string& parameters) {
  options.smooth.Check();
  const Scene scene = LoadScene(options.scene);
  const PathArtifact input = ReadPathArtifact(options.path);
  if (!input.success || input.waypoints.empty()) {
    throw InputErrorAt(options.path, "holds no path (the planner did not succeed)");
  }
  Provenance provenance{"ausbau-smooth", AUSBAU_VERSION, parameters, {}};
  AddSceneInputs(scene, &provenance);
  provenance.inputs.emplace_back("path", HashFile(options.path));
  if (!options.force &&
      ExistingProvenanceHash(options.output, kPathSchema, kPathSchemaVersion) == provenance.Hash()) {
    LogInfo("%s is up to date (same inputs and options); use --force to smooth again", options.output.c_str());
    if (!options.csv.empty()) WritePathCsv(options.csv, ReadPathArtifact(options.output).waypoints);
    return kExitOk;
  }

  PlanningProblem problem = MakePlanningProblem(scene);
  if ((problem.reference_point - input.reference_point).norm() > 1e-9 * (1.0 + problem.robot_diagonal)) {
    throw InputErrorAt(options.path, "was planned about another reference point than this scene's");
  }
  const DenseCheckReport input_check = DenseCheckPath(scene, input.reference_point, input.waypoints, 0.01);
  if (!input_check.valid) {
    throw InputErrorAt(options.path, "the input path is not valid in this scene: segment " +
                                         std::to_string(input_check.first_bad_segment) + " " + input_check.reason);
  }
  std::vector<Pose> planning_path;
  for (const Pose& pose : input.waypoints) planning_path.push_back(problem.SceneToPlanning(pose));

  const FclCollisionChecker checker(problem.robot, problem.environment);
  SmoothResult result = SmoothPath(problem, checker, planning_path, options.smooth);
  PathArtifact output = input;
  output.waypoints.clear();
  for (const Pose& pose : result.path) output.waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&output.waypoints);
  const DenseCheckReport output_check = DenseCheckPath(scene, problem.reference_point, output.waypoints, 0.01);
  if (!output_check.valid) {
    // The smoother's own check is discrete; if the independent check finds
    // a collision on a shortcut, keep the input path rather than a bad one.
    LogWarn("smoothed path fails the dense re-check (segment %d, %s); keeping the input path",
            output_check.first_bad_segment, output_check.reason.c_str());
    output.waypoints = input.waypoints;
    result.after = result.before;
  }
  output.length_normalized = result.after.normalized;
  output.length_translation = result.after.translation;
  output.length_rotation = result.after.rotation;
  WritePathArtifact(options.output, output, provenance);
  if (!options.csv.empty()) WritePathCsv(options.csv, output.waypoints);
  LogInfo("length %.4f -> %.4f (normalized), translation %.4g -> %.4g, rotation %.3f -> %.3f rad; "
          "%zu -> %zu waypoints, %d shortcuts in %d attempts",
          result.before.normalized, result.after.normalized, result.before.translation, result.after.translation,
          result.before.rotation, result.after.rotation, input.waypoints.size(), output.waypoints.size(),
          result.shortcuts, result.attempts);
  LogInfo("written to %s%s%s", options.output.c_str(), options.csv.empty() ? "" : " and ", options.csv.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  SmoothStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-smooth", "Shortens a planned path by shortcuts that keep it collision-free."}, argc, argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--path", options.path, "path artifact from ausbau-plan")->required();
        app.add_option("--seed", options.smooth.seed, "random seed")->capture_default_str();
        app.add_option("--attempts", options.smooth.attempts, "shortcut attempts, 0 = automatic")
            ->capture_default_str();
        app.add_option("--time-limit", options.smooth.time_limit_s, "seconds")->capture_default_str();
        app.add_option("--resolution", options.smooth.resolution,
                       "edge check step as a fraction of D's AABB diagonal")
            ->capture_default_str();
        app.add_option("-o,--output", options.output, "smoothed path artifact (HDF5)")->capture_default_str();
        app.add_option("--csv", options.csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)");
        app.add_flag("--force", options.force, "smooth even when the output is up to date");
      },
      [&] { return Run(options, OptionsYaml(*app_ptr, {"scene", "path", "output", "csv", "force"})); });
}
