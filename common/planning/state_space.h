// The rigid-body planning problem in the planning convention, the
// normalized SE(3) metric of the thesis and the motion (edge) check.
//
// Scene convention:    x_world = R(q) (x_mesh - dynamic_origin) + t_scene
// Planning convention: x_world = R(q) (x_mesh - reference_point) + t
// The reference point lies inside D (see MakePlanningProblem), so rotations in
// the planner turn D about itself even when a CAD export puts D metres away
// from its mesh origin. Conversions happen only at the boundary.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "collision/validity.h"
#include "core/random.h"
#include "geometry/mesh.h"
#include "geometry/pose.h"
#include "planning/reach_crop.h"

namespace ausbau {

struct Scene;

// Thesis eq. 2 and 3. nu is the extent (diagonal) of the translation bounds.
struct Metric {
  double nu = 1.0;

  // d'_t in [0, 1] within the bounds.
  double Translation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const { return (a - b).norm() / nu; }
  // d'_q = min(acos(q1.q2), acos(q1.(-q2))) / pi, in [0, 1/2].
  static double Rotation(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
    const double dot = std::min(1.0, std::abs(a.coeffs().dot(b.coeffs())));
    return std::acos(dot) / M_PI;
  }
  // d'_c(c1, c2, u) = u d'_t + (1 - u) d'_q, eq. 2.
  double Distance(const Pose& a, const Pose& b, double u) const {
    return u * Translation(a.t, b.t) + (1.0 - u) * Rotation(a.q, b.q);
  }
  // range(c1, c2) = max(d'_t, d'_q), eq. 3.
  double Range(const Pose& a, const Pose& b) const { return std::max(Translation(a.t, b.t), Rotation(a.q, b.q)); }
};

struct PlanningProblem {
  TriangleMesh robot;                                         // D relative to reference_point (its mesh frame, shifted)
  TriangleMesh environment;                                   // S in world coordinates
  Eigen::Vector3d reference_point = Eigen::Vector3d::Zero();  // in D's mesh coordinates
  Eigen::Vector3d dynamic_origin = Eigen::Vector3d::Zero();   // in D's mesh coordinates
  // Translation bounds apply to the world position of the point
  // `bounded_point` (relative to the reference point, in D's frame): the
  // scene's dynamic_origin when the scene gives bounds, else the reference
  // point itself (derived bounds).
  Aabb bounds;
  Eigen::Vector3d bounded_point = Eigen::Vector3d::Zero();
  bool bounds_given = false;
  Pose start;                // planning convention
  std::optional<Pose> goal;  // planning convention; none = disassembly region
  // When set, every sampled pose has this orientation: translation-only
  // planning (the smoother's alternative without turning D).
  std::optional<Eigen::Quaterniond> fixed_rotation;
  // When set, SampleUniform draws half of its samples near this path
  // (planning convention): a pose along one of its segments, moved by a
  // distance drawn log-uniformly between 1/1000 and 1 of D's AABB diagonal
  // and turned (unless fixed_rotation) by at most that distance over
  // robot_radius. A path found with D turned guides the translation-only
  // alternative through the same narrow passages, and a segment that fails
  // certification guides its repair: uniform samples in the bounds hardly
  // ever land there.
  std::vector<Pose> sampling_guide;
  Aabb robot_local_box;       // AABB of `robot`
  double robot_radius = 0;    // max distance of a vertex of D from the reference point
  double robot_diagonal = 0;  // diagonal of D's AABB
  Aabb environment_box;       // AABB of S (of the cropped S when `crop` is set)
  // Set when S is cropped to D's reach (planning/reach_crop.h): then
  // `environment` is the cropped S, `bounds` keep D inside crop->box and
  // `goal_test` is crop->InGoal.
  std::shared_ptr<const ReachCrop> crop;
  Metric metric;

  Pose SceneToPlanning(const Pose& scene_pose) const;
  Pose PlanningToScene(const Pose& planning_pose) const;

