// The independent exact check of a finished path, as a file states it: the
// waypoints in the scene convention (x_world = R(q)(x - dynamic_origin) + t),
// interpolated the plain way (lerp of t, slerp of q along the shorter arc),
// which is how any other tool reads path.csv, not about the planner's
// reference point. A path passes when
//  1. its first waypoint is the scene's start (the installed pose);
//  2. its last waypoint meets the scene's goal (planning/scene_goal.h): by
//     default D's world AABB separated from S's; the goal pose; or the
//     goal condition (clearance from S, region of dynamic_origin);
//     (for a scene cropped to D's reach, planning/reach_crop.h: D's AABB is
//     clear of S by the crop's clearance and inside its box);
//  3. along the whole interpolated motion, no rigid shell of D penetrates S
//     deeper than `tolerance` (exact separating-axis depth per shell pair,
//     collision/rigid_depth.h); fasteners are measured, not judged. Poses
//     are checked by conservative advancement:
//     the next pose is as far as the current slack allows (never less than
//     `tolerance` / 10), with a rigorous bound on how far a point moves, so
//     between two checked poses the depth can exceed the checked one by at
//     most that floor. On a segment that is a pure translation, stretches
//     are first proved whole by the swept bound (RigidDepthChecker::
//     TranslationValid: no rigid shell beyond its allowed depth anywhere on
//     the stretch), which a part sliding along a fit or a contact needs: its
//     slack stays near zero, a pose per tolerance / 10 of the way.
// The same shells and roles as the planners (ClassifyParts at the start;
// `unmeasured` as there).
// A large S is checked within the smallest crop box (planning/reach_crop.h)
// that holds D along the whole path, which the check itself ensures (D's
// bounding ball is kept inside the box, the steps bounded by its distance to
// the box); S's triangles outside the box cannot touch D, so the answer is
// the one for the whole S.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "collision/rigid_depth.h"
#include "core/log.h"
#include "geometry/pose.h"

