#include "planning/planner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>

#include "core/cancel.h"
#include "core/error.h"
#include "core/log.h"
#include "geometry/principal_axes.h"
#include "planning/certify.h"
#include "planning/prm.h"
#include "planning/rrt_connect.h"
#include "planning/sampler.h"
#include "planning/single_tree_planners.h"

namespace ausbau {

const char* PlanStopReason(PlanStatus status, bool budget_bound) {
  switch (status) {
    case PlanStatus::kSolved: return "solved";
    case PlanStatus::kIterationLimit: return "iteration limit";
    case PlanStatus::kTimeLimit: return budget_bound ? "time budget used up" : "time limit";
    case PlanStatus::kCancelled: return "cancelled";
  }
  return "unknown";
}

namespace {

PlanResult RunRrtcVariant(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options,
                          bool randomize_parameters) {
  RrtConnectSettings settings;
  settings.randomize_parameters = randomize_parameters;
  settings.u = options.u;
  settings.range_max = options.range_max;
  settings.passage_neighbors = options.passage_neighbors;
  settings.exit_axes = std::max(0, options.exit_axes);  // -1 (automatic) unresolved: none
  return RunRrtConnect(problem, motion, settings, options);
}

PlanResult RunRrtc(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options) {
  return RunRrtcVariant(problem, motion, options, false);
}

PlanResult RunCrRrtc(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options) {
  return RunRrtcVariant(problem, motion, options, true);
}

PlanResult RunEstPlanner(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options) {
  return RunEst(problem, motion, EstSettings{options.est_range, options.est_range}, options);
}

PlanResult RunPrmPlanner(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options) {
  PrmSettings settings;
  settings.threads = options.threads;
  PrmResult result = RunPrm(problem, motion, {PrmQuery{problem.start, problem.goal}}, settings, options);
  return result.queries.front();
}

// The planner registry: a new planner is its own file plus one row here;
// --planner, its checks and its error message follow from this table.
struct PlannerEntry {
  const char* name;
  PlanResult (*run)(const PlanningProblem&, const MotionChecker&, const PlannerOptions&);
};
const PlannerEntry kPlanners[] = {
    {"rrt", RunRrt},         // single-tree RRT (single_tree_planners.h)
    {"rrtc", RunRrtc},       // RRT-Connect with fixed u and range (rrt_connect.h)
    {"cr-rrtc", RunCrRrtc},  // RRT-Connect with randomized parameters (thesis ch. 3)
    {"est", RunEstPlanner},  // EST (single_tree_planners.h)
    {"prm", RunPrmPlanner},  // PRM (prm.h)
};

const PlannerEntry* FindPlanner(const std::string& name) {
  for (const PlannerEntry& entry : kPlanners) {
    if (name == entry.name) return &entry;
  }
  return nullptr;
}

}  // namespace

const std::vector<std::string>& PlannerNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const PlannerEntry& entry : kPlanners) out.push_back(entry.name);
    return out;
  }();
  return names;
}

std::int64_t CoarseFirstIterationsFor(const std::string& planner) {
  return planner == "cr-rrtc" || planner == "rrtc" ? kCoarseFirstIterations : 0;
}

