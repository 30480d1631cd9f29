#include "workflow/plan_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "collision/farr_checker.h"
#include "collision/fcl_checker.h"
#include "collision/rigid_depth.h"
#include "collision/scene_parts.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/format.h"
#include "core/log.h"
#include "geometry/shells.h"
#include "inistate/inistate_planner.h"
#include "inistate/tau_estimate.h"
#include "planning/certify.h"
#include "planning/clearance.h"
#include "planning/dense_check.h"
#include "planning/exact_check.h"
#include "planning/smoother.h"
#include "scene/scene_check.h"
#include "scene/units.h"
#include "workflow/made_from.h"

namespace ausbau {
namespace {

// FCL, or FARR in front of FCL with the distance fields of S and D (given,
// or built / reused through the cache beside the scene).
std::unique_ptr<PoseValidity> MakeChecker(const PlanSceneOptions& options, const Scene& scene,
                                          const PlanningProblem& problem) {
  if (options.collision != CollisionMode::kFarr) {
    if (!options.distfield.empty()) LogWarn("--distfield is ignored with --collision fcl");
    return std::make_unique<FclCollisionChecker>(problem.robot, problem.environment);
  }
  std::shared_ptr<const DistanceField> static_field, dynamic_field;
  const std::vector<std::string> paths = DistfieldPaths(options);
  if (!paths.empty()) {
    static_field = ReadDistanceField(paths[0]);
    dynamic_field = ReadDistanceField(paths[1]);
    // The triangle count too: the hash is an attribute, and the cells' triangle
    // indices are only checked against the count the file itself declares.
    if (static_field->mesh_hash() != MeshContentHash(problem.environment) ||
        static_field->triangle_count() != static_cast<std::int64_t>(problem.environment.triangles.size())) {
      throw InputErrorAt(paths[0],
                         "distance field built for another mesh than this scene's S (ausbau-distfield-build)");
    }
    if (dynamic_field->mesh_hash() != MeshContentHash(problem.robot) ||
        dynamic_field->triangle_count() != static_cast<std::int64_t>(problem.robot.triangles.size())) {
      throw InputErrorAt(paths[1],
                         "distance field built for another mesh than this scene's D (ausbau-distfield-build)");
    }
  } else {
    DistanceFieldOptions field_options;
    field_options.threads = options.planner.threads;
    field_options.progress = ShowProgress("distance field");
    const std::filesystem::path cache = DefaultDistanceFieldCacheDir(scene.file);
    static_field = LoadOrBuildDistanceField(problem.environment, field_options, cache, "distance field of S",
                                            scene.units, "world");
    dynamic_field = LoadOrBuildDistanceField(problem.robot, field_options, cache, "distance field of D", scene.units,
                                             "D relative to its reference point");
  }
  return std::make_unique<FarrCollisionChecker>(problem.robot, problem.environment, dynamic_field, static_field,
                                                options.planner.seed);
}

// The planner of sigma_1 (volume modes) or of the whole path: "auto" picks
// EST near an invalid start (thesis 5.4.4) and CR-RRTC otherwise.
PlannerOptions ResolvedPlanner(const PlanSceneOptions& options, bool volume_mode) {
  PlannerOptions planner = options.planner;
  if (planner.planner == "auto") planner.planner = volume_mode ? "est" : "cr-rrtc";
  // Exit moves where they were measured: the collision validity's planner.
  if (planner.exit_axes < 0) planner.exit_axes = options.validity == ValidityMode::kCollision ? 1 : 0;
  // The coarse first search where it was measured: the collision
  // validity's RRT-Connect planners.
  if (planner.coarse_iterations < 0) {
    planner.coarse_iterations =
        options.validity == ValidityMode::kCollision ? CoarseFirstIterationsFor(planner.planner) : 0;
  }
  return planner;
}

// The planner's time limit cut to what is left of the run's budget (at
// least half a second, so that a stage started late still answers with its
// best partial path); *bound says the budget is the smaller.
PlannerOptions WithinDeadline(PlannerOptions planner, double deadline, bool* bound) {
  planner.time_limit_s = LimitByDeadline(planner.time_limit_s, deadline, 0.5, bound);
  if (*bound) LogInfo("time budget: %.1f s left for planning", planner.time_limit_s);
  return planner;
}

// An unsolved run: its best partial path (scene convention) and whether the
// budget ended it.
void FillPartial(const PlanningProblem& problem, const PlanResult& result, PathArtifact* artifact) {
  if (result.solved()) return;
  for (const Pose& pose : result.partial) artifact->partial_waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&artifact->partial_waypoints);
  // Any clock (--time-limit, the safety net, or the --budget / --deadline
  // of the run) that ends the search makes the result one cut short, not
  // the deterministic answer: the verdict says "not-removable (budget)" and
  // the next run plans again (stages/plan/main.cpp: CutShort).
  artifact->stopped_by_budget = result.status == PlanStatus::kTimeLimit;
}

void LogResult(const char* what, const PlanStats& stats, bool solved) {
  LogInfo("%s %s after %.3f s: %lld iterations, %lld nodes, %lld validity checks (%.1f%% invalid)", what,
          solved ? "solved" : "no path", stats.time_s, static_cast<long long>(stats.iterations),
          static_cast<long long>(stats.nodes), static_cast<long long>(stats.collision_checks),
          stats.collision_checks > 0 ? 100.0 * stats.invalid_checks / stats.collision_checks : 0.0);
}

// The clearance the planner itself keeps: only one the user asked for
// (--clearance d >= 0). The default (-1: 0.5 mm) is the smoother's alone:
// planning under distance queries first made the default run 20-40x slower
// on the OMPL scenes (alpha-1.5: 12-27 s against 0.4-0.8 s) and bent
// straight paths, for a clearance smoothing keeps anyway (issue 29).
double PlannerClearance(const PlanSceneOptions& options, double clearance) {
  if (options.clearance >= 0) return clearance;
  LogInfo("clearance: %.4g kept by smoothing, not while planning (the default; --clearance asks the planner too)",
          clearance);
  return 0;
}

// --clearance while planning: a first try under the validity with D's part
// (`robot`, ClearanceRobot) at least min(d, its clearance at the start and
// goal) from S, capped at 2048 iterations and nothing else (a time cap made
// the answer depend on the machine's load: the golden demo planned
// differently under load), so the answer depends on the seed only; without
// a path, `plan` as asked, with its whole time limit. A start in contact (clearance 0) leaves nothing
// to keep: the clearance is then the smoother's (workflow/smooth_path.h).
// Never less valid: the first try's validity only adds a condition.
// `grow_crop_on_free_pull` (a crop level that is not the last): where a
// straight pull is free up to the crop's edge, return unsolved before any
// sampling, so that the next level is tried at once.
PlanResult PlanKeepingClearance(
    const PlanningProblem& problem, const PoseValidity& validity, const PlannerOptions& planner,
    const TriangleMesh& robot, double clearance, const std::string& units,
    const std::function<PlanResult(const PoseValidity&, const PlannerOptions&)>& plan_as_asked,
    bool grow_crop_on_free_pull = false) {
  const auto plan = [&](const PoseValidity& validity, const PlannerOptions& options) {
    PlanResult result = plan_as_asked(validity, options);
    ThrowIfCancelled();  // a cancelled search is no answer (core/cancel.h)
    return result;
  };
  // Straight pulls first (planning/planner.h): a peg in a tight fit or a cap
  // on its post comes out along one axis, which sampling finds last; no
  // clearance is kept there (the straight way out bends nothing).
  const PlanResult pulled = TryStraightPulls(problem, validity, planner);
  if (pulled.solved()) {
    std::string legs;
    for (std::size_t i = 1; i < pulled.path.size(); ++i) {
      const Eigen::Vector3d way = pulled.path[i].t - pulled.path[i - 1].t;
      if (!(way.norm() > 0)) continue;  // certification may repeat a pose
      legs += Fmt("%s[%.4f, %.4f, %.4f] (%.4g %s)", legs.empty() ? "" : ", then ", way.normalized().x(),
                  way.normalized().y(), way.normalized().z(), way.norm(), units.c_str());
    }
    LogInfo("straight pull: D comes out along %s; %lld checks", legs.c_str(),
            static_cast<long long>(pulled.stats.collision_checks));
    return pulled;
  }
  if (!problem.goal) {
    LogInfo("straight pulls: none of %lld gets D out (%lld checks, %.1f s)",
            static_cast<long long>(pulled.stats.iterations), static_cast<long long>(pulled.stats.collision_checks),
            pulled.stats.time_s);
  }
  // A pull free up to the edge of S's crop: the next, larger crop first,
  // before this one's sampling iterations (a pin in a tube longer than the
  // crop comes out only beyond it; each level's sampling would cost its
  // whole share of work first).
  if (grow_crop_on_free_pull && pulled.pull_left_crop && pulled.status != PlanStatus::kTimeLimit) {
    LogInfo("straight pulls: one moves D freely to the edge of S's crop: growing the crop before sampling");
    return pulled;
  }
  const auto with_pulls = [&](PlanResult result) {
    result.stats.time_s += pulled.stats.time_s;
    result.stats.collision_checks += pulled.stats.collision_checks;
    result.stats.invalid_checks += pulled.stats.invalid_checks;
    return result;
  };
  // The pulls' time counts against the time limit: sampling gets what is
  // left (the pulls themselves count work, not seconds, so that whether
  // they get D out does not depend on the machine; a stage's limit is
  // then overrun only by pulls longer than the limit).
  PlannerOptions sampling = planner;
  sampling.time_limit_s = planner.time_limit_s - pulled.stats.time_s;
  sampling.start_branches = pulled.pull_stops;  // the tree grows from where the pulls stopped, too
  if (!(sampling.time_limit_s > 0)) {
    LogInfo("straight pulls took %.1f s of the time limit of %.1f s: none left for sampling", pulled.stats.time_s,
            planner.time_limit_s);
    PlanResult none = pulled;
    none.path.clear();
    none.status = PlanStatus::kTimeLimit;
    return none;
  }
  if (!(clearance > 0)) return with_pulls(plan(validity, sampling));
  const ClearanceMeter meter(problem, robot);
  double floor = std::min(clearance, meter.At(problem.start).clearance);
  if (problem.goal) floor = std::min(floor, meter.At(*problem.goal).clearance);
  if (!(floor > 0)) {
    LogInfo("clearance: D starts in contact with S; the clearance of %.4g %s is left to smoothing", clearance,
            units.c_str());
    return with_pulls(plan(validity, sampling));
  }
  PlannerOptions first = sampling;
  first.start_branches.clear();  // walked under `validity`, not checked for the clearance
  constexpr std::int64_t kFirstTryIterations = 2048;
  first.max_iterations =
      planner.max_iterations > 0 ? std::min(planner.max_iterations, kFirstTryIterations) : kFirstTryIterations;
  const std::unique_ptr<PoseValidity> keeping = WithClearance(validity, problem, robot, floor);
  const PlanResult kept = plan(*keeping, first);
  if (kept.solved()) {
    LogInfo("clearance: planned keeping at least %.4g %s from S (--clearance %.4g)", floor, units.c_str(), clearance);
    return with_pulls(kept);
  }
  if (kept.status == PlanStatus::kTimeLimit) {
    // The clock, not the 2048 iterations, ended the first try: falling back
    // would give another path than the one an idle machine finds, so the
    // run is cut short (stopped_by_budget) instead.
    LogInfo("clearance: the time limit ended the first try (keeping %.4g %s) before its %lld iterations", floor,
            units.c_str(), static_cast<long long>(first.max_iterations));
    return with_pulls(kept);
  }
  LogInfo("clearance: no path keeping %.4g %s from S within %lld iterations; planning without it", floor, units.c_str(),
          static_cast<long long>(first.max_iterations));
  // The plan as asked gets its whole time limit: the first try, bounded by
  // its iterations only, comes on top (on a fine mesh its 2048 iterations
  // took most of a 60 s limit, and a remainder left too little to plan).
  PlanResult result = plan(validity, sampling);
  result.stats.time_s += kept.stats.time_s;
  result.stats.iterations += kept.stats.iterations;
  result.stats.nodes += kept.stats.nodes;
  result.stats.collision_checks += kept.stats.collision_checks;
  result.stats.invalid_checks += kept.stats.invalid_checks;
  return with_pulls(result);
}

// Fills the waypoints (scene convention) and lengths of an artifact.
void FillPath(const PlanningProblem& problem, const std::vector<Pose>& path, PathArtifact* artifact) {
  for (const Pose& pose : path) artifact->waypoints.push_back(problem.PlanningToScene(pose));
  AlignQuaternionSigns(&artifact->waypoints);
  const PathLength length = MeasurePath(problem, path);
  artifact->length_normalized = length.normalized;
  artifact->length_translation = length.translation;
  artifact->length_rotation = length.rotation;
}

// Re-checks the rigid part of a path (waypoints from `first` on) with the
// independent dense check; throws when it fails (a bug, not bad input).
// `done`: that check of the whole path, already run and passed (the
// collision validity's re-certification runs it first).
void VerifyRigid(const Scene& scene, const PathArtifact& artifact, int first,
                 const std::optional<DenseCheckReport>& done = std::nullopt) {
  const DenseCheckReport report =
      done ? *done
           : DenseCheckPath(scene, artifact.reference_point,
                            std::vector<Pose>(artifact.waypoints.begin() + first, artifact.waypoints.end()), 0.01);
  if (!report.valid) {
    throw std::runtime_error("planned path fails the dense re-check: segment " +
                             std::to_string(first + report.first_bad_segment) + " " + report.reason);
  }
  LogInfo("dense re-check passed (%lld poses, step 1%% of D's diagonal)", static_cast<long long>(report.poses_checked));
}

// --validity collision: whether the path stays out of S by the exact check
// too; where it does not, it is no path (the artifact says success = 0 and
// keeps it as the partial path; exit 3). FCL intersects surfaces only, and
// the planner and the dense re-check both look at poses a step of 1% of
// D's diagonal apart: a part thinner than that step goes through a wall of
// S thicker than itself unseen, since at every pose looked at it is either
// clear of the wall or wholly inside it, where no surfaces cross (a plate
// through a 3 mm wall: 1.5 mm deep in its middle, "dense re-check
// passed"). The exact check measures depth, convex shell by shell, by
// conservative advancement, as the verdict does. "Deep in S" means
// something only where D and S are solids: on a soup of open surfaces (the
// OMPL.app scenes) a shell has no inside, and the exact check measures
// depths that are none (117 units on alpha-1.5, whose path is free), so it
// runs where every shell of D and S is closed with a volume.
bool AllSolid(const TriangleMesh& mesh) {
  const std::vector<Shell> shells = SplitIntoShells(mesh);
  return std::all_of(shells.begin(), shells.end(), [](const Shell& s) { return s.closed && s.volume > 0; });
}

// The exact check of the written path where D and S are solids; none where
// they are not.
std::optional<ExactCheckReport> ExactCheckWhereSolid(const Scene& scene, const PlanSceneOptions& options,
                                                     const PathArtifact& artifact) {
  if (!AllSolid(scene.dynamic_mesh) || !AllSolid(scene.static_mesh)) return std::nullopt;
  const double tolerance = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene.units, nullptr);
  return ExactCheckPath(scene, artifact.waypoints, tolerance);
}

