// Shortcut smoothing under the planner's own motion check: a change is kept
// only when its motion is valid and it makes the path shorter, so the result
// is never less valid than the input. In order:
//   1. shortcuts: the path between two random points replaced by the
//      straight motion (all degrees of freedom at once);
//   2. a straight retreat (disassembly only: no goal pose): from the
//      earliest waypoint where it is free, D leaves along one straight
//      translation until its AABB is clear of S's, instead of the planner's
//      way out;
//   3. partial shortcuts (Geraerts & Overmars 2007): between two waypoints
//      one degree of freedom (x, y, z, or the rotation) is made linear while
//      the others keep their course; in a disassembly the rotation of the
//      tail is also frozen where the part needs it no longer, which removes
//      needless turning;
//   4. waypoints whose neighbours see each other are dropped;
//   5. (disassembly, when the result still turns D by more than 0.1 rad in
//      all) a translation-only path is planned (D's start orientation
//      fixed), smoothed by 1-4, and kept when it is shorter.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/log.h"
#include "planning/state_space.h"

namespace ausbau {

class ReplacementGuard;

struct SmoothOptions {
  std::uint64_t seed = 1;
  int attempts = 0;  // 0 = automatic: 100 + 10 per waypoint, at most 2000
  // A safety net only: the work is bounded by `attempts` (full shortcuts,
  // then a quarter of them partial ones) and the translation-only
  // alternative by its 20000 iterations, so the result is the same on any
  // machine unless this fires (the OMPL Apartment scene takes about 12 s,
  // the demo 10 s). Past it every motion counts as blocked and the rest is
  // kept as it is: a valid, less smooth path, marked SmoothResult::cut_short.
  double time_limit_s = 60.0;
  double resolution = 0.01;  // as PlannerOptions::resolution
  // --clearance: the distance from S to keep where the geometry allows, in
  // mm (as the flag; ClearanceInSceneUnits, planning/clearance.h, converts
  // it); < 0: the default.
  double clearance = -1;
  // Shortcut attempts done of those planned, then the translation-only
  // alternative's iterations (core/log.h); empty = silent.
  ProgressCallback progress;
  void Check() const;
};

struct PathLength {
  double translation = 0;  // reference point travel, world units
  double rotation = 0;     // summed rotation angle, radians
  double normalized = 0;   // sum of d'_c with u = 0.5 (thesis metric)
};

PathLength MeasurePath(const PlanningProblem& problem, const std::vector<Pose>& path);

// The pose reached from `from` (planning convention) by the shortest
// straight translation along `direction` that takes D's AABB clear of S's
// (the disassembly goal region), plus 1% of D's diagonal; nothing when the
// direction separates along no axis or the pose leaves the bounds. No
// collision check.
std::optional<Pose> StraightExitPose(const PlanningProblem& problem, const Pose& from, Eigen::Vector3d direction);

struct SmoothResult {
  std::vector<Pose> path;
  PathLength before, after;
  int shortcuts = 0;  // full and partial shortcuts kept
  int attempts = 0;
  int partial_shortcuts = 0;      // of them: partial ones (one degree of freedom)
  int retreat_from = -1;          // waypoint the straight retreat leaves from; -1 = none
  bool translation_only = false;  // the path is the translation-only alternative (step 5)
  // The time limit (a safety net) fired: some of the work was not done, so
  // the path (still valid: every change is checked) is not the
  // deterministic one. The smoothed artifact and the verdict record it.
  bool cut_short = false;
};

// With `guard` (planning/replacement_guard.h), every change (shortcut,
// retreat, dropped waypoint, the translation-only alternative) must also be
// accepted by it: with a clearance guard (planning/clearance.h), its motion
// comes no closer to S than min(d, the closest the part it replaces comes);
// without one, or with d = 0, exactly the unguarded smoothing.
SmoothResult SmoothPath(const PlanningProblem& problem, const PoseValidity& validity, const std::vector<Pose>& path,
                        const SmoothOptions& options, const ReplacementGuard* guard = nullptr);

// A copy of `path` with a waypoint at `fraction` (0 to 1) of the metric
// length (u = 1/2) of its part up to waypoint `last`: a pose inside a
// segment is inserted there (the motion stays the same). `index` receives
// that waypoint's index in the copy.
std::vector<Pose> WithWaypointAt(const PlanningProblem& problem, const std::vector<Pose>& path, std::size_t last,
                                 double fraction, std::size_t* index);

// Where a rotation freeze is tried (the tail freeze of step 3 and the
// InIState freeze across c_inter): 16 fractions of the length evenly
// spread, and after the first that works, 7 more between it and the one
// before, which failed. `try_at` returns whether the freeze at a fraction
// works (the caller keeps the last that did: the earliest found); returns
// whether one did.
bool FirstFreezeThatWorks(const std::function<bool(double fraction)>& try_at);

// Step 3 on the rotation alone, over waypoints [first, last] of a path:
// the rotation made linear in the path parameter (the partial shortcut on
// the rotation) over each section between two waypoints, the longest
// first. Each kept when valid, shorter and accepted by the guard; the
// endpoints stay. Returns whether the path changed (the InIState smoother
// takes out the wobble that sigma_1 keeps before a rotation freeze).
bool StraightenRotation(const PlanningProblem& problem, const PoseValidity& validity, const SmoothOptions& options,
                        const ReplacementGuard* guard, std::size_t first, std::size_t last, std::vector<Pose>* path);

// Step 2 alone, on a path of which only the part from waypoint `first` on
// may be replaced (the InIState path: a retreat may leave from sigma_1 once
// D is free there, validity the rigid one): from points evenly spread along
// that part, the straight retreat that makes the whole path shortest. The
// path then ends with the pose it leaves from and the retreat's end;
// returns the index of the former, or -1 (path unchanged) when none is
// valid and shorter. Disassembly only (no goal pose): else -1.
int StraightRetreatFrom(const PlanningProblem& problem, const PoseValidity& validity, const SmoothOptions& options,
                        const ReplacementGuard* guard, std::size_t first, std::vector<Pose>* path);

}  // namespace ausbau