void PlannerOptions::Check() const {
  if (FindPlanner(planner) == nullptr) {
    std::string expected;
    for (const std::string& name : PlannerNames()) expected += (expected.empty() ? "" : ", ") + name;
    throw OptionError(&planner, "planner", "unknown planner '" + planner + "' (expected " + expected + ")");
  }
  try {
    ParseSamplerKind(sampler);
  } catch (const InputError& e) {
    throw OptionError(&sampler, "sampler", e.what());
  }
  if (!(sampler_sigma >= 0) || !std::isfinite(sampler_sigma))
    throw OptionError(&sampler_sigma, "sigma", "must be >= 0");
  if (threads < 0) throw OptionError(&threads, "threads", "must be >= 0");
  if (!(time_limit_s > 0) || !std::isfinite(time_limit_s)) {
    throw OptionError(&time_limit_s, "time_limit", "must be a positive number of seconds");
  }
  if (max_iterations < 0) throw OptionError(&max_iterations, "max_iterations", "must be >= 0");
  if (max_checks < 0) throw OptionError(&max_checks, "max_checks", "must be >= 0");
  if (max_total_iterations < 0) throw OptionError(&max_total_iterations, "max_total_iterations", "must be >= 0");
  if (!(u > 0 && u < 1)) throw OptionError(&u, "u", "must lie in (0, 1)");
  if (!(range_max > 0 && range_max <= 1)) throw OptionError(&range_max, "range_max", "must lie in (0, 1]");
  if (passage_neighbors < 0 || passage_neighbors > 1000) {
    throw OptionError(&passage_neighbors, "passage_neighbors", "must lie in [0, 1000] (0 = no second try)");
  }
  if (pull_legs < 1 || pull_legs > 2) throw OptionError(&pull_legs, "pull_legs", "must be 1 or 2");
  if (exit_axes < -1 || exit_axes > 3) {
    throw OptionError(&exit_axes, "exit_axes", "must lie in [-1, 3] (0 = none, -1 = automatic)");
  }
  if (!(est_range >= 0 && est_range <= 1))
    throw OptionError(&est_range, "est_range", "must lie in [0, 1] (0 = automatic)");
  if (coarse_iterations < -1) {
    throw OptionError(&coarse_iterations, "coarse_iterations", "must be >= 0 (0 = none, -1 = automatic)");
  }
  if (!(resolution > 0 && resolution <= 0.1)) {
    throw OptionError(&resolution, "resolution", "must lie in (0, 0.1] (a fraction of D's diagonal)");
  }
}

void CheckEndpoints(const PlanningProblem& problem, const PoseValidity& validity, const std::string& where) {
  if (!validity.IsValid(problem.start)) {
    throw InputErrorAt(where, "start pose is in collision (rigid planning needs a collision-free start)");
  }
  if (problem.goal && !validity.IsValid(*problem.goal)) throw InputErrorAt(where, "goal pose is in collision");
}

double SecondsLeft(double deadline_epoch_s) {
  if (!(deadline_epoch_s > 0)) return std::numeric_limits<double>::infinity();
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  return deadline_epoch_s - now;
}

double LimitByDeadline(double limit, double deadline_epoch_s, double floor, bool* bound) {
  const double left = SecondsLeft(deadline_epoch_s);
  const bool deadline_first = left < limit;
  if (bound != nullptr) *bound = deadline_first;
  return deadline_first ? std::max(floor, left) : limit;
}

double PartialProgress(const PlanningProblem& problem, const Pose& pose) {
  if (problem.goal) return -problem.metric.Range(pose, *problem.goal);
  const Aabb robot = problem.RobotBoxAt(pose);
  const Aabb& environment = problem.environment_box;
  double gap = -std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    gap = std::max({gap, robot.min[axis] - environment.max[axis], environment.min[axis] - robot.max[axis]});
  }
  return gap;
}

namespace {

// One search at options.resolution, its path certified at the
// certification's step (planning/certify.h), the certification's checks and
// time counted in the statistics. A path that cannot be certified is no
// path: kTimeLimit where the clock stopped the repair (a safety net), else
// kIterationLimit with *uncertified set.
PlanResult SearchAndCertify(const PlanningProblem& problem, const PoseValidity& validity, const PlannerOptions& options,
                            bool* uncertified) {
  *uncertified = false;
  const auto begin = std::chrono::steady_clock::now();
  const double step = options.resolution * problem.robot_diagonal;
  const MotionChecker motion(problem, validity, step,
                             begin + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                         std::chrono::duration<double>(options.time_limit_s)));
  PlanResult result = FindPlanner(options.planner)->run(problem, motion, options);
  if (!result.solved()) return result;
  const std::int64_t checks = validity.checks(), invalid = validity.invalid_checks();
  PlannerOptions repair_options = options;
  repair_options.time_limit_s = std::max(1.0, options.time_limit_s - result.stats.time_s);
  const CertifyReport report =
      CertifyPath(problem, validity, CertificationStep(problem, step), repair_options, &result.path);
  LogDebug("certification: %lld checks, %d segment(s) re-planned", static_cast<long long>(validity.checks() - checks),
           report.repaired_segments);
  result.stats.collision_checks += validity.checks() - checks;
  result.stats.invalid_checks += validity.invalid_checks() - invalid;
  result.stats.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (!report.certified) {
    result.path.clear();
    result.status = report.stopped_by_time_limit ? PlanStatus::kTimeLimit : PlanStatus::kIterationLimit;
    *uncertified = !report.stopped_by_time_limit;
  }
  return result;
}

}  // namespace