// `done`: ExactCheckWhereSolid of the written path, already run (the
// re-certification below runs it; none there where D or S is no solid), or
// null.
bool ThroughS(const Scene& scene, const PlanSceneOptions& options, PathArtifact* artifact,
              const std::optional<ExactCheckReport>* done) {
  const std::optional<ExactCheckReport> report = done ? *done : ExactCheckWhereSolid(scene, options, *artifact);
  if (!report) {
    LogInfo("no exact re-check: D or S is not made of closed solids (a path inside S would not be seen)");
    return true;
  }
  const ExactCheckReport& exact = *report;
  if (exact.valid) {
    LogInfo("exact check passed (%lld poses): deepest rigid penetration %.4g %s",
            static_cast<long long>(exact.poses_checked), exact.max_rigid_depth, scene.units.c_str());
    return true;
  }
  LogError(
      "the planned path passes the dense re-check but not the exact one: %s (FCL sees surfaces only, and a part "
      "thinner than the check's step goes through a thicker wall unseen): no valid path (try a finer --resolution, "
      "or --validity rigid-exact)",
      exact.reason.c_str());
  artifact->partial_waypoints = artifact->waypoints;
  artifact->waypoints.clear();
  artifact->success = false;
  return false;
}

// Volume modes: sigma_1 under the volume validity out of the fasteners'
// reach, sigma_2 rigid (thesis 5.4.4).
PathArtifact PlanVolumeMode(const PlanSceneOptions& options, const Scene& scene, const PlanningProblem& problem,
                            const PoseValidity& rigid_checker, PlanStats* stats, PlanStatus* status) {
  const ValidityMode mode = options.validity;
  const std::unique_ptr<VolumeModel> model = LoadVolumeModel(scene, problem, mode, options.volume);
  double tau = options.tau, psi = options.psi > 0 ? MillimetresInSceneUnits(options.psi, scene.units) : options.psi;
  TauEstimate estimate;  // where tau comes from an estimate: its sigma_1 too
  if (!options.tau_file.empty()) {
    const TauArtifact stored = ReadTauArtifact(options.tau_file);
    CheckMadeFrom(options.tau_file, kTauSchema, kTauSchemaVersion, scene, MadeFrom::kMeshes);
    if (stored.validity != options.validity) {
      throw InputErrorAt(options.tau_file, "tau was estimated for --validity " + ValidityModeName(stored.validity) +
                                               ", not " + ValidityModeName(options.validity));
    }
    estimate = stored.estimate;
    if (tau < 0) tau = stored.estimate.tau;
    if (psi <= 0) psi = stored.estimate.psi;
  }
  if (psi <= 0) psi = model->EstimatePsi();
  const double start_volume = model->Measure(problem.start);
  const FclCollisionChecker fcl(problem.robot, problem.environment);
  if (tau < 0) {
    if (mode == ValidityMode::kShrink) {
      tau = 0;
    } else {
      LogInfo("no --tau or --tau-file: estimating tau here (ausbau-tau-estimate caches it)");
      TauEstimateOptions tau_options;
      tau_options.planner = ResolvedPlanner(options, true);
      estimate = EstimateTau(FastenerProblem(problem, fcl, psi), model->volume(), model->measure(), psi, tau_options);
      tau = estimate.tau;
    }
  }
  LogInfo("validity %s: tau %.6g %s^3 (start: %.6g), psi %.6g %s", ValidityModeName(mode).c_str(), tau,
          scene.units.c_str(), start_volume, psi, scene.units.c_str());
  if (start_volume > tau) {
    throw InputError("--tau " + std::to_string(tau) + " is below the start's volume " + std::to_string(start_volume) +
                     " under --validity " + ValidityModeName(mode) + ": the start would be invalid");
  }
  const VolumeValidity volume_validity(model->volume(), model->measure(), tau);
  InIStateOptions inistate;
  inistate.local = ResolvedPlanner(options, true);
  inistate.rigid = options.planner;
  inistate.rigid.planner = options.rigid_planner;
  inistate.psi = psi;
  // The estimate's successful round planned sigma_1 already; with the same
  // tau, psi, planner and seed (and no iteration cap: the round's cap on
  // checks only ended it no earlier than it found the path, so the same
  // search without one finds the same path), planning it again would repeat
  // that work (PlanInIState re-checks the path and plans anew if it does
  // not hold).
  if (estimate.solved && estimate.tau == tau && estimate.psi == psi && estimate.local_seed == inistate.local.seed &&
      estimate.local_planner == inistate.local.planner && inistate.local.max_iterations == 0) {
    inistate.known_local_path = estimate.local_path;
  }
  const InIStateResult result = PlanInIState(problem, volume_validity, rigid_checker, fcl, inistate);
  *stats = result.Stats();
  *status = result.status;

  PathArtifact artifact;
  artifact.planner = inistate.local.planner + "+" + inistate.rigid.planner;
  artifact.validity = options.validity;
  artifact.tau = tau;
  artifact.psi = psi;
  if (!result.solved()) return artifact;
  FillPath(problem, result.path, &artifact);
  artifact.inter_index = result.inter_index;
  DescribeWaypoints(*model, fcl, result.path, &artifact);
  return artifact;
}

