#include "workflow/smooth_path.h"

#include <algorithm>

#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "core/error.h"
#include "core/log.h"
#include "inistate/volume_smoother.h"
#include "planning/clearance.h"
#include "planning/dense_check.h"
#include "planning/exact_check.h"
#include "workflow/made_from.h"

namespace ausbau {
namespace {

std::vector<Pose> ToPlanning(const PlanningProblem& problem, const std::vector<Pose>& waypoints) {
  std::vector<Pose> out;
  for (const Pose& pose : waypoints) out.push_back(problem.SceneToPlanning(pose));
  return out;
}

std::vector<Pose> ToScene(const PlanningProblem& problem, const std::vector<Pose>& path) {
  std::vector<Pose> out;
  for (const Pose& pose : path) out.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&out);
  return out;
}

// The clearance guard of --clearance (planning/clearance.h) on the part of
// D that must keep clear (`robot`: ClearanceRobot's, planning convention);
// `contact`: as ClearanceGuard's.
std::unique_ptr<ClearanceGuard> MakeGuard(const Scene& scene, const PlanningProblem& problem,
                                          const SmoothOptions& options, const TriangleMesh& robot,
                                          const std::vector<Pose>& input, double contact = 0) {
  const double clearance = ClearanceInSceneUnits(options.clearance, scene.units);
  LogInfo("keeping a clearance of %.4g %s from S where the path allows (--clearance)", clearance, scene.units.c_str());
  return std::make_unique<ClearanceGuard>(problem, robot, clearance, ClearanceStep(problem, clearance), input, contact);
}

// The warning line where the smoothed path (from segment `first` on) comes
// closer to S than the guard's d: the geometry leaves no more there (a
// shortcut with more room would have been kept).
void WarnBelowClearance(const Scene& scene, const ClearanceGuard& guard, const std::vector<Pose>& path, int first) {
  if (!(guard.clearance() > 0) || path.size() < 2) return;
  const ClearanceSample closest = guard.Closest(path);
  if (closest.clearance >= guard.clearance()) return;
  LogWarn(
      "clearance: the path comes %.4g %s from S (segment %d), below --clearance %.4g %s; ausbau-verdict lists "
      "every such segment",
      closest.clearance, scene.units.c_str(), first + closest.segment, guard.clearance(), scene.units.c_str());
}

void SetLengths(const SmoothResult& result, PathArtifact* artifact) {
  artifact->length_normalized = result.after.normalized;
  artifact->length_translation = result.after.translation;
  artifact->length_rotation = result.after.rotation;
}

// A rigid-exact path (ausbau-plan --validity rigid-exact): shortcuts under
// the same exact rigid check, the result densified for plain interpolation
// and checked exactly as written; the input is kept when that fails.
SmoothedPath SmoothRigidExact(const Scene& scene, const PlanningProblem& problem, const PathArtifact& input,
                              const std::string& input_file, const SmoothPlannedPathOptions& options) {
  const double tolerance = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene, nullptr);
  // The input's and the output's checks classify each crop level once.
  ExactCheckModels exact_models;
  const ExactCheckReport input_check =
      ExactCheckPath(scene, input.waypoints, tolerance, UnmeasuredInterference::kRigid, {}, &exact_models);
  if (!input_check.valid) throw InputErrorAt(input_file, "the input path fails the exact check: " + input_check.reason);
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance,
                                   UnmeasuredInterference::kRigid, SceneFitRule(scene));
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4, NewContacts::kCollide);
  SmoothedPath out;
  out.clearance_robot = ClearanceRobot(problem, parts.get());
  out.planning_path = ToPlanning(problem, input.waypoints);
  const std::unique_ptr<ClearanceGuard> guard =
      MakeGuard(scene, problem, options.smooth, out.clearance_robot, out.planning_path, tolerance);
  out.result = SmoothPath(problem, checker, out.planning_path, options.smooth, guard.get());
  out.artifact = input;
  out.artifact.units = scene.units;
  out.artifact.clearance = guard->clearance();
  out.artifact.waypoints = DensifyForPlainInterpolation(ToScene(problem, out.result.path), problem.reference_point,
                                                        problem.dynamic_origin, tolerance / 10);
  const ExactCheckReport check =
      ExactCheckPath(scene, out.artifact.waypoints, tolerance, UnmeasuredInterference::kRigid, {}, &exact_models);
  if (!check.valid) {
    LogWarn("smoothed path fails the exact check (%s); keeping the input path", check.reason.c_str());
    out.artifact.waypoints = input.waypoints;
    out.result.path = out.planning_path;
    out.result.after = out.result.before;
  }
  SetLengths(out.result, &out.artifact);
  out.artifact.smoothing_cut_short = out.result.cut_short;
  WarnBelowClearance(scene, *guard, out.result.path, 0);
  const SmoothResult& r = out.result;
  LogInfo(
      "length %.4f -> %.4f (normalized), translation %.4g -> %.4g, rotation %.3f -> %.3f rad; %d shortcuts in %d "
      "attempts; deepest rigid penetration %.4g %s",
      r.before.normalized, r.after.normalized, r.before.translation, r.after.translation, r.before.rotation,
      r.after.rotation, r.shortcuts, r.attempts, check.valid ? check.max_rigid_depth : input_check.max_rigid_depth,
      scene.units.c_str());
  return out;
}

