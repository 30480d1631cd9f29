// ausbau-plan's work: one scene planned under one validity.
//   collision     rigid planning from a collision-free start (FCL, or FARR
//                 in front of FCL with distance fields)
//   rigid-exact   D's rigid shells never deeper in S than the tolerance,
//                 its fasteners free (collision/rigid_depth.h); densified
//                 for plain interpolation and checked exactly
//   volume modes  InIState planning (thesis 5.4.4): sigma_1 under the
//                 volume validity out of the fasteners' reach, sigma_2 rigid
#pragma once

#include <string>
#include <vector>

#include "planning/path_io.h"
#include "planning/planner.h"
#include "scene/scene.h"
#include "workflow/volume_inputs.h"

namespace ausbau {

// How ausbau-plan checks collisions in the modes that do (--collision):
//   fcl   FCL alone
//   farr  FARR's rays in front of FCL, with distance fields (same answers)
enum class CollisionMode { kFcl, kFarr };
const std::vector<std::string>& CollisionModeNames();  // fcl, farr
// Throws InputError "--collision: unknown mode '<name>' (expected fcl or farr)".
CollisionMode ParseCollisionMode(const std::string& name);
std::string CollisionModeName(CollisionMode mode);

inline constexpr std::int64_t kDefaultCropLevelIterations = 61440;

struct PlanSceneOptions {
  // "auto": CR-RRTC, or EST for sigma_1 in the volume modes.
  PlannerOptions planner = [] {
    PlannerOptions p;
    p.planner = "auto";
    return p;
  }();
  CollisionMode collision = CollisionMode::kFcl;
  std::string distfield;  // farr: "S.h5,D.h5"; empty: built or reused through the cache
  ValidityMode validity = ValidityMode::kCollision;
  double tau = -1;       // < 0: from tau_file, else estimated here (shrink: 0)
  std::string tau_file;  // ausbau-tau-estimate artifact
  double psi = 0;        // mm (--psi; converted by the scene's units); 0: from tau_file, else from the labels
  VolumeInputs volume;
  std::string rigid_planner = "cr-rrtc";
  bool verify = true;  // the independent dense (or exact) re-check of the result
  // The run's time budget (planning/planner.h: SecondsLeft): the time limits
  // are cut to what is left before it; an unsolved run it ended is marked
  // stopped_by_budget in the artifact. 0: none.
  double deadline = 0;
  // rigid-exact: how often the crop of a large S around D may grow when no
  // path is found (planning/reach_crop.h); -1: until it holds all of S.
  int max_crop_level = -1;
  // rigid-exact: the planner iterations (restarts together) a level that
  // crops S gets before the crop grows; the last level has no cap (the
  // time limit is its safety net). Work, not a share of the time limit, so
  // that the level that answers is the same on any machine at any load.
  // 61440 = four restart rounds (4096 + 8192 + 16384 + 32768): about 10-20 s
  // on the cropped scenes of a vehicle on this 2-core machine, what the old
  // share of 60 s over 3-5 levels gave.
  std::int64_t crop_level_iterations = kDefaultCropLevelIterations;
  // --clearance (scene units; < 0: the default, planning/clearance.h, kept
  // by smoothing only): a given one makes a first try keep D this far from
  // S where the start allows (rigid-exact and collision; the volume modes
  // leave it to smoothing's sigma_2).
  double clearance = -1;

  // Throws InputError naming the flag of a value that does not fit.
  void Check() const;
};

// The two files of `distfield`, or none (collision fcl, or not given).
std::vector<std::string> DistfieldPaths(const PlanSceneOptions& options);

struct PlannedPath {
  PathArtifact artifact;  // success = a path was found; written either way
  PlanStatus status = PlanStatus::kTimeLimit;
};

// Plans; logs what it does and, where no path is found, why. Throws
// InputError for inputs that do not fit the scene, std::runtime_error when
// a found path fails its independent re-check (a bug). Under --validity
// collision, where D and S are closed solids, a path that passes the dense
// re-check but not the exact check (a thin part through a thicker wall of
// S, which surface checks a step apart do not see) is no path: success = 0,
// the path kept as the partial one.
PlannedPath PlanScene(const Scene& scene, const PlanSceneOptions& options);

// The validity this scene needs: rigid-exact, unless a shell of D other
// than its anchor intersects S at the installed pose in a pair with a
// non-convex shell (a clip in a plate with holes welded into one mesh, where
// a snap clip and a friction-fit rail look alike): that interference needs
// the volume model, labeled-mliv. A single-solid part (a cap, a peg, a
// bracket: the anchor alone) that overlaps S is rigid-exact: its overlap is
// a fit interference or a clash (collision/rigid_depth.h). So is a scene
// where a shell the volume model keeps rigid already clashes with S: the
// verdict's exact check would refuse any path the volume model found.
ValidityMode ChooseValidity(const Scene& scene, double rigid_tolerance_mm);

}  // namespace ausbau