// --validity rigid-exact: D's rigid shells never deeper in S than the
// tolerance (half of it while planning, so that the plain-interpolated,
// densified file passes the full tolerance), its fasteners free
// (collision/rigid_depth.h). A collision-free start is the same problem
// without fasteners: plain rigid planning with a tolerance.
// One crop level (planning/reach_crop.h) with `time_limit_s` (the safety
// net: what is left of the stage's) and at most `work_iterations` planner
// iterations over its restarts (0: unlimited); *cropped says whether the
// level cropped S.
PlannedPath PlanRigidExactAt(const PlanSceneOptions& options, const Scene& scene, int crop_level, double time_limit_s,
                             std::int64_t work_iterations, bool* cropped) {
  const double tolerance = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene, nullptr);
  const PlanningProblem problem = MakePlanningProblem(scene, crop_level);
  *cropped = problem.crop != nullptr;
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance,
                                   UnmeasuredInterference::kRigid, SceneFitRule(scene));
  LogInfo("scene %s: D %zu shells (%d fasteners, anchor %s), S %zu shells; rigid tolerance %.4g %s", scene.name.c_str(),
          parts->robot_shells.size(), parts->FastenerCount(), parts->Describe(parts->anchor, true).c_str(),
          parts->static_shells.size(), tolerance, scene.units.c_str());
  PlannedPath planned;
  PathArtifact& artifact = planned.artifact;
  artifact.validity = ValidityMode::kRigidExact;
  artifact.reference_point = problem.reference_point;
  artifact.dynamic_origin = problem.dynamic_origin;
  artifact.scene = scene.name;
  artifact.units = scene.units;
  if (!parts->rigid_interference.empty()) {
    const int shell = parts->rigid_interference.front();
    if (std::isinf(parts->installed_depth[shell])) {
      LogError(
          "not removable as far as the exact check can tell: %s of D intersects S at the installed pose, in a "
          "non-convex pair whose depth is not measured (docs/rigid-exact.md; the volume modes, "
          "VALIDITY=labeled-mliv, bound such fits by tau)",
          parts->Describe(shell, true).c_str());
    } else {
      LogError("not removable without cutting: rigid %s of D penetrates S %.4g %s deep at the installed pose",
               parts->Describe(shell, true).c_str(), parts->installed_depth[shell], scene.units.c_str());
    }
    artifact.planner = "none";
    planned.status = PlanStatus::kTimeLimit;
    return planned;
  }
  const RigidDepthChecker checker(parts, tolerance / 2, tolerance / 4, NewContacts::kCollide);
  CheckEndpoints(problem, checker, scene.file.string());
  PlannerOptions planner = ResolvedPlanner(options, false);
  planner.time_limit_s = time_limit_s;
  planner.max_total_iterations = work_iterations;
  bool budget_bound = false;
  planner = WithinDeadline(planner, options.deadline, &budget_bound);
  LogInfo("planning with %s, seeds from %llu (restarts after 4096, 8192, ... iterations), time limit %.1f s (%s start)",
          planner.planner.c_str(), static_cast<unsigned long long>(planner.seed), planner.time_limit_s,
          parts->FastenerCount() > 0 ? "fastened" : "collision-free");
  const double clearance = ClearanceInSceneUnits(options.clearance, scene.units);
  artifact.clearance = clearance;
  const PlanResult result = PlanKeepingClearance(
      problem, checker, planner, ClearanceRobot(problem, parts.get()), PlannerClearance(options, clearance),
      scene.units,
      [&](const PoseValidity& validity, const PlannerOptions& p) { return PlanWithRestarts(problem, validity, p); },
      work_iterations > 0);
  artifact.planner = planner.planner;
  artifact.stats = result.stats;
  artifact.success = result.solved();
  LogResult("planning", result.stats, result.solved());
  FillPartial(problem, result, &artifact);
  if (result.solved()) {
    FillPath(problem, result.path, &artifact);
    artifact.waypoints = DensifyForPlainInterpolation(artifact.waypoints, problem.reference_point,
                                                      problem.dynamic_origin, tolerance / 10);
    if (options.verify) {
      const ExactCheckReport check = ExactCheckPath(scene, artifact.waypoints, tolerance);
      if (!check.valid) throw std::runtime_error("planned path fails the exact check: " + check.reason);
      LogInfo(
          "exact check passed (%lld poses, %lld stretches proved swept): deepest rigid penetration %.4g %s, "
          "fasteners %.4g %s",
          static_cast<long long>(check.poses_checked), static_cast<long long>(check.stretches_proved),
          check.max_rigid_depth, scene.units.c_str(), check.max_fastener_depth, scene.units.c_str());
    }
  }
  planned.status = result.status;
  if (!result.solved()) {
    LogError("no path within the budget (%s)", PlanStopReason(result.status, budget_bound));
  }
  return planned;
}