PlanResult Plan(const PlanningProblem& problem, const PoseValidity& validity, const PlannerOptions& options) {
  options.Check();
  const auto begin = std::chrono::steady_clock::now();
  const double thesis_resolution = 4 * kCertificationResolution;  // 1%, the certification's step x 4
  // The first search: at the coarse step for coarse_iterations (when the
  // step asked for is finer), else the only one. -1 (automatic) unresolved: none.
  const bool coarse_first = options.coarse_iterations > 0 && options.resolution < kCoarseResolution;
  PlannerOptions first_options = options;
  if (coarse_first) {
    first_options.resolution = kCoarseResolution;
    first_options.max_iterations = options.max_iterations > 0
                                       ? std::min(options.max_iterations, options.coarse_iterations)
                                       : options.coarse_iterations;
  }
  bool uncertified = false;
  PlanResult first = SearchAndCertify(problem, validity, first_options, &uncertified);
  if (first.solved() || first.status == PlanStatus::kTimeLimit || first.status == PlanStatus::kCancelled) {
    return first;
  }
  // A search at a step coarser than the thesis's may have passed through a
  // wall thinner than its step, which no repair between the two sides can
  // mend; and a coarse first search may find nothing in its iterations
  // where the passage is narrower than its step (flange-1.0's tube in its
  // hole). Both are followed by a search at the finer step, afresh (same
  // seed), in the time and iterations left.
  PlannerOptions fine = options;
  fine.coarse_iterations = 0;
  if (coarse_first) {
    if (options.max_iterations > 0 && first.stats.iterations >= options.max_iterations) return first;
    if (options.max_iterations > 0) fine.max_iterations = options.max_iterations - first.stats.iterations;
    LogDebug("no certified path in %lld iterations at a step of %g of D's diagonal; searching at %g",
             static_cast<long long>(first.stats.iterations), kCoarseResolution, options.resolution);
  } else if (uncertified && options.resolution > thesis_resolution) {
    fine.resolution = thesis_resolution;
    LogInfo("the path found at a step of %g of D's diagonal cannot be certified; planning again at %g",
            options.resolution, thesis_resolution);
  } else {
    return first;
  }
  fine.time_limit_s =
      options.time_limit_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  if (!(fine.time_limit_s > 0)) {
    first.status = PlanStatus::kTimeLimit;
    return first;
  }
  PlanResult again = SearchAndCertify(problem, validity, fine, &uncertified);
  again.stats.iterations += first.stats.iterations;
  again.stats.nodes += first.stats.nodes;
  again.stats.collision_checks += first.stats.collision_checks;
  again.stats.invalid_checks += first.stats.invalid_checks;
  again.stats.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return again;
}

std::vector<Eigen::Vector3d> SurfaceNormalAxes(const TriangleMesh& mesh, const Eigen::Quaterniond& rotation) {
  Eigen::Matrix3d tensor = Eigen::Matrix3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d cross =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    const double twice_area = cross.norm();
    if (twice_area > 0) tensor += (0.5 / twice_area) * cross * cross.transpose();  // area x n n^T
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(tensor);
  std::vector<Eigen::Vector3d> axes;
  if (solver.info() != Eigen::Success || !solver.eigenvectors().allFinite()) return axes;
  for (int k = 2; k >= 0; --k) {
    Eigen::Vector3d axis = rotation * solver.eigenvectors().col(k).normalized();
    int largest = 0;
    axis.cwiseAbs().maxCoeff(&largest);
    if (axis[largest] < 0) axis = -axis;
    axes.push_back(axis);
  }
  return axes;
}

