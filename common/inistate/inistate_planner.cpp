#include "inistate/inistate_planner.h"

#include <algorithm>
#include <chrono>
#include <string>

#include "collision/fcl_checker.h"
#include "core/error.h"
#include "core/log.h"

namespace ausbau {

PlanStats InIStateResult::Stats() const {
  PlanStats stats = local.stats;
  stats.time_s += rigid.stats.time_s;
  stats.iterations += rigid.stats.iterations;
  stats.nodes += rigid.stats.nodes;
  stats.collision_checks += rigid.stats.collision_checks;
  stats.invalid_checks += rigid.stats.invalid_checks;
  return stats;
}

namespace {

// Gap between two boxes (0 when they overlap or touch).
double BoxGap(const Aabb& a, const Aabb& b) {
  const Eigen::Vector3d gap = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(Eigen::Vector3d::Zero());
  return gap.norm();
}

// Why `path` cannot serve as sigma_1 of `local_problem`, or "" when it can.
std::string KnownLocalPathFault(const PlanningProblem& local_problem, const PoseValidity& validity,
                                const PlannerOptions& local, const std::vector<Pose>& path) {
  const Pose& start = local_problem.start;
  if ((path.front().t - start.t).norm() > 1e-9 * local_problem.robot_diagonal ||
      path.front().q.angularDistance(start.q) > 1e-9) {
    return "it does not start at the start pose";
  }
  const MotionChecker motion(local_problem, validity, local.resolution * local_problem.robot_diagonal / 4.0);
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (!motion.MotionValid(path[i - 1], path[i])) return "segment " + std::to_string(i) + " is not valid here";
  }
  if (!local_problem.InGoalRegion(path.back())) return "it does not end clear of the fasteners (psi)";
  return "";
}

}  // namespace

std::function<bool(const Pose&)> ClearOfFasteners(const PlanningProblem& problem,
                                                  std::function<bool(const Pose&)> colliding,
                                                  std::function<double(const Pose&)> distance, double psi) {
  return [&problem, colliding = std::move(colliding), distance = std::move(distance), psi](const Pose& pose) {
    if (BoxGap(problem.RobotBoxAt(pose), problem.environment_box) > psi) return true;
    if (colliding(pose)) return false;
    return distance(pose) > psi;
  };
}

PlannerOptions LocalPlannerOptions(const PlanningProblem& problem, double psi, PlannerOptions local) {
  if (local.planner == "est" && local.est_range == 0) local.est_range = std::clamp(psi / problem.metric.nu, 1e-4, 0.05);
  return local;
}

PlanningProblem FastenerProblem(const PlanningProblem& problem, const FclCollisionChecker& fcl, double psi) {
  PlanningProblem local = problem;
  local.goal.reset();
  local.goal_region.reset();  // sigma_1's goal is clear of the fasteners, anywhere
  // Captures `problem`, not the copy, which the caller may move.
  local.goal_test = ClearOfFasteners(
      problem, [&fcl](const Pose& pose) { return fcl.InCollision(pose); },
      [&fcl](const Pose& pose) { return fcl.Distance(pose); }, psi);
  return local;
}

InIStateResult PlanInIState(const PlanningProblem& problem, const PoseValidity& volume_validity,
                            const PoseValidity& rigid_validity, const FclCollisionChecker& fcl,
                            const InIStateOptions& options) {
  return PlanInIState(
      problem, volume_validity, rigid_validity, [&fcl](const Pose& pose) { return fcl.InCollision(pose); },
      [&fcl](const Pose& pose) { return fcl.Distance(pose); }, options);
}

InIStateResult PlanInIState(const PlanningProblem& problem, const PoseValidity& volume_validity,
                            const PoseValidity& rigid_validity, const std::function<bool(const Pose&)>& colliding,
                            const std::function<double(const Pose&)>& distance, const InIStateOptions& options) {
  if (!(options.psi > 0)) throw InputError("psi must be > 0");
  if (!volume_validity.IsValid(problem.start)) {
    throw InputError("the start pose exceeds tau: tau must be at least the start's intersection volume");
  }
  InIStateResult result;

  // sigma_1: out of the clips.
  PlanningProblem local_problem = problem;
  local_problem.goal.reset();
  local_problem.goal_region.reset();  // sigma_1's goal is clear of the fasteners, anywhere
  local_problem.goal_test = ClearOfFasteners(local_problem, colliding, distance, options.psi);
  std::string planner = options.local.planner;
  if (!options.known_local_path.empty()) {
    const auto begin = std::chrono::steady_clock::now();
    const std::int64_t checks = volume_validity.checks(), invalid = volume_validity.invalid_checks();
    const std::string fault =
        KnownLocalPathFault(local_problem, volume_validity, options.local, options.known_local_path);
    if (fault.empty()) {
      result.local.status = PlanStatus::kSolved;
      result.local.path = options.known_local_path;
      result.local.stats.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      result.local.stats.collision_checks = volume_validity.checks() - checks;
      result.local.stats.invalid_checks = volume_validity.invalid_checks() - invalid;
      planner = "known path, re-checked";
    } else {
      LogWarn("the given sigma_1 (%zu poses) is not used: %s; planning sigma_1", options.known_local_path.size(),
              fault.c_str());
    }
  }
  if (!result.local.solved()) {
    result.local = Plan(local_problem, volume_validity, LocalPlannerOptions(problem, options.psi, options.local));
  }
  LogInfo("InIState part 1 (%s, volume validity): %s after %.2f s, %lld nodes, %lld checks", planner.c_str(),
          result.local.solved() ? "clear of the fasteners" : "no path", result.local.stats.time_s,
          static_cast<long long>(result.local.stats.nodes),
          static_cast<long long>(result.local.stats.collision_checks));
  if (!result.local.solved()) {
    result.status = result.local.status;
    return result;
  }

  // sigma_2: rigid, from c_inter out (or to the goal).
  PlanningProblem rigid_problem = problem;
  rigid_problem.start = result.local.path.back();
  result.rigid = Plan(rigid_problem, rigid_validity, options.rigid);
  LogInfo("InIState part 2 (%s, collision): %s after %.2f s, %lld nodes, %lld checks", options.rigid.planner.c_str(),
          result.rigid.solved() ? "solved" : "no path", result.rigid.stats.time_s,
          static_cast<long long>(result.rigid.stats.nodes),
          static_cast<long long>(result.rigid.stats.collision_checks));
  if (!result.rigid.solved()) {
    result.status = result.rigid.status;
    return result;
  }
  result.path = result.local.path;
  result.inter_index = static_cast<int>(result.path.size()) - 1;
  result.path.insert(result.path.end(), result.rigid.path.begin() + 1, result.rigid.path.end());
  result.status = PlanStatus::kSolved;
  return result;
}

}  // namespace ausbau
