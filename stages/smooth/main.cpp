// ausbau-smooth: shortcut smoothing of a planned path under the same
// validity check; never returns a path that fails the dense re-check.
#include <cmath>

#include "cli/stage_main.h"
#include "cli/volume_inputs.h"
#include "inistate/volume_smoother.h"
#include "core/atomic_file.h"
#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "core/hash.h"
#include "core/log.h"
#include "planning/dense_check.h"
#include "planning/exact_check.h"
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
  std::string profile;  // intersection and clearance profile (CSV)
  bool force = false;
  SmoothOptions smooth;
  VolumeInputs volume;  // InIState paths: the voxels and labels they were planned with
};

// Poses along a path (planning convention), densely: between two of them no
// vertex of D moves more than `step`. Each with its segment and fraction.
struct DensePose {
  Pose pose;
  int segment;
  double fraction;
};
std::vector<DensePose> Densify(const PlanningProblem& problem, const std::vector<Pose>& path, double step) {
  std::vector<DensePose> out;
  if (path.empty()) return out;
  out.push_back({path.front(), 0, 0.0});
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double d = MaxDisplacement(path[i], path[i + 1], problem.robot_radius);
    const int steps = std::max(1, static_cast<int>(std::ceil(d / step)));
    for (int k = 1; k <= steps; ++k) {
      const double f = static_cast<double>(k) / steps;
      out.push_back({Interpolate(path[i], path[i + 1], f), static_cast<int>(i), f});
    }
  }
  return out;
}

// The profile: per dense pose the path parameter, the mode's volume with its
// part and deformability (volume modes), and the clearance to S (FCL
// distance, 0 in contact).
void WriteProfile(const std::filesystem::path& file, const PlanningProblem& problem, const std::vector<Pose>& path,
                  VolumeModel* model) {
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  // At most ~2000 rows: the step is 1% of D's diagonal or longer.
  double total = 0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) total += MaxDisplacement(path[i], path[i + 1], problem.robot_radius);
  const double step = std::max(0.01 * problem.robot_diagonal, total / 2000.0);
  std::string text = "segment,fraction,s,volume,part,deformability,clearance\n";
  double s = 0;
  Pose previous = path.front();
  char line[256];
  for (const DensePose& p : Densify(problem, path, step)) {
    s += problem.metric.Distance(previous, p.pose, 0.5);
    previous = p.pose;
    VolumeReport report;
    if (model != nullptr) report = model->Describe(p.pose);
    const double clearance = fcl.InCollision(p.pose) ? 0.0 : fcl.Distance(p.pose);
    if (model != nullptr) {
      std::snprintf(line, sizeof line, "%d,%.6f,%.8g,%.8g,%d,%.4f,%.8g\n", p.segment, p.fraction, s, report.value,
                    report.value > 0 ? report.part : -1, report.deformability, clearance);
    } else {
      std::snprintf(line, sizeof line, "%d,%.6f,%.8g,,,,%.8g\n", p.segment, p.fraction, s, clearance);
    }
    text += line;
  }
  WriteTextFileAtomically(file, text);
}