std::vector<Eigen::Vector3d> PullAxes(const TriangleMesh& robot, const Eigen::Quaterniond& orientation) {
  // D's principal axes in the world, then the world's axes (CAD parts sit
  // square to the vehicle), less those along an axis already there. "Along"
  // means within a micro-radian: a bolt's principal axis, tilted a few
  // milliradians by its tessellation, drives its shank into the bore after
  // a few mm, where the world's axis (or its normals' axis) draws it out.
  std::vector<Eigen::Vector3d> vertices;
  for (const auto& v : robot.vertices) vertices.push_back(orientation * v);
  const Eigen::Matrix3d principal = vertices.empty() ? Eigen::Matrix3d::Identity() : PrincipalAxes(vertices);
  std::vector<Eigen::Vector3d> axes;
  const auto add_axis = [&](const Eigen::Vector3d& axis) {
    if (std::none_of(axes.begin(), axes.end(),
                     [&](const Eigen::Vector3d& a) { return std::abs(a.dot(axis)) > std::cos(1e-6); }))
      axes.push_back(axis);
  };
  for (int k = 0; k < 3; ++k) add_axis(principal.col(k).normalized());
  for (int k = 0; k < 3; ++k) add_axis(Eigen::Vector3d::Unit(k));
  // The axes of D's surface normals, weighted by area: a plate's normal
  // (its largest), a pin's or a bore's axis (its smallest: the normals of a
  // cylinder lie across it), exactly, where the spread of the vertices
  // (the principal axes) is tilted by whatever stands on the plate.
  for (const Eigen::Vector3d& axis : SurfaceNormalAxes(robot, orientation)) add_axis(axis);
  return axes;
}