  bool InBounds(const Pose& pose) const;
  // World AABB of D at `pose`, conservative: the box around the 8 transformed
  // corners of D's local AABB.
  Aabb RobotBoxAt(const Pose& pose) const;
  // Optional goal region replacing the disassembly region (the InIState
  // planner's distance(S, D) > psi, inistate/inistate_planner.h). Must be
  // thread-safe. Planners that sample the goal region (RRT-Connect's goal
  // tree, PRM) draw AABB-separated poses and keep those it accepts.
  std::function<bool(const Pose&)> goal_test;
  // The scene's goal region (goal: {region}) for dynamic_origin's world
  // position: SampleGoalRegion draws there instead of in all the bounds.
  std::optional<Aabb> goal_region;
  // Disassembly goal: D's AABB (conservative) separated from S's, or
  // goal_test when set.
  bool InGoalRegion(const Pose& pose) const {
    return goal_test ? goal_test(pose) : RobotBoxAt(pose).SeparatedFrom(environment_box);
  }

  Pose SampleUniform(Random& random) const;
};

// Builds the planning problem: a goal condition of the scene (goal:
// {clearance, region}) becomes goal_test (planning/scene_goal.h) and, with a
// region, goal_region; a clearance widens the derived bounds by itself so
// that D can get that far. The reference point is the scene's
// dynamic_origin when given (the OMPL.app scenes give D's centroid), else the
// centre of D's AABB. Derived bounds: S's AABB together with the start (and
// goal) positions, grown by 1.5x D's AABB diagonal on every side, which leaves
// room for D to leave S's AABB in any direction. Throws InputError when
// start or goal lie outside the bounds.
// A large S is cropped to D's reach at `crop_level` (planning/reach_crop.h:
// the rule, the bounds, the goal); at a level whose box holds all of S, or
// for a scene the rule does not crop, `crop` stays empty and the problem is
// the uncropped one.
PlanningProblem MakePlanningProblem(const Scene& scene, int crop_level = 0);

// The problem at the smallest crop level whose bounds hold every waypoint
// (scene convention) of a path planned before (the smoother's and the
// report's problem for a path that may have been found at a grown crop).
PlanningProblem MakePlanningProblemHolding(const Scene& scene, const std::vector<Pose>& scene_waypoints);

// A pose in the goal region (InGoalRegion) and in bounds, drawn uniformly in
// the bounds, or with goal_region set, with dynamic_origin uniformly in that
// box (and in the bounds). Collision-free: by construction for the AABB
// separation, by the goal test for conditions. False after 100 misses.
bool SampleGoalRegion(const PlanningProblem& problem, Random& random, Pose* pose);

// Checks straight motions (linear t, slerp q about the reference point)
// between poses at a step size bound: between two checked poses no vertex of
// D moves more than `step` (world units). A validity that measures its slack
// (collision/validity.h: SlackValidity, e.g. the exact rigid-depth check) is
// walked by conservative advancement instead: steps as long as the slack
// allows, never shorter than its MinStep.
class MotionChecker {
 public:
  // `deadline`: a motion stops there, as if blocked (a planner's time
  // limit, which an edge of thousands of slow checks in a narrow passage,
  // or of billions of steps across huge bounds, would otherwise overrun by
  // minutes or hours).
  MotionChecker(const PlanningProblem& problem, const PoseValidity& validity, double step,
                std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

  bool IsValid(const Pose& pose) const {
    Count();
    return problem_->InBounds(pose) && validity_->IsValid(pose);
  }
  // The poses checked so far (validity or slack measured; the smoother
  // logs them).
  std::int64_t checks() const { return checks_.load(std::memory_order_relaxed); }
  // Whether motions are walked by conservative advancement (the validity
  // measures its slack): their poses then do not depend on `step`.
  bool WalksBySlack() const { return slack_ != nullptr; }
  // Number of equal sub-steps needed between a and b.
  std::int64_t Steps(const Pose& a, const Pose& b) const;
  // Whole motion valid (a is assumed valid and not re-checked; b is checked).
  bool MotionValid(const Pose& a, const Pose& b) const;
  // For several motions from one pose (the smoother's straight retreats try
  // up to 28 directions from each point): whether `a` is valid, measured
  // once; with a validity that measures slack, that slack, which
  // MotionValidFrom then reuses instead of measuring it again for each
  // motion (in rigid-exact, a blocked retreat is two depth searches, one
  // of them at `a`). Negative: `a` is invalid or out of bounds.
  double StartSlack(const Pose& a) const;
  // MotionValid(a, b) with `a`'s StartSlack (>= 0) known. With slack, the
  // pose one step (step()) along is checked first: a retreat that runs
  // into S from a contact is blocked there, at a depth the check decides
  // at once, where the walk's first step (MinStep, a pose just beyond the
  // tolerance) is the slowest pose to decide (as1's rod in its bores: 29 s
  // -> 7 s of retreats). A motion through an invalid pose is blocked, so
  // this answers as MotionValid does, except that a motion the walk would
  // pass by stepping over such a pose (a step of MinStep allows the
  // tolerance plus MinStep, collision/rigid_depth.h) is blocked too.
  bool MotionValidFrom(const Pose& a, double start_slack, const Pose& b) const;
  // Walks from a towards b and returns the fraction in [0, 1] of the last
  // valid checked pose (0 = no progress), and that pose in *last_valid.
  double ValidPrefix(const Pose& a, const Pose& b, Pose* last_valid) const;
  double step() const { return step_; }
  // Also prove stretches of MotionValid by D's clearance at their middle
  // (PoseValidity::ProveMotionByClearance), where the validity can: for
  // the certification's fine step (planning/certify.h), where a proof of a
  // short stretch near S saves many checks. Not in the search: its motions
  // are mostly longer than the clearance there, and on cubicles 95% of such
  // proofs with a reach above a third of D's radius failed, at about 2.5
  // checks' time each (docs/planning.md "Proofs by clearance").
  void ProveByClearance() { clearance_proofs_ = validity_->ProvesMotionsByClearance(); }
  const PoseValidity& validity() const { return *validity_; }

 private:
  // With a SlackValidity: walks from a towards b by conservative
  // advancement; returns how far it got in [0, 1] (1 when every pose was
  // valid, -1 when a is invalid) and the last valid pose.
  // `a_slack`: a's slack where already measured (StartSlack), else NaN.
  double Advance(const Pose& a, const Pose& b, Pose* last_valid,
                 double a_slack = std::numeric_limits<double>::quiet_NaN()) const;
  // Past the deadline, or cancelled.
  bool OutOfTime() const;
  void Count() const { checks_.fetch_add(1, std::memory_order_relaxed); }

  // Sweeps (PoseValidity::ProveMotion) of the walk without slack: only
  // after this many steps pose by pose, and only over this many steps or
  // more (a shorter one saves too few checks for what a failed one costs).
  static constexpr std::int64_t kStepsBeforeSweeping = 4;
  static constexpr std::int64_t kShortestSweep = 8;
  // Whether every pose of the straight motion a -> b keeps the bounded point
  // in the bounds (what a sweep of the validity does not prove).
  bool StretchInBounds(const Pose& a, const Pose& b) const;
  // Whether to try a sweep now, and what one tried gained (`proved_steps`
  // the poses it proved, 0 when it proved nothing): see sweep_gain_.
  bool SweepWorthTrying() const;
  void RecordSweep(std::int64_t proved_steps) const;

  const PlanningProblem* problem_;
  const PoseValidity* validity_;
  const SlackValidity* slack_;  // validity_ when it measures slack, else null
  double step_;
  bool clearance_proofs_ = false;
  std::chrono::steady_clock::time_point deadline_;
  // A moving average (over about the last 32 sweeps) of the checks a sweep
  // saved less the one it cost: the poses it proved minus one (at most 64),
  // or -1 when it proved nothing. Where D is rarely farther from S than its
  // own radius (the alpha puzzles: about a tenth of the sweeps prove
  // anything) they would only add work, so while the average is not
  // positive only every kSweepProbe-th chance is taken, to notice when
  // they start to pay.
  // Atomic for PRM's threads, which share the checker (the answers never
  // depend on it, only the number of checks).
  mutable std::atomic<double> sweep_gain_{1.0};
  mutable std::atomic<std::int64_t> sweep_chances_{0};
  mutable std::atomic<std::int64_t> checks_{0};
  static constexpr std::int64_t kSweepProbe = 16;
};

}  // namespace ausbau