// Rigid-exact planning within D's reach, grown as needed: crop level 0,
// then each level doubles the margin (planning/reach_crop.h) while no path
// is found, up to the uncropped scene or --max-crop-level. A level that
// crops gets options.crop_level_iterations planner iterations (its
// restarts together), the last level (the uncropped scene, or the level
// --max-crop-level allows) no cap: counted in work, not in a share of the
// time limit, so which level answers does not depend on the machine's load.
// A level where a straight pull moves D freely to the crop's edge grows at
// once, without sampling (PlanKeepingClearance).
// The time limit is the whole stage's safety net: every level gets what is
// left of it, and when it fires the path artifact says so (stopped_by_budget).
PlannedPath PlanRigidExact(const PlanSceneOptions& options, const Scene& scene) {
  bool assumed = false;
  RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene, &assumed);
  if (assumed) {
    LogWarn("scene units '%s' unknown: --rigid-tolerance %.4g taken in scene units (as mm)", scene.units.c_str(),
            options.volume.rigid_tolerance_mm);
  }
  int levels = 1;  // the levels that crop, then one uncropped (unless capped)
  while (ChooseReachCrop(scene, levels - 1) && (options.max_crop_level < 0 || levels - 1 < options.max_crop_level)) {
    ++levels;
  }
  const auto begin = std::chrono::steady_clock::now();
  for (int level = 0;; ++level) {
    const bool last = level + 1 >= levels;
    const double left =
        options.planner.time_limit_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    bool cropped = false;
    PlannedPath planned = PlanRigidExactAt(options, scene, level, std::max(0.1, left),
                                           last ? 0 : options.crop_level_iterations, &cropped);
    if (planned.artifact.success || !cropped || planned.artifact.planner == "none") return planned;
    if (planned.artifact.stopped_by_budget) return planned;  // the clock ended it (cut short): no larger crop
    if (options.max_crop_level >= 0 && level >= options.max_crop_level) {
      LogError("no path within D's reach up to crop level %d (--max-crop-level)", level);
      return planned;
    }
    LogInfo("no path within the crop of level %d: growing it (margin x2)", level);
  }
}

}  // namespace

