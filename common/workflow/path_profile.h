// The profile along a path (ausbau-smooth --profile, the report's plots):
// per dense pose the path parameter, the volume mode's intersection with
// its part and deformability, and the clearance to S.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "geometry/pose.h"
#include "inistate/volume_model.h"
#include "planning/clearance.h"
#include "planning/state_space.h"
#include "scene/scene.h"

namespace ausbau {

// A pose along a path (planning convention) with its segment and the
// fraction of that segment.
struct DensePose {
  Pose pose;
  int segment;
  double fraction;
};

// Poses along `path` such that between two of them no vertex of D moves
// more than `step`.
std::vector<DensePose> Densify(const PlanningProblem& problem, const std::vector<Pose>& path, double step);

// The part of D whose clearance a path of `validity` reports and keeps
// (planning convention): the rigid shells for rigid-exact (its fasteners
// bend through S by design; classified at the tolerance, mm), else all of D.
// `classified` (or null): D's parts as another check of this scene at this
// tolerance classified them, in whatever frame (the verdict's exact
// check): where that found no fastener, all of D is rigid, and it is not
// classified again (seconds on a large S).
TriangleMesh PathClearanceRobot(const Scene& scene, const PlanningProblem& problem, ValidityMode validity,
                                double rigid_tolerance_mm, const PartModel* classified = nullptr);

// Per dense pose along a path: the pose, its path parameter s (normalized
// metric length from the start, u = 0.5) and its clearance with where (its
// segment and fraction).
struct ProfilePose {
  DensePose dense;
  double s = 0;
  ClearanceSample clearance;
};

// The dense poses of the profile: a step of 1% of D's diagonal, or longer
// so that there are at most ~2000; clearance measured at every one (FCL
// distance of `meter`'s part of D and S; 0 in contact). Without the
// nearest points (ClearanceMeter::At's `with_points`: a collision query and
// a slower distance query at every pose), which the rows do not need.
std::vector<ProfilePose> ProfileAlongPath(const PlanningProblem& problem, const ClearanceMeter& meter,
                                          const std::vector<Pose>& path);

// profile.csv: a first comment line with the units and the pose
// convention, then the header
//   segment,fraction,s,tx,ty,tz,qw,qx,qy,qz,volume,part,deformability,clearance
// one row per dense pose (ProfileAlongPath); the pose in the scene
// convention (as path.csv), the volume columns empty without a model.
// Units (also in the comment line): t and clearance in scene units, q
// unitless, s normalized (unitless), volume scene units^3, deformability
// 0..1. Written atomically.
void WritePathProfile(const std::filesystem::path& file, const PlanningProblem& problem, const std::vector<Pose>& path,
                      VolumeModel* model, const TriangleMesh& clearance_robot, const std::string& units);

}  // namespace ausbau
