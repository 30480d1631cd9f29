// RRT-Connect with the thesis metric (Def-/Opt-RRTC: fixed u and range_max)
// and the Completely Randomized RRT-Connect (CR-RRTC, thesis alg. 5: u and
// range_max drawn from U(0, 1) at every extension, the tree with fewer nodes
// grows).
#pragma once

#include "planning/planner.h"

namespace ausbau {

struct RrtConnectSettings {
  bool randomize_parameters = false;  // CR-RRTC
  double u = 0.583;
  double range_max = 0.417;
  // true: an extension keeps the valid part of its edge (the thesis's
  // getValidEdge), checked front to back; false: only a whole valid edge is
  // added (as OMPL's RRTConnect does), checked in bisection order.
  bool partial_extension = true;
};

PlanResult RunRrtConnect(const PlanningProblem& problem, const MotionChecker& motion,
                         const RrtConnectSettings& settings, const PlannerOptions& options);

}  // namespace ausbau
