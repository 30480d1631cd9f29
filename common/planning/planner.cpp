#include "planning/planner.h"

#include <cmath>

#include "core/error.h"
#include "planning/rrt_connect.h"

namespace ausbau {

void PlannerOptions::Check() const {
  if (planner != "rrtc" && planner != "cr-rrtc") {
    throw InputError("--planner: unknown planner '" + planner + "' (expected rrtc or cr-rrtc)");
  }
  if (!(time_limit_s > 0) || !std::isfinite(time_limit_s)) {
    throw InputError("--time-limit: must be a positive number of seconds");
  }
  if (max_iterations < 0) throw InputError("--max-iterations: must be >= 0");
  if (!(u > 0 && u < 1)) throw InputError("--u: must lie in (0, 1)");
  if (!(range_max > 0 && range_max <= 1)) throw InputError("--range-max: must lie in (0, 1]");
  if (!(resolution > 0 && resolution <= 0.1)) {
    throw InputError("--resolution: must lie in (0, 0.1] (a fraction of D's diagonal)");
  }
}

void CheckEndpoints(const PlanningProblem& problem, const PoseValidity& validity, const std::string& where) {
  if (!validity.IsValid(problem.start)) {
    throw InputErrorAt(where, "start pose is in collision (rigid planning needs a collision-free start)");
  }
  if (problem.goal && !validity.IsValid(*problem.goal)) throw InputErrorAt(where, "goal pose is in collision");
}

PlanResult Plan(const PlanningProblem& problem, const PoseValidity& validity, const PlannerOptions& options) {
  options.Check();
  const MotionChecker motion(problem, validity, options.resolution * problem.robot_diagonal);
  RrtConnectSettings settings;
  settings.randomize_parameters = options.planner == "cr-rrtc";
  settings.u = options.u;
  settings.range_max = options.range_max;
  return RunRrtConnect(problem, motion, settings, options);
}

}  // namespace ausbau
