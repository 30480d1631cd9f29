// Planner options, results and the entry point that dispatches on the
// planner's name.
#pragma once

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/log.h"
#include "planning/state_space.h"

namespace ausbau {

struct PlannerOptions {
  std::string planner = "cr-rrtc";  // rrt | rrtc | cr-rrtc | est | prm
  std::string sampler = "uniform";  // uniform | gaussian | bridge | mixed (thesis 2.2.5)
  // Gaussian / bridge-test standard deviation as a fraction of the metric's
  // unit (nu for translation, pi for rotation); 0 = automatic.
  double sampler_sigma = 0.0;
  int threads = 0;  // prm edge verification; 0 = all cores
  std::uint64_t seed = 1;
  // Wall-clock safety net: a run it stops is cut short (kTimeLimit), which
  // the artifacts and the verdict record; the answer is set by the work
  // budgets below (and the seed), never by it.
  double time_limit_s = 60.0;
  std::int64_t max_iterations = 0;  // 0 = unlimited (tests use it for exact budgets)
  // PlanWithRestarts: all rounds together at most this many iterations (a
  // work budget: the rigid-exact crop levels, plan_scene.h); 0 = unlimited.
  std::int64_t max_total_iterations = 0;
  // At most this many validity checks (the work a planner does, counted on
  // its validity: the tau estimate's rounds, tau_estimate.h), checked once
  // per iteration, so a run may overshoot by one iteration's checks; status
  // kIterationLimit. Sequential planners only (PRM's threads share the
  // count); 0 = unlimited.
  std::int64_t max_checks = 0;
  double u = 0.583;          // rrtc: metric weight (Def-RRTC default)
  double range_max = 0.417;  // rrtc: maximal edge range (Def-RRTC default)
  // rrtc, cr-rrtc: a trapped extension is tried once more along the
  // principal directions of this many nearby tree nodes
  // (planning/passage_direction.h); 0 = no second try.
  int passage_neighbors = 12;
  // rrtc, cr-rrtc, disassembly problems: exit moves (straight pulls out and
  // quarter turns) from each new start-tree node about this many of D's
  // surface-normal axes (planning/rrt_connect.h); 0 = none; -1 = automatic:
  // ausbau-plan's collision validity 1 (measured: docs/benchmarks.md, "Exit
  // moves"), every other use 0 (not measured yet with slower validities).
  int exit_axes = 0;
  // Disassembly: TryStraightPulls' legs. 1: single straight pulls only;
  // 2: where none is free, two legs, and where the pulls stopped kept for
  // start_branches (docs/rigid-exact.md, "Two legs, and where the pulls
  // stopped").
  int pull_legs = 2;
  // rrtc, cr-rrtc: poses joined to the start tree's root before sampling,
  // each reached from the start by a straight motion already walked valid
  // at `resolution` (PlanResult::pull_stops: D lifted out of a tight bore
  // up to what stops it, where sampling would need the few poses that
  // line up with the bore); the path is certified as any other. Empty: none.
  std::vector<Pose> start_branches;
  // Edge resolution: between two checked poses no vertex of D moves more
  // than this fraction of D's AABB diagonal.
  double resolution = 0.01;
  // A first search at kCoarseResolution for at most this many iterations
  // (where `resolution` is finer); when it finds no path that can be
  // certified, the search at `resolution` starts afresh in the time left
  // (Plan). 0 = none; ausbau-plan's collision validity uses
  // kCoarseFirstIterations (docs/planning.md, "A coarse search first").
  std::int64_t coarse_iterations = 0;
  // est: expansion radius r1 (range, eq. 3); 0 = automatic (single_tree_planners.h).
  double est_range = 0.0;
  // When set and true, the planner stops at its next iteration with
  // kCancelled (the tau estimate's speculative rounds, tau_estimate.h); so
  // does the process-wide flag (core/cancel.h), after which the caller
  // throws Cancelled.
  const std::atomic<bool>* cancel = nullptr;
  // Called from the planner's thread about 5 times a second with the
  // iterations so far and max_iterations (0: unlimited): the stage's
  // progress display (core/log.h). Never changes the answer; empty = silent.
  ProgressCallback progress;