// Needless turning across c_inter: sigma_1's planner turns D at random and
// sigma_2 starts with that orientation, so neither part alone can take it
// out (sigma_1's end is held while it is smoothed). From the first pose
// along sigma_1 (planning/smoother.h, FirstFreezeThatWorks: by length, a
// pose inside a segment becomes a waypoint) from which it works, the rest
// of the path keeps that pose's orientation: sigma_1's remainder under the
// volume guard, from c_inter on under collision (`rigid`) and the clearance
// guard, its end in the goal region. Disassembly only (a goal pose holds
// the end's orientation). Returns whether the path changed; `inter_index`
// follows an inserted waypoint.
bool FreezeRotationAcrossInter(const PlanningProblem& problem, const MotionChecker& rigid,
                               const PoseValidity& sigma1_validity, const VolumeGuard& volume_guard,
                               const ClearanceGuard& clearance_guard, std::size_t* inter_index,
                               std::vector<Pose>* path) {
  if (problem.goal.has_value() || *inter_index == 0 || *inter_index >= path->size()) return false;
  const double old_rotation = MeasurePath(problem, *path).rotation;
  const auto slice = [](const std::vector<Pose>& p, std::size_t from, std::size_t to) {
    return std::vector<Pose>(p.begin() + from, p.begin() + to + 1);
  };
  std::vector<Pose> kept;
  std::size_t kept_inter = 0, kept_from = 0;
  const bool frozen = FirstFreezeThatWorks([&](double fraction) {
    std::size_t k = 0;
    // The same motion with a waypoint at `fraction`; the replaced part is
    // measured on it.
    const std::vector<Pose> old = WithWaypointAt(problem, *path, *inter_index, fraction, &k);
    const std::size_t inter = *inter_index + (old.size() - path->size());
    std::vector<Pose> next = old;
    for (std::size_t m = k + 1; m < next.size(); ++m) next[m].q = old[k].q;
    if (!(MeasurePath(problem, next).rotation < old_rotation - 1e-9) || !problem.InGoalRegion(next.back())) {
      return false;
    }
    // Every waypoint from k to c_inter valid under sigma_1's volume (k
    // itself may be a pose inside a segment, which can fail it between the
    // poses sigma_1's smoothing checked: a rigid solid grazing S), and
    // c_inter, where the rigid part starts, also under collision.
    for (std::size_t m = k; m <= inter; ++m) {
      if (!sigma1_validity.IsValid(next[m])) return false;
    }
    if (!rigid.IsValid(next[inter])) return false;
    for (std::size_t m = inter; m + 1 < next.size(); ++m) {
      if (!rigid.MotionValid(next[m], next[m + 1])) return false;
    }
    if (!volume_guard.Accepts(slice(old, k, inter), slice(next, k, inter)) ||
        !clearance_guard.Accepts(slice(old, inter, old.size() - 1), slice(next, inter, next.size() - 1))) {
      return false;
    }
    kept = std::move(next);
    kept_inter = inter;
    kept_from = k;
    return true;
  });
  if (!frozen) return false;
  LogInfo("rotation held from sigma_1's waypoint %zu on: %.3f -> %.3f rad", kept_from, old_rotation,
          MeasurePath(problem, kept).rotation);
  path->swap(kept);
  *inter_index = kept_inter;
  return true;
}