namespace {

// The shortest pull from `from` along `direction` (to a probe's step) that
// takes D into the goal region within the bounds; nothing when none within
// `reach`. Where S is cropped, *last_in_bounds (if given) is the pull's last
// probe within the bounds (convex: the ray leaves them once), `from` when
// none. Reach over probe is about 100 (1 + S's size / D's) steps; for a D of
// 1e-6 mm in S of tens it was billions, so the clock is read every 4096 of
// them (past the deadline: nothing).
std::optional<Pose> ShortestPullOut(const PlanningProblem& problem, const Pose& from, const Eigen::Vector3d& direction,
                                    double reach, double probe, std::chrono::steady_clock::time_point deadline,
                                    Pose* last_in_bounds) {
  Pose end = from;
  bool left_bounds = !problem.crop || last_in_bounds == nullptr;
  if (last_in_bounds != nullptr) *last_in_bounds = from;
  std::int64_t probes = 0;
  for (double s = probe; s <= reach; s += probe) {
    if (++probes % 4096 == 0 && std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    end.t = from.t + s * direction;
    if (problem.InGoalRegion(end) && problem.InBounds(end)) return end;
    if (!left_bounds) {
      left_bounds = !problem.InBounds(end);
      if (!left_bounds) *last_in_bounds = end;
    }
  }
  return std::nullopt;
}

}  // namespace

PlanResult TryStraightPulls(const PlanningProblem& problem, const PoseValidity& validity,
                            const PlannerOptions& options) {
  PlanResult result;
  result.status = PlanStatus::kIterationLimit;
  if (problem.goal) return result;
  const auto begin = std::chrono::steady_clock::now();
  const std::int64_t checks = validity.checks(), invalid = validity.invalid_checks();
  const std::vector<Eigen::Vector3d> axes = PullAxes(problem.robot, problem.start.q);
  const double step = options.resolution * problem.robot_diagonal;
  // The pulls count work, not seconds: each is walked to its end (a pull
  // stopped by the clock would turn a right answer into "not removable" on
  // a slower machine). The time limit is only a safety net: a part sliding
  // along a contact in general position (dm1's L-bracket on its bolts: each
  // check a surface-depth search of about 0.2 s, a slack of hundredths of a
  // mm) took more than 10 minutes, which a batch of parts cannot wait for.
  // Past it the pulls stop as blocked, and the run has no time left to
  // sample (PlanKeepingClearance): "no path within the time limit".
  const auto deadline = begin + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                    std::chrono::duration<double>(options.time_limit_s));
  const MotionChecker motion(problem, validity, step, deadline);
  const double reach = 2 * (problem.robot_diagonal + problem.environment_box.Diagonal());
  const double probe = 0.02 * problem.robot_diagonal;
  // A path of straight pulls from the start, certified (planning/certify.h):
  // solved into `result` when it holds.
  const auto certified = [&](std::vector<Pose> path) {
    ThrowIfCancelled();  // a pull stopped by a cancel is no answer
    PlannerOptions repair = options;
    repair.time_limit_s =
        std::max(1.0, std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count());
    if (!CertifyPath(problem, validity, CertificationStep(problem, step), repair, &path, deadline).certified)
      return false;
    result.path = std::move(path);
    result.status = PlanStatus::kSolved;
    return true;
  };
  // Where S is cropped, the pulls whose goal lies beyond the crop: their
  // last pose within the bounds, walked only once no pull got D out.
  std::vector<Pose> to_crop_edge;
  // The pulls blocked on the way out: (axis, sign, end), for the second legs.
  struct Blocked {
    std::size_t axis;
    double sign;
    Pose end;
  };
  std::vector<Blocked> blocked;
  for (std::size_t a = 0; a < axes.size() && !result.solved(); ++a) {
    for (double sign : {1.0, -1.0}) {
      ThrowIfCancelled();  // serial here (core/cancel.h)
      ++result.stats.iterations;
      Pose last_in_bounds;
      const std::optional<Pose> end =
          ShortestPullOut(problem, problem.start, sign * axes[a], reach, probe, deadline, &last_in_bounds);
      if (!end) {
        if (problem.crop && last_in_bounds.t != problem.start.t) to_crop_edge.push_back(last_in_bounds);
        continue;
      }
      if (!motion.MotionValid(problem.start, *end)) {
        blocked.push_back({a, sign, *end});
        continue;
      }
      if (certified({problem.start, *end})) break;
    }
  }
  // No goal within the bounds along these ways: where S is cropped to D's
  // reach, a pull that is free up to the crop's edge (a pin in a long tube,
  // a rail that runs out of the box) may get D out of a larger crop: said,
  // so that the crop grows before any sampling (PlanResult::pull_left_crop).
  // Asked only once no pull got D out: a part sliding along a fit to the
  // crop's edge is walked a surface-depth search per stretch (CAx-IF s1's
  // CATIA foot: 47 s on its first such pull, before the pull down that
  // frees it in 3 s).
  for (const Pose& edge : to_crop_edge) {
    if (result.solved() || result.pull_left_crop) break;
    ThrowIfCancelled();
    result.pull_left_crop = motion.MotionValid(problem.start, edge);
  }
  // Two legs: a pin pulled out of its bore under a bracket, a bolt that
  // must clear its hole before it slides out from under a flange. Each
  // blocked pull is walked to where it stops, and from there D is pulled
  // along every other axis, both ways (ShortestPullOut, as the first legs).
  // Asked only once no single pull got D out, nor to the crop's edge (a
  // larger crop comes first); a pull stopped at once gives no second leg.
  // The walks count work: at most kSecondLegChecks checks in all (a part
  // sliding along a contact in general position is walked a surface-depth
  // search per pose), so that sampling keeps its time.
  const std::int64_t second_legs_from = validity.checks();
  for (const Blocked& first : blocked) {
    if (options.pull_legs < 2 || result.solved() || result.pull_left_crop ||
        validity.checks() - second_legs_from >= kSecondLegChecks)
      break;
    ThrowIfCancelled();
    Pose stop;
    const auto walk_began = std::chrono::steady_clock::now();
    const std::int64_t walk_checks = validity.checks();
    const double fraction = motion.ValidPrefix(problem.start, first.end, &stop);
    LogDebug("straight pulls: pull %zu%c stops after %.4g (%lld checks, %.2f s)", first.axis,
             first.sign > 0 ? '+' : '-', (stop.t - problem.start.t).norm(),
             static_cast<long long>(validity.checks() - walk_checks),
             std::chrono::duration<double>(std::chrono::steady_clock::now() - walk_began).count());
    // A pull stopped within a step of the start (what a planner's edge of
    // one step reaches too) took D out of nothing: a panel on its clips
    // moves a fraction of a mm any way, and a second leg from there is
    // as blocked as the first (the external set's moulded panels: 18 such
    // stops, 16 second legs from each, each a surface-depth search).
    const double walked = (stop.t - problem.start.t).norm();
    if (fraction <= 0.0 || walked <= step) continue;
    result.pull_stops.push_back(stop);
    // And a step short of it, where the pull was not yet in contact with
    // what stopped it (a tree grown from a contact walks its floor steps).
    if (walked > 2 * step) {
      Pose short_of = stop;
      short_of.t -= (step / walked) * (stop.t - problem.start.t);
      if (motion.IsValid(short_of)) result.pull_stops.push_back(short_of);
    }
    for (std::size_t a = 0; a < axes.size() && !result.solved(); ++a) {
      if (a == first.axis) continue;
      for (double sign : {1.0, -1.0}) {
        if (validity.checks() - second_legs_from >= kSecondLegChecks) break;
        ThrowIfCancelled();
        ++result.stats.iterations;
        const std::optional<Pose> end = ShortestPullOut(problem, stop, sign * axes[a], reach, probe, deadline, nullptr);
        if (!end) continue;
        const auto leg_began = std::chrono::steady_clock::now();
        const std::int64_t leg_checks = validity.checks();
        const bool free = motion.MotionValid(stop, *end);
        LogDebug("straight pulls: then %zu%c: %s (%lld checks, %.2f s)", a, sign > 0 ? '+' : '-',
                 free ? "free" : "blocked", static_cast<long long>(validity.checks() - leg_checks),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - leg_began).count());
        if (!free) continue;
        if (certified({problem.start, stop, *end})) break;
      }
    }
  }
  // Pulls stopped by the clock (the safety net) are no answer: the run was
  // cut short (kTimeLimit), which the path artifact records.
  if (!result.solved() && std::chrono::steady_clock::now() >= deadline) result.status = PlanStatus::kTimeLimit;
  if (result.solved()) result.pull_stops.clear();
  result.stats.nodes = result.solved() ? static_cast<std::int64_t>(result.path.size()) : 0;
  result.stats.collision_checks = validity.checks() - checks;
  result.stats.invalid_checks = validity.invalid_checks() - invalid;
  result.stats.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return result;
}

