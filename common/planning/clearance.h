// Clearance: the distance between D (or the part of D that must stay clear,
// see ClearanceRobot) and S along a path, measured with FCL at poses along
// each straight motion (the planners' interpolation, planning convention).
//
// Two uses:
//  - reporting (the verdict's path_quality, profile.csv): the smallest
//    clearance of every segment at dense poses, with where it is attained;
//  - keeping a clearance d (ausbau-plan / ausbau-smooth --clearance): only
//    whether a motion stays at or above a floor matters, so a sample whose
//    clearance c exceeds the floor lets the walk jump c - floor ahead (no
//    point of D can close that gap sooner: conservative advancement), and
//    only near the floor does it take the fixed step.
// Clearance is a preference, never a validity: it only ever adds a
// condition to what the validity check already accepted.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "collision/fcl_checker.h"
#include "planning/replacement_guard.h"
#include "planning/state_space.h"

namespace ausbau {

struct PartModel;

// The default --clearance, in millimetres: ten times the default rigid
// tolerance (RIGID_TOLERANCE, 0.05 mm: how deep a rigid part may touch
// into S), so a kept clearance is a gap and not a touch within that
// tolerance, and about the chord tolerance of a CAD export's tessellation
// (0.1-0.5 mm): a smaller gap on the meshes need not exist on the real
// part. Small enough to leave every realistic fit its way out (it is a
// preference; where a passage is narrower the path goes through it anyway
// and the verdict says where).
inline constexpr double kDefaultClearanceMm = 0.5;

// --clearance in scene units: `clearance` (mm, as every length flag) when
// >= 0, else the default kDefaultClearanceMm, converted by the scene's
// `units` (mm, cm, m, in; unknown or no units: the number as scene units,
// as the rigid tolerance; scene/units.h MillimetresInSceneUnits).
double ClearanceInSceneUnits(double clearance, const std::string& units);

// The sample step of the clearance walks that keep d: d itself, within
// 0.1% and 1% of D's diagonal.
double ClearanceStep(const PlanningProblem& problem, double clearance);

// The smallest clearance found along a motion and where: the segment, the
// fraction of it, and the nearest points of D and S (world coordinates;
// both at a contact point when the clearance is 0).
struct ClearanceSample {
  double clearance = std::numeric_limits<double>::infinity();
  int segment = -1;
  double fraction = 0;
  Eigen::Vector3d on_robot = Eigen::Vector3d::Zero();
  Eigen::Vector3d on_static = Eigen::Vector3d::Zero();
};

// The part of D that must keep clear of S, relative to D's reference point
// (planning convention): D's rigid shells when `parts` is given (the exact
// rigid check, collision/rigid_depth.h: a fastener is meant to bend through
// S, its distance says nothing), else all of D.
TriangleMesh ClearanceRobot(const PlanningProblem& problem, const PartModel* parts);

class ClearanceMeter {
 public:
  // `robot` relative to D's reference point (ClearanceRobot), S from the problem.
  ClearanceMeter(const PlanningProblem& problem, const TriangleMesh& robot);

  // `with_points` false: the clearance only (on_robot, on_static left
  // unset), one FCL distance query instead of a collision query and a
  // distance query with nearest points: what the guard's accept/reject needs.
  ClearanceSample At(const Pose& pose, bool with_points = true) const;

  // The smallest clearance along the straight motion a -> b (segment 0),
  // walked from a: where a sample's clearance c exceeds `floor` the next is
  // c - floor farther (largest vertex displacement), else `step` farther.
  // Exact at the samples; between two samples the clearance is at least the
  // smaller of them minus `step`, and at least `floor` where the walk jumped.
  // floor = +infinity samples every `step` (reporting). The walk ends early
  // at the first sample below `stop_below` (a rejection needs no more).
  ClearanceSample Along(const Pose& a, const Pose& b, double floor, double step,
                        double stop_below = -std::numeric_limits<double>::infinity(), bool with_points = true) const;
  // Along's samples of a -> b in order, each handed to `visit` (its
  // fraction set; segment 0); the walk ends where `visit` returns false.
  void Walk(const Pose& a, const Pose& b, double floor, double step, bool with_points,
            const std::function<bool(const ClearanceSample&)>& visit) const;