// sigma_1 under its volume, no shortcut deepening any intersection
// (inistate/volume_smoother.h); sigma_2 under collision; no shortcut
// crosses c_inter. Across it, only the turning taken out and a straight
// retreat from sigma_1, each checked part by part. Returns the index of
// c_inter in the smoothed path.
int SmoothInIState(const Scene& scene, const PlanningProblem& problem, const PathArtifact& input,
                   const FclCollisionChecker& checker, int first_rigid, const SmoothPlannedPathOptions& options,
                   SmoothedPath* out) {
  out->model = LoadVolumeModel(scene, problem, input.validity, options.volume);
  const std::vector<Pose>& path = out->planning_path;
  const std::vector<Pose> sigma1(path.begin(), path.begin() + first_rigid + 1);
  const std::vector<Pose> sigma2(path.begin() + first_rigid, path.end());
  IntersectionVolume volume = out->model->volume().Clone();
  const VolumeSmoothResult first = SmoothUnderVolume(problem, volume, out->model->measure(), sigma1, options.smooth);
  if (first.max_before > input.tau * (1 + 1e-9) + 1e-12) {
    LogWarn("the input path's largest volume %.6g exceeds its tau %.6g (other voxels or labels than planned with?)",
            first.max_before, input.tau);
  }
  LogInfo(
      "sigma_1: %zu -> %zu waypoints, largest %s %.6g -> %.6g %s^3 (tau %.6g), %d shortcuts (%d partial) in %d "
      "attempts",
      sigma1.size(), first.path.size(), ValidityModeName(input.validity).c_str(), first.max_before, first.max_after,
      scene.units.c_str(), input.tau, first.shortcuts, first.partial_shortcuts, first.attempts);
  SmoothOptions second_options = options.smooth;
  second_options.seed = options.smooth.seed + 1;
  const std::unique_ptr<ClearanceGuard> guard = MakeGuard(scene, problem, options.smooth, problem.robot, sigma2);
  const SmoothResult second = SmoothPath(problem, checker, sigma2, second_options, guard.get());
  SmoothResult& result = out->result;
  result.path = first.path;
  int inter_index = static_cast<int>(result.path.size()) - 1;
  result.path.insert(result.path.end(), second.path.begin() + 1, second.path.end());
  // The smoother's check step (planning/smoother.h), for both parts.
  const double step = options.smooth.resolution * problem.robot_diagonal / 4.0;
  const MotionChecker rigid(problem, checker, step);
  const VolumeGuard volume_guard(problem, volume, out->model->measure(), step);
  const VolumeValidity sigma1_validity(volume, out->model->measure(), first.max_before);
  std::size_t frozen_inter = static_cast<std::size_t>(inter_index);
  FreezeRotationAcrossInter(problem, rigid, sigma1_validity, volume_guard, *guard, &frozen_inter, &result.path);
  inter_index = static_cast<int>(frozen_inter);
  // The turning left in sigma_1 (before a freeze), straightened: its
  // wobble out, under sigma_1's own validity and the volume guard.
  const double turning = MeasurePath(problem, result.path).rotation;
  if (StraightenRotation(problem, sigma1_validity, options.smooth, &volume_guard, 0, frozen_inter, &result.path)) {
    LogInfo("sigma_1's rotation straightened: %.3f -> %.3f rad", turning, MeasurePath(problem, result.path).rotation);
  }
  // A straight retreat may also leave from sigma_1, where D is already free
  // of S before sigma_1's end (c_inter only had to be psi clear of the
  // fasteners): from there on the path is rigid, so the pose it leaves from
  // becomes c_inter. Checked like sigma_2 (collision, clearance guard).
  // The pose it leaves from must also be valid under sigma_1's volume (a
  // pose between two checked ones may not be: the volume model keeps rigid
  // solids within half the rigid tolerance), else the retreat is undone.
  const std::vector<Pose> before_retreat = result.path;
  const int retreat = StraightRetreatFrom(problem, checker, second_options, guard.get(), 0, &result.path);
  if (retreat >= 0 && retreat < inter_index) {
    if (sigma1_validity.IsValid(result.path[retreat])) {
      LogInfo("straight retreat from sigma_1's waypoint %d (was c_inter: %d)", retreat, inter_index);
      inter_index = retreat;
    } else {
      result.path = before_retreat;
    }
  }
  WarnBelowClearance(scene, *guard, std::vector<Pose>(result.path.begin() + inter_index, result.path.end()),
                     inter_index);
  result.before = MeasurePath(problem, path);
  result.after = MeasurePath(problem, result.path);
  result.shortcuts = first.shortcuts + second.shortcuts;
  result.attempts = first.attempts + second.attempts;
  result.cut_short = second.cut_short;  // sigma_1's volume smoothing counts work only
  return inter_index;
}

}  // namespace

