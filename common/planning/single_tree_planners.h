// Single-tree planners: RRT (thesis alg. 1) and EST (thesis alg. 4).
#pragma once

#include "planning/planner.h"

namespace ausbau {

// RRT: grows one tree from the start towards samples by at most range_max
// (eq. 3) with the metric weight u, keeping the valid part of each edge. The
// goal region ends it; with a goal pose, a new node within range_max of the
// goal is connected to it directly, and 5% of the samples are the goal
// itself (the thesis's alg. 1 has no goal bias; without one a single goal
// pose is practically never hit).
PlanResult RunRrt(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options);

struct EstSettings {
  double r1 = 0;  // expansion radius (range, eq. 3); 0 = automatic
  double r2 = 0;  // density radius (d'_c with u = 1/2); 0 = automatic
};

// The automatic radii: r1 such that one expansion moves D's reference point
// by up to a quarter of D's AABB diagonal (and turns it by up to 2 pi r1),
// clamped to [1e-3, 0.05]; r2 = r1.
EstSettings AutomaticEstSettings(const PlanningProblem& problem);

// EST: each node's weight is 1 / #neighbours within r2; a node is chosen with
// probability proportional to its weight (sparse regions grow, as in Hsu et
// al. 1997), expanded by a sample within r1 of it whose edge must be valid.
PlanResult RunEst(const PlanningProblem& problem, const MotionChecker& motion, const EstSettings& settings,
                  const PlannerOptions& options);

}  // namespace ausbau