  // Throws InputError naming the option when a value is out of range.
  void Check() const;
};

// The coarse first search's step: 4x the thesis's (1% of D's diagonal).
inline constexpr double kCoarseResolution = 0.04;

enum class PlanStatus { kSolved, kTimeLimit, kIterationLimit, kCancelled };

// Why a search ended, in the words every log line uses (one list, so that
// no mode reports an iteration limit as a time limit): "solved",
// "iteration limit" (--max-iterations or a work cap such as
// --crop-level-iterations), "time limit" (--time-limit or a safety net),
// "time budget used up" (a time limit that the run's --budget or
// --deadline had shortened: `budget_bound`), "cancelled".
const char* PlanStopReason(PlanStatus status, bool budget_bound);

struct PlanStats {
  double time_s = 0;
  std::int64_t iterations = 0;
  std::int64_t nodes = 0;
  std::int64_t collision_checks = 0;
  std::int64_t invalid_checks = 0;  // collision checks that found D invalid
};

struct PlanResult {
  PlanStatus status = PlanStatus::kTimeLimit;
  std::vector<Pose> path;  // planning convention; empty unless solved
  // Unsolved: the best partial path, from the start to the start tree's node
  // with the most progress (PartialProgress); empty where the planner keeps
  // no tree (PRM) or when solved.
  std::vector<Pose> partial;
  double partial_progress = -std::numeric_limits<double>::infinity();
  PlanStats stats;
  // Unsolved straight pulls (TryStraightPulls) where S is cropped to D's
  // reach: one moved D validly up to the crop's edge without reaching the
  // goal, so a larger crop may let it out.
  bool pull_left_crop = false;
  // Unsolved straight pulls: where the blocked pulls whose stops were
  // walked (the two legs') stopped, each valid and reached from the start
  // by its pull; for PlannerOptions::start_branches.
  std::vector<Pose> pull_stops;
  bool solved() const { return status == PlanStatus::kSolved; }
};

// How far a pose has come, for the best partial path of an unsolved run:
// with a goal pose, minus the metric range to it; without one (disassembly),
// how far D's AABB is separated from S's, the largest gap along one world
// axis (negative while they overlap along every axis: then the least
// overlap). Larger is better.
double PartialProgress(const PlanningProblem& problem, const Pose& pose);

// The time budget of a run (--budget / --deadline, pipelines/inistate.mk
// BUDGET): an absolute deadline in seconds since the Unix epoch (system
// clock), so that every stage of a pipeline measures against the same end
// whatever ran before it. 0: none. SecondsLeft: +infinity without a deadline.
double SecondsLeft(double deadline_epoch_s);
// The time limit a stage gets under a deadline: `limit` or what is left, the
// smaller, but at least `floor` (a stage stopped by the budget still answers
// with what it has: the best partial path). Sets *bound when the deadline is
// the smaller of the two.
double LimitByDeadline(double limit, double deadline_epoch_s, double floor, bool* bound);

// The planners Plan() knows.
const std::vector<std::string>& PlannerNames();

// Plans from problem.start to problem.goal (or into the disassembly region)
// with the validity check given, and certifies the path (planning/certify.h).
// With options.coarse_iterations, a search at kCoarseResolution first; a
// search at a step coarser than 1% whose path cannot be certified is
// followed by one at 1%. Deterministic for a given seed as long as it does
// not run into the time limit.
PlanResult Plan(const PlanningProblem& problem, const PoseValidity& validity, const PlannerOptions& options);

// Plan() in rounds with restarts: round k uses seed + k and at most
// kFirstRestartIterations x 2^k iterations (4096, 8192, ...), all rounds
// together at most options.time_limit_s. A tree stuck in a narrow passage is
// given up for a fresh one: sampling planners' run times are heavy-tailed,
// and restarting on a doubling schedule bounds the expected time (measured:
// one seed of a tight L-channel scene needed more than 60 s, the next 1 s).
// The schedule counts iterations, not seconds, so the result depends on the
// seed only, not on the machine or its load (unless the time limit ends
// the run). With options.max_iterations set, one round (the iteration cap is
// the budget); with options.max_total_iterations, the rounds stop when they
// have used that many together (the last round capped to the rest), with
// kIterationLimit. Statistics are summed over the rounds.
inline constexpr std::int64_t kFirstRestartIterations = 4096;
// The coarse first search's iterations: the first restart round's.
inline constexpr std::int64_t kCoarseFirstIterations = kFirstRestartIterations;
// The coarse first search's iterations for a planner where it was measured:
// kCoarseFirstIterations for the RRT-Connect planners (rrtc, cr-rrtc), 0 for
// the others. ausbau-plan's collision validity and ausbau-bench use it.
std::int64_t CoarseFirstIterationsFor(const std::string& planner);
PlanResult PlanWithRestarts(const PlanningProblem& problem, const PoseValidity& validity,
                            const PlannerOptions& options);

// The eigenvectors of the area-weighted normal tensor sum a n n^T of D's
// triangles, turned by `rotation`, largest first (a plate's normal first, a
// pin's axis last: the normals of a cylinder lie across it); none when the
// eigen solver fails. Each points to the positive side of its largest
// coordinate.
std::vector<Eigen::Vector3d> SurfaceNormalAxes(const TriangleMesh& mesh, const Eigen::Quaterniond& rotation);

// The directions a part is pulled along, in the world, without repeats (a
// direction within a micro-radian of one already there): D's principal axes
// (the spread of its vertices) turned by `orientation`, the world's axes, and
// the axes of D's area-weighted surface normals turned by `orientation`.
std::vector<Eigen::Vector3d> PullAxes(const TriangleMesh& robot, const Eigen::Quaterniond& orientation);

// Straight pulls from the start (a peg or a pin in a tight fit, a cap on a
// post: what a sampler finds last, with a clearance of hundredths of a mm,
// is a single straight motion): along D's principal axes at the start and
// the world's axes, both ways, each as far as D needs to reach the goal
// region, checked as a planner's edge (and certified). Solved with the
// two-pose path of the first pull that is valid, in that order; otherwise
// not solved (kIterationLimit), with the checks counted, and where S is
// cropped and a pull's goal lies beyond the crop, whether that pull is free
// up to the crop's edge (PlanResult::pull_left_crop; asked only once no
// pull got D out). Then, where no single pull is free (not even to the
// crop's edge), two legs: each blocked pull walked to where it stops, and
// from there a pull along each other axis, both ways (a pin lifted out of
// its bore under a bracket, then slid out from under it), solved with the
// three-pose path of the first free one; those walks stop after
// kSecondLegChecks checks in all, and where first legs stopped more than a
// step from the start is kept (PlanResult::pull_stops). Nothing is tried
// where the problem has a goal pose.
inline constexpr std::int64_t kSecondLegChecks = 1024;
PlanResult TryStraightPulls(const PlanningProblem& problem, const PoseValidity& validity,
                            const PlannerOptions& options);

// A goal pose (or the start) that is invalid makes the problem unsolvable;
// these throw InputError with the reason.
void CheckEndpoints(const PlanningProblem& problem, const PoseValidity& validity, const std::string& where);

}  // namespace ausbau
