// The profile along a path (ausbau-smooth --profile, the report's plots):
// per dense pose the path parameter, the volume mode's intersection with
// its part and deformability, and the clearance to S.
#pragma once

#include <filesystem>
#include <vector>

#include "geometry/pose.h"
#include "inistate/volume_model.h"
#include "planning/state_space.h"

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

// CSV `segment,fraction,s,volume,part,deformability,clearance`, at most
// ~2000 rows (the step is 1% of D's diagonal or longer); the volume columns
// are empty without a model; clearance is the FCL distance (0 in contact).
// Written atomically.
void WritePathProfile(const std::filesystem::path& file, const PlanningProblem& problem, const std::vector<Pose>& path,
                      VolumeModel* model);

}  // namespace ausbau