namespace ausbau {

struct Scene;

struct ExactCheckReport {
  bool valid = false;
  std::string reason;  // empty when valid
  std::int64_t poses_checked = 0;
  // Stretches of translations proved at once by the swept bound (their ends
  // are among the poses checked).
  std::int64_t stretches_proved = 0;
  // >= 0; deepest rigid penetration along the path. Where it exceeds the
  // tolerance the path has failed and the stretch is sampled at steps of
  // the excess: the number is then at least half way from the tolerance to
  // the true deepest.
  double max_rigid_depth = 0;
  int rigid_shell = -1, static_shell = -1;
  int worst_segment = -1;  // where the deepest rigid penetration is
  double worst_fraction = 0;
  Pose worst_pose;                // scene convention
  double max_fastener_depth = 0;  // deepest fastener penetration (reported)
  int first_bad_segment = -1;     // first segment that breaks the limits
  bool starts_at_start = false;
  bool ends_separated = false;         // D's exact AABB at the last waypoint clear of S's
  bool ends_in_goal = false;           // the last waypoint meets the scene's goal (SceneGoal)
  std::string goal;                    // the goal, in words (SceneGoal::Describe)
  int crop_level = -1;                 // the crop the check used (planning/reach_crop.h); -1: the whole S
  std::int64_t checked_triangles = 0;  // S's triangles the check measured against
  std::shared_ptr<const PartModel> parts;
};

// Whether a path that ExactCheckPath judged removes D: it passes, starts at
// the installed pose and ends in the scene's goal (SceneGoal: by default D's
// AABB separated from S's, which is then what ends_separated says). One
// definition for ausbau-verdict and ausbau-order: the order's scenes
// (workflow/disassembly_order.cpp, AttemptScene) have no goal, so for them
// this is the "separated" test the order had used.
bool RemovesPart(const ExactCheckReport& report);

// `progress`: the segments checked of the path's (core/log.h); empty =
// silent. Throws Cancelled between poses when cancelled (core/cancel.h).
// `models` (or null): the parts classified per crop level, kept between
// calls: a caller that checks several paths of one scene with the same
// tolerance and rule (ausbau-smooth: its input and its output) passes the
// same one, and each level is classified once (a classification of s1's
// head, S about 300,000 triangles, takes seconds).
struct ExactCheckModels {
  std::map<int, std::shared_ptr<const PartModel>> by_level;  // -1: the whole S
};
ExactCheckReport ExactCheckPath(const Scene& scene, const std::vector<Pose>& waypoints, double tolerance,
                                UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid,
                                const ProgressCallback& progress = {}, ExactCheckModels* models = nullptr);

// Adds waypoints so that interpolating each segment the plain way (about
// D's mesh origin shifted by dynamic_origin) stays within `deviation` of
// interpolating it about `reference_point` (the planners' way). Both sets of
// waypoints are in the scene convention. The two differ by a chord against
// an arc of radius |reference_point - dynamic_origin|, at most
// |c| (1 - cos(angle / 2)) per segment, so long turns far from the origin
// are split.
// What blocks D, for a verdict of "not removable": straight pulls from the
// installed pose along D's principal axes (both ways; the eigenvectors of
// the covariance of D's vertices, in the world at the installed pose), each
// advanced conservatively like the exact check until a rigid shell of D
// penetrates S deeper than the tolerance (blocked: which shell of D, which
// of S, how deep, after how far) or D's AABB clears S's (the pull gets D
// out). Where no path was found this names the parts that hold D; it is
// not a search (a pull that comes out does not make D removable: a planner
// would have found it, unless a fastener that the pull drags through S may
// not go so far).
struct BlockingProbe {
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // world, unit
  double free_distance = 0;                             // how far D moved within the tolerance (scene units)
  bool separated = false;                               // the pull got D's AABB clear of S's
  // Neither: the pull used its kMaxPullSteps (sliding in contact, where a
  // conservative step is a tenth of the tolerance) or left the crop's box.
  bool unfinished = false;
  int steps = 0;     // depth measurements and proofs of stretches made (the work it cost)
  double depth = 0;  // the rigid penetration that stopped it
  int rigid_shell = -1, static_shell = -1;
  // The scene's part of S that static_shell belongs to ("" where S is one
  // part or the shell was not matched to a triangle of it).
  std::string static_part_name;
};
// The work one pull may do (depth measurements and proofs of stretches): a
// count, so the report is the same under any load. A pull that slides in
// contact (a bolt in its bore, coincident tessellated faces) may advance by
// only a tenth of the tolerance per step (0.005 mm at the default) where no
// stretch of it can be proved whole: unbounded, such a pull measured for
// minutes. 2,048 steps carry D at least 200 tolerances (10 mm at the
// default), and the whole reach where nothing is within the tolerance
// (steps of 5% of D's diagonal, which pass S's box in about 20 + 20 x S's
// size / D's).
inline constexpr int kMaxPullSteps = 2048;
struct BlockingReport {
  std::vector<BlockingProbe> probes;  // +axis 0, -axis 0, +axis 1, ... (largest spread first)
  int farthest = -1;                  // the blocked probe that got farthest (-1: none blocked)
  std::shared_ptr<const PartModel> parts;
  std::string summary;  // one line for a user
};
// `parts`: D's solids as ClassifySceneParts(scene, tolerance, unmeasured)
// gives them, when the caller has them already (null: classified here).
// `until_out`: stop at the first pull that gets D out (the caller asks only
// whether one does; the pulls not made are not in `probes`), and a pull
// that is too deep one largest step along is blocked at once (its
// free_distance 0, not measured).
BlockingReport ProbeWhatBlocks(const Scene& scene, double tolerance,
                               UnmeasuredInterference unmeasured = UnmeasuredInterference::kRigid,
                               std::shared_ptr<const PartModel> parts = nullptr, bool until_out = false);

std::vector<Pose> DensifyForPlainInterpolation(const std::vector<Pose>& waypoints,
                                               const Eigen::Vector3d& reference_point,
                                               const Eigen::Vector3d& dynamic_origin, double deviation);

}  // namespace ausbau