PlanResult PlanWithRestarts(const PlanningProblem& problem, const PoseValidity& validity,
                            const PlannerOptions& options) {
  if (options.max_iterations > 0) return Plan(problem, validity, options);
  const auto begin = std::chrono::steady_clock::now();
  PlanResult result;
  PlanStats total;
  std::vector<Pose> best_partial;  // over the rounds
  double best_progress = -std::numeric_limits<double>::infinity();
  std::int64_t budget = kFirstRestartIterations;
  for (int round = 0;; ++round, budget *= 2) {
    const double left =
        options.time_limit_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    if (left <= 0) {
      result.status = PlanStatus::kTimeLimit;  // the safety net: cut short
      break;
    }
    std::int64_t round_budget = budget;
    if (options.max_total_iterations > 0) {
      const std::int64_t rest = options.max_total_iterations - total.iterations;
      if (rest <= 0) {
        result.status = PlanStatus::kIterationLimit;  // the work budget is used up
        break;
      }
      round_budget = std::min(round_budget, rest);
    }
    PlannerOptions round_options = options;
    round_options.seed = options.seed + static_cast<std::uint64_t>(round);
    round_options.max_iterations = round_budget;
    round_options.time_limit_s = left;  // the whole run's limit, a safety net
    result = Plan(problem, validity, round_options);
    ThrowIfCancelled();  // a cancelled round is no answer (core/cancel.h)
    total.iterations += result.stats.iterations;
    total.nodes += result.stats.nodes;
    total.collision_checks += result.stats.collision_checks;
    total.invalid_checks += result.stats.invalid_checks;
    if (!result.partial.empty() && (best_partial.empty() || result.partial_progress > best_progress)) {
      best_partial = result.partial;
      best_progress = result.partial_progress;
    }
    if (result.status != PlanStatus::kIterationLimit) break;  // solved, cancelled or out of time
  }
  total.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  result.stats = total;
  if (!result.solved()) {
    result.partial = std::move(best_partial);
    result.partial_progress = best_progress;
  }
  return result;
}

}  // namespace ausbau