  // The smallest clearance over the consecutive motions of `path` (its
  // segment index and fraction); the same walk as Along on each.
  ClearanceSample AlongPath(const std::vector<Pose>& path, double floor, double step,
                            double stop_below = -std::numeric_limits<double>::infinity(),
                            bool with_points = true) const;

 private:
  const PlanningProblem* problem_;
  FclCollisionChecker fcl_;
};

// What the smoother keeps: a motion replacing part of the path being
// smoothed is accepted when its smallest clearance is at least
//   min(d, the smallest clearance of the part it replaces), or
//   the path's floor: min(d, the smallest clearance of the input path from
//   where D is first d from S on; of the whole input path where it never is).
// So no change makes the clearance worse below d than it was there, or than
// the path must come anyway (a narrow place it passes later); D's way out of
// its seat (before it is first d from S) does not count for the floor. A
// part that starts where D touches S (within `contact`: clearances below
// the rigid tolerance are contact, not a clearance to keep) may be replaced
// by any motion. d = 0 (or no guard) accepts everything. Without the floor,
// a planned detour kept its shape wherever a shortcut came closer to S than
// the detour did: a Voron bowden module's M3 screw, whose planned path
// passes 0.0014 mm from S after leaving its hole, smoothed to 114 mm and
// 3.5 rad of motion (25.5 mm and 0.32 rad without a guard).
class ClearanceGuard : public ReplacementGuard {
 public:
  // `input`: the path to be smoothed (the floor). `contact`: how close
  // to S counts as touching it (the rigid tolerance, where the validity
  // allows that much depth; else 0), see Accepts.
  ClearanceGuard(const PlanningProblem& problem, const TriangleMesh& robot, double clearance, double step,
                 const std::vector<Pose>& input, double contact = 0);

  double clearance() const { return clearance_; }
  // Walked the first time it is asked (Accepts asks only for a replacement
  // closer than d): a walk of the whole input path, 15 s along a pin's
  // 310 mm bore, which most smoothings never need.
  double floor() const;
  // Whether `replacement` (a sequence of poses joined by straight motions)
  // may take the place of `replaced`.
  bool Accepts(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const override;
  // The smallest clearance of a path, capped at d (d when it stays clear).
  double MinCapped(const std::vector<Pose>& path) const;
  // The closest sample of a path's walk (exact where below d), with where
  // (segment and fraction; not the nearest points).
  ClearanceSample Closest(const std::vector<Pose>& path) const;

 private:
  // Whether `replacement` is one translation along the first segment of
  // `replaced` (also a translation), from its start and no farther than its
  // end (up to on_line_): its poses are poses of the replaced path, so it
  // comes no closer, and nothing need be walked. A straight pull's retreat
  // to where D leaves S's box is such a motion. Walked, a pin pulled 310 mm
  // along its bore took two walks of 1,350 distance queries each (11 s).
  bool RetracesFirstSegment(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const;
  // The floor of `path` (above), walked as Along with floor d.
  double FloorOf(const std::vector<Pose>& path) const;

  ClearanceMeter meter_;
  double clearance_, step_, on_line_, contact_;
  std::vector<Pose> input_;
  mutable std::optional<double> floor_;
};

// The planner's first try with a clearance (ausbau-plan --clearance): the
// validity `base` and, in addition, D's part (the meter's) at least `floor`
// from S. Only ever stricter than `base`. A SlackValidity base (the exact
// rigid check) stays one: the slack is the smaller of the base's and
// clearance - floor (no point of D moving less than that can close the gap
// to below floor), so the motion check walks it by conservative advancement
// as before.
std::unique_ptr<PoseValidity> WithClearance(const PoseValidity& base, const PlanningProblem& problem,
                                            const TriangleMesh& robot, double floor);

}  // namespace ausbau