// A rigid-exact path (ausbau-plan --validity rigid-exact): shortcuts under
// the same exact rigid check, the result densified for plain interpolation
// and checked exactly as written; the input is kept when that fails.
int SmoothRigidExact(const SmoothStageOptions& options, const Scene& scene, const PathArtifact& input,
                     const Provenance& provenance) {
  const double tolerance = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene.units, nullptr);
  const PlanningProblem problem = MakePlanningProblem(scene);
  if ((problem.reference_point - input.reference_point).norm() > 1e-9 * (1.0 + problem.robot_diagonal)) {
    throw InputErrorAt(options.path, "was planned about another reference point than this scene's");
  }
  const ExactCheckReport input_check = ExactCheckPath(scene, input.waypoints, tolerance);
  if (!input_check.valid) throw InputErrorAt(options.path, "the input path fails the exact check: " + input_check.reason);
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance);
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4);
  std::vector<Pose> planning_path;
  for (const Pose& pose : input.waypoints) planning_path.push_back(problem.SceneToPlanning(pose));
  SmoothResult result = SmoothPath(problem, checker, planning_path, options.smooth);
  PathArtifact output = input;
  output.waypoints.clear();
  for (const Pose& pose : result.path) output.waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&output.waypoints);
  output.waypoints = DensifyForPlainInterpolation(output.waypoints, problem.reference_point, problem.dynamic_origin,
                                                  tolerance / 10);
  const ExactCheckReport check = ExactCheckPath(scene, output.waypoints, tolerance);
  if (!check.valid) {
    LogWarn("smoothed path fails the exact check (%s); keeping the input path", check.reason.c_str());
    output.waypoints = input.waypoints;
    result.path = planning_path;
    result.after = result.before;
  }
  output.length_normalized = result.after.normalized;
  output.length_translation = result.after.translation;
  output.length_rotation = result.after.rotation;
  WritePathArtifact(options.output, output, provenance);
  if (!options.csv.empty()) WritePathCsv(options.csv, output.waypoints);
  if (!options.profile.empty()) WriteProfile(options.profile, problem, result.path, nullptr);
  LogInfo("length %.4f -> %.4f (normalized), translation %.4g -> %.4g, rotation %.3f -> %.3f rad; %d shortcuts in %d "
          "attempts; deepest rigid penetration %.4g %s",
          result.before.normalized, result.after.normalized, result.before.translation, result.after.translation,
          result.before.rotation, result.after.rotation, result.shortcuts, result.attempts,
          check.valid ? check.max_rigid_depth : input_check.max_rigid_depth, scene.units.c_str());
  return kExitOk;
}

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
  AddVolumeInputs(options.volume, &provenance);
  if (!options.force &&
      ExistingProvenanceHash(options.output, kPathSchema, kPathSchemaVersion) == provenance.Hash()) {
    LogInfo("%s is up to date (same inputs and options); use --force to smooth again", options.output.c_str());
    if (!options.csv.empty()) WritePathCsv(options.csv, ReadPathArtifact(options.output).waypoints);
    if (!options.profile.empty() && !std::filesystem::exists(options.profile)) {
      const PathArtifact cached = ReadPathArtifact(options.output);
      const PlanningProblem problem = MakePlanningProblem(scene);
      std::unique_ptr<VolumeModel> model;
      if (IsVolumeValidity(cached.validity)) {
        model = LoadVolumeModel(scene, problem, ParseValidityMode(cached.validity), options.volume);
      }
      std::vector<Pose> path;
      for (const Pose& pose : cached.waypoints) path.push_back(problem.SceneToPlanning(pose));
      WriteProfile(options.profile, problem, path, model.get());
    }
    return kExitOk;
  }

  if (input.validity == kRigidExactValidity) return SmoothRigidExact(options, scene, input, provenance);
  PlanningProblem problem = MakePlanningProblem(scene);
  if ((problem.reference_point - input.reference_point).norm() > 1e-9 * (1.0 + problem.robot_diagonal)) {
    throw InputErrorAt(options.path, "was planned about another reference point than this scene's");
  }
  const bool volume_mode = input.validity != "collision";
  const int first_rigid = volume_mode ? std::max(0, input.inter_index) : 0;
  const std::vector<Pose> input_rigid(input.waypoints.begin() + first_rigid, input.waypoints.end());
  const DenseCheckReport input_check = DenseCheckPath(scene, input.reference_point, input_rigid, 0.01);
  if (!input_check.valid) {
    throw InputErrorAt(options.path, "the input path is not valid in this scene: segment " +
                                         std::to_string(first_rigid + input_check.first_bad_segment) + " " +
                                         input_check.reason);
  }
  std::vector<Pose> planning_path;
  for (const Pose& pose : input.waypoints) planning_path.push_back(problem.SceneToPlanning(pose));

  const FclCollisionChecker checker(problem.robot, problem.environment);
  std::unique_ptr<VolumeModel> model;
  SmoothResult result;
  int inter_index = -1;
  if (!volume_mode) {
    if (!options.volume.voxels.empty() || !options.volume.labels.empty()) {
      LogWarn("--voxels and --labels are ignored: the path was planned under plain collision");
    }
    result = SmoothPath(problem, checker, planning_path, options.smooth);
  } else {
    // sigma_1 under its volume, no shortcut deepening any intersection
    // (inistate/volume_smoother.h); sigma_2 under collision; no shortcut
    // crosses c_inter.
    model = LoadVolumeModel(scene, problem, ParseValidityMode(input.validity), options.volume);
    const std::vector<Pose> sigma1(planning_path.begin(), planning_path.begin() + first_rigid + 1);
    const std::vector<Pose> sigma2(planning_path.begin() + first_rigid, planning_path.end());
    IntersectionVolume volume = model->volume().Clone();
    const VolumeSmoothResult first = SmoothUnderVolume(problem, volume, model->measure(), sigma1, options.smooth);
    if (first.max_before > input.tau * (1 + 1e-9) + 1e-12) {
      LogWarn("the input path's largest volume %.6g exceeds its tau %.6g (other voxels or labels than planned with?)",
              first.max_before, input.tau);
    }
    LogInfo("sigma_1: %zu -> %zu waypoints, largest %s %.6g -> %.6g %s^3 (tau %.6g), %d shortcuts in %d attempts",
            sigma1.size(), first.path.size(), input.validity.c_str(), first.max_before, first.max_after,
            scene.units.c_str(), input.tau, first.shortcuts, first.attempts);
    SmoothOptions second_options = options.smooth;
    second_options.seed = options.smooth.seed + 1;
    const SmoothResult second = SmoothPath(problem, checker, sigma2, second_options);
    result.path = first.path;
    inter_index = static_cast<int>(result.path.size()) - 1;
    result.path.insert(result.path.end(), second.path.begin() + 1, second.path.end());
    result.before = MeasurePath(problem, planning_path);
    result.after = MeasurePath(problem, result.path);
    result.shortcuts = first.shortcuts + second.shortcuts;
    result.attempts = first.attempts + second.attempts;
  }
  PathArtifact output = input;
  output.waypoints.clear();
  for (const Pose& pose : result.path) output.waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&output.waypoints);
  const std::vector<Pose> output_rigid(output.waypoints.begin() + std::max(0, inter_index), output.waypoints.end());
  const DenseCheckReport output_check = DenseCheckPath(scene, problem.reference_point, output_rigid, 0.01);
  if (!output_check.valid) {
    // The smoother's own check is discrete; if the independent check finds
    // a collision on a shortcut, keep the input path rather than a bad one.
    LogWarn("smoothed path fails the dense re-check (segment %d, %s); keeping the input path",
            output_check.first_bad_segment, output_check.reason.c_str());
    output.waypoints = input.waypoints;
    result.path = planning_path;
    result.after = result.before;
    inter_index = input.inter_index;
  }
  if (volume_mode) {
    output.inter_index = inter_index;
    output.waypoint_volume.clear();
    output.waypoint_part.clear();
    output.waypoint_deformability.clear();
    for (const Pose& pose : result.path) {
      const VolumeReport report = model->Describe(pose);
      output.waypoint_volume.push_back(report.value);
      output.waypoint_part.push_back(report.value > 0 ? report.part : -1);
      output.waypoint_deformability.push_back(report.deformability);
    }
  }
  output.length_normalized = result.after.normalized;
  output.length_translation = result.after.translation;
  output.length_rotation = result.after.rotation;
  WritePathArtifact(options.output, output, provenance);
  if (!options.csv.empty()) WritePathCsv(options.csv, output.waypoints);
  if (!options.profile.empty()) WriteProfile(options.profile, problem, result.path, model.get());
  LogInfo("length %.4f -> %.4f (normalized), translation %.4g -> %.4g, rotation %.3f -> %.3f rad; "
          "%zu -> %zu waypoints, %d shortcuts in %d attempts",
          result.before.normalized, result.after.normalized, result.before.translation, result.after.translation,
          result.before.rotation, result.after.rotation, input.waypoints.size(), output.waypoints.size(),
          result.shortcuts, result.attempts);
  LogInfo("written to %s%s%s%s%s", options.output.c_str(), options.csv.empty() ? "" : ", ", options.csv.c_str(),
          options.profile.empty() ? "" : ", ", options.profile.c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  SmoothStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-smooth", "Shortens a planned path by shortcuts that keep it valid (collision-free, or within its InIState volume)."}, argc, argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--path", options.path, "path artifact from ausbau-plan")->required();
        app.add_option("--seed", options.smooth.seed, "random seed")->capture_default_str()->check(NonNegative());
        app.add_option("--attempts", options.smooth.attempts, "shortcut attempts, 0 = automatic")
            ->capture_default_str();
        app.add_option("--time-limit", options.smooth.time_limit_s, "seconds")->capture_default_str()->check(TimeLimit());
        app.add_option("--resolution", options.smooth.resolution,
                       "edge check step as a fraction of D's AABB diagonal")
            ->capture_default_str();
        app.add_option("-o,--output", options.output, "smoothed path artifact (HDF5)")->capture_default_str();
        app.add_option("--csv", options.csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)");
        app.add_option("--profile", options.profile,
                       "also write the intersection and clearance profile along the path (CSV)");
        app.add_option("--voxels", options.volume.voxels,
                       "InIState paths: voxels they were planned with (ausbau-voxelize); default: voxelized here");
        app.add_option("--labels", options.volume.labels, "InIState paths: labels of D (the labeled modes)");
        app.add_flag("--force", options.force, "smooth even when the output is up to date");
        app.add_option("--rigid-tolerance", options.volume.rigid_tolerance_mm,
                       "rigid-exact paths, and labeled-mliv's rigid guard: how deep D's rigid part may touch into S, "
                       "in mm (scene units converted)")
            ->capture_default_str();
      },
      [&] { return Run(options, OptionsYaml(*app_ptr, {"scene", "path", "output", "csv", "profile", "force", "voxels", "labels"})); });
}
