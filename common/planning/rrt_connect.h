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
  // Measured with CR-RRTC (5 seeds each): whole edges are faster on Easy
  // (0.03-0.17 s vs 0.1-0.5 s) but much slower on Twistycool (13-32 s vs
  // 1.5-5 s); partial stays the default, as in the thesis.
  bool partial_extension = true;
  // While more than 80% of a tree's recent extensions were trapped, a
  // trapped extension is tried once more, shaped by the principal directions
  // of this many of the tree's nodes nearest to the node it grows from
  // (passage_direction.h); 0 = no second try.
  int passage_neighbors = 12;
  // Disassembly problems (no goal pose): from each new node of the start
  // tree, straight pulls out of S along D's first this many surface-normal
  // axes (largest first: a plate's normal, then the others), both ways,
  // then quarter turns about them, each followed by the pulls
  // (docs/planning.md, "Exit moves"); 0 = none.
  int exit_axes = 0;
};

PlanResult RunRrtConnect(const PlanningProblem& problem, const MotionChecker& motion,
                         const RrtConnectSettings& settings, const PlannerOptions& options);

}  // namespace ausbau
