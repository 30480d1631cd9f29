// PRM (thesis alg. 3): a roadmap of valid samples shared by several queries.
#pragma once

#include <optional>
#include <vector>

#include "planning/planner.h"

namespace ausbau {

struct PrmQuery {
  Pose start;                // planning convention, must be valid
  std::optional<Pose> goal;  // none = the disassembly goal region
};

struct PrmSettings {
  double radius = 0.1;      // connection radius in d'_c with u = 1/2
  int max_neighbours = 15;  // of those, only the nearest k are tried
  int first_batch = 200;    // samples in the first round; each round doubles it
  int threads = 0;          // edge verification threads; 0 = all cores
};

struct PrmResult {
  std::vector<PlanResult> queries;  // one per query, same order; stats are the roadmap's
  PlanStats stats;
  std::int64_t edges = 0;
};

// Grows the roadmap in rounds (sample a batch of valid configurations, and
// for goal-region queries a few poses in the region; connect each new
// vertex to its neighbours, verifying the candidate edges in parallel) until
// every query's start and goal are connected or the budget is spent; then
// the shortest path (Dijkstra, edge length d'_c with u = 1/2) per query.
// Deterministic for a seed whatever the thread count.
PrmResult RunPrm(const PlanningProblem& problem, const MotionChecker& motion, const std::vector<PrmQuery>& queries,
                 const PrmSettings& settings, const PlannerOptions& options);

}  // namespace ausbau