const std::vector<std::string>& CollisionModeNames() {
  static const std::vector<std::string> names = {"fcl", "farr"};  // in the enum's order
  return names;
}

CollisionMode ParseCollisionMode(const std::string& name) {
  if (name == "fcl") return CollisionMode::kFcl;
  if (name == "farr") return CollisionMode::kFarr;
  throw InputError("--collision: unknown mode '" + name + "' (expected fcl or farr)");
}

std::string CollisionModeName(CollisionMode mode) { return CollisionModeNames().at(static_cast<std::size_t>(mode)); }

std::vector<std::string> DistfieldPaths(const PlanSceneOptions& options) {
  if (options.collision != CollisionMode::kFarr || options.distfield.empty()) return {};
  const auto comma = options.distfield.find(',');
  if (comma == std::string::npos || comma == 0 || comma + 1 == options.distfield.size() ||
      options.distfield.find(',', comma + 1) != std::string::npos) {
    throw InputError("--distfield: expected two files, S.h5,D.h5 (got '" + options.distfield + "')");
  }
  return {options.distfield.substr(0, comma), options.distfield.substr(comma + 1)};
}

void PlanSceneOptions::Check() const {
  if (!(clearance == -1 || (clearance >= 0 && std::isfinite(clearance)))) {
    throw OptionError(&clearance, "clearance", "must be a finite number >= 0 (scene units)");
  }
  if (validity == ValidityMode::kRigidExact) {
    if (tau >= 0 || !tau_file.empty() || psi > 0) {
      throw InputError("--tau, --tau-file and --psi do not apply to --validity rigid-exact");
    }
    if (max_crop_level < -1) throw InputError("--max-crop-level: must be >= -1");
    if (!(volume.rigid_tolerance_mm > 0) || !std::isfinite(volume.rigid_tolerance_mm)) {
      throw InputError("--rigid-tolerance: must be a positive number (mm)");
    }
    ResolvedPlanner(*this, false).Check();
    return;
  }
  const bool volume_mode = IsVolumeValidity(validity);
  if (!volume_mode && (tau >= 0 || !tau_file.empty() || psi > 0)) {
    throw InputError(
        "--tau, --tau-file and --psi need a volume --validity (shrink, iv, mliv, labeled-mliv, "
        "labeled-mliv-unguarded)");
  }
  if (!(tau < 0 || std::isfinite(tau))) throw InputError("--tau: must be a finite number");
  if (!(psi >= 0) || !std::isfinite(psi)) throw InputError("--psi: must be >= 0");
  if (max_crop_level < -1) throw InputError("--max-crop-level: must be >= -1");
  if (crop_level_iterations < 1) throw InputError("--crop-level-iterations: must be >= 1");
  ResolvedPlanner(*this, volume_mode).Check();
  PlannerOptions rigid = planner;
  rigid.planner = rigid_planner;
  rigid.Check();
}