SmoothedPath SmoothPlannedPath(const Scene& scene, const PlanningProblem& problem, const PathArtifact& input,
                               const std::string& input_file, const SmoothPlannedPathOptions& options) {
  // A path of another scene whose poses happen to be valid here was smoothed.
  CheckMadeFrom(input_file, kPathSchema, kPathSchemaVersion, scene, MadeFrom::kMeshes);
  if (!input.success || input.waypoints.empty()) {
    throw InputErrorAt(input_file, "holds no path (the planner did not succeed)");
  }
  if ((problem.reference_point - input.reference_point).norm() > 1e-9 * (1.0 + problem.robot_diagonal)) {
    throw InputErrorAt(input_file, "was planned about another reference point than this scene's");
  }
  if (input.validity == ValidityMode::kRigidExact) return SmoothRigidExact(scene, problem, input, input_file, options);

  const bool volume_mode = input.validity != ValidityMode::kCollision;
  const int first_rigid = volume_mode ? std::max(0, input.inter_index) : 0;
  const std::vector<Pose> input_rigid(input.waypoints.begin() + first_rigid, input.waypoints.end());
  const DenseCheckReport input_check = DenseCheckPath(scene, input.reference_point, input_rigid, 0.01);
  if (!input_check.valid) {
    throw InputErrorAt(input_file, "the input path is not valid in this scene: segment " +
                                       std::to_string(first_rigid + input_check.first_bad_segment) + " " +
                                       input_check.reason);
  }
  SmoothedPath out;
  out.clearance_robot = problem.robot;
  out.planning_path = ToPlanning(problem, input.waypoints);
  const FclCollisionChecker checker(problem.robot, problem.environment);
  if (!volume_mode && (!options.volume.voxels.empty() || !options.volume.labels.empty())) {
    LogWarn("--voxels and --labels are ignored: the path was planned under plain collision");
  }
  int inter_index = -1;
  DenseCheckReport output_check;
  // The smoother's checks are discrete (a quarter of the planning step): a
  // shortcut that slides along S a few microns off can graze it between
  // two checked poses, which the dense re-check then finds (panel-channel
  // seed 4, plain collision: 0.0004 mm from S). Under plain collision the
  // path is then smoothed again at a 4x finer step before the input path is
  // kept, as ausbau-plan certifies again (plan_scene.cpp).
  const std::unique_ptr<ClearanceGuard> guard =
      volume_mode ? nullptr : MakeGuard(scene, problem, options.smooth, problem.robot, out.planning_path);
  for (int round = 1;; ++round) {
    SmoothPlannedPathOptions within = options;
    if (round > 1) within.smooth.resolution /= 4;
    if (!volume_mode) {
      out.result = SmoothPath(problem, checker, out.planning_path, within.smooth, guard.get());
    } else {
      inter_index = SmoothInIState(scene, problem, input, checker, first_rigid, within, &out);
    }
    out.artifact = input;
    out.artifact.units = scene.units;
    out.artifact.clearance = ClearanceInSceneUnits(options.smooth.clearance, scene.units);
    out.artifact.waypoints = ToScene(problem, out.result.path);
    if (!volume_mode) {
      // Written for readers that interpolate about the mesh origin, as the
      // rigid-exact branch and ausbau-plan do (plan_scene.cpp): a part placed
      // metres from that origin would otherwise sweep off the smoothed motion
      // on turning segments. The volume modes keep their rows (one per
      // planned pose, with per-row volumes); simplified there.
      const double deviation = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene, nullptr) / 10;
      out.artifact.waypoints = DensifyForPlainInterpolation(out.artifact.waypoints, problem.reference_point,
                                                            problem.dynamic_origin, deviation);
    }
    const std::vector<Pose> output_rigid(out.artifact.waypoints.begin() + std::max(0, inter_index),
                                         out.artifact.waypoints.end());
    output_check = DenseCheckPath(scene, problem.reference_point, output_rigid, 0.01);
    if (output_check.valid || volume_mode || round == 2) break;
    LogInfo("smoothed path fails the dense re-check (segment %d, %s); smoothing again at a 4x finer step",
            output_check.first_bad_segment, output_check.reason.c_str());
  }
  if (guard) WarnBelowClearance(scene, *guard, out.result.path, 0);
  SmoothResult& result = out.result;
  if (!output_check.valid) {
    // The smoother's own check is discrete; if the independent check finds
    // a collision on a shortcut, keep the input path rather than a bad one.
    LogWarn("smoothed path fails the dense re-check (segment %d, %s); keeping the input path",
            output_check.first_bad_segment, output_check.reason.c_str());
    out.artifact.waypoints = input.waypoints;
    result.path = out.planning_path;
    result.after = result.before;
    inter_index = input.inter_index;
  }
  if (volume_mode) {
    PathArtifact& a = out.artifact;
    a.inter_index = inter_index;
    DescribeWaypoints(*out.model, checker, result.path, &a);
  }
  SetLengths(result, &out.artifact);
  out.artifact.smoothing_cut_short = result.cut_short;
  LogInfo(
      "length %.4f -> %.4f (normalized), translation %.4g -> %.4g, rotation %.3f -> %.3f rad; "
      "%zu -> %zu waypoints, %d shortcuts in %d attempts",
      result.before.normalized, result.after.normalized, result.before.translation, result.after.translation,
      result.before.rotation, result.after.rotation, input.waypoints.size(), out.artifact.waypoints.size(),
      result.shortcuts, result.attempts);
  return out;
}

}  // namespace ausbau