PlannedPath PlanScene(const Scene& scene, const PlanSceneOptions& options) {
  options.Check();
  // Every mode's path ends in the exact check at the rigid tolerance: a
  // scene whose meshes single precision rounded coarser than that is
  // refused before any work, whatever the validity (planning/exact_check.h).
  CheckStoredPrecision(scene, RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene.units, nullptr));
  // A hand-written scene whose start is far off S plans a task nobody meant (scene/scene_check.h).
  const std::string far_start = FarStartWarning(scene);
  if (!far_start.empty()) LogWarn("%s: %s", scene.file.string().c_str(), far_start.c_str());
  if (options.validity == ValidityMode::kRigidExact) return PlanRigidExact(options, scene);
  const bool volume_mode = IsVolumeValidity(options.validity);
  const PlanningProblem problem = MakePlanningProblem(scene);
  bool budget_bound = false;
  const PlannerOptions planner = WithinDeadline(ResolvedPlanner(options, volume_mode), options.deadline, &budget_bound);
  LogInfo("scene %s: S %zu triangles, D %zu triangles, validity %s, planner %s, seed %llu, time limit %.1f s",
          scene.name.c_str(), problem.environment.triangles.size(), problem.robot.triangles.size(),
          ValidityModeName(options.validity).c_str(), planner.planner.c_str(),
          static_cast<unsigned long long>(planner.seed), planner.time_limit_s);
  const std::unique_ptr<PoseValidity> checker_owner = MakeChecker(options, scene, problem);
  const PoseValidity& checker = *checker_owner;

  PlannedPath planned;
  PathArtifact& artifact = planned.artifact;
  PlanStats stats;
  bool solved = false;
  // The dense re-check of the whole written path when it already ran and
  // passed (collision validity, below).
  std::optional<DenseCheckReport> dense_of_written;
  // The same for the exact check (ran: whether it did, solids or not).
  std::optional<ExactCheckReport> exact_of_written;
  bool exact_ran = false;
  PlanStatus status = PlanStatus::kTimeLimit;
  if (volume_mode) {
    // Both of its planners within the budget (no partial path: sigma_1 and
    // sigma_2 keep none yet).
    PlanSceneOptions within = options;
    within.planner = WithinDeadline(options.planner, options.deadline, &budget_bound);
    artifact = PlanVolumeMode(within, scene, problem, checker, &stats, &status);
    solved = status == PlanStatus::kSolved;
    // The clock (time limit or budget) ended sigma_1's or sigma_2's search: cut short.
    artifact.stopped_by_budget = !solved && status == PlanStatus::kTimeLimit;
  } else {
    CheckEndpoints(problem, checker, scene.file.string());
    const double clearance = ClearanceInSceneUnits(options.clearance, scene.units);
    artifact.clearance = clearance;
    const PlanResult result = PlanKeepingClearance(
        problem, checker, planner, problem.robot, PlannerClearance(options, clearance), scene.units,
        [&](const PoseValidity& validity, const PlannerOptions& p) { return Plan(problem, validity, p); });
    artifact.planner = planner.planner;
    stats = result.stats;
    solved = result.solved();
    status = result.status;
    if (solved) {
      // The planner turns D about its reference point; readers of path.csv
      // interpolate about the pose convention's origin (README "What the
      // verdict promises"). For a part placed metres from its mesh origin a
      // turn of a degree or two then sweeps millimetres off the planned
      // motion, through S (the L-channel family: 5 mm deep by the external
      // oracle). Split such segments as the rigid-exact mode does, to a tenth
      // of the rigid tolerance; the motion stays the one planned.
      const double deviation = RigidToleranceInSceneUnits(options.volume.rigid_tolerance_mm, scene, nullptr) / 10;
      std::vector<Pose> path = result.path;
      const auto write = [&] {
        artifact.waypoints.clear();
        FillPath(problem, path, &artifact);
        artifact.waypoints = DensifyForPlainInterpolation(artifact.waypoints, problem.reference_point,
                                                          problem.dynamic_origin, deviation);
      };
      write();
      // The dense re-check looks at other poses than the certification did
      // (the written waypoints among them). Where it finds one in S, the
      // planned motion grazes S between the certification's poses (a
      // panel-channel scene, 0.2 mm clearance, did): certify again at a 4x
      // and a 16x finer step before calling the path a bug (VerifyRigid).
      // The same where D and S are solids and the exact check finds D
      // deeper in S than the rigid tolerance between two poses: the
      // certification's step (a quarter of a percent of D's diagonal) may
      // be wider than twice the tolerance (a panel-keyhole scene: 0.057 mm
      // deep for a tolerance of 0.05, D 60 mm across).
      // The re-check may take as long as the planner could have: a path
      // across bounds of 1e9 (goal: {clearance: 1e9}), which sweeps through
      // open space find in a moment, is billions of poses for it; such a
      // path is no answer (the time limit's), not one written unchecked.
      // The rounds certify at a quarter and a sixteenth of the
      // certification's step.
      const double certified = CertificationStep(problem, planner.resolution * problem.robot_diagonal);
      const auto dense_deadline =
          std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                 std::chrono::duration<double>(planner.time_limit_s));
      for (int round = 1; round <= 2 && options.verify; ++round) {
        const DenseCheckReport dense =
            DenseCheckPath(scene, problem.reference_point, artifact.waypoints, 0.01, dense_deadline);
        if (dense.valid) {
          dense_of_written = dense;                                           // VerifyRigid's check, done
          exact_of_written = ExactCheckWhereSolid(scene, options, artifact);  // ThroughS's
          exact_ran = true;
          if (!exact_of_written || exact_of_written->valid) break;
          LogInfo("the exact check finds %s; certifying the path again at 1/%d of the certification's step",
                  exact_of_written->reason.c_str(), 1 << (2 * round));
          if (!CertifyPath(problem, checker, certified / std::pow(4.0, round), planner, &path).certified) break;
          write();
          dense_of_written.reset();
          exact_of_written.reset();
          exact_ran = false;
          continue;
        }
        if (dense.stopped_by_deadline) {
          LogWarn(
              "the dense re-check of the planned path did not finish within --time-limit (%lld poses checked): "
              "no path",
              static_cast<long long>(dense.poses_checked));
          solved = false;
          status = PlanStatus::kTimeLimit;
          artifact.waypoints.clear();
          artifact.stopped_by_budget = true;  // cut short: the next run plans again
          break;
        }
        LogInfo("the dense re-check finds segment %d %s; certifying the path again at 1/%d of the certification's step",
                dense.first_bad_segment, dense.reason.c_str(), 1 << (2 * round));
        if (!CertifyPath(problem, checker, certified / std::pow(4.0, round), planner, &path).certified) break;
        write();
      }
    }
    FillPartial(problem, result, &artifact);
  }
  ThrowIfCancelled();  // the planners stopped early: no answer (core/cancel.h)
  planned.status = status;
  if (const auto* farr = dynamic_cast<const FarrCollisionChecker*>(&checker)) {
    const FarrStats farr_stats = farr->stats();
    LogInfo(
        "FARR: %lld queries, %lld collisions proven by rays, %lld answered by FCL (%lld of them collisions), "
        "%d rays per query at the end",
        static_cast<long long>(farr_stats.queries), static_cast<long long>(farr_stats.witnesses),
        static_cast<long long>(farr_stats.fcl_calls), static_cast<long long>(farr_stats.fcl_collisions),
        farr_stats.rays_now);
  }
  artifact.reference_point = problem.reference_point;
  artifact.dynamic_origin = problem.dynamic_origin;
  artifact.scene = scene.name;
  artifact.units = scene.units;
  artifact.success = solved;
  artifact.stats = stats;
  LogResult(volume_mode ? "InIState planning" : "planning", stats, solved);
  if (solved && options.verify) VerifyRigid(scene, artifact, std::max(0, artifact.inter_index), dense_of_written);
  if (solved && options.verify && options.validity == ValidityMode::kCollision &&
      !ThroughS(scene, options, &artifact, exact_ran ? &exact_of_written : nullptr)) {
    return planned;
  }
  if (!solved) {
    // The volume modes too: sigma_1's or sigma_2's status (an iteration
    // cap is not the clock).
    LogError("no path within the budget (%s)", PlanStopReason(status, budget_bound));
  }
  return planned;
}

ValidityMode ChooseValidity(const Scene& scene, double rigid_tolerance_mm) {
  const double tolerance = RigidToleranceInSceneUnits(rigid_tolerance_mm, scene, nullptr);
  const PlanningProblem problem = MakePlanningProblem(scene);
  // Classified as the volume model's rigid guard and the verdict's check of
  // a volume path do (VolumeModel::GuardRigidParts): which shells other
  // than the anchor intersect a non-convex shell does not depend on that,
  // and it says which shells the volume model keeps rigid.
  const auto parts = ClassifyParts(problem.robot, problem.environment, problem.start, tolerance,
                                   UnmeasuredInterference::kFastener, SceneFitRule(scene));
  if (parts->non_convex_interference.empty()) return ValidityMode::kRigidExact;
  // The volume model bounds how far such shells bend. Where a shell it keeps
  // rigid already clashes with S (the anchor of a bowden collet pressed 2.6
  // mm into its plate), its exact check refuses every path: the volume model
  // would only take minutes (voxels, labels, tau: 168 s) to the same NOT
  // REMOVABLE that rigid-exact gives at once, with the clash named.
  if (!parts->rigid_interference.empty()) {
    LogInfo(
        "%s of D intersects a non-convex shell of S at the installed pose, but %s, rigid in the volume model "
        "too, already penetrates S %.4g deep there: rigid-exact",
        parts->Describe(parts->non_convex_interference.front(), true).c_str(),
        parts->Describe(parts->rigid_interference.front(), true).c_str(),
        parts->installed_depth[parts->rigid_interference.front()]);
    return ValidityMode::kRigidExact;
  }
  LogInfo(
      "%s of D intersects a non-convex shell of S at the installed pose (a clip or a fit in a welded "
      "plate?): labeled-mliv",
      parts->Describe(parts->non_convex_interference.front(), true).c_str());
  return ValidityMode::kLabeledMliv;
}

}  // namespace ausbau
